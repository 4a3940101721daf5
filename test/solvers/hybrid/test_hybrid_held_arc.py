"""A fixed-fixed, low-tension, stiff arc with bending (benchmarks/studies/hybrid_held_arc.py:
L = 325 m, chord 316 m sloping 100 m, EA = 455 MN, EI = 2620 N m^2, end tensions ~11 and ~9 kN).

Before 2026-11-23 the hybrid started this case several kN off (its initial arc sagged along a wrong
direction for a sloping chord and missed the far end by 8 m; the relaxation could not absorb that on
an EA/T ~ 4e4 cable) and Newton then diverged within 1.5 s; all-catenary zoning failed already in the
static relaxation (docs/hybrid_solver.md, "Held arcs").
"""

import numpy as np

from benchmarks.studies.hybrid_held_arc import held_arc_config, ship_motion
from tether_sim.physics.statics import solve_static
from tether_sim.solvers.hybrid.solver import HybridRodCatenarySolver


def test_held_arc_statics_and_gentle_motion():
    cfg = held_arc_config(zoning="adaptive", dt=0.02)  # the script runs 600 s at the default 0.01 s
    s = HybridRodCatenarySolver(cfg)
    sol = solve_static(cfg)  # elastic catenary; the DG solver's static state agrees with it to 5e-6
    ref = [float(np.linalg.norm(sol.force_at(np.array([x]))[0])) for x in (0.0, cfg.cable.length)]
    F = s.end_forces()
    # box scheme, 60 cells of 5.4 m: O(ds^2) ~ 2e-4 measured; EI's share ~ sqrt(EI/T)/L ~ 1e-3 at most.
    # The issue asks 0.5 % against DG; 0.1 % keeps a margin of 4 over the measured 0.023 %.
    assert abs(F.ship_tension / ref[0] - 1.0) < 1e-3
    assert abs(F.vehicle_tension / ref[1] - 1.0) < 1e-3
    # held still for 3 s: the static state is an equilibrium of the dynamic equations (drift measured
    # 1e-5 relative; 1e-4 asserted, 10x below the 0.1 % for the DG solver's stationarity test)
    T0 = np.array([F.ship_tension, F.vehicle_tension])
    for k in range(1, 4):
        s.advance_to(float(k))
        F = s.end_forces()
        assert np.abs(np.array([F.ship_tension, F.vehicle_tension]) / T0 - 1.0).max() < 1e-4
    # 20 s of gentle ship-end motion (circle r = 0.5 m, period 20 s, smooth ramp over the period): no
    # divergence; the vertical end forces carry the cable's wet weight up to its inertia and drag. If the
    # whole cable moved like its end: (mass + added mass) r omega^2 = 55 N and drag 0.5 rho d Cdn L
    # (r omega)^2 = 128 N; its swing adds to that (measured: a steady +-210 N at the forcing period over
    # 40 s, no growth), so 1.5x the sum (275 N) is asserted; tensions stay in the quasi-static band
    weight = cfg.cable.length * s.net_weight
    c = cfg.cable
    om = 2.0 * np.pi / 20.0
    bound = 1.5 * c.length * ((c.gamma0 + 1025.0 * c.area * c.Cmn) * 0.5 * om**2
                              + 0.5 * 1025.0 * c.diameter * c.Cdn * (0.5 * om) ** 2)
    t0 = s.time
    for k in range(1, 401):
        t = 0.05 * k
        p, v = ship_motion(t)
        s.set_end_motion("ship", p, v)
        s.advance_to(t0 + t)
        F = s.end_forces()
        assert abs(F.ship_force[2] + F.vehicle_force[2] + weight) < bound
        assert 0.5 * T0[0] < F.ship_tension < 2.0 * T0[0]
    assert s.stats["halvings"] == 0
