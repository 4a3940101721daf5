"""SSP-RK3 [PE2020 Eq. 31-33]: third-order convergence and the stability limits used by the step rule."""

import numpy as np

from tether_sim.numerics.integrators import SSPRK3_IMAG_LIMIT, SSPRK3_REAL_LIMIT, ssprk3_amplification, ssprk3_step


def solve(dt, T=1.0):
    u = np.array([1.0, 0.0])
    t = 0.0
    rhs = lambda u, t: np.array([u[1], -u[0] + np.cos(2.0 * t)])  # noqa: E731 forced oscillator
    for _ in range(int(round(T / dt))):
        u = ssprk3_step(rhs, u, t, dt)
        t += dt
    return u


def test_third_order_convergence():
    ref = solve(1e-4)
    errs = [np.linalg.norm(solve(dt) - ref) for dt in (0.1, 0.05, 0.025)]
    rates = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all(np.abs(rates - 3.0) < 0.15), rates  # asymptotic rate 3 (+-5%)


def test_stability_limits():
    assert abs(abs(ssprk3_amplification(-SSPRK3_REAL_LIMIT)) - 1.0) < 1e-12
    assert abs(abs(ssprk3_amplification(1j * SSPRK3_IMAG_LIMIT)) - 1.0) < 1e-12
    assert abs(ssprk3_amplification(1j * 1.7)) < 1.0
