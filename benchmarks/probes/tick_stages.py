"""The compiled node tick's fixed work split by stage: each stage of ``tick.node_tick`` beyond the substeps
called alone, in a loop of compiled calls, on a warmed solver of a live file.

Every stage is wrapped in a compiled function of (F, I, S, tin, t) that binds what the stage needs and runs
it once; its cost is the wrapper's time per call less that of an empty wrapper with the same arguments
(the call itself, also printed). ``bind`` is the views of every slot passed to an opaque compiled callee
(what dg_tick does before dg_advance). Thread CPU, min over --repeat blocks of --calls calls, the stages
interleaved block by block.

The wrappers below follow node_tick's stages in this tree; each is called on its own copy of the warmed
solver's arenas, so that no stage sees another's writes.

Usage: PYTHONPATH=. python benchmarks/probes/tick_stages.py [--params config/ropos_L1730.yaml] [--ei 2620]
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
from tether_sim.solvers.dg import tick as K  # noqa: E402
from tether_sim.solvers.dg.damping_layout import MODE_EXPLICIT  # noqa: E402
from tether_sim.solvers.dg.sampling import evaluate_outputs  # noqa: E402
from tether_sim.solvers.dg.stepper import dg_advance  # noqa: E402
from tether_sim.solvers.dg.workspace import (  # noqa: E402
    X_BC, X_BP, X_BS, X_ENDS, X_FRESH, X_H, X_IDP, X_IPRM, X_IPRM_STEP, X_PRM, X_PRM_STEP, X_SNAP, X_SNAP_I, X_TARGET, X_U,
    X_VBC, bind, flat,
)

# not cached on disk: numba keys a cache on this file alone, and the wrappers inline the package's kernels
jit = njit(**dict(OPTIONS, cache=False), _nrt=False)


@jit
def _sink(A):
    return 0


@jit
def st_empty(F, I, S, tin, t):
    return 0


@jit
def st_bind(F, I, S, tin, t):
    return _sink(bind(F, I, S))


@jit
def st_targets(F, I, S, tin, t):
    for e in range(2):
        if 1 >> e & 1:
            for c in range(6):
                if not math.isfinite(tin[e, c]):
                    return K.BAD_INPUT - e
    target = K._f2(F, S, X_TARGET)
    for c in range(3):
        target[0, K.TG_P + c] = tin[0, K.TI_P + c]
        target[0, K.TG_V + c] = tin[0, K.TI_V + c]
    target[0, K.TG_SET] = 1.0
    return 0


@jit
def st_same_inputs(F, I, S, tin, t):
    A = bind(F, I, S)
    return K.same_inputs(flat(F, S, X_U), A[X_PRM], A[X_IPRM_STEP], A[X_H], flat(F, S, X_BC), flat(F, S, X_VBC),
                         A[X_SNAP], A[X_SNAP_I])


@jit
def st_prepare_ends(F, I, S, tin, t):
    A = bind(F, I, S)
    K.prepare_ends(A[X_BC], A[X_IPRM], t, t, A[X_ENDS], A[X_TARGET])
    return 0


@jit
def st_prm_copy(F, I, S, tin, t):
    A = bind(F, I, S)
    prm, prm_step = A[X_PRM], A[X_PRM_STEP]
    for k in range(prm.shape[0]):
        prm_step[k] = prm[k]
    return 0


@jit
def st_first_stage_reusable(F, I, S, tin, t):
    A = bind(F, I, S)
    return K.first_stage_reusable(A[X_PRM_STEP], A[X_IPRM_STEP], A[X_U].size, A[X_BC], A[X_VBC], flat(F, S, X_VBC),
                                  A[X_BS], A[X_BP], t, A[X_SNAP], A[X_IDP][0] == MODE_EXPLICIT)


@jit
def st_dg_advance_0(F, I, S, tin, t):
    dg_advance(0, t, 0.0, False, F, I, S)
    return 0


@jit
def st_finish_ends(F, I, S, tin, t):
    A = bind(F, I, S)
    K.finish_ends(A[X_BC], A[X_IPRM], t, A[X_ENDS], A[X_TARGET])
    return 0


@jit
def st_output_evaluation(F, I, S, tin, t):
    evaluate_outputs(t, F, I, S)
    return 0


@jit
def st_keep_inputs(F, I, S, tin, t):
    A = bind(F, I, S)
    K.keep_inputs(flat(F, S, X_U), A[X_PRM], A[X_IPRM], A[X_H], flat(F, S, X_BC), flat(F, S, X_VBC), A[X_SNAP],
                  A[X_SNAP_I])
    A[X_FRESH][0] = 1
    return 0


@jit
def st_outputs_total(F, I, S, tin, t):
    K._outputs_held(F, I, S, bind(F, I, S), t)
    return 0


@jit
def st_drain(F, I, S, tin, t):
    return K.drain_now(F, I, S)


@jit
def st_node_tick_0(F, I, S, tin, t):
    return K.node_tick(F, I, S, tin, 1, t, t, 0, 0.0, True)


STAGES = dict(empty=st_empty, bind=st_bind, targets=st_targets, same_inputs=st_same_inputs,
              prepare_ends=st_prepare_ends, prm_copy=st_prm_copy, first_stage_reusable=st_first_stage_reusable,
              dg_advance_0_substeps=st_dg_advance_0, finish_ends=st_finish_ends,
              output_evaluation=st_output_evaluation, keep_inputs=st_keep_inputs,
              outputs_total=st_outputs_total, drain=st_drain, node_tick_0_substeps=st_node_tick_0)


def main(argv=None):
    args = tick_parser(__doc__.split("\n")[0]).parse_args(argv)
    cfg, s = warmed_solver(args.params, args.ei, args.warm)
    t = s.time
    tin = np.concatenate(motion(t)).reshape(1, 6).repeat(2, axis=0)
    stages = dict(STAGES)
    arenas = {name: (s.ws.F.copy(), s.ws.I.copy()) for name in stages}
    S = s.ws.spec

    def timed(name, calls):
        fn = stages[name]
        F, I = arenas[name]
        c = time.thread_time()
        for _ in range(calls):
            fn(F, I, S, tin, t)
        return (time.thread_time() - c) / calls

    best = {name: np.inf for name in stages}
    names = list(stages)
    for r in range(args.repeat + 2):  # two rounds to compile and warm, then timed
        for name in (names if r % 2 == 0 else names[::-1]):
            v = timed(name, args.calls)
            if r >= 2:
                best[name] = min(best[name], v)
    dt = s._substep()
    print(f"{args.params}: N = {s.N}, P = {s.P}, EI = {cfg.cable.EI:g}, {math.ceil(0.02 / dt * (1 - 1e-12))} substeps "
          f"per 50 Hz tick; us per call, min of {args.repeat} x {args.calls}, load {os.getloadavg()[0]:.1f}")
    empty = best["empty"]
    print(f"  {'empty (the call)':34s} {1e6 * empty:7.3f}")
    for name in names:
        if name != "empty":
            print(f"  {name:34s} {1e6 * (best[name] - empty):7.3f}   ({1e6 * best[name]:.3f} with the call)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
