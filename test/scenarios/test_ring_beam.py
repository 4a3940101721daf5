"""Ring-shaped beam [PE2020 Sec. 4.1, Eq. 34-36, Fig. 1] through the scenario driver.

Cheap subset of the convergence table (full table: benchmarks/studies/ring_beam_convergence.py, output in
docs/verification.md). The static ring is the discrete fixed point du/dt = 0 of the DG scheme
(Newton), so the errors are spatial errors alone.

Measured (docs/verification.md): the LDG curvature (Eq. 26) converges at the paper's rate P + 1 for
P = 1, 2 (2.01, 2.00 and 3.00, 2.87 over successive doublings); the positions converge faster than
the paper's Eq. 34 rates, at P + 2 (P = 1, N = 16 ... 128: 3.39, 3.19, 3.06 -> 3), because
r = r(0) + int q ds is one degree higher per element than q. Tolerance +-0.3 (the issue's): in the asymptotic range the rate
drifts by < 0.15 between doublings, while a one-order loss (P instead of P + 1, the paper's odd-P
penalty) changes it by 1. P = 1 uses N = 32, 64, 128: with 2 or 3 Gauss points per element
(automatic quadrature rule before / after 2026-11-21) the last pair gives 3.06 / 3.08 (positions)
and 2.00 / 1.99 (curvature); the pair 32 -> 64 still depends on it (3.19 / 3.61).
"""

import numpy as np
import pytest

from tether_sim.scenarios import ring_beam
from tether_sim.scenarios.ring_beam_analysis import discrete_equilibrium, linearised_spectrum
from tether_sim.solvers.dg.layout import P_RELAX


def _errors(order, meshes):
    pos, cur = [], []
    for n in meshes:
        config, solver = ring_beam.static_solution(n, order)
        pos.append(ring_beam.ring_error(solver, config))
        cur.append(ring_beam.curvature_error(solver, config))
    return ring_beam.rates(pos), ring_beam.rates(cur), pos


def test_ring_convergence_rates_p1():
    rp, rc, pos = _errors(1, (32, 64, 128))
    print(f"P=1: position errors {pos}, rates {rp}, curvature rates {rc}")
    assert abs(rc[-1] - ring_beam.paper_rate(1)) <= 0.3  # paper: P + 1 = 2
    assert abs(rp[-1] - 3.0) <= 0.3  # positions: P + 2
    assert pos[-1] < 1e-6


def test_ring_convergence_rates_p2():
    rp, rc, pos = _errors(2, (16, 32))
    print(f"P=2: position errors {pos}, rates {rp}, curvature rates {rc}")
    assert abs(rc[-1] - ring_beam.paper_rate(2)) <= 0.3  # paper: P + 1 = 3
    assert rp[-1] >= ring_beam.paper_rate(2) - 0.3  # positions at least the paper's rate (measured 5.4)
    assert pos[-1] < 2e-5


def test_paper_model_flutters_where_axial_and_bending_waves_cross():
    """The linearised operator about the ring has a growing in-plane pair near omega = c k*, with
    c = sqrt(EA/gamma0) and k* = sqrt(EA/EI), on a mesh that resolves k* (N = 16, P = 3: measured
    Re = +0.17 1/s, Im = 32.3 rad/s; the mesh-converged value is +0.41 1/s), none on a coarse one
    (N = 8, P = 2: max Re -8e-5); relaxation damping 0.06 1/s plus zeta = 2 N s removes it."""
    omega_star = np.sqrt(100.0 / 10.0) * np.sqrt(100.0 / 1.0)
    _, solver = ring_beam.ring_solver(16, 3)
    discrete_equilibrium(solver)
    w_in, w_out = linearised_spectrum(solver)
    k = np.argmax(w_in.real)
    assert w_in[k].real > 0.1
    assert abs(abs(w_in[k].imag) / omega_star - 1.0) < 0.1
    assert w_out.real.max() > 0.1  # out-of-plane (lateral) instability of a torsion-free ring
    _, solver = ring_beam.ring_solver(16, 3, {"cable.damping": ring_beam.RELAX_ZETA})
    discrete_equilibrium(solver)
    w_in, _ = linearised_spectrum(solver, ring_beam.RELAX_DAMPING)
    assert w_in.real.max() < 0.0
    _, solver = ring_beam.ring_solver(8, 2)
    discrete_equilibrium(solver)
    w_in, _ = linearised_spectrum(solver)
    assert w_in.real.max() < 1e-6


def test_relaxation_reaches_the_newton_fixed_point():
    """Dynamic relaxation (RELAX_DAMPING, RELAX_ZETA) from the straight beam ends on the Newton fixed
    point of the same damped equations (N = 4, P = 3): the time stepper and the Newton solver solve
    the same discrete equations. (The damping terms shift the DG fixed point, whose momentum v is not
    zero where it balances the Lax-Friedrichs penalty on the jumps of q; the table uses no damping.)"""
    overrides = {"cable.damping": ring_beam.RELAX_ZETA}
    config, solver = ring_beam.ring_solver(4, 3, overrides)
    solver.ws.prm[P_RELAX] = ring_beam.RELAX_DAMPING  # as during relaxation
    discrete_equilibrium(solver)
    e_newton = ring_beam.ring_error(solver, config)
    e_relax = ring_beam.static_error(4, 3, method="relax", relax_time=500.0)
    assert e_relax == pytest.approx(e_newton, rel=1e-3)  # 500 s = 15 decay times of the slowest mode


def test_ramped_moment_curls_the_beam_down_in_plane():
    tr = ring_beam.run_transient(n_elements=4, order=3, t_end=100.0, update=5.0, snapshot_every=50.0)
    r = tr["positions"][-1]
    assert np.all(np.isfinite(tr["positions"]))
    assert np.max(np.abs(r[:, 1])) < 1e-9  # stays in the x-z plane
    assert r[-1, 2] < -0.3  # moment +y bends the tip towards -z (ring centred at (0, 0, -1))
    assert np.all(np.diff(r[:, 2]) <= 1e-12)  # monotone curl, no wiggles
