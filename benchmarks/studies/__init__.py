"""Studies whose results are in docs/: resolution ladders (``resolution_ladder``, tables by
``resolution_report``; docs/resolution_ladder.md), the bending effect at 200 m (``bending_effect_study``,
``bending_shapes``, ``moordyn_bending_rungs``), the DG stability limit (``calibrate_timestep``) and
cfl safety (``dg_cfl_study``), held arcs and the q-equation penalty (``hybrid_held_arc``,
``held_arc_modes``, ``held_arc_q_penalty``, ``q_penalty_ropos``), the ring beam [PE2020 Sec. 4.1]
(``ring_beam_convergence``), the hybrid solver on ROPOS (``ropos_hybrid``, ``ropos_slack_zones``,
``ropos_cross_check``), the PE2020 Sec. 6.2 figures and slack bending (``pe2020_sec62_figures``,
``sec62_moordyn_ladder``, ``slack_bending_ladder``); against MoorDyn: its own decks and chain cases
(``moordyn_decks``, ``chain_cases``; docs/moordyn.md, docs/verification.md), the wave loads
(``moordyn_waves``; docs/waves.md), where the two codes differ on the ROPOS snap
(``moordyn_physics_ladder``), line networks (``network_vs_moordyn``, ``network_excursion_spike``,
``network_vs_single_line``; docs/network.md); the vehicle in the loop: the input delay and the
station-keeping thrust in a current (``vehicle_loop_delay``, ``vehicle_tether_drag``), on the TMS excursion tether (``vehicle_on_tms``;
docs/coupling.md)."""
