"""SSP-RK3 [PE2020 Eq. 31-33] and the other dg.stepper rows: third-order convergence and the stability limits
used by the step rule."""

import numpy as np
import pytest

from tether_sim.numerics.integrators import (
    SSPRK3_IMAG_LIMIT, SSPRK3_REAL_LIMIT, STEPPER_NAMES, STEPPERS, ssprk3_amplification, ssprk3_step, stepper_step,
)


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


def solve_with(name, dt, T=1.0):
    u = np.array([1.0, 0.0])
    t = 0.0
    rhs = lambda u, t: np.array([u[1], -u[0] + np.cos(2.0 * t)])  # noqa: E731 forced oscillator
    for _ in range(int(round(T / dt))):
        u = stepper_step(name, rhs, u, t, dt)
        t += dt
    return u


@pytest.mark.parametrize("name", STEPPER_NAMES)
def test_every_stepper_is_third_order_with_time_dependent_forcing(name):
    ref = solve(1e-4)
    errs = [np.linalg.norm(solve_with(name, dt) - ref) for dt in (0.1, 0.05, 0.025)]
    rates = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all(np.abs(rates - 3.0) < 0.2), rates  # a wrong stage time c drops the rate to 1


def amplification(name, z):
    """R(z) of a stepper's rows: one step of du/dt = lambda u from u = 1 with dt lambda = z."""
    return stepper_step(name, lambda u, t: u * (z / 1.0), np.array([1.0 + 0j]), 0.0, 1.0)[0]


@pytest.mark.parametrize("name", STEPPER_NAMES)
def test_the_step_rule_factors_are_inside_each_steppers_stability_region(name):
    _, _, fr, fi = STEPPERS[name]
    for r in np.linspace(0.01, 1.0, 200):
        assert abs(amplification(name, -r * fr * SSPRK3_REAL_LIMIT)) <= 1.0 + 1e-12
        assert abs(amplification(name, 1j * r * fi * SSPRK3_IMAG_LIMIT)) <= 1.0 + 1e-12
    assert abs(amplification("ssprk3", 1j * 1.7)) == pytest.approx(abs(ssprk3_amplification(1j * 1.7)), abs=1e-14)
