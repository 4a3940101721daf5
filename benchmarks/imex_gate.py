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


def run_path(cache, alpha, dt_ms, refresh, duration, t_start):
    tail = f"_from{t_start:g}" if t_start > 0 else ""
    return os.path.join(cache, f"imex_a{alpha:g}_dt{dt_ms:g}ms_r{refresh}_T{duration:g}{tail}.npz")


def imex_run(alpha, dt, duration, cache, refresh, t_start=0.0):
    """IMEX run from the static state, or (t_start > 0) from the explicit solver's state at t_start
    (the reference trajectory itself: same solver, same 50 Hz forcing) -- the smooth start-up
    phase costs the prototype most of its time and is not what the gate is about."""
    path = run_path(cache, alpha, dt * 1e3, refresh, duration, t_start)
    if os.path.exists(path):
        return dict(np.load(path, allow_pickle=True))
    s = build_solver(config(alpha))
    for k in range(int(round(t_start * RATE))):
        t = (k + 1) / RATE
        p, v = rc.fairlead_motion(t)
        s.set_end_motion("ship", p, v)
        s.advance_to(t)
    stepper = IP.DGImex(s, dt, refresh=refresh)
    t, T0, T1, cpu = IP.run_driven(s, stepper, duration - t_start, motion=rc.fairlead_motion, rate=RATE,
                                   progress=lambda tt: log(f"    t = {tt:.0f} s, {stepper.stats}"))
    err = np.array(stepper.err_log) if stepper.err_log else np.zeros((0, 3))
    out = {"t": t, "ship": T0, "vehicle": T1, "cpu": cpu, "stats": json.dumps(stepper.stats), "err": err,
           "load": os.getloadavg()[0]}
    np.savez(path, **out)
    return out


def first_peak(t, T):
    return rc.snap_peak(t, T, *WINDOW)


def _stable_dt(lam, R):
    lo, hi = 0.0, 1.0
    lam = lam[(np.abs(lam) > 1e-9) & (lam.real <= 1e-6 * np.abs(lam).max())]  # growing modes: not a step limit
    for _ in range(50):
        mid = 0.5 * (lo + hi)
        if np.all(np.abs(R(mid * lam)) <= 1.0 + 1e-12):
            lo = mid
        else:
            hi = mid
    return lo


def _R_ark3_explicit(z):
    tab = IP.ARK3
    e = np.ones(tab.s)
    z = np.atleast_1d(z)
    return np.array([1.0 + x * tab.b @ np.linalg.solve(np.eye(tab.s) - x * tab.AE, e) for x in z])


def _R_rk3(z):
    return 1.0 + z + z * z / 2.0 + z**3 / 6.0


def explicit_part_limit(alpha):
    """Eigenvalues of Jacobians (dense forward differences in U) at the static state:
    "f_E": the prototype's explicit part (weight, drag, added mass, bending);
    "penalty": the right-hand side with EA = zeta = 0 but the Lax-Friedrichs speed kept at c
    (lambda_floor = c): transport + penalty alone, what an explicit transverse block would carry
    if the penalty of Eq. 24 (one speed for all components) stayed explicit;
    "full": the whole right-hand side (explicit SSP-RK3 reference).
    Returns max |lambda| and the largest stable dt of the ARK3 explicit part and of SSP-RK3."""
    s = build_solver(config(alpha))
    st = IP.DGImex(s, 1e-3)
    U, ra, bs = s.U.copy(), s.ra.copy(), s._bs.copy()
    c = s.prm[IP.Y.P_LAMBDA_BC]
    pen_prm = st.prmE.copy()
    pen_prm[IP.Y.P_LAMBDA_FLOOR] = c
    pen_prm[IP.Y.P_LAMBDA_BC] = c
    cases = {"f_E": None, "penalty": (pen_prm, st.iprmE), "full": (st.prm, st.iprm)}
    out = {}
    for name, pp in cases.items():
        def f(Ux):
            if pp is None:
                return st.split_rhs(0.0, Ux, ra, bs)[0].reshape(-1)
            st.prmE, st.iprmE, saved = pp[0], pp[1], (st.prmE, st.iprmE)
            try:
                st._eval(0.0, Ux, ra, bs, True)
            finally:
                st.prmE, st.iprmE = saved
            return st._dU.reshape(-1).copy()
        f0 = f(U)
        J = np.zeros((f0.size, f0.size))
        for j in range(f0.size):
            Up = U.copy().reshape(-1)
            h = st.hfd.reshape(-1)[j]
            Up[j] += h
            J[:, j] = (f(Up.reshape(U.shape)) - f0) / h
        if name == "f_E":
            JE = J
        elif name == "full":
            JI = J - JE
        lam = np.linalg.eigvals(J)
        k = np.argmax(np.abs(lam))
        out[name] = {"max_abs": float(np.abs(lam[k])), "lam_max": complex(lam[k]), "max_re": float(lam.real.max()),
                     "dt_ark3_E": _stable_dt(lam, _R_ark3_explicit), "dt_rk3": _stable_dt(lam, _R_rk3)}
    out["ark"] = {dt: ark_spectral_radius(JE, JI, dt) for dt in (0.25e-3, 0.5e-3, 1e-3, 2e-3, 4e-3, 8e-3, 16e-3, 32e-3)}
    out["growth_full"] = float(np.linalg.eigvals(JE + JI).real.max())
    return out


def ark_spectral_radius(JE, JI, dt, tab=IP.ARK3):
    """Spectral radius of the ARK step's amplification matrix for y' = (JE + JI) y (stages solved
    one by one: Y_i = (I - dt a_ii JI)^-1 (y + dt sum_j<i (AE_ij JE + AI_ij JI) Y_j))."""
    n = JE.shape[0]
    eye = np.eye(n)
    Y, F = [], []
    for i in range(tab.s):
        rhs = eye + dt * sum(tab.AE[i, j] * (JE @ Y[j]) + tab.AI[i, j] * F[j] for j in range(i)) if i else eye.copy()
        Yi = np.linalg.solve(eye - dt * tab.AI[i, i] * JI, rhs) if tab.AI[i, i] else rhs
        Y.append(Yi)
        F.append(JI @ Yi)
    R = eye + dt * sum(tab.b[j] * ((JE + JI) @ Y[j]) for j in range(tab.s))
    return float(np.abs(np.linalg.eigvals(R)).max())


def transverse_rule_limit(alpha, tension):
    """Explicit SSP-RK3 limit (cfl = 1, timestep.py rule) of the transverse string waves at a
    tension T (speed sqrt(T / (gamma0 + m_n))) plus bending: what bounds the step of an IMEX whose
    implicit block is the axial part only (and the Lax-Friedrichs penalty)."""
    from tether_sim.physics.hydrodynamics import added_mass_per_length
    from tether_sim.solvers.dg.timestep import stable_dt
    cfg = config(alpha)
    cab = cfg.cable
    _, mn = added_mass_per_length(cab, cfg.environment)
    h = np.full(20, LENGTH / 20)
    slope = tension * cab.gamma0 / (cab.gamma0 + mn)  # c_t^2 gamma0
    return stable_dt(h, 4, slope, cab.gamma0, 0.0, cab.EI, 0.0, implicit_damping=True)


def kernel_costs(alpha, repeats=200):
    """Thread-CPU cost (s) of the compiled pieces a production IMEX step is made of, at the static
    state: one full right-hand side (dg_evaluate), the banded LU of I - dt gamma J (numerics/banded.py,
    half bandwidth 3 (P+1) 6 - 1: f_I couples elements e-2..e+2) and one banded forward/back solve."""
    from tether_sim.numerics.banded import band_factor, band_solve
    s = build_solver(config(alpha))
    st = IP.DGImex(s, 1e-3)
    U, ra, bs = s.U.copy(), s.ra.copy(), s._bs.copy()
    st._eval(0.0, U, ra, bs, False)
    c0 = time.thread_time()
    for _ in range(repeats):
        st._eval(0.0, U, ra, bs, False)
    t_rhs = (time.thread_time() - c0) / repeats
    M = (np.eye(st.n) - 1e-3 * IP.ARK3.AI[1, 1] * st.jacobian(0.0, U, ra, bs).toarray())
    kl = 3 * st.nel - 1
    band0 = np.zeros((st.n, 2 * kl + 1))
    for i in range(st.n):
        for j in range(max(0, i - kl), min(st.n, i + kl + 1)):
            band0[i, j - i + kl] = M[i, j]
    row = np.zeros(kl + 1)
    x = np.ones((1, st.n))
    band = band0.copy()
    band_factor(band, st.n, kl, row)
    band_solve(band, st.n, kl, x, 0)
    err = np.abs(M @ x[0] - 1.0).max()
    reps = max(5, repeats // 20)
    c0 = time.thread_time()
    for _ in range(reps):
        band[...] = band0
        band_factor(band, st.n, kl, row)
    t_lu = (time.thread_time() - c0) / reps
    c0 = time.thread_time()
    for _ in range(repeats):
        band_solve(band, st.n, kl, x, 0)
    t_solve = (time.thread_time() - c0) / repeats
    return {"rhs": t_rhs, "lu": t_lu, "solve": t_solve, "n": st.n, "kl": kl, "lu_residual": float(err)}


def projection(stats, dt, costs, stride=5):
    """Projected CPU per simulated second of a compiled IMEX with this run's counts: RHS evaluations
    (the prototype's pairs full + explicit-part; a fused kernel would cost ~1 RHS per pair, given as
    the optimistic figure), banded solves and LU; Jacobian either by coloured differences (as here)
    or analytic (assumed 3 RHS)."""
    steps = max(stats["steps"], 1)
    probes = stats["jac"] * 2 * stride * 30
    pairs = (stats["rhs"] - probes) / 2.0 / steps
    lu = stats["lu"] / steps
    solves = stats["solves"] / steps
    per_s = 1.0 / dt
    fd = per_s * (2 * pairs * costs["rhs"] + solves * costs["solve"] + lu * (costs["lu"] + 2 * stride * 30 * costs["rhs"]))
    best = per_s * (pairs * costs["rhs"] + solves * costs["solve"] + lu * (costs["lu"] + 3 * costs["rhs"]))
    return {"pairs_per_step": pairs, "solves_per_step": solves, "lu_per_step": lu, "cpu_per_s_fd": fd,
            "cpu_per_s_best": best}


def plot(cache, alphas, dts, duration, refresh, t_start, out):
    """Ship and cage tension around the first snap: reference and every cached IMEX run."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(len(alphas), 2, figsize=(11, 3.6 * len(alphas)), squeeze=False)
    for r, alpha in enumerate(alphas):
        ref = reference(alpha, duration, cache)
        for c, end in enumerate(("ship", "vehicle")):
            ax = axes[r, c]
            pk = first_peak(ref["t"], ref[end])
            sel = np.abs(ref["t"] - pk[1]) < 0.8
            ax.plot(ref["t"][sel], ref[end][sel] / 1e3, "k-", lw=2.5, label=f"explicit {float(ref['dt']) * 1e6:.1f} us")
            for dt_ms in dts:
                path = run_path(cache, alpha, dt_ms, refresh, duration, t_start)
                if not os.path.exists(path):
                    continue
                d = np.load(path, allow_pickle=True)
                sel = np.abs(d["t"] - pk[1]) < 0.8
                ax.plot(d["t"][sel], d[end][sel] / 1e3, ".-", ms=3, lw=1, label=f"IMEX {dt_ms:g} ms")
            ax.set_title(f"alpha = {alpha:g}, {'ship' if end == 'ship' else 'cage'} end, first snap")
            ax.set_xlabel("t (s)")
            ax.set_ylabel("tension (kN)")
            ax.grid(alpha=0.3)
            ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--alphas", type=float, nargs="+", default=[0.0, 1.0])
    p.add_argument("--dts", type=float, nargs="*", default=[2.0, 1.0, 0.5, 0.25], help="ms")
    p.add_argument("--duration", type=float, default=10.0)
    p.add_argument("--refresh", type=int, default=20, help="Jacobian refresh every k steps")
    p.add_argument("--cache", default="/tmp/imex_gate")
    p.add_argument("--limits", action="store_true", help="also the explicit-part step limit")
    p.add_argument("--costs", action="store_true", help="compiled kernel costs and the projected RTF")
    p.add_argument("--t-start", type=float, default=0.0, help="IMEX from the explicit state at this time (s)")
    p.add_argument("--plot", default=None, help="PNG of the snap from the cached runs (no new runs)")
    a = p.parse_args(argv)
    os.makedirs(a.cache, exist_ok=True)
    if a.plot:
        plot(a.cache, a.alphas, a.dts, a.duration, a.refresh, a.t_start, a.plot)
        return []
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
            lims = explicit_part_limit(alpha)
            log("  ARK3 amplification about the static state, spectral radius (prototype split; the full "
                f"linearisation itself grows at {lims.pop('growth_full'):.3g} 1/s): " +
                ", ".join(f"{dt * 1e3:g} ms: {r:.6f}" for dt, r in lims.pop("ark").items()))
            for T in (float(ref["ship"][0]), rs[0]):
                log(f"  transverse waves at T = {T / 1e3:.1f} kN + bending (EI = {alpha * rc.EI_STAR:g}): explicit "
                    f"SSP-RK3 limit {transverse_rule_limit(alpha, T) * 1e3:.2f} ms (timestep.py rule, cfl 1)")
            for name, lim in lims.items():
                log(f"  {name:8s} at the static state: max |lambda| {lim['max_abs']:.4g} 1/s "
                    f"({lim['lam_max']:.4g}), max Re {lim['max_re']:.3g}; stable dt: ARK3 explicit part "
                    f"{lim['dt_ark3_E'] * 1e3:.4f} ms, SSP-RK3 {lim['dt_rk3'] * 1e3:.4f} ms")
        costs = kernel_costs(alpha) if a.costs else None
        if costs:
            log(f"  compiled kernels (thread CPU, load {os.getloadavg()[0]:.1f}): RHS {costs['rhs'] * 1e6:.1f} us, "
                f"banded LU (n = {costs['n']}, kl = {costs['kl']}) {costs['lu'] * 1e3:.2f} ms, "
                f"banded solve {costs['solve'] * 1e6:.1f} us (residual {costs['lu_residual']:.1e})")
        log("  dt (ms) | ship peak (kN) | err | shift (ms) | ref at steps | cage peak (kN) | err | shift (ms) | "
            "ref at steps | CPU s | RHS/step | Jac/step | LU/step | Newton fails | max est. err q | fallback")
        for dt_ms in a.dts:
            dt = dt_ms * 1e-3
            c0 = time.time()
            r = imex_run(alpha, dt, a.duration, a.cache, a.refresh, a.t_start)
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
                f"{st['jac'] / steps:.3f} | {st['lu'] / steps:.3f} | {st['newton_fail']} | {emax:.2e} | "
                f"fallback {st['fallback']} x, {st['fallback_time']:.3f} s ({st['fallback_substeps']} explicit substeps), "
                f"loose {st['loose']} (max {st['loose_max']:.1f}), rejected {st['rejected']}  "
                f"(wall {time.time() - c0:.0f} s, load {os.getloadavg()[0]:.1f})")
            if costs:
                pj = projection(st, dt, costs)
                row["projection"] = pj
                log(f"           projected compiled IMEX: {pj['pairs_per_step']:.1f} RHS pairs, "
                    f"{pj['solves_per_step']:.1f} solves, {pj['lu_per_step']:.3f} LU per step -> CPU per simulated s "
                    f"{pj['cpu_per_s_fd']:.3f} (FD Jacobian, 2 RHS per pair) / {pj['cpu_per_s_best']:.3f} "
                    f"(analytic Jacobian, fused pair): RTF {1 / pj['cpu_per_s_fd']:.2f} / {1 / pj['cpu_per_s_best']:.2f}")
            rows.append(row)
    with open(os.path.join(a.cache, "gate_rows.json"), "w") as f:
        json.dump(rows, f, indent=1, default=str)
    return rows


if __name__ == "__main__":
    main()
