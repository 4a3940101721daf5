"""Legendre modal basis: values, derivatives, integrals against numpy's Legendre series."""

import numpy as np
from numpy.polynomial import legendre as npl

from tether_sim.numerics.polys import legendre_at, legendre_derivative_at, legendre_integral_at, modal_mass_diagonal
from tether_sim.numerics.quadrature import gauss_legendre

X = np.linspace(-1.0, 1.0, 23)


def unit(k):
    c = np.zeros(k + 1)
    c[k] = 1.0
    return c


def test_values_derivatives_integrals_match_numpy():
    P = 9
    phi, dphi, iphi = legendre_at(P, X), legendre_derivative_at(P, X), legendre_integral_at(P, X)
    for k in range(P + 1):
        assert np.allclose(phi[:, k], npl.legval(X, unit(k)), atol=1e-13)
        assert np.allclose(dphi[:, k], npl.legval(X, npl.legder(unit(k))), atol=1e-11)
        assert np.allclose(iphi[:, k], npl.legval(X, npl.legint(unit(k), lbnd=-1.0)), atol=1e-13)


def test_orthogonality_gives_diagonal_mass():
    P = 8
    x, w = gauss_legendre(P + 1)  # exact for degree 2P + 1
    phi = legendre_at(P, x)
    M = (phi.T * w) @ phi
    assert np.allclose(M, np.diag(modal_mass_diagonal(P)), atol=1e-13)
