"""Explicit steppers on the DG cable's own spectrum: stable dt per right-hand-side evaluation.

The linearised axial-wave operator of the compiled right-hand side (upwind flux, c = 1, h = 1, a straight
taut cable between pins: benchmarks/studies/calibrate_timestep.py) is the spectrum that binds the substep of
the explicit part of the split step (dg.damping implicit or rkl2). For each explicit scheme (its stability
polynomial R, s stages = right-hand sides per step) this prints the largest dt with |R(dt lambda)| <= 1 on
every eigenvalue, its real-axis and imaginary-axis limits, and dt / s: the simulated time per right-hand
side, against SSP-RK3's. "optimal(s, p)" is the best any s-stage order-p scheme can do on this spectrum
(the stability polynomial's free coefficients optimised for it, the convex problem of Ketcheson and
Ahmadia 2012, solved by bisection on dt), the bound for low-storage schemes tuned to DG spectra.

    PYTHONPATH=. python benchmarks/probes/stepper_gate.py [P] [N]
"""

import math
import sys

import numpy as np
from scipy.optimize import minimize

sys.path.insert(0, ".")

from benchmarks.studies.calibrate_timestep import jacobian_eigs, make  # noqa: E402


def taylor(p):
    return [1.0 / math.factorial(k) for k in range(p + 1)]


def shu_osher_poly(stages):
    """Stability polynomial coefficients of u <- a u_n + b (u + d z u) stages (the stepper's table form)."""
    un = np.array([1.0])
    u = un.copy()
    for a, b, d in stages:
        zu = np.concatenate(([0.0], u))
        u = a * np.concatenate((un, np.zeros(len(zu) - len(un)))) + b * (np.concatenate((u, [0.0])) + d * zu)
        u = np.trim_zeros(u, "b")
    return list(u)


SCHEMES = {
    "SSP-RK3 (3,3)": (3, taylor(3)),
    "RK4 (4,4)": (4, taylor(4)),
    "SSPRK(4,3)": (4, shu_osher_poly([(0.0, 1.0, 0.5), (0.0, 1.0, 0.5), (2.0 / 3.0, 1.0 / 3.0, 0.5),
                                      (0.0, 1.0, 0.5)])),
    "SSPRK(9,3)": (9, None),  # Ketcheson 2008, n = 3: s = n^2 stages, SSP coefficient n^2 - n
}


def ssprk_n2_3(n=3):
    """Stability polynomial of Ketcheson's SSPRK(n^2, 3) (SIAM J. Sci. Comput. 30, 2008; r = n^2 - n)."""
    s, r = n * n, n * n - n
    k1, k2 = (n - 1) * (n - 2) // 2, n * (n + 1) // 2
    q1 = np.zeros(s + 1)
    q1[0] = 1.0
    q2 = q1.copy()

    def euler(q):
        return q + np.concatenate(([0.0], q[:-1])) / r

    for i in range(1, s + 1):
        if i == k2:
            q1 = n / (2 * n - 1) * q2 + (n - 1) / (2 * n - 1) * euler(q1)
        else:
            q1 = euler(q1)
        if i == k1:
            q2 = q1.copy()
    if k1 == 0:
        raise ValueError("n >= 2")
    return list(np.trim_zeros(q1, "b"))


def limit_dt(coef, lam, hi):
    lo = 0.0
    c = np.array(coef, dtype=float)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        z = mid * lam
        if np.all(np.abs(np.polyval(c[::-1], z)) <= 1.0 + 1e-9):
            lo = mid
        else:
            hi = mid
    return lo


def axis_limit(coef, direction):
    """Largest r with |R(r t direction)| <= 1 for all t in [0, 1] (scanned)."""
    c = np.array(coef, dtype=float)[::-1]
    rs = np.linspace(1e-3, 40.0, 40000)
    ok = np.abs(np.polyval(c, rs * direction)) <= 1.0 + 1e-9
    bad = np.nonzero(~ok)[0]
    return rs[bad[0] - 1] if len(bad) else rs[-1]


def optimal(s, p, lam, hi):
    """Best dt of an s-stage, order-p stability polynomial on eigenvalues lam (bisection over dt)."""
    fixed = np.array(taylor(p))
    free = s - p

    def worst(x, dt):
        z = dt * lam
        R = np.polyval(fixed[::-1], z) + sum(x[k] * z ** (p + 1 + k) for k in range(free))
        return np.max(np.abs(R))

    lo, x_best = 0.0, np.zeros(free)
    x0 = np.array([1.0 / math.factorial(p + 1 + k) for k in range(free)])
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        best = None
        for start in (x0, x_best):
            r = minimize(lambda x: worst(x, mid), start, method="Nelder-Mead",
                         options={"xatol": 1e-12, "fatol": 1e-12, "maxiter": 4000 * free})
            if best is None or r.fun < best.fun:
                best = r
        if best.fun <= 1.0 + 1e-7:
            lo, x_best = mid, best.x
        else:
            hi = mid
    return lo, list(fixed) + list(x_best)


def main(P=4, N=4):
    lam = jacobian_eigs(make(P, N, 1.0, 0.0, 0.0, 0.0))
    lam = lam[np.abs(lam) > 1e-9 * np.max(np.abs(lam))]
    print(f"P = {P}, N = {N}: {len(lam)} eigenvalues (c = 1, h = 1); min Re = {lam.real.min():.3f}, "
          f"max |Im| = {np.abs(lam.imag).max():.3f}")
    SCHEMES["SSPRK(9,3)"] = (9, ssprk_n2_3(3))
    hi = 60.0 / np.max(np.abs(lam))
    ref = None
    rows = []
    for name, (s, coef) in SCHEMES.items():
        rows.append((name, s, coef))
    for s, p in ((4, 3), (5, 3), (6, 3), (5, 4), (6, 4), (8, 4)):
        dt, coef = optimal(s, p, lam, hi)
        rows.append((f"optimal({s},{p})", s, coef))
    print(f"{'scheme':16s} {'s':>2s} {'real lim':>9s} {'imag lim':>9s} {'dt c/h':>9s} {'dt/s':>9s} {'vs RK3':>7s}")
    for name, s, coef in rows:
        dt = limit_dt(coef, lam, hi)
        if ref is None:
            ref = dt / s
        print(f"{name:16s} {s:2d} {axis_limit(coef, -1.0):9.3f} {axis_limit(coef, 1j):9.3f} {dt:9.5f} "
              f"{dt / s:9.5f} {dt / s / ref:7.3f}", flush=True)


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:3]))
