"""The banded solve of the implicit damping step (numerics/banded.band_solve; n = N Q = 140, kl = 3 Q - 1 = 20 on the
PE2020 Sec. 6.2 mesh) in other loop forms, timed on a random diagonally dominant band LU of that size (CPU time,
min of 5 x 20 000 solves): the row forms of the forward and back substitution apart, the column (axpy) forms on the
row-stored band and on a column-stored copy, the back substitution with four partial sums or its sum in descending
order. Prints which forms give band_solve's bits (the column forward substitution subtracts in the same order as the
row form; every other back substitution changes the order of the sums).

    PYTHONPATH=. python benchmarks/probes/band_solve_forms.py
"""
import sys
import time
from pathlib import Path

import numpy as np
from numba import njit

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from tether_sim.numerics.banded import band_factor, band_solve  # noqa: E402


@njit
def fwd_row(A, n, kl, x, col):
    for i in range(n):
        s = x[col, i]
        for j in range(max(0, i - kl), i):
            s -= A[i, j - i + kl] * x[col, j]
        x[col, i] = s


@njit
def back_row(A, n, kl, x, col):
    for i in range(n - 1, -1, -1):
        s = x[col, i]
        for j in range(i + 1, min(n, i + kl + 1)):
            s -= A[i, j - i + kl] * x[col, j]
        x[col, i] = s / A[i, kl]


@njit
def fwd_col(A, n, kl, x, col):
    # x[i] -= L[i, j] x[j] for j ascending: for each i the same order as the row form
    for j in range(n):
        xj = x[col, j]
        for i in range(j + 1, min(n, j + kl + 1)):
            x[col, i] -= A[i, j - i + kl] * xj


@njit
def back_col(A, n, kl, x, col):
    for j in range(n - 1, -1, -1):
        xj = x[col, j] / A[j, kl]
        x[col, j] = xj
        for i in range(max(0, j - kl), j):
            x[col, i] -= A[i, j - i + kl] * xj


@njit
def back_row4(A, n, kl, x, col):
    for i in range(n - 1, -1, -1):
        s0 = x[col, i]
        s1 = 0.0
        s2 = 0.0
        s3 = 0.0
        j = i + 1
        last = min(n, i + kl + 1)
        while j + 3 < last:
            s0 -= A[i, j - i + kl] * x[col, j]
            s1 -= A[i, j + 1 - i + kl] * x[col, j + 1]
            s2 -= A[i, j + 2 - i + kl] * x[col, j + 2]
            s3 -= A[i, j + 3 - i + kl] * x[col, j + 3]
            j += 4
        while j < last:
            s0 -= A[i, j - i + kl] * x[col, j]
            j += 1
        x[col, i] = ((s0 + s1) + (s2 + s3)) / A[i, kl]


@njit
def back_rowdesc(A, n, kl, x, col):
    for i in range(n - 1, -1, -1):
        s = x[col, i]
        for j in range(min(n, i + kl + 1) - 1, i, -1):
            s -= A[i, j - i + kl] * x[col, j]
        x[col, i] = s / A[i, kl]


@njit
def transpose_band(A, n, kl, T):
    # T[j, kl + (i - j)] = A[i, j - i + kl]: column j of the band contiguous (L below the diagonal: kl+1.., U above: ..kl-1)
    for j in range(n):
        for d in range(-kl, kl + 1):
            i = j + d
            if 0 <= i < n:
                T[j, kl + d] = A[i, j - i + kl]


@njit
def solve_cols(T, n, kl, x, col):
    for j in range(n):
        xj = x[col, j]
        m = min(kl, n - 1 - j)
        for d in range(1, m + 1):
            x[col, j + d] -= T[j, kl + d] * xj
    for j in range(n - 1, -1, -1):
        xj = x[col, j] / T[j, kl]
        x[col, j] = xj
        m = min(kl, j)
        for d in range(1, m + 1):
            x[col, j - d] -= T[j, kl - d] * xj


FORMS = ("band_solve", "forward, rows", "forward, columns", "back, rows", "back, columns", "back, rows, 4 partial sums",
         "back, rows, descending sum", "both, columns of a column-stored copy", "forward columns + back rows")


@njit
def loop(which, A, T, n, kl, x, b, reps):
    for _ in range(reps):
        for i in range(n):
            x[0, i] = b[i]
        if which == 0:
            band_solve(A, n, kl, x, 0)
        elif which == 1:
            fwd_row(A, n, kl, x, 0)
        elif which == 2:
            fwd_col(A, n, kl, x, 0)
        elif which == 3:
            back_row(A, n, kl, x, 0)
        elif which == 4:
            back_col(A, n, kl, x, 0)
        elif which == 5:
            back_row4(A, n, kl, x, 0)
        elif which == 6:
            back_rowdesc(A, n, kl, x, 0)
        elif which == 7:
            solve_cols(T, n, kl, x, 0)
        else:
            fwd_col(A, n, kl, x, 0)
            back_row(A, n, kl, x, 0)


def main():
    n, kl = 140, 20
    rng = np.random.default_rng(1)
    A = np.zeros((n, 2 * kl + 1))
    for i in range(n):
        for j in range(max(0, i - kl), min(n, i + kl + 1)):
            A[i, j - i + kl] = rng.normal() * 0.05
        A[i, kl] += 1.0 + abs(rng.normal())
    band_factor(A, n, kl, np.zeros(kl + 1))
    T = np.zeros((n, 2 * kl + 1))
    transpose_band(A, n, kl, T)
    b = rng.normal(size=n)
    x = np.zeros((1, n))
    ref = x.copy()
    ref[0] = b
    band_solve(A, n, kl, ref, 0)
    for w in range(len(FORMS)):
        loop(w, A, T, n, kl, x, b, 2)
    best = {}
    for _ in range(5):
        for w in range(len(FORMS)):
            c = time.process_time()
            loop(w, A, T, n, kl, x, b, 20000)
            best[w] = min(best.get(w, 1e9), (time.process_time() - c) / 20000 * 1e6)
    for w, name in enumerate(FORMS):
        line = f"{name:40s} {best[w]:6.3f} us"
        if w in (0, 7, 8):
            loop(w, A, T, n, kl, x, b, 1)
            line += "  bits of band_solve: " + ("yes" if np.array_equal(x, ref) else
                                                f"no (max rel. change {np.max(np.abs(x - ref) / np.abs(ref)):.1e})")
        print(line)


if __name__ == "__main__":
    main()
