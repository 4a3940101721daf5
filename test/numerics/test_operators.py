"""Reference-element operators: exact derivative of polynomials, projection, lift identity."""

import numpy as np
from numpy.polynomial import legendre as npl

from tether_sim.numerics.operators import derivative_matrix, element_operators, project_function


def test_derivative_matrix_is_exact_for_any_polynomial():
    P = 7
    rng = np.random.default_rng(1)
    c = rng.normal(size=P + 1)
    D = derivative_matrix(P)
    dc = npl.legder(c)
    assert np.allclose(D @ c, np.concatenate((dc, [0.0])), atol=1e-12)


def test_projection_recovers_polynomials_and_integral_operator():
    P = 5
    ops = element_operators(P)
    f = lambda s: 1.0 + 2.0 * s - s**3 + 0.5 * s**5  # noqa: E731 (degree P on [0, 2])
    coef = project_function(P, f, 0.0, 2.0)
    s = np.linspace(0.0, 2.0, 11)
    xi = s - 1.0
    assert np.allclose(npl.legval(xi, coef), f(s), atol=1e-12)
    # integral operator: int_0^s f = (h/2) int_{-1}^{xi} sum c_k phi_k
    sq = 1.0 + ops.points
    F = lambda s: s + s**2 - s**4 / 4 + s**6 / 12  # noqa: E731
    assert np.allclose(ops.integral @ coef, F(sq), atol=1e-12)


def test_strong_form_equals_weak_form_with_arbitrary_fluxes():
    """Strong form [PE2020 Eq. 23] = weak form M^-1 [phi_l F_hat |_L^R - (dphi_l/ds, F)] for polynomial F."""
    from tether_sim.numerics.polys import legendre_at, legendre_derivative_at
    from tether_sim.numerics.quadrature import gauss_legendre

    P, h = 4, 0.7
    ops = element_operators(P)
    c = np.array([0.3, -1.0, 0.5, 2.0, -0.7])
    fL, fR = 0.9, -1.3  # numerical fluxes at xi = -1, +1
    FL, FR = ops.trace[0] @ c, ops.trace[1] @ c
    strong = 2.0 / h * ops.derivative @ c + (ops.lift[1] * (fR - FR) - ops.lift[0] * (fL - FL)) / h
    x, w = gauss_legendre(P + 2)
    phi, dphi = legendre_at(P, x), legendre_derivative_at(P, x)
    F = phi @ c
    k = np.arange(P + 1)
    weak = (2 * k + 1) / h * (ops.trace[1] * fR - ops.trace[0] * fL - (dphi.T * w) @ F)
    assert np.allclose(strong, weak, atol=1e-12)
