"""The arithmetic of a DG right-hand side against its measured time (a roofline count).

1. The multiply-adds of the block operators of one right-hand side at N elements of order P with Q Gauss points
   (kernels.py steps 1-5 and the nested LDG of ldg.py, the stepper's configuration of the Sec. 6.2 case: implicit
   damping, so no strain-rate or bending-damping terms; bilinear law; no current, seabed or waves), counted from
   the loops: a map between M modes and Q points of C channels costs M Q C, a trace pair 2 M C, a strong derivative
   C (M (M - 1) / 2 + 2 M) (the strictly upper D and the two lifts).
2. The rate at which the machine does such a block operator when nothing else is in the way: the tension
   projection of kernels._project_tension (Q points -> M modes, three channels) on the real work-array shapes,
   repeated in a compiled loop (ns per multiply-add), and the banded LU solve of the damping step
   (numerics/banded.band_solve, n = N Q, kl = 3 Q - 1) with its serial inner sums, and the same solve with four
   partial sums (not bit-identical: the order of the sum changes), interleaved, min of --repeat.

The RHS times to hold these against come from profile_slack_step.py (the same case).

Usage: PYTHONPATH=. python benchmarks/probes/rhs_roofline.py [--N 20] [--P 4] [--repeat 5] [--reps 20000]
"""

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np
from numba import njit

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from tether_sim.numerics.banded import band_factor, band_solve  # noqa: E402
from tether_sim.numerics.quadrature import dg_quadrature_points  # noqa: E402
from tether_sim.solvers.dg import layout as Y  # noqa: E402


def rhs_counts(N, P):
    """Multiply-adds of the block operators per right-hand side: (base, nested LDG, held shear), each for N elements."""
    M = P + 1
    Q = dg_quadrature_points(P)

    def pts(C):  # modes -> points or points -> modes
        return M * Q * C

    def trc(C):  # modes -> both traces
        return 2 * M * C

    def der(C):  # strong derivative: strictly upper D and the two lifts
        return C * (M * (M - 1) // 2 + 2 * M)

    base = {
        "q, v at the points and traces (6 channels)": pts(6) + trc(6),
        "dq/dt (strong derivative, 3)": der(3),
        "tension vector -> modes -> traces (3)": pts(3) + trc(3),
        "dT/ds, to the points, dv/dt -> modes (3)": der(3) + pts(3) + pts(3),
    }
    ldg = {
        "b -> modes -> traces": pts(3) + trc(3),
        "kappa: derivative, to the points": der(3) + pts(3),
        "M* -> modes -> traces": pts(3) + trc(3),
        "tau: derivative, to the points": der(3) + pts(3),
    }
    held = Q * 3 * 3  # T_s = sum of three weighted records
    return ({k: N * v for k, v in base.items()}, {k: N * v for k, v in ldg.items()}, N * held, M, Q)


@njit(nogil=True, _nrt=False)
def _projection(Pj, wq, wm, N, reps):
    nm, nq = Pj.shape
    for _ in range(reps):
        for e in range(N):
            for l in range(nm):
                s0 = 0.0
                s1 = 0.0
                s2 = 0.0
                for j in range(nq):
                    a = Pj[l, j]
                    s0 += a * wq[e, j, Y.W_TV]
                    s1 += a * wq[e, j, Y.W_TV + 1]
                    s2 += a * wq[e, j, Y.W_TV + 2]
                wm[e, l, Y.M_TV] = s0
                wm[e, l, Y.M_TV + 1] = s1
                wm[e, l, Y.M_TV + 2] = s2


@njit(nogil=True, _nrt=False)
def _solves(A, n, kl, x, reps):
    for _ in range(reps):
        for i in range(n):
            x[1, i] = x[0, i]
        band_solve(A, n, kl, x, 1)


@njit(nogil=True, _nrt=False)
def _solve4(A, n, kl, x, col):
    """band_solve with four partial sums per row (the sum reassociated: last bits differ)."""
    for i in range(n):
        a0 = 0.0
        a1 = 0.0
        a2 = 0.0
        a3 = 0.0
        j = max(0, i - kl)
        while j + 3 < i:
            a0 += A[i, j - i + kl] * x[col, j]
            a1 += A[i, j + 1 - i + kl] * x[col, j + 1]
            a2 += A[i, j + 2 - i + kl] * x[col, j + 2]
            a3 += A[i, j + 3 - i + kl] * x[col, j + 3]
            j += 4
        while j < i:
            a0 += A[i, j - i + kl] * x[col, j]
            j += 1
        x[col, i] = x[col, i] - ((a0 + a1) + (a2 + a3))
    for i in range(n - 1, -1, -1):
        j1 = min(n, i + kl + 1)
        a0 = 0.0
        a1 = 0.0
        a2 = 0.0
        a3 = 0.0
        j = i + 1
        while j + 3 < j1:
            a0 += A[i, j - i + kl] * x[col, j]
            a1 += A[i, j + 1 - i + kl] * x[col, j + 1]
            a2 += A[i, j + 2 - i + kl] * x[col, j + 2]
            a3 += A[i, j + 3 - i + kl] * x[col, j + 3]
            j += 4
        while j < j1:
            a0 += A[i, j - i + kl] * x[col, j]
            j += 1
        x[col, i] = (x[col, i] - ((a0 + a1) + (a2 + a3))) / A[i, kl]


@njit(nogil=True, _nrt=False)
def _solves4(A, n, kl, x, reps):
    for _ in range(reps):
        for i in range(n):
            x[1, i] = x[0, i]
        _solve4(A, n, kl, x, 1)


def _best(fn, args, reps, repeat):
    best = np.inf
    for _ in range(repeat):
        c = time.process_time()
        fn(*args, reps)
        best = min(best, (time.process_time() - c) / reps)
    return 1e6 * best


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--N", type=int, default=20)
    ap.add_argument("--P", type=int, default=4)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--reps", type=int, default=20000)
    args = ap.parse_args(argv)
    base, ldg, held, M, Q = rhs_counts(args.N, args.P)
    print(f"# {time.strftime('%Y-%m-%d %H:%M')} load {os.getloadavg()[0]:.1f}; N = {args.N}, P = {args.P} "
          f"(M = {M} modes, Q = {Q} points)")
    print("block-operator multiply-adds per right-hand side:")
    for k, v in {**base, **ldg}.items():
        print(f"  {k:48s} {v:7d}")
    nb, nl = sum(base.values()), sum(ldg.values())
    print(f"  shear extrapolated (base + held T_s {held}): {nb + held}; with the nested LDG: {nb + nl}")
    rng = np.random.default_rng(1)
    N = args.N
    Pj = rng.normal(size=(M, Q))
    wq = rng.normal(size=(N, Q, Y.NWQ))
    wm = np.zeros((N, M, Y.NWM))
    n, kl = N * Q, 3 * Q - 1
    A = np.zeros((n, 2 * kl + 1))
    for i in range(n):
        for j in range(max(0, i - kl), min(n, i + kl + 1)):
            A[i, j - i + kl] = 0.05 * rng.normal()
        A[i, kl] = 3.0
    band_factor(A, n, kl, np.zeros(n))
    x = np.zeros((2, n))
    x[0] = rng.normal(size=n)
    _projection(Pj, wq, wm, N, 2)
    _solves(A, n, kl, x, 2)
    _solves4(A, n, kl, x, 2)
    y = x.copy()
    _solves4(A, n, kl, y, 1)
    _solves(A, n, kl, x, 1)
    diff = np.max(np.abs(x[1] - y[1])) / np.max(np.abs(x[1]))
    t = {"p": np.inf, "s": np.inf, "s4": np.inf}
    for _ in range(args.repeat):  # interleaved
        t["p"] = min(t["p"], _best(_projection, (Pj, wq, wm, N), args.reps, 1))
        t["s"] = min(t["s"], _best(_solves, (A, n, kl, x), args.reps, 1))
        t["s4"] = min(t["s4"], _best(_solves4, (A, n, kl, x), args.reps, 1))
    ma_p = N * M * Q * 3
    ma_s = 2 * n * kl - kl * (kl + 1)
    print(f"tension projection alone: {t['p']:.3f} us for {ma_p} multiply-adds = {1e3 * t['p'] / ma_p:.3f} ns each")
    print(f"  -> the block operators of a right-hand side at that rate: {1e-3 * (nb + held) * 1e3 * t['p'] / ma_p:.2f} us "
          f"(shear extrapolated), {1e-3 * (nb + nl) * 1e3 * t['p'] / ma_p:.2f} us (nested LDG)")
    print(f"band solve n = {n}, kl = {kl}: {t['s']:.2f} us ({1e3 * t['s'] / ma_s:.2f} ns per multiply-add); "
          f"four partial sums {t['s4']:.2f} us (x{t['s'] / t['s4']:.2f}; max difference "
          f"{diff:.1e} of the solution)")
    print(f"# load {os.getloadavg()[0]:.1f} at the end")


if __name__ == "__main__":
    main()
