"""Transverse standing wave of a taut cable in water: frequency with normal added mass [Eq. 13].

Straight taut cable, no gravity (so no sag), water with C_m,perp = 1 and no drag (C_d = 0, so the
vibration is undamped). A slow transverse excursion of the ship end excites the low modes; the
projection of nu_y on the first mode sin(pi s / L) isolates mode 1 (orthogonal modes in material
coordinates), and its zero crossings over ~5 periods give the period.

Expected omega_1 = (pi/L) sqrt(T0 / (l_eps (gamma0 + rho_f A_d C_mn))), A_d = pi d^2/4 (the
hydrodynamic diameter; the material area gamma0/rho_c is deliberately different here so that the
test sees which area the added mass uses). 0.5% tolerance: the discretisation error of mode 1 at
N = 6, P = 4 is < 1e-6 and the crossing interpolation error ~1e-4; the added mass shifts the
frequency by ~30%, so the test cannot pass without it.
"""

import numpy as np
import pytest

from tether_sim.scenarios import harness
from tether_sim.scenarios import references as ref

L, EA, GAMMA0, EPS0, RHO_C, D, RHO_F, CMN = 10.0, 1.0e4, 2.0, 0.02, 2000.0, 0.05, 1025.0, 1.0
AMP, SIGMA = 0.01, 0.4  # small: geometric stiffening ~ EA (pi A / L)^2 / (8 T0) stays < 1e-4
T_C = 4 * SIGMA


def flat():
    return {
        "solver": "dg", "dg.n_elements": 6, "dg.order": 4,
        "cable.length": L, "cable.EA": EA, "cable.gamma0": GAMMA0, "cable.density": RHO_C,
        "cable.diameter": D, "cable.material": "bilinear", "cable.damping": 0.0, "cable.EI": 0.0,
        "cable.Cmn": CMN, "cable.Cmt": 0.0, "cable.Cdn": 0.0, "cable.Cdt": 0.0,
        "environment.g": 0.0, "environment.fluid_density": RHO_F,
        "ship_end.kind": "prescribed", "ship_end.position": [0.0, 0.0, 0.0],
        "vehicle_end.kind": "fixed", "vehicle_end.position": [L * (1 + EPS0), 0.0, 0.0],
        "initial.kind": "straight",
    }


def ship_motion(t):
    if t >= 2 * T_C:
        return {"ship": ([0.0, 0.0, 0.0], [0.0, 0.0, 0.0])}
    g, dg = ref.gaussian_pulse(t, AMP, T_C, SIGMA)
    return {"ship": ([0.0, 0.0, float(g)], [0.0, 0.0, float(dg)])}


def test_first_mode_frequency_includes_normal_added_mass():
    added = ref.normal_added_mass(RHO_F, D, CMN)
    omega = ref.taut_string_frequency(1, L, EA * EPS0, GAMMA0, EPS0, added)
    omega_dry = ref.taut_string_frequency(1, L, EA * EPS0, GAMMA0, EPS0)
    assert omega_dry / omega > 1.2  # the effect measured is far larger than the tolerance
    period = 2 * np.pi / omega
    config, solver = harness.make_solver(flat())
    s, w = harness.quadrature_points(config)
    harness.run_sampled(solver, np.arange(0.02, 2 * T_C + 1e-9, 0.02), motion=ship_motion, keep=())
    times = solver.time + np.arange(0.04, 5.3 * period, 0.04)
    res = harness.run_sampled(solver, times, arc_lengths=s, motion=ship_motion, keep=("velocity",))
    modal = res["velocity"][:, :, 2] @ (w * np.sin(np.pi * s / L))
    measured = harness.period_from_crossings(res["t"], modal)
    print(f"mode-1 period: measured {measured:.5f} s, expected {period:.5f} s (dry {2 * np.pi / omega_dry:.5f} s)")
    assert measured == pytest.approx(period, rel=5e-3)
