"""Reference-element DG operators for the modal Legendre basis [PE2020 Eq. 23, 26-28].

For an element of size h mapped from xi in [-1, 1], d/ds = (2/h) d/dxi and the modal mass
matrix is diag(h / (2l + 1)). The strong-form derivative of a flux F with numerical fluxes
F_hat at the element ends is, per mode l (Eq. 23 with M^-1 applied):

    dF_l = (2/h) sum_m D[l, m] F_m + ((2l + 1)/h) [(F_hat_R - F_R) - (-1)^l (F_hat_L - F_L)]

with F_R = sum_m F_m and F_L = sum_m (-1)^m F_m the element's own traces.
"""

from dataclasses import dataclass

import numpy as np

from tether_sim.numerics.polys import legendre_at, legendre_derivative_at, legendre_integral_at
from tether_sim.numerics.quadrature import dg_quadrature_points, gauss_legendre


def derivative_matrix(order: int) -> np.ndarray:
    """D[l, m] = ((2l+1)/2) (phi_l, dphi_m/dxi): modal coefficients of phi_m' (strictly upper)."""
    x, w = gauss_legendre(order + 1)
    phi = legendre_at(order, x)
    dphi = legendre_derivative_at(order, x)
    k = np.arange(order + 1)
    D = ((2 * k + 1) / 2.0)[:, None] * (phi.T * w) @ dphi
    D[np.abs(D) < 1e-13] = 0.0
    return np.ascontiguousarray(D)


@dataclass(frozen=True)
class ElementOperators:
    """Everything a kernel needs on the reference element (all C-contiguous float64).

    vandermonde (Q, P+1): phi_l(xi_j) at the Gauss points; projection (P+1, Q):
    ((2l+1)/2) w_j phi_l(xi_j) (L2 projection onto the modes); derivative (P+1, P+1);
    lift (2, P+1): (2l+1) * phi_l(-1) and (2l+1) * phi_l(+1) (h^-1 applied by the kernel);
    trace (2, P+1): phi_l(-1), phi_l(+1); integral (Q, P+1): int_{-1}^{xi_j} phi_l dxi.
    """

    order: int
    points: np.ndarray
    weights: np.ndarray
    vandermonde: np.ndarray
    projection: np.ndarray
    derivative: np.ndarray
    lift: np.ndarray
    trace: np.ndarray
    integral: np.ndarray


def element_operators(order: int, n_quad: int | None = None) -> ElementOperators:
    """Build the operators of an order-P element with the DG quadrature rule (see quadrature)."""
    if order < 1:
        raise ValueError("element_operators: order P must be >= 1")
    nq = dg_quadrature_points(order) if n_quad is None else n_quad
    x, w = gauss_legendre(nq)
    V = legendre_at(order, x)
    k = np.arange(order + 1)
    proj = ((2 * k + 1) / 2.0)[:, None] * (V.T * w)
    tr = legendre_at(order, np.array([-1.0, 1.0]))
    lift = tr * (2 * k + 1)[None, :]
    c = np.ascontiguousarray
    return ElementOperators(order, c(x), c(w), c(V), c(proj), derivative_matrix(order), c(lift), c(tr),
                            c(legendre_integral_at(order, x)))


def project_function(order: int, f, a: float, b: float, n_quad: int | None = None) -> np.ndarray:
    """L2 projection of f(s) (returning (n, m) or (n,)) onto the modes of element [a, b]."""
    nq = max(2 * order + 2, 8) if n_quad is None else n_quad
    x, w = gauss_legendre(nq)
    s = a + (x + 1.0) * (b - a) / 2.0
    vals = np.asarray(f(s), dtype=float)
    V = legendre_at(order, x)
    k = np.arange(order + 1)
    proj = ((2 * k + 1) / 2.0)[:, None] * (V.T * w)
    return proj @ vals
