"""One SSP-RK3 substep of the DG stepper split by part, on a warmed solver of a live file (default the
1730 m live mesh: N = 6, P = 2).

Every part is wrapped in a compiled function of (F, I, S, t) that binds what it needs and runs the part once;
its cost is the wrapper's time per call less that of an empty wrapper with the same arguments (the call
itself, also printed). Each wrapper runs on its own copy of the warmed solver's arenas (no part sees another's
writes; a part that steps moves its copy's state on, a few ms of simulated time over the run). Thread CPU,
min over --repeat blocks of --calls calls, the parts interleaved block by block.

Parts: a substep (stepper.dg_advance, one substep of the rule's step; the first stage not reused); one
right-hand side with the stepper's parameters (stepper.dg_evaluate) and its pieces: the end kinematics,
steps 1-3 (kernels.tension_scalar, generic), steps 1-4 (internal_forces: the end fluxes and loads added),
step 5 (kernels.momentum_rate, generic), the bodies' derivatives; the stage update of U, r_a and the bodies;
and, where the mesh's size is one of kernels.SIZED, steps 1-3 and step 5 at fixed sizes (what the stepper
calls there).

Usage: PYTHONPATH=. python benchmarks/probes/substep_parts.py [--params config/ropos_L1730.yaml] [--ei 2620]
       [--calls 200] [--repeat 15]
"""

import math
import os
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from benchmarks.probes.tick_fixed_work import motion, tick_parser, warmed_solver  # noqa: E402

from numba import njit  # noqa: E402

from tether_sim.numerics.jit import OPTIONS  # noqa: E402
from tether_sim.physics.bodies import body_derivatives  # noqa: E402
from tether_sim.physics.end_conditions import has_body  # noqa: E402
from tether_sim.solvers.dg import kernels as KR  # noqa: E402
from tether_sim.solvers.dg.layout import E_F, I_KIND0  # noqa: E402
from tether_sim.solvers.dg.stepper import dg_advance, dg_evaluate, fill_end_kinematics  # noqa: E402
from tether_sim.solvers.dg.workspace import (  # noqa: E402
    X_BC, X_BP, X_BS, X_BS0, X_D, X_DBS, X_DRA, X_DU, X_ENDF, X_FDAMP, X_FL, X_H, X_IPRM_STEP, X_IQ, X_LF,
    X_PJ, X_PRM_STEP, X_RA, X_RA0, X_RS, X_TAB_EPS, X_TAB_T, X_TMP, X_TR, X_TRC, X_U, X_U0, X_V, X_VBC, X_WM, X_WQ,
    X_CX, X_CY, X_CZ, bind,
)

# not cached on disk: numba keys a cache on this file alone, and the wrappers inline the package's kernels
jit = njit(**dict(OPTIONS, cache=False), _nrt=False)


@jit
def p_empty(F, I, S, t, dt):
    return 0


@jit
def p_substep(F, I, S, t, dt):
    dg_advance(1, t, dt, False, F, I, S)
    return 0


@jit
def p_rhs(F, I, S, t, dt):
    A = bind(F, I, S)
    dg_evaluate(t, A, A[X_PRM_STEP], A[X_IPRM_STEP], A[X_FDAMP], False, True)
    return 0


@jit
def p_end_kinematics(F, I, S, t, dt):
    A = bind(F, I, S)
    fill_end_kinematics(A[X_BC], A[X_IPRM_STEP], t, A[X_VBC], A[X_BS], A[X_BP])
    return 0


@jit
def p_tension_scalar(F, I, S, t, dt):
    A = bind(F, I, S)
    KR.tension_scalar(A[X_U], A[X_PRM_STEP], A[X_IPRM_STEP], A[X_H], A[X_V], A[X_PJ], A[X_D], A[X_LF], A[X_TR],
                      A[X_TAB_EPS], A[X_TAB_T], A[X_BC], A[X_VBC], A[X_WQ], A[X_WM], A[X_TRC], A[X_FL], A[X_DU])
    return 0


@jit
def p_internal_forces(F, I, S, t, dt):
    A = bind(F, I, S)
    KR.internal_forces(A[X_U], A[X_PRM_STEP], A[X_IPRM_STEP], A[X_H], A[X_V], A[X_PJ], A[X_D], A[X_LF], A[X_TR],
                       A[X_TAB_EPS], A[X_TAB_T], A[X_BC], A[X_VBC], A[X_WQ], A[X_WM], A[X_TRC], A[X_FL], A[X_DU],
                       A[X_ENDF], A[X_TMP])
    return 0


@jit
def p_momentum_rate(F, I, S, t, dt):
    A = bind(F, I, S)
    KR.momentum_rate(A[X_U], A[X_RA], A[X_PRM_STEP], A[X_IPRM_STEP], A[X_H], A[X_V], A[X_PJ], A[X_D], A[X_LF],
                     A[X_IQ], A[X_CZ], A[X_CX], A[X_CY], A[X_WQ], A[X_WM], A[X_TRC], A[X_FL], A[X_RS], A[X_TMP],
                     A[X_DU])
    return 0


@jit
def p_bodies(F, I, S, t, dt):
    A = bind(F, I, S)
    iprm, bs, bp, endf, dbs, tmp = A[X_IPRM_STEP], A[X_BS], A[X_BP], A[X_ENDF], A[X_DBS], A[X_TMP]
    for end in range(2):
        if has_body(iprm[I_KIND0 + end]):
            uc = tmp[12:15]
            uc[0] = 0.0
            uc[1] = 0.0
            uc[2] = 0.0
            body_derivatives(bs[end], bp[end], endf[end, E_F:E_F + 3], uc, dbs[end])
    return 0


@jit
def p_stage_update(F, I, S, t, dt):
    A = bind(F, I, S)
    U, U0, dU, ra, ra0, dra, bs, bs0, dbs = (A[X_U], A[X_U0], A[X_DU], A[X_RA], A[X_RA0], A[X_DRA], A[X_BS],
                                             A[X_BS0], A[X_DBS])
    nu = U.size
    Uf = U.reshape(nu)
    U0f = U0.reshape(nu)
    dUf = dU.reshape(nu)
    a, b = 0.75, 0.25
    for i in range(nu):
        Uf[i] = a * U0f[i] + b * (Uf[i] + 0.0 * dUf[i])
    for c in range(3):
        ra[c] = a * ra0[c] + b * (ra[c] + 0.0 * dra[c])
    for end in range(2):
        for c in range(bs.shape[1]):
            bs[end, c] = a * bs0[end, c] + b * (bs[end, c] + 0.0 * dbs[end, c])
    return 0


PARTS = dict(empty=p_empty, substep=p_substep, rhs=p_rhs, end_kinematics=p_end_kinematics,
             tension_scalar=p_tension_scalar, internal_forces=p_internal_forces, momentum_rate=p_momentum_rate,
             bodies=p_bodies, stage_update=p_stage_update)


def sized_parts(nm, nq):
    """Steps 1-3 and step 5 at fixed sizes (kernels.SIZED: what the stepper calls at this mesh), as parts."""
    ts, mr = getattr(KR, f"tension_scalar_{nm}_{nq}"), getattr(KR, f"momentum_rate_{nm}_{nq}")

    @jit
    def p_ts(F, I, S, t, dt):
        A = bind(F, I, S)
        ts(A[X_U], A[X_PRM_STEP], A[X_IPRM_STEP], A[X_H], A[X_V], A[X_PJ], A[X_D], A[X_LF], A[X_TR], A[X_TAB_EPS],
           A[X_TAB_T], A[X_BC], A[X_VBC], A[X_WQ], A[X_WM], A[X_TRC], A[X_FL], A[X_DU])
        return 0

    @jit
    def p_mr(F, I, S, t, dt):
        A = bind(F, I, S)
        mr(A[X_U], A[X_RA], A[X_PRM_STEP], A[X_IPRM_STEP], A[X_H], A[X_V], A[X_PJ], A[X_D], A[X_LF], A[X_IQ],
           A[X_CZ], A[X_CX], A[X_CY], A[X_WQ], A[X_WM], A[X_TRC], A[X_FL], A[X_RS], A[X_TMP], A[X_DU])
        return 0

    return {f"tension_scalar_{nm}_{nq}": p_ts, f"momentum_rate_{nm}_{nq}": p_mr}


def main(argv=None):
    args = tick_parser(__doc__.split("\n")[0]).parse_args(argv)
    cfg, s = warmed_solver(args.params, args.ei, args.warm)
    t = s.time
    dt = s._substep()
    parts = dict(PARTS)
    nm, nq = s.ws.V.shape[1], s.ws.V.shape[0]
    if (nm, nq) in KR.SIZED:
        parts.update(sized_parts(nm, nq))
    arenas = {name: (s.ws.F.copy(), s.ws.I.copy()) for name in parts}
    S = s.ws.spec
    clock = {name: t for name in parts}

    def timed(name, calls):
        fn = parts[name]
        F, I = arenas[name]
        tt = clock[name]
        step = dt if name == "substep" else 0.0  # (the substep moves its copy on; the bc segment is held)
        c = time.thread_time()
        for _ in range(calls):
            fn(F, I, S, tt, dt)
            tt += step
        el = (time.thread_time() - c) / calls
        clock[name] = tt
        return el

    best = {name: np.inf for name in parts}
    names = list(parts)
    for r in range(args.repeat + 2):  # two rounds to compile and warm, then timed
        for name in (names if r % 2 == 0 else names[::-1]):
            v = timed(name, args.calls)
            if r >= 2:
                best[name] = min(best[name], v)
    print(f"{args.params}: N = {s.N}, P = {s.P}, Q = {s.ws.V.shape[0]}, EI = {cfg.cable.EI:g}, substep "
          f"{dt * 1e3:.3f} ms; us per call, min of {args.repeat} x {args.calls}, load {os.getloadavg()[0]:.1f}")
    empty = best["empty"]
    print(f"  {'empty (the call)':24s} {1e6 * empty:7.3f}")
    for name in names:
        if name != "empty":
            print(f"  {name:24s} {1e6 * (best[name] - empty):7.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
