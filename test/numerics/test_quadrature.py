"""Gauss-Legendre / Gauss-Lobatto rules integrate polynomials exactly to their stated degree."""

import numpy as np
import pytest

from tether_sim.numerics.quadrature import dg_quadrature_points, gauss_legendre, gauss_lobatto


def exact_monomial(k):
    return 0.0 if k % 2 else 2.0 / (k + 1)


@pytest.mark.parametrize("n", [1, 2, 5, 9])
def test_gauss_legendre_degree(n):
    x, w = gauss_legendre(n)
    for k in range(2 * n):
        assert abs(np.dot(w, x**k) - exact_monomial(k)) < 1e-13
    assert abs(np.dot(w, x ** (2 * n)) - exact_monomial(2 * n)) > 1e-6  # and not beyond


@pytest.mark.parametrize("n", [2, 3, 6, 10])
def test_gauss_lobatto_degree_and_ends(n):
    x, w = gauss_lobatto(n)
    assert x[0] == -1.0 and x[-1] == 1.0
    for k in range(2 * n - 2):
        assert abs(np.dot(w, x**k) - exact_monomial(k)) < 1e-12


def test_dg_rule_is_exact_for_cubic_products():
    for P in range(1, 13):
        Q = dg_quadrature_points(P)
        # one degree of margin beyond the cubic products (the tension is not a polynomial)
        assert 2 * Q - 1 >= 3 * P + 1 and Q >= P + 1
    assert [dg_quadrature_points(P) for P in range(1, 6)] == [3, 4, 6, 7, 9]
