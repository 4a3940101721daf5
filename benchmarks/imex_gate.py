"""IMEX gate of issue 14: how does the first snap peak at both ends move with the IMEX step?

ROPOS tether + cage body, L = 200 m, N = 20, P = 4, circular fairlead a = 2 m, f = 0.2 Hz (ropos_case),
alpha = 0 and 1. Reference: the explicit solver (SSP-RK3, dg.cfl 0.5, explicit damping: the stable
step ~1.8e-5 s), driven like the node (benchmarks/drive.py: targets at 50 Hz). Prototype: ARK3(2)4L[2]SA
IMEX (benchmarks/imex_proto.py) at dt = 0.25, 0.5, 1, 2 ms, started from the same static state and
driven by the same 50 Hz Hermite segments. Reported: first snap peak (largest tension in 5-10 s) at
the ship and at the cage, its relative error and time shift against the reference, the reference
itself sampled at the IMEX step times (how much of the difference is sampling), cost counters, and
the explicit-part step limit (eigenvalues of d f_E / dU).

``nice -n 5 .venv/bin/python benchmarks/imex_gate.py [--alphas 0 1] [--dts 2 1 0.5 0.25] [--cache DIR]``
Every run is cached (npz in --cache): a reference or IMEX run is never computed twice.
"""

import argparse
import json
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

import imex_proto as IP  # noqa: E402
import ropos_case as rc  # noqa: E402
from tether_sim.solvers.factory import build_solver  # noqa: E402

LENGTH = 200.0
WINDOW = rc.FIRST_SNAP_WINDOW
RATE = 50.0


def log(*a):
    print(*a, flush=True)


def config(alpha, cfl=0.5):
    return rc.ropos_config(LENGTH, alpha=alpha, n_elements=20, order=4, cfl=cfl)


def reference(alpha, duration, cache, cfl=0.5):
    """Explicit run (per-substep end tensions), cached."""
    path = os.path.join(cache, f"ref_a{alpha:g}_cfl{cfl:g}_T{duration:g}.npz")
    if os.path.exists(path):
        return dict(np.load(path))
    s = build_solver(config(alpha, cfl))
    s.drain_end_tensions()
    ts, t0, t1 = [], [], []
    c0 = time.thread_time()
    for k in range(int(round(duration * RATE))):
        t = (k + 1) / RATE
        p, v = rc.fairlead_motion(t)
        s.set_end_motion("ship", p, v)
        s.advance_to(t)
        a, b, c = s.drain_end_tensions()
        ts.append(a)
        t0.append(b)
        t1.append(c)
    cpu = time.thread_time() - c0
    out = {"t": np.concatenate(ts), "ship": np.concatenate(t0), "vehicle": np.concatenate(t1),
           "dt": s.stable_time_step(), "cpu": cpu, "load": os.getloadavg()[0]}
    np.savez(path, **out)
    return out


def imex_run(alpha, dt, duration, cache, refresh):
    path = os.path.join(cache, f"imex_a{alpha:g}_dt{dt * 1e3:g}ms_r{refresh}_T{duration:g}.npz")
    if os.path.exists(path):
        return dict(np.load(path, allow_pickle=True))
    s = build_solver(config(alpha))
    stepper = IP.DGImex(s, dt, refresh=refresh)
    t, T0, T1, cpu = IP.run_driven(s, stepper, duration, motion=rc.fairlead_motion, rate=RATE,
                                   progress=lambda tt: log(f"    t = {tt:.0f} s, {stepper.stats}"))
    err = np.array(stepper.err_log) if stepper.err_log else np.zeros((0, 3))
    out = {"t": t, "ship": T0, "vehicle": T1, "cpu": cpu, "stats": json.dumps(stepper.stats), "err": err,
           "load": os.getloadavg()[0]}
    np.savez(path, **out)
    return out


def first_peak(t, T):
    return rc.snap_peak(t, T, *WINDOW)


def explicit_part_limit(alpha):
    """Largest |eigenvalue| of d f_E / dU at the static state and the largest dt with
    |R_E(dt lambda)| <= 1 for the ARK3 explicit part and for SSP-RK3 (indicator: f_E alone)."""
    s = build_solver(config(alpha))
    st = IP.DGImex(s, 1e-3)
    U, ra, bs = s.U.copy(), s.ra.copy(), s._bs.copy()
    f0 = st.split_rhs(0.0, U, ra, bs)[0].reshape(-1)
    n = f0.size
    J = np.zeros((n, n))
    for j in range(n):
        Up = U.copy().reshape(-1)
        h = st.hfd.reshape(-1)[j]
        Up[j] += h
        J[:, j] = (st.split_rhs(0.0, Up.reshape(U.shape), ra, bs)[0].reshape(-1) - f0) / h
    lam = np.linalg.eigvals(J)
    tab = IP.ARK3
    e = np.ones(tab.s)

    def R_ark(z):
        return 1.0 + z * tab.b @ np.linalg.solve(np.eye(tab.s) - z * tab.AE, e)

    def R_rk3(z):
        return 1.0 + z + z * z / 2.0 + z**3 / 6.0

    def limit(R):
        lo, hi = 0.0, 1.0
        for _ in range(50):
            mid = 0.5 * (lo + hi)
            if all(abs(R(mid * x)) <= 1.0 + 1e-12 for x in lam if abs(x) > 1e-9):
                lo = mid
            else:
                hi = mid
        return lo

    k = np.argmax(np.abs(lam))
    return {"max_abs": float(np.abs(lam[k])), "lam_max": complex(lam[k]), "max_re": float(lam.real.max()),
            "dt_ark3_E": limit(R_ark), "dt_rk3": limit(R_rk3)}


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--alphas", type=float, nargs="+", default=[0.0, 1.0])
    p.add_argument("--dts", type=float, nargs="*", default=[2.0, 1.0, 0.5, 0.25], help="ms")
    p.add_argument("--duration", type=float, default=10.0)
    p.add_argument("--refresh", type=int, default=20, help="Jacobian refresh every k steps")
    p.add_argument("--cache", default="/tmp/imex_gate")
    p.add_argument("--limits", action="store_true", help="also the explicit-part step limit")
    a = p.parse_args(argv)
    os.makedirs(a.cache, exist_ok=True)
    log(f"IMEX gate, ROPOS L = {LENGTH:g} m, N = 20, P = 4, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, "
        f"load {os.getloadavg()[0]:.1f}")
    rows = []
    for alpha in a.alphas:
        ref = reference(alpha, a.duration, a.cache)
        rs, rv = first_peak(ref["t"], ref["ship"]), first_peak(ref["t"], ref["vehicle"])
        log(f"alpha = {alpha:g}: explicit reference dt {float(ref['dt']):.3e} s, CPU {float(ref['cpu']):.1f} s "
            f"(load {float(ref['load']):.1f}); first snap ship {rs[0] / 1e3:.3f} kN at {rs[1]:.4f} s, "
            f"cage {rv[0] / 1e3:.3f} kN at {rv[1]:.4f} s")
        if a.limits:
            lim = explicit_part_limit(alpha)
            log(f"  explicit part f_E at the static state: max |lambda| {lim['max_abs']:.4g} 1/s "
                f"({lim['lam_max']:.4g}), max Re {lim['max_re']:.3g}; stable dt: ARK3 explicit part "
                f"{lim['dt_ark3_E'] * 1e3:.3f} ms, SSP-RK3 {lim['dt_rk3'] * 1e3:.3f} ms")
        log("  dt (ms) | ship peak (kN) | err | shift (ms) | ref at steps | cage peak (kN) | err | shift (ms) | "
            "ref at steps | CPU s | RHS/step | Jac/step | LU/step | Newton fails | max est. err q")
        for dt_ms in a.dts:
            dt = dt_ms * 1e-3
            c0 = time.time()
            r = imex_run(alpha, dt, a.duration, a.cache, a.refresh)
            st = json.loads(str(r["stats"]))
            row = {"alpha": alpha, "dt_ms": dt_ms, "stats": st, "cpu": float(r["cpu"])}
            cells = []
            for end, pr in (("ship", rs), ("vehicle", rv)):
                pk = first_peak(r["t"], r[end])
                sampled = first_peak(r["t"], np.interp(r["t"], ref["t"], ref[end]))
                row[end] = {"peak": pk[0], "t": pk[1], "err": pk[0] / pr[0] - 1.0, "shift": pk[1] - pr[1],
                            "ref_sampled_err": sampled[0] / pr[0] - 1.0}
                cells.append(f"{pk[0] / 1e3:9.3f} | {pk[0] / pr[0] - 1:+.3%} | {1e3 * (pk[1] - pr[1]):+7.2f} | "
                             f"{sampled[0] / pr[0] - 1:+.3%}")
            steps = max(st["steps"], 1)
            err = r["err"]
            emax = float(err[:, 1].max()) if len(err) else float("nan")
            log(f"  {dt_ms:7.2f} | " + " | ".join(cells) + f" | {float(r['cpu']):6.0f} | {st['rhs'] / steps:6.1f} | "
                f"{st['jac'] / steps:.3f} | {st['lu'] / steps:.3f} | {st['newton_fail']} | {emax:.2e}  "
                f"(wall {time.time() - c0:.0f} s, load {os.getloadavg()[0]:.1f})")
            rows.append(row)
    with open(os.path.join(a.cache, "gate_rows.json"), "w") as f:
        json.dump(rows, f, indent=1, default=str)
    return rows


if __name__ == "__main__":
    main()
