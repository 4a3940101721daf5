"""One compiled call per advance_to: driven-end motion, the substep loop, end bookkeeping, outputs.

``dg_tick`` does everything ``DGCableSolver.advance_to`` needs between two output times, with no
Python per substep and only the call itself per tick:

1. the Hermite segment of every driven end (kind ``prescribed``) from its state at t0 to the
   target of ``set_end_motion`` at t1 (no target: it keeps its velocity);
2. the stepper's parameters (with ``dg.damping: implicit`` the damping is zeroed in the copy the
   explicit stages see, implicit_damping.py);
3. the substeps (stepper.dg_advance: SSP-RK3, bodies, ring buffer of end tensions);
4. the driven ends' state at t1 and the end data held there for the outputs;
5. on request, the evaluation the outputs read (sampling.evaluate_outputs), so that state(),
   end_forces() and body_state() after the tick need no further right-hand side.

**The output evaluation is the next tick's first stage.** It is kernels.internal_forces at the
state reached, and the next tick's first stage starts with internal_forces at the same state and
time. When every input of internal_forces is what the output evaluation used -- U, the parameters
(prm, iprm; prm's stage time aside, which only the momentum rate reads), the element sizes h, the end
data bc and the end kinematics vbc at t0, all compared bit for bit against the copy kept in the
``snap`` slots -- and nothing else has written the work arrays since (``fresh``, set by the output
evaluation and cleared by every other evaluation), that stage does the momentum rate only. Not
with implicit damping or a moving winch (their stage inputs differ from the output's). The
result is bit-identical to evaluating again (test/solvers/dg/test_first_stage_reuse.py); it
saves one of the seven internal-force evaluations of a two-substep tick. The comparisons run over flat
views without early exit (one pass the compiler vectorises) and the kept copy is made the same way.

The arrays come from the arenas of workspace.py (three array arguments per call).

``node_tick`` is what a node (or a benchmark coupled at its rate) calls once per tick: the driven
ends' new targets, ``dg_tick`` with the outputs, and the drain of the end-tension ring, in one
compiled call (solver.tick, the interface's ``tick``).
"""

import math

from tether_sim.numerics.jit import jit, jit_inline
from tether_sim.physics.end_conditions import is_driven
from tether_sim.solvers.dg.damping_layout import MODE_EXPLICIT
from tether_sim.solvers.dg.layout import B_P0, B_P1, B_T0, B_T1, B_V0, B_V1, I_KIND0, P_TIME, P_ZETA, P_ZETAB
from tether_sim.solvers.dg.sampling import evaluate_outputs
from tether_sim.solvers.dg.stepper import STATUS_OK, dg_advance, dg_evaluate, fill_end_kinematics
from tether_sim.solvers.dg.winch import winch_active, winch_finish, winch_moving
from tether_sim.solvers.dg.workspace import (
    X_BC, X_BP, X_BS, X_BUF, X_CNT, X_DRAIN, X_DRAINED, X_ENDS, X_FRESH, X_H, X_HW, X_IDP, X_IPRM, X_IPRM_STEP,
    X_NO_FDAMP, X_OUT, X_PRM, X_PRM_STEP, X_SNAP, X_SNAP_I, X_TARGET, X_U, X_VBC, _f1, _f2, bind, flat,
)

# target[end, :]: 0 = a target was set (1.0) or not (0.0), 1:4 position (m), 4:7 velocity (m/s)
TG_SET, TG_P, TG_V = 0, 1, 4
# ends[end, :]: position (m) 0:3 and velocity (m/s) 3:6 of a driven end at the solver time
EN_P, EN_V = 0, 3
# node_tick's input tin[end, :]: position (m) 0:3 and velocity (m/s) 3:6 of a driven end at t1
TI_P, TI_V = 0, 3
# node_tick's results below zero: the stepper's status s as -1 - s; a non-finite row e of tin as BAD_INPUT - e
BAD_INPUT = -10
# ship_tick's result when it did nothing and the general path (node_tick from Python) must take the tick
NOT_PLAIN = -20


@jit
def prepare_ends(bc, iprm, t0, t1, ends, target):
    """Hermite segment of every driven end from (t0, its state) to (t1, target or extrapolation)."""
    for e in range(2):
        if not is_driven(iprm[I_KIND0 + e]):
            continue
        bc[e, B_T0] = t0
        bc[e, B_T1] = t1
        for c in range(3):
            p0 = ends[e, EN_P + c]
            v0 = ends[e, EN_V + c]
            if target[e, TG_SET] != 0.0:
                p1 = target[e, TG_P + c]
                v1 = target[e, TG_V + c]
            else:  # no new input: keep the current velocity
                p1 = p0 + (t1 - t0) * v0
                v1 = v0
            bc[e, B_P0 + c] = p0
            bc[e, B_V0 + c] = v0
            bc[e, B_P1 + c] = p1
            bc[e, B_V1 + c] = v1


@jit
def hold_ends(bc, iprm, t, ends):
    """End data of driven ends held at their state at time t (what the outputs evaluate)."""
    for e in range(2):
        if is_driven(iprm[I_KIND0 + e]):
            bc[e, B_T0] = t
            bc[e, B_T1] = t
            for c in range(3):
                bc[e, B_P0 + c] = ends[e, EN_P + c]
                bc[e, B_V0 + c] = ends[e, EN_V + c]


@jit
def finish_ends(bc, iprm, t, ends, target):
    """Driven ends reached their segment's end point at t; targets are consumed."""
    for e in range(2):
        if is_driven(iprm[I_KIND0 + e]):
            for c in range(3):
                ends[e, EN_P + c] = bc[e, B_P1 + c]
                ends[e, EN_V + c] = bc[e, B_V1 + c]
            target[e, TG_SET] = 0.0
    hold_ends(bc, iprm, t, ends)


@jit
def outputs_now(F, I, S, t):
    """The evaluation the outputs read, at time t (sampling.evaluate_outputs, full parameters)."""
    A = bind(F, I, S)
    hold_ends(A[X_BC], A[X_IPRM], t, A[X_ENDS])
    _outputs_held(F, I, S, A, t)


@jit_inline
def _outputs_held(F, I, S, A, t):
    """outputs_now once the driven ends are held at t (hold_ends; dg_tick's finish_ends has done it), on views
    already bound (inlined into dg_tick; sampling.evaluate_outputs binds its own: a call passes the arenas, not
    the tuple of every view); with the explicit scheme the inputs of the evaluation are kept for its reuse
    (module docstring)."""
    prm, iprm = A[X_PRM], A[X_IPRM]
    evaluate_outputs(t, F, I, S)
    if A[X_IDP][0] == MODE_EXPLICIT:  # (implicit damping never reuses: its stages see other parameters)
        keep_inputs(flat(F, S, X_U), prm, iprm, A[X_H], flat(F, S, X_BC), flat(F, S, X_VBC), A[X_SNAP], A[X_SNAP_I])
        A[X_FRESH][0] = 1


@jit_inline
def _snap_offsets(nu, npr, nb, nv):
    """Offsets of prm, bc, vbc and h in snap, whose order is U, prm, bc, vbc, h (keep_inputs)."""
    return nu, nu + npr, nu + npr + nb, nu + npr + nb + nv


@jit_inline
def keep_inputs(Uf, prm, iprm, h, bcf, vbcf, snap, snap_i):
    """snap = (U, prm, bc, vbc, h) flattened (Uf, bcf, vbcf: the flat U, bc, vbc), snap_i = iprm: the
    inputs of internal_forces."""
    o_prm, o_bc, o_vbc, o_h = _snap_offsets(Uf.size, prm.size, bcf.size, vbcf.size)
    _copy_into(snap, 0, Uf)
    _copy_into(snap, o_prm, prm)
    _copy_into(snap, o_bc, bcf)
    _copy_into(snap, o_vbc, vbcf)
    _copy_into(snap, o_h, h)
    for i in range(iprm.size):
        snap_i[i] = iprm[i]


@jit_inline
def _copy_into(dst, k, src):
    for i in range(src.size):
        dst[k + i] = src[i]


@jit_inline
def _differs(snap, k, src, lo, hi):
    """Whether src[lo:hi] differs from snap[k + lo:k + hi]: in a number or in the sign of a zero (a NaN
    always differs: no reuse). No early exit: one pass without branches, which the compiler vectorises."""
    d = False
    for i in range(lo, hi):
        a = snap[k + i]
        b = src[i]
        d |= (a != b) | (math.copysign(1.0, a) != math.copysign(1.0, b))
    return d


@jit_inline
def _equal_at(snap, k, src, skip):
    """snap[k:k + src.size] equals src (_differs), index skip excepted (-1: none)."""
    if skip < 0:
        return not _differs(snap, k, src, 0, src.size)
    return not (_differs(snap, k, src, 0, skip) or _differs(snap, k, src, skip + 1, src.size))


@jit_inline
def same_inputs(Uf, prm, iprm, h, bcf, vbcf, snap, snap_i):
    """U, prm (its stage time P_TIME aside), iprm, bc and h are those kept by keep_inputs (flat Uf, bcf)."""
    d = False
    for i in range(iprm.size):
        d |= iprm[i] != snap_i[i]
    if d:
        return False
    o_prm, o_bc, o_vbc, o_h = _snap_offsets(Uf.size, prm.size, bcf.size, vbcf.size)
    return (_equal_at(snap, 0, Uf, -1) and _equal_at(snap, o_prm, prm, P_TIME) and _equal_at(snap, o_bc, bcf, -1)
            and _equal_at(snap, o_h, h, -1))


@jit_inline
def first_stage_reusable(prm_step, iprm_step, nu, bc, vbc, vbcf, bs, bp, t0, snap, explicit):
    """After prepare_ends and the copy of the stepper's parameters, with the kept inputs matching at
    the start of the tick (dg_tick): the kept output evaluation is the first stage's internal_forces
    when the stages' parameters and the end kinematics at t0 are those it used (module docstring).
    explicit: prm_step is the copy of prm just made, unchanged (the explicit scheme), which same_inputs
    has compared already: its comparison is not repeated (the same answer)."""
    o_prm, _, o_vbc, _ = _snap_offsets(nu, prm_step.size, bc.size, vbcf.size)
    if not explicit and not _equal_at(snap, o_prm, prm_step, P_TIME):  # the stages see prm_step
        return False
    fill_end_kinematics(bc, iprm_step, t0, vbc, bs, bp)  # what the first stage computes
    return _equal_at(snap, o_vbc, vbcf, -1)


@jit
def dg_tick(F, I, S, t0, t1, nsteps, dt, outputs):
    """nsteps substeps of dt from t0 to t1 (module docstring); returns the stepper's status."""
    A = bind(F, I, S)
    prm, iprm, ends, target = A[X_PRM], A[X_IPRM], A[X_ENDS], A[X_TARGET]
    fresh, snap = A[X_FRESH], A[X_SNAP]
    bc, vbc, prm_step, iprm_step = A[X_BC], A[X_VBC], A[X_PRM_STEP], A[X_IPRM_STEP]
    Uf, bcf, vbcf = flat(F, S, X_U), flat(F, S, X_BC), flat(F, S, X_VBC)
    # the kept evaluation counts only while the winch is still and every input is unchanged (checked
    # before prepare_ends rewrites the segment columns of bc)
    if fresh[0] != 0 and (winch_moving(prm, iprm) or winch_active(prm, iprm)
                          or not same_inputs(Uf, prm, iprm_step, A[X_H], bcf, vbcf, snap, A[X_SNAP_I])):
        fresh[0] = 0
    prepare_ends(bc, iprm, t0, t1, ends, target)
    for k in range(prm.shape[0]):
        prm_step[k] = prm[k]
    explicit = A[X_IDP][0] == MODE_EXPLICIT
    if not explicit:
        prm_step[P_ZETA] = 0.0
        prm_step[P_ZETAB] = 0.0
    winch = winch_moving(prm, iprm)
    reuse = fresh[0] != 0 and first_stage_reusable(prm_step, iprm_step, Uf.size, bc, vbc, vbcf, A[X_BS], A[X_BP], t0,
                                                   snap, explicit)
    fresh[0] = 0
    if reuse:
        fresh[1] += 1  # first stages reused (a count for tests and benchmarks)
    dg_advance(nsteps, t0, dt, reuse, F, I, S)
    status = int(A[X_OUT][1])
    if status != STATUS_OK:
        return status
    if winch:  # length, rate and element sizes at t1 back to the driver's parameters
        winch_finish(prm, prm_step, A[X_HW], A[X_H])
    finish_ends(bc, iprm, t1, ends, target)  # (holds the ends at t1: what the outputs evaluate)
    if outputs:
        _outputs_held(F, I, S, A, t1)
    return status


@jit
def evaluate_now(F, I, S, t):
    """One full right-hand-side evaluation at time t with the full parameters (solver._evaluate)."""
    A = bind(F, I, S)
    iprm = A[X_IPRM]
    A[X_FRESH][0] = 0  # the work arrays now hold this evaluation, not the kept outputs'
    hold_ends(A[X_BC], iprm, t, A[X_ENDS])
    dg_evaluate(t, A, A[X_PRM], iprm, A[X_NO_FDAMP], False, True)


@jit
def drain_now(F, I, S):
    """drain_ring on the workspace's ring (see there); binds only the four views it reads."""
    return drain_ring(_f2(F, S, X_BUF), _f1(I, S, X_CNT), _f1(I, S, X_DRAINED), _f2(F, S, X_DRAIN))


@jit
def drain_ring(buf, cnt, drained, dst):
    """Copy the ring entries written since the last drain (newest cap kept) into dst (3, cap) in
    time order; returns their number and records them as drained (drained[0])."""
    total = cnt[0]
    cap = buf.shape[0]
    first = drained[0]
    if total - cap > first:
        first = total - cap
    drained[0] = total
    n = total - first
    for k in range(n):
        slot = (first + k) % cap
        dst[0, k] = buf[slot, 0]
        dst[1, k] = buf[slot, 1]
        dst[2, k] = buf[slot, 2]
    return n


@jit
def node_tick(F, I, S, tin, ends_set, t0, t1, nsteps, dt, drain):
    """One node tick (module docstring): for every end e with bit e of ends_set, the target of
    set_end_motion from tin[e]; dg_tick(t0 -> t1, nsteps of dt) with the outputs; then, if drain,
    the ring of end tensions into the drain slot. Returns the number of drained samples (>= 0),
    -1 - status when the stepper stopped, or BAD_INPUT - e when tin[e] is not finite (nothing
    was changed then)."""
    for e in range(2):
        if ends_set >> e & 1:
            for c in range(6):
                if not math.isfinite(tin[e, c]):
                    return BAD_INPUT - e
    target = _f2(F, S, X_TARGET)
    for e in range(2):
        if ends_set >> e & 1:
            for c in range(3):
                target[e, TG_P + c] = tin[e, TI_P + c]
                target[e, TG_V + c] = tin[e, TI_V + c]
            target[e, TG_SET] = 1.0
    status = dg_tick(F, I, S, t0, t1, nsteps, dt, True)
    if status != STATUS_OK:
        return -1 - status
    if not drain:
        return 0
    return drain_now(F, I, S)


@jit
def ship_tick(F, I, S, p, v, t0, t1, step, drain):
    """node_tick of the common node tick -- the ship end given (position p, velocity v), no winch -- with
    the substeps of advance_to's rule over t1 - t0 (stepping.substeps: the same operations, so the same
    numbers) and the inputs read from p and v themselves (no copy into tin in Python). Returns
    (node_tick's result, substeps); (NOT_PLAIN, 0) without changing anything when the interval is not
    plainly > 0 or p, v are not 3 finite numbers each: the general path then takes the tick."""
    span = t1 - t0
    if not (0.0 < span < math.inf) or p.size != 3 or v.size != 3:
        return NOT_PLAIN, 0
    for c in range(3):  # (.flat: an array of any shape with 3 numbers, as numpy's copy into tin takes it)
        if not (math.isfinite(p.flat[c]) and math.isfinite(v.flat[c])):
            return NOT_PLAIN, 0
    n = max(1, math.ceil(span / step * (1.0 - 1e-12)))
    target = _f2(F, S, X_TARGET)
    for c in range(3):
        target[0, TG_P + c] = p.flat[c]
        target[0, TG_V + c] = v.flat[c]
    target[0, TG_SET] = 1.0
    status = dg_tick(F, I, S, t0, t1, n, span / n, True)
    if status != STATUS_OK:
        return -1 - status, n
    if not drain:
        return 0, n
    return drain_now(F, I, S), n
