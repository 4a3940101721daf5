"""Studies whose results are in docs/: resolution ladders (``resolution_ladder``, tables by
``resolution_report``; docs/resolution_ladder.md), the bending effect at 200 m (``bending_effect_study``,
``bending_shapes``, ``moordyn_bending_rungs``), the DG stability limit (``calibrate_timestep``) and
cfl safety (``dg_cfl_study``), held arcs and the q-equation penalty (``hybrid_held_arc``,
``held_arc_modes``, ``held_arc_q_penalty``, ``q_penalty_ropos``), the ring beam [PE2020 Sec. 4.1]
(``ring_beam_convergence``), and the hybrid solver on ROPOS (``ropos_hybrid``, ``ropos_slack_zones``,
``ropos_cross_check``)."""
