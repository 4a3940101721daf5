"""Legendre modal basis phi_k(xi), k = 0..P, on xi in [-1, 1] [PE2020 Sec. 3].

Shapes: values at n points are returned as (n, P + 1) arrays (row = point, column = mode).
"""

import numpy as np


def legendre_at(order: int, x) -> np.ndarray:
    """phi_k(x) for k = 0..order by the three-term recurrence; (n, order + 1)."""
    x = np.atleast_1d(np.asarray(x, dtype=float))
    out = np.empty((x.size, order + 1))
    out[:, 0] = 1.0
    if order >= 1:
        out[:, 1] = x
    for k in range(1, order):
        out[:, k + 1] = ((2 * k + 1) * x * out[:, k] - k * out[:, k - 1]) / (k + 1)
    return out


def legendre_derivative_at(order: int, x) -> np.ndarray:
    """d phi_k / dxi at x; (n, order + 1). Uses P'_{k+1} = P'_{k-1} + (2k + 1) P_k."""
    x = np.atleast_1d(np.asarray(x, dtype=float))
    p = legendre_at(order, x)
    out = np.zeros((x.size, order + 1))
    for k in range(1, order + 1):
        out[:, k] = (out[:, k - 2] if k >= 2 else 0.0) + (2 * k - 1) * p[:, k - 1]
    return out


def legendre_integral_at(order: int, x) -> np.ndarray:
    """int_{-1}^{x} phi_k dxi; (n, order + 1). int P_k = (P_{k+1} - P_{k-1}) / (2k + 1), k >= 1."""
    x = np.atleast_1d(np.asarray(x, dtype=float))
    p = legendre_at(order + 1, x)
    out = np.empty((x.size, order + 1))
    out[:, 0] = x + 1.0
    for k in range(1, order + 1):
        out[:, k] = (p[:, k + 1] - p[:, k - 1]) / (2 * k + 1)
    return out


def modal_mass_diagonal(order: int) -> np.ndarray:
    """(phi_k, phi_k) on [-1, 1] = 2 / (2k + 1); the modal mass matrix is diagonal."""
    k = np.arange(order + 1)
    return 2.0 / (2 * k + 1)


def lagrange_at(nodes, x) -> np.ndarray:
    """Lagrange basis of distinct nodes x_j at x: l_j(x) = prod_{k != j} (x - x_k) / (x_j - x_k); (n, m).
    At a node every factor of its own l_j is exactly 1 and every other l_j has a factor 0, so the
    interpolant takes the node values there exactly."""
    nodes = np.asarray(nodes, dtype=float)
    x = np.atleast_1d(np.asarray(x, dtype=float))
    out = np.ones((x.size, nodes.size))
    for j in range(nodes.size):
        for k in range(nodes.size):
            if k != j:
                out[:, j] *= (x - nodes[k]) / (nodes[j] - nodes[k])
    return out
