"""Convergence of the DG solver on a smooth exact solution [PE2020 Sec. 3, Eq. 23-25, 31-33].

Problem: taut straight cable (linear law, no gravity, no fluid) on [0, L], the ship end driven
axially by a Gaussian displacement pulse g(t), the vehicle end fixed. Axial motion of a straight
cable with T = EA eps is exactly the linear wave equation, so the exact solution is d'Alembert's
with images (references.axial_pulse_solution). Errors are relative L2 norms (Gauss quadrature per
element) of the DG unknowns: velocity nu_x and strain eps.

- fixed N = 8, P = 1..6: exponential convergence. Measured: the error falls by a nearly constant
  factor 0.10-0.14 per order from P = 2 (0.19-0.42 from the unresolved P = 1) down to 4e-5 at
  P = 6; asserted: factors < 0.3 from P = 2 (< 0.5 from P = 1) and the P = 6 error < 2e-4;
- fixed P, halving h: at least the optimal rate P + 1 of a Lax-Friedrichs (here upwind, lambda = c)
  DG scheme on a linear hyperbolic system. Measured on these meshes: 2.55-2.7 for P = 1 and
  3.6-3.8 for P = 2 (pre-asymptotic superconvergence: the pulse spans only a few elements).
  Asserted: P + 1 - 0.3 < rate < P + 2 on the finest pair;
- the fixed dt = 5e-4 s keeps the RK3 error (~(dt/sigma)^3 ~ 1e-7) below every spatial error;
- SSP-RK3 (Eq. 31-33): halving a fixed dt divides the error against a dt/8 reference run by 8
  (rate 3 +- 0.3). The end is driven by the same cubic-Hermite boundary data in all runs, so this
  also checks that the boundary value is taken at the Runge-Kutta stage times.
"""

import numpy as np
import pytest

from tether_sim.scenarios import harness
from tether_sim.scenarios import references as ref

L, EA, GAMMA0, EPS0 = 1.0, 1.0, 1.0, 0.01  # c = 1 m/s, L/c = 1 s
AMP, T_C, SIGMA = 3.0e-4, 0.6, 0.12  # pulse 0.12 m wide: strain amplitude ~0.002 < EPS0
T_END, DT_OUT = 1.45, 2.0e-3  # at T_END the pulse is half-way through its reflection at the fixed end


def pulse_flat(n_elements, order, dt):
    return {
        "solver": "dg", "dg.n_elements": n_elements, "dg.order": order, "dg.fixed_time_step": dt,
        "cable.length": L, "cable.EA": EA, "cable.gamma0": GAMMA0, "cable.density": 1000.0,
        "cable.material": "linear", "cable.damping": 0.0, "cable.EI": 0.0,
        "environment.g": 0.0, "environment.fluid_density": 0.0,
        "ship_end.kind": "prescribed", "ship_end.position": [0.0, 0.0, 0.0],
        "vehicle_end.kind": "fixed", "vehicle_end.position": [L * (1 + EPS0), 0.0, 0.0],
        "initial.kind": "straight",
    }


def ship_motion(t):
    g, dg = ref.gaussian_pulse(t, AMP, T_C, SIGMA)
    return {"ship": ([float(g), 0.0, 0.0], [float(dg), 0.0, 0.0])}


def run_pulse(n_elements, order, dt):
    """Drive the pulse to T_END (end state set every DT_OUT) and sample at Gauss points."""
    config, solver = harness.make_solver(pulse_flat(n_elements, order, dt))
    s, w = harness.quadrature_points(config)
    for t in np.arange(1, int(round(T_END / DT_OUT)) + 1) * DT_OUT:
        (pos, vel), = ship_motion(t).values()
        solver.set_end_motion("ship", pos, vel)
        solver.advance_to(t)
    st = solver.state(s)
    return s, w, {"velocity": st.velocity, "strain": st.strain, "position": st.position}


def errors(n_elements, order, dt=5.0e-4):
    """Relative L2 errors (velocity, strain, position) at T_END vs the exact solution."""
    s, w, st = run_pulse(n_elements, order, dt)
    c = np.sqrt(EA / GAMMA0)
    u, ut, us = ref.axial_pulse_solution(s, T_END, L, c, AMP, T_C, SIGMA)
    norm_v = np.sqrt(np.sum(w * ut**2))
    norm_e = np.sqrt(np.sum(w * us**2))
    ev = np.sqrt(np.sum(w * ((st["velocity"][:, 0] - ut) ** 2 + st["velocity"][:, 1] ** 2 + st["velocity"][:, 2] ** 2))) / norm_v
    ee = np.sqrt(np.sum(w * (st["strain"] - EPS0 - us) ** 2)) / norm_e
    x_exact = s * (1 + EPS0) + u
    ex = np.sqrt(np.sum(w * (st["position"][:, 0] - x_exact) ** 2)) / np.sqrt(np.sum(w * u**2))
    return ev, ee, ex


def test_exponential_convergence_in_order():
    errs = np.array([errors(8, p)[:2] for p in range(1, 7)])  # (P, [velocity, strain])
    print("P-convergence N=8 (velocity, strain):\n", errs)
    for k in range(2):
        ratios = errs[1:, k] / errs[:-1, k]
        assert ratios[0] < 0.5 and np.all(ratios[1:] < 0.3), ratios  # P=1 is unresolved; then > 3.3x per order
    assert np.all(errs[-1] < 2e-4)  # P = 6 on 8 elements: measured 4e-5


@pytest.mark.parametrize("order", [1, 2])
def test_algebraic_rate_in_h(order):
    meshes = (8, 16, 32) if order == 2 else (16, 32, 64)
    errs = np.array([errors(n, order)[:2] for n in meshes])
    rates = ref.convergence_rates(errs[:, 0]), ref.convergence_rates(errs[:, 1])
    print(f"P={order} h-convergence {meshes}: errors {errs.tolist()} rates {rates}")
    for r in rates:
        assert order + 1 - 0.3 < r[-1] < order + 2, r


def test_ssp_rk3_is_third_order():
    dts = (2.0e-3, 1.0e-3, 5.0e-4)  # all divide DT_OUT, so every run sees the same boundary data
    s, w, ref_state = run_pulse(8, 3, 1.25e-4)
    errs = []
    for dt in dts:
        _, _, st = run_pulse(8, 3, dt)
        errs.append(np.sqrt(np.sum(w * (st["velocity"][:, 0] - ref_state["velocity"][:, 0]) ** 2)))
    rates = ref.convergence_rates(errs)
    print("RK3 errors", errs, "rates", rates)
    assert np.all(np.abs(rates - 3.0) < 0.3), rates
