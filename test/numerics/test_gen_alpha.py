"""Generalized-alpha coefficients [GP Sec. 3; Jansen, Whiting & Hulbert 2000]."""

import numpy as np
import pytest

from tether_sim.numerics.gen_alpha import amplification_factor, derivative_update, gen_alpha_coefficients, spectral_radius


@pytest.mark.parametrize("rho", [0.0, 0.3, 0.8, 1.0])
def test_spectral_radius_at_infinity_is_rho(rho):
    # |R| -> rho_inf as lambda*h -> -inf (the controllable numerical dissipation)
    assert abs(spectral_radius(rho, -1e12) - rho) < 1e-5  # rho=0: double root ~ (lam h)^-1/2


@pytest.mark.parametrize("rho", [0.0, 0.5, 1.0])
def test_unconditionally_stable_on_the_negative_axis_and_oscillators(rho):
    for lam in (-1e-3, -0.5, -3.0, -50.0, 1j * 0.1, 1j * 2.0, 1j * 40.0):
        assert spectral_radius(rho, lam) <= 1.0 + 1e-12


@pytest.mark.parametrize("rho", [0.0, 0.6, 1.0])
def test_second_order_accuracy(rho):
    # global error after t = 1 of y' = lam y scales as h^2: halving h divides it by ~4
    lam = -1.0 + 2.0j
    # (the start value y0' = lam y0 is consistent, as the solver's rest start is)
    errs = []
    for n in (20, 40, 80):
        h = 1.0 / n
        errs.append(abs(amplification_factor(rho, lam * h) ** n - np.exp(lam)))
    ratios = [errs[0] / errs[1], errs[1] / errs[2]]
    assert all(3.6 < r < 4.4 for r in ratios), ratios


def test_rho_one_is_trapezoidal_and_derivative_update():
    am, af, g = gen_alpha_coefficients(1.0)
    assert (am, af, g) == (0.5, 0.5, 0.5)
    out = np.empty(2)
    derivative_update(np.array([1.0, 2.0]), np.array([0.0, 1.0]), np.array([2.0, 0.0]), 0.5, 0.5, out)
    # trapezoid: y1 = y0 + h/2 (y0' + y1')  ->  y1' = 2 (y1 - y0)/h - y0'
    assert np.allclose(out, [2.0, 4.0])
    with pytest.raises(ValueError):
        gen_alpha_coefficients(1.5)
