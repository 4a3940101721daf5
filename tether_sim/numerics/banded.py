"""Banded LU without pivoting, storage A[i, j - i + kl] (half bandwidth kl), for diagonally
dominant-like systems such as I + dt x (dissipative operator) (solvers/dg/implicit_damping.py)."""

from tether_sim.numerics.jit import jit


@jit
def band_factor(A, n, kl, row):
    """In-place LU (no pivoting) of the band matrix A[i, j - i + kl], half bandwidth kl (row: work
    vector of length >= kl + 1 holding the pivot row, so that the update loop vectorises)."""
    for k in range(n - 1):
        inv = 1.0 / A[k, kl]
        last = min(n - 1, k + kl)
        m = last - k
        for j in range(m):
            row[j] = A[k, kl + 1 + j]
        for i in range(k + 1, last + 1):
            li = A[i, k - i + kl] * inv
            A[i, k - i + kl] = li
            o = k + 1 - i + kl
            for j in range(m):
                A[i, o + j] -= li * row[j]


@jit
def band_solve(A, n, kl, x, col):
    """Solve (LU) y = x[col] in place with the factors of band_factor."""
    for i in range(n):
        s = x[col, i]
        for j in range(max(0, i - kl), i):
            s -= A[i, j - i + kl] * x[col, j]
        x[col, i] = s
    for i in range(n - 1, -1, -1):
        s = x[col, i]
        for j in range(i + 1, min(n, i + kl + 1)):
            s -= A[i, j - i + kl] * x[col, j]
        x[col, i] = s / A[i, kl]
