"""Where a substep of the PE2020 Sec. 6.2 case goes (L = 200 m, N = 20, P = 4, alpha as given, dg.damping and
dg.bending_multirate as given; the fairlead orbit of bench_slack_bending.py), measured in one process:

1. the Python side: cProfile of the 50 Hz advance_to loop over the window (what is not one compiled call);
2. the implicit damping step's paths over the window (counters idp ID_NSTEPS / ID_NFACT / ID_NUPD: steps,
   new factorisations, low-rank updates; ID_NWHY: the new factorisations by reason);
3. the compiled side, per kernel, at states sampled through the window (each kernel repeated --reps times in a
   compiled loop on the solver's workspace, CPU time): a right-hand side with the nested LDG, one with the bending
   shear extrapolated (the multirate's other stages), the damping step with a new LU, with the stored LU
   (defect correction) and the LU's assembly + factorisation alone; the parts of a right-hand side (steps 1-3,
   steps 1-4 with the shear extrapolated, the nested LDG alone, step 5: rows " part: ...", for the roofline count
   of rhs_roofline.py); the parts of the stored-LU damping step (rows " damping: ...": the frozen geometry, the
   strain rates of the state, the clip set and released ends, one matrix-free K x of a defect correction and its
   three pieces, one band solve, one solve with the low-rank update, the final divergence and the end forces);
   and --reps substeps of dg_advance from the sampled state (the state restored afterwards) for the sum.

Usage: PYTHONPATH=. python benchmarks/probes/profile_slack_step.py [--alpha 1] [--damping implicit]
       [--start 5] [--seconds 3] [--samples 6] [--reps 2000]
"""

import argparse
import cProfile
import io
import os
import pstats
import sys
import time
from pathlib import Path

import numpy as np
from numba import njit

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from benchmarks.bench_slack_bending import tree  # noqa: E402
from benchmarks.studies.slack_bending_ladder import EI_STAR  # noqa: E402
from tether_sim.numerics.banded import band_factor  # noqa: E402
from tether_sim.solvers.dg import damping_layout as DL  # noqa: E402
from tether_sim.solvers.dg import layout as Y  # noqa: E402
from tether_sim.numerics.banded import band_solve  # noqa: E402
from tether_sim.solvers.dg.damping_ops import (  # noqa: E402
    axial_tension_points, clip_set, damping_geometry, end_damping_forces, release_ends, strain_rates, tension_divergence,
)
from tether_sim.solvers.dg.damping_update import update_solve  # noqa: E402
from tether_sim.solvers.dg.implicit_damping import assemble_axial  # noqa: E402
from tether_sim.solvers.dg.kernels import internal_forces, momentum_rate, tension_scalar  # noqa: E402
from tether_sim.solvers.dg.ldg import ldg_shear_force  # noqa: E402
from tether_sim.solvers.dg.stepper import _damping, dg_advance, dg_evaluate  # noqa: E402
from tether_sim.solvers.dg.workspace import (  # noqa: E402
    X_BAND, X_BC, X_BLK, X_BVEC, X_CX, X_CY, X_CZ, X_D, X_DPRM, X_DTMP, X_DU, X_ENDF, X_FDAMP, X_FL, X_H, X_IDP,
    X_IPRM_STEP, X_IQ, X_LF, X_PJ, X_PRM_STEP, X_RA, X_RS, X_TAB_EPS, X_TAB_T, X_TMP, X_TR, X_TRC, X_U, X_V, X_VBC,
    X_VEC, X_WM, X_WP, X_WQ, bind,
)
from tether_sim.solvers.dg.workspace import X_DWOOD, X_WD  # noqa: E402

DAMPING_PARTS = ("geometry (damping_geometry)", "strain rates of the state", "clip set + released ends",
                 "K x (defect correction)", " K x: tension points", " K x: tension_divergence", " K x: strain_rates",
                 "band solve", "solve with the low-rank update", "final divergence", "final end forces")


@njit
def _rhs(F, I, S, n, t, extrapolated):
    A = bind(F, I, S)
    prm = A[X_PRM_STEP]
    for _ in range(n):
        if extrapolated:
            prm[Y.P_BMR] = 1.0
        dg_evaluate(t, A, prm, A[X_IPRM_STEP], A[X_FDAMP], True, True)
    prm[Y.P_BMR] = 0.0


@njit
def _part(F, I, S, n, which):
    """One part of a right-hand side, n times, on the state the last full evaluation left in the work arrays:
    0 tension_scalar (steps 1-3, shear extrapolated), 1 internal_forces (steps 1-4, shear extrapolated),
    2 the nested LDG alone (ldg_shear_force), 3 momentum_rate (step 5)."""
    A = bind(F, I, S)
    prm, iprm = A[X_PRM_STEP], A[X_IPRM_STEP]
    U, h, V, Pj, D, Lf, Tr = A[X_U], A[X_H], A[X_V], A[X_PJ], A[X_D], A[X_LF], A[X_TR]
    wq, wm, tr, fl, dU = A[X_WQ], A[X_WM], A[X_TRC], A[X_FL], A[X_DU]
    for _ in range(n):
        if which == 0:
            prm[Y.P_BMR] = 1.0
            tension_scalar(U, prm, iprm, h, V, Pj, D, Lf, Tr, A[X_TAB_EPS], A[X_TAB_T], A[X_BC], A[X_VBC], wq, wm, tr,
                           fl, dU)
        elif which == 1:
            prm[Y.P_BMR] = 1.0
            internal_forces(U, prm, iprm, h, V, Pj, D, Lf, Tr, A[X_TAB_EPS], A[X_TAB_T], A[X_BC], A[X_VBC], wq, wm,
                            tr, fl, dU, A[X_ENDF], A[X_TMP])
        elif which == 2:
            ldg_shear_force(prm, iprm, h, V, Pj, D, Lf, Tr, A[X_BC], wq, wm, tr, fl)
        else:
            momentum_rate(U, A[X_RA], prm, iprm, h, V, Pj, D, Lf, A[X_IQ], A[X_CZ], A[X_CX], A[X_CY], wq, wm, tr, fl,
                          A[X_RS], A[X_TMP], dU)
    prm[Y.P_BMR] = 0.0


@njit
def _damp(F, I, S, n, dt, U0, fresh):
    A = bind(F, I, S)
    U = A[X_U]
    idp = A[X_IDP]
    for _ in range(n):
        U[:] = U0
        if fresh:
            idp[DL.ID_LU_AGE] = -1
        else:
            idp[DL.ID_LU_AGE] = 1
        _damping(dt, A)


@njit
def _damp_part(F, I, S, n, which):
    """One part of the stored-LU damping step (DAMPING_PARTS[which]), n times, on the frozen geometry and LU the
    last damping step left in the work arrays."""
    A = bind(F, I, S)
    U, vbc, idp, dprm, blk, bvec, V, Pj, Tr = (A[X_U], A[X_VBC], A[X_IDP], A[X_DPRM], A[X_BLK], A[X_BVEC], A[X_V],
                                               A[X_PJ], A[X_TR])
    te, tT, wp, wd, band, vec, wood = A[X_TAB_EPS], A[X_TAB_T], A[X_WP], A[X_WD], A[X_BAND], A[X_VEC], A[X_DWOOD]
    n_e = wp.shape[0] * wp.shape[1]
    kl = idp[DL.ID_KL]
    for _ in range(n):
        if which == 0:
            damping_geometry(U, V, idp, dprm, wp, te, tT)
        elif which == 1:
            strain_rates(U, 3, True, vbc, blk, bvec, wp, DL.WP_E0)
        elif which == 2:
            clip_set(idp, dprm, wp, te, tT)
            release_ends(U, vbc, idp, dprm, bvec, Tr, wp, te, tT)
        elif which == 3 or which == 4:
            axial_tension_points(wp, DL.WP_KX, False)
        if which == 3 or which == 5:
            tension_divergence(blk, Pj, bvec, idp, dprm, wp, wd, DL.WD_P, False)
        if which == 3 or which == 6:
            strain_rates(wd, DL.WD_P, False, vbc, blk, bvec, wp, DL.WP_KY)
        elif which == 7 or which == 8:
            for r in range(n_e):
                vec[3, r] = wp[r // wp.shape[1], r % wp.shape[1], DL.WP_E0]
            if which == 7:
                band_solve(band, n_e, kl, vec, 3)
            else:
                update_solve(band, n_e, kl, vec, 3, wood, idp)
        elif which == 9:
            axial_tension_points(wp, DL.WP_X, True)
            tension_divergence(blk, Pj, bvec, idp, dprm, wp, wd, DL.WD_F, True)
        elif which == 10:
            axial_tension_points(wp, DL.WP_E2, True)
            end_damping_forces(idp, dprm, bvec, U, Tr, wp, A[X_FDAMP])


@njit
def _factor(F, I, S, n, gh):
    A = bind(F, I, S)
    band, idp = A[X_BAND], A[X_IDP]
    kl = idp[DL.ID_KL]
    wp = A[X_WP]
    for _ in range(n):
        assemble_axial(A[X_BLK], A[X_BVEC], idp, A[X_DPRM], wp, gh, band, kl, A[X_DTMP])
        band_factor(band, wp.shape[0] * wp.shape[1], kl, A[X_VEC][2])


@njit
def _substeps(F, I, S, n, t, dt):
    dg_advance(n, t, dt, False, F, I, S)


def kernel_times(s, reps):
    ws = s.ws
    F0, I0 = ws.F.copy(), ws.I.copy()
    dt = s._substep()
    row = {}
    args = (ws.F, ws.I, ws.spec)
    for name, fn, extra in (("rhs, nested LDG", _rhs, (s.time, False)), ("rhs, shear extrapolated", _rhs, (s.time, True)),
                            ("damping step, new LU", _damp, (dt, ws.U.copy(), True)),
                            ("damping step, stored LU", _damp, (dt, ws.U.copy(), False)),
                            ("assembly + factorisation", _factor, (DL.GAMMA_SDIRK * dt,)),
                            (" part: steps 1-3 (tension_scalar)", _part, (0,)),
                            (" part: steps 1-4 (internal_forces)", _part, (1,)),
                            (" part: nested LDG alone", _part, (2,)),
                            (" part: step 5 (momentum_rate)", _part, (3,)),
                            *((" damping: " + name, _damp_part, (k,)) for k, name in enumerate(DAMPING_PARTS))):
        fn(*args, 2, *extra)  # compile
        ws.F[:] = F0
        ws.I[:] = I0
        c = time.process_time()
        fn(*args, reps, *extra)
        row[name] = 1e6 * (time.process_time() - c) / reps
        ws.F[:] = F0
        ws.I[:] = I0
    _substeps(*args, 2, s.time, dt)
    ws.F[:] = F0
    ws.I[:] = I0
    c = time.process_time()
    _substeps(*args, reps, s.time, dt)  # the ends held at their present motion: reps substeps from this state
    row["whole substep (dg_advance)"] = 1e6 * (time.process_time() - c) / reps
    ws.F[:] = F0
    ws.I[:] = I0
    return row


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--alpha", type=float, default=1.0)
    ap.add_argument("--damping", default="implicit")
    ap.add_argument("--multirate", default="on", choices=["on", "off"])
    ap.add_argument("--start", type=float, default=5.0)
    ap.add_argument("--seconds", type=float, default=3.0)
    ap.add_argument("--samples", type=int, default=6)
    ap.add_argument("--reps", type=int, default=2000)
    args = ap.parse_args(argv)
    load_config, build_motion, build_solver = tree("tether_sim")
    overrides = {"cable.EI": args.alpha * EI_STAR, "motion.kind": "circle", "motion.amplitude": 2.0,
                 "motion.frequency": 0.2, "motion.ramp_time": 5.0, "duration": 60.0, "dg.n_elements": 20,
                 "dg.order": 4, "dg.damping": args.damping, "dg.bending_multirate": args.multirate == "on"}
    cfg = load_config(ROOT / "config" / "ropos_L200_paper.yaml", overrides)
    motion = build_motion(cfg.motion, cfg.ship_end.position)
    s = build_solver(cfg)
    print(f"# {time.strftime('%Y-%m-%d %H:%M')} load {os.getloadavg()[0]:.1f}; alpha {args.alpha:g}, "
          f"dg.damping {args.damping}, multirate {args.multirate} (K = {s.bending_multirate_k}), window "
          f"{args.start:g}-{args.start + args.seconds:g} s", flush=True)
    rate, t0 = 50.0, s.time
    k = 0

    def tick():
        nonlocal k
        k += 1
        p, v, _ = motion.at(k / rate)
        s.set_end_motion("ship", p, v)
        n = s.advance_to(t0 + k / rate)
        s.drain_end_tensions()
        return n or 0

    while k / rate < args.start - 1e-9:
        tick()
    idp = s.ws.idp
    counters = [DL.ID_NSTEPS, DL.ID_NFACT, DL.ID_NUPD] + [DL.ID_NWHY + w for w in range(5)]
    c0 = [int(idp[c]) for c in counters]
    marks = set(np.linspace(0, int(args.seconds * rate) - 1, args.samples).astype(int))
    prof = cProfile.Profile()
    rows, steps, cpu = [], 0, 0.0
    for i in range(int(args.seconds * rate)):
        if i in marks:
            rows.append(kernel_times(s, args.reps))
        c = time.process_time()
        prof.enable()
        steps += tick()
        prof.disable()
        cpu += time.process_time() - c
    c1 = [int(idp[c]) for c in counters]
    d = [b - a for a, b in zip(c0, c1)]
    print(f"window: {args.seconds / cpu:.3f} x real time per CPU s, {steps / args.seconds:.0f} substeps/s, "
          f"{1e6 * cpu / steps:.1f} us per substep (profiler on)")
    if d[0]:
        print(f"damping steps {d[0]}: new LU {d[1]} ({100 * d[1] / d[0]:.1f} %), low-rank update {d[2]} "
              f"({100 * d[2] / d[0]:.1f} %), stored LU as it was {d[0] - d[1] - d[2]}")
        why = ("none kept for the step size", "released ends", "age", "update refused", "correction above tol")
        print("new LUs by reason: " + ", ".join(f"{w} {n}" for w, n in zip(why, d[3:])))
    print("per call, us (median over the samples; min-max):")
    for name in rows[0]:
        v = np.array([r[name] for r in rows])
        print(f"  {name:32s} {np.median(v):8.2f}  ({v.min():.2f}-{v.max():.2f})")
    out = io.StringIO()
    pstats.Stats(prof, stream=out).sort_stats("tottime").print_stats(12)
    print("Python side (cProfile, by own time):")
    print("\n".join(out.getvalue().splitlines()[:30]))
    print(f"# load {os.getloadavg()[0]:.1f} at the end")


if __name__ == "__main__":
    main()
