"""The compiled substep loop: SSP-RK3 [PE2020 Eq. 31-33] over the DG state, the position anchor and
rigid bodies at "body" ends (Table 1 last row: v_hat = v_RB at P, the body feels -n T_hat at P),
with the per-substep end-tension ring buffer. The loop itself allocates nothing.

Bending multirate (iprm[I_BMR_K] = K > 1, timestep.bending_multirate_steps): the nested LDG of the
bending shear T_s (ldg.py, the costliest part of a right-hand side with bending) runs at stage 0 of the
substeps 0, K, 2K, ... (counted across calls, below), whose T_s are recorded (wq W_TSH, three slots); from
the third record on, every other stage takes T_s = the quadratic through the last three records at the
stage time (kernels.held_shear_force), the rest of the right-hand side evaluated as always. On a bending
mode of frequency w that is the third-order Adams-Bashforth method on the macro step H = K dt, stable for
w H <= 0.72; K keeps w_max H <= 0.25. The records are carried to the next call (slot bmr: their count and
times, the substeps since the last, the end time and the end state U, r_a, bodies) and used there only
when that call starts where this one ended: the same time (to 1e-9 s) and bit for bit the same state.
Anything that moved the state between calls (restore, set_shape, relax, a new start) restarts the
records: the first 2K substeps after it evaluate T_s at every stage. The first stage of every call evaluates
T_s in full (as the output evaluation it may reuse did: tick.py; reuse or not, the same numbers).

With ``dg.damping: implicit`` the loop is the Strang splitting D(m dt/2) E(dt)^m D(m dt/2) over macro steps
of m substeps (idp ID_EVERY: dg.damping_substeps with axial damping only, else 1; consecutive half steps
merged into one D(m dt); the last macro step of a call is shorter when m does not divide its substeps): E is
the SSP-RK3 step of the right-hand side without the damping terms (the caller passes prm/iprm with
zeta = zeta_b = 0), D the implicit damping step of ``implicit_damping.py``. The damping end forces of the latest D (fdamp) are added to the end loads
of every E stage (bodies feel them; the recorded end tension includes them).
"""

import math

from tether_sim.numerics.integrators import SSPRK3_STAGES
from tether_sim.numerics.jit import jit, jit_inline
from tether_sim.physics.bodies import body_attachment_kinematics, body_derivatives
from tether_sim.physics.constitutive import LAW_LINEAR, compression_cap
from tether_sim.physics.end_conditions import has_body, is_kinematic
from tether_sim.physics.hydrodynamics import added_mass_rate, current_at
from tether_sim.solvers.dg.damping_layout import ID_EVERY, MODE_EXPLICIT
from tether_sim.solvers.dg.fluxes import axial_clip, trace_tangent
from tether_sim.solvers.dg.implicit_damping import damping_step
from tether_sim.solvers.dg.kernels import dg_rhs, hermite_end
from tether_sim.solvers.dg.layout import (
    E_F, E_T, F_V, I_ANCHOR, I_BENDING, I_BMR_K, I_CURRENT, I_KIND0, I_LAW, I_N, I_P, I_SURFACE, P_BMR, P_BMR_W,
    P_EIC, P_GAMMA0, P_LAMBDA_BC, P_MN, P_MT, P_RELAX, P_TIME, P_WL, T_LAM, T_TS, T_TV, T_V, W_I, W_TS, W_TSH, W_WET,
)
from tether_sim.solvers.dg.workspace import (
    X_BAND, X_BC, X_BLK, X_BMR, X_BP, X_BS, X_BS0, X_BUF, X_BVEC, X_CNT, X_CX, X_CY, X_CZ, X_D, X_DBS, X_DPRM, X_DRA, X_DTMP,
    X_DWOOD, X_DU, X_ENDF, X_FDAMP, X_FL, X_H, X_HW, X_IDP, X_IPRM_STEP, X_IQ, X_LF, X_OUT, X_PJ, X_PRM_STEP, X_RA, X_RA0, X_RS,
    X_TAB_EPS, X_TAB_T, X_TMP, X_TR, X_TRC, X_U, X_U0, X_V, X_VBC, X_VEC, X_WD, X_WM, X_WP, X_WQ, bind,
)
from tether_sim.solvers.dg.winch import (
    winch_active, winch_end_velocity, winch_length, winch_moving, winch_stage, winch_transport, winch_update,
)

STATUS_OK = 0
STATUS_DIVERGED = 1

# slot bmr (bending multirate records carried between calls; module docstring)
BMR_N = 0  # records made since the last restart
BMR_R = 1  # times of record slots 0, 1, 2
BMR_DUE = 4  # substeps since the last record
BMR_T = 5  # end time of the last call
BMR_OK = 6  # 1: the carried records belong to the state saved at BMR_STATE
BMR_STATE = 7  # U (flat), r_a (3), body states (2 x 13) at the end of the last call


@jit_inline
def fill_end_kinematics(bc, iprm, t, vbc, bs, bp):
    """vbc[end] = (position, velocity) of every kinematic end at time t (Hermite segment or body P)."""
    for end in range(2):
        kind = iprm[I_KIND0 + end]
        if has_body(kind):
            body_attachment_kinematics(bs[end], bp[end], vbc[end, 0:3], vbc[end, 3:6])
        elif is_kinematic(kind):
            hermite_end(bc, end, t, vbc[end])


@jit_inline
def dg_evaluate(t, A, prm, iprm, fdamp, implicit, internal=True):
    """One right-hand-side evaluation at time t (cable and bodies; also used for outputs) on the
    workspace A (workspace.bind) with the parameters prm, iprm (the stepper's or the full ones).

    implicit: the damping is integrated separately (dg.damping = implicit); fdamp (2, 4) holds its
    end forces (3) and tensions, added to endf, and the no-compression clip of velocity-end
    fluxes is applied to the sum (clip_end_fluxes).
    internal = False: the work arrays already hold kernels.internal_forces of exactly these inputs
    (the output evaluation reused as a tick's first stage, tick.py); only the momentum rate is done."""
    U, ra, h, bc, vbc, bs, bp = A[X_U], A[X_RA], A[X_H], A[X_BC], A[X_VBC], A[X_BS], A[X_BP]
    V, Pj, Lf, Tr, tmp, cz, cx, cy = A[X_V], A[X_PJ], A[X_LF], A[X_TR], A[X_TMP], A[X_CZ], A[X_CX], A[X_CY]
    wq, tr, fl, dU, dra, endf, dbs = A[X_WQ], A[X_TRC], A[X_FL], A[X_DU], A[X_DRA], A[X_ENDF], A[X_DBS]
    fill_end_kinematics(bc, iprm, t, vbc, bs, bp)
    prm[P_TIME] = t  # the wave field is evaluated at the stage time (kernels.momentum_rate)
    winch = winch_active(prm, iprm)
    if winch:  # the material at the sheave moves along the tangent (winch.py)
        winch_end_velocity(U, prm, iprm, Tr, vbc)
    dg_rhs(U, ra, prm, iprm, h, V, Pj, A[X_D], Lf, Tr, A[X_IQ], A[X_TAB_EPS], A[X_TAB_T], cz, cx, cy, bc, vbc,
           wq, A[X_WM], tr, fl, A[X_RS], tmp, dU, dra, endf, internal)
    if winch:  # transport of the moving mapping onto the elements
        winch_transport(U, prm, iprm, h, Lf, tr, vbc, dU, dra)
    if implicit:
        for end in range(2):
            for c in range(3):
                endf[end, E_F + c] += fdamp[end, c]
            endf[end, E_T] += fdamp[end, 3]
        if iprm[I_LAW] != LAW_LINEAR:
            clip_end_fluxes(prm, iprm, h, V, Pj, Lf, vbc, wq, tr, fl, dU, endf, fdamp)
    for end in range(2):
        if has_body(iprm[I_KIND0 + end]):
            uc = tmp[12:15]
            if iprm[I_CURRENT] != 0:
                current_at(bs[end, 2], cz, cx, cy, uc)
            else:
                uc[0] = 0.0
                uc[1] = 0.0
                uc[2] = 0.0
            body_derivatives(bs[end], bp[end], endf[end, E_F:E_F + 3], uc, dbs[end])
            relax = prm[P_RELAX]
            if relax > 0.0:
                for c in range(7, 13):
                    dbs[end, c] -= relax * bs[end, c]


@jit
def clip_end_fluxes(prm, iprm, h, V, Pj, Lf, vbc, wq, tr, fl, dU, endf, fdamp):
    """Velocity-end flux of a law without compression with implicit damping (fluxes.clip_compression's
    axial clip, fluxes.axial_clip, applied to the sum of the fluxes).

    The explicit scheme clips the axial part of T_hat = T+ + T_d+ + n lambda (gamma0 v_BC - v+) at 0.
    With the damping split off, dg_rhs clipped only the elastic part and the damping step applied
    its own trace T_d+ (fdamp): the difference Delta = clip(sum) - clip(elastic) - T_d+ is added
    here to the end element's dv/dt (lift of Delta through the added mass) and to the end loads.
    The unclipped elastic flux is rebuilt from the traces exactly as dg_rhs builds it."""
    N = iprm[I_N]
    g0 = prm[P_GAMMA0]
    nq = V.shape[0]
    nm = V.shape[1]
    for end in range(2):
        if not is_kinematic(iprm[I_KIND0 + end]):
            continue
        e = end * (N - 1)
        k = end * N
        sgn = 1.0 if end == 0 else -1.0  # -n
        lam = max(tr[e, end, T_LAM], prm[P_LAMBDA_BC])
        i0, i1, i2, ok = trace_tangent(tr, e, end)
        if not ok:
            continue
        tot0 = tr[e, end, T_TV] - sgn * lam * (g0 * vbc[end, 3] - tr[e, end, T_V]) + sgn * fdamp[end, 0]
        tot1 = tr[e, end, T_TV + 1] - sgn * lam * (g0 * vbc[end, 4] - tr[e, end, T_V + 1]) + sgn * fdamp[end, 1]
        tot2 = tr[e, end, T_TV + 2] - sgn * lam * (g0 * vbc[end, 5] - tr[e, end, T_V + 2]) + sgn * fdamp[end, 2]
        pc = compression_cap(iprm[I_LAW], prm[P_EIC], iprm[I_P], h[e])
        if iprm[I_BENDING] != 0:  # the clip leaves the bending shear out (fluxes.clip_compression)
            s0 = tr[e, end, T_TS]
            s1 = tr[e, end, T_TS + 1]
            s2 = tr[e, end, T_TS + 2]
            tot0, tot1, tot2 = axial_clip(tot0 - s0, tot1 - s1, tot2 - s2, i0, i1, i2, pc)
            tot0 += s0
            tot1 += s1
            tot2 += s2
        else:
            tot0, tot1, tot2 = axial_clip(tot0, tot1, tot2, i0, i1, i2, pc)
        d0 = tot0 - fl[k, F_V] - sgn * fdamp[end, 0]
        d1 = tot1 - fl[k, F_V + 1] - sgn * fdamp[end, 1]
        d2 = tot2 - fl[k, F_V + 2] - sgn * fdamp[end, 2]
        if d0 == 0.0 and d1 == 0.0 and d2 == 0.0:
            continue
        endf[end, E_F] += sgn * d0
        endf[end, E_F + 1] += sgn * d1
        endf[end, E_F + 2] += sgn * d2
        endf[end, E_T] += d0 * i0 + d1 * i1 + d2 * i2
        # strong derivative: + (1/h) Lf[1] Delta at s = L, - (1/h) Lf[0] Delta at s = 0
        w = -sgn / h[e]
        for j in range(nq):
            lj = 0.0
            for l in range(nm):
                lj += V[j, l] * Lf[end, l]
            wet = wq[e, j, W_WET] if iprm[I_SURFACE] != 0 else 1.0  # added mass of the wetted part
            a0, a1, a2 = added_mass_rate(wq[e, j, W_I], wq[e, j, W_I + 1], wq[e, j, W_I + 2], w * lj * d0,
                                         w * lj * d1, w * lj * d2, g0, wet * prm[P_MT], wet * prm[P_MN])
            for l in range(nm):
                dU[e, l, 3] += Pj[l, j] * a0
                dU[e, l, 4] += Pj[l, j] * a1
                dU[e, l, 5] += Pj[l, j] * a2


@jit
def dg_advance(nsteps, t0, dt, reuse, F, I, S):
    """Take nsteps SSP-RK3 substeps of size dt from t0 on the workspace of the arenas F, I and the spec S
    (workspace.py; the views are bound here, so that a call passes three arrays, not the tuple of every
    view), with the stepper's parameters (slots prm_step, iprm_step). out[0] = steps done, out[1] = status.

    reuse: the first stage's internal forces are already in the work arrays (the output evaluation
    at t0 on the same inputs, checked by tick.dg_tick); that stage does the momentum rate only.

    The end tensions at the start of every substep (from the first stage, no extra work) go into
    the ring buffer buf (cap, 3) = (t, T_ship, T_vehicle); cnt[0] counts entries ever written.
    idp ... fdamp: arrays of implicit_damping.DampingWork; idp[0] = 0 (explicit) skips the splitting.
    hw: element sizes / length; while a winch moves, the stages take h = hw L and update on L u (winch.py).
    """
    A = bind(F, I, S)
    U, ra, prm, iprm, h, bc, vbc = A[X_U], A[X_RA], A[X_PRM_STEP], A[X_IPRM_STEP], A[X_H], A[X_BC], A[X_VBC]
    dU, dra, endf, bs, bp, dbs = A[X_DU], A[X_DRA], A[X_ENDF], A[X_BS], A[X_BP], A[X_DBS]
    bs0, U0, ra0, buf, cnt, out, idp, fdamp, hw = (A[X_BS0], A[X_U0], A[X_RA0], A[X_BUF], A[X_CNT], A[X_OUT],
                                                   A[X_IDP], A[X_FDAMP], A[X_HW])
    implicit = idp[0] != MODE_EXPLICIT
    winch = winch_moving(prm, iprm)
    t1 = t0 + nsteps * dt
    L_tick = prm[P_WL]
    # the RK update, copy and finiteness sum run over flat views (element-major order, as U's
    # own loops would: the same operations in the same order)
    nu = U.size
    Uf = U.reshape(nu)
    U0f = U0.reshape(nu)
    dUf = dU.reshape(nu)
    # bending multirate (module docstring): records of T_s at stage 0 of every K-th substep (slot = record
    # count mod 3, times r0..r2), carried from the last call when it ended on this state; from the third
    # record on the other stages extrapolate
    K = iprm[I_BMR_K] if iprm[I_BENDING] != 0 else 0
    wq = A[X_WQ]
    bmr = A[X_BMR]
    nrec = 0
    due = 0
    r0 = 0.0
    r1 = 0.0
    r2 = 0.0
    if K > 1 and _records_carry(bmr, t0, Uf, ra, bs):
        nrec = int(bmr[BMR_N])
        due = int(bmr[BMR_DUE])
        r0 = bmr[BMR_R]
        r1 = bmr[BMR_R + 1]
        r2 = bmr[BMR_R + 2]
    bmr[BMR_OK] = 0.0
    every = idp[ID_EVERY] if implicit else 1
    if implicit:
        fill_end_kinematics(bc, iprm, t0, vbc, bs, bp)
        _damping(0.5 * dt * max(1, min(every, nsteps)), A)
    cap = buf.shape[0]
    anchor = iprm[I_ANCHOR]
    kind_a = iprm[I_KIND0 + anchor]
    kinematic_anchor = is_kinematic(kind_a)
    out[0] = 0.0
    out[1] = STATUS_OK
    for n in range(nsteps):
        t = t0 + n * dt
        for i in range(nu):
            U0f[i] = Uf[i]
        for c in range(3):
            ra0[c] = ra[c]
        for end in range(2):
            for c in range(bs.shape[1]):
                bs0[end, c] = bs[end, c]
        Ls = prm[P_WL]
        # SSP-RK3 [PE2020 Eq. 31-33] on u = (U, ra, body states), L the right-hand side (dg_evaluate):
        #   stage 0:  u1      = u_n + dt L(u_n, t_n)                          (a, b, c) = (0, 1, 0)
        #   stage 1:  u2      = 3/4 u_n + 1/4 (u1 + dt L(u1, t_n + dt))       (3/4, 1/4, 1)
        #   stage 2:  u_{n+1} = 1/3 u_n + 2/3 (u2 + dt L(u2, t_n + dt/2))     (1/3, 2/3, 1/2)
        # i.e. u <- a u_n + b (u + dt L(u, t_n + c dt)) with (a, b, c) = SSPRK3_STAGES[stage]
        for stage in range(3):
            a, b, cs = SSPRK3_STAGES[stage]
            ts = t + cs * dt
            if winch:
                winch_stage(prm, hw, h, ts, t0, t1)
            internal = not reuse or n > 0 or stage > 0
            record = K > 1 and stage == 0 and (nrec == 0 or due >= K)
            if K > 1 and nrec >= 3 and not record and (n > 0 or stage > 0):  # a call's first stage in full
                _extrapolation_weights(prm, ts, r0, r1, r2)
            dg_evaluate(ts, A, prm, iprm, fdamp, implicit, internal)
            prm[P_BMR] = 0.0
            if record:
                slot = nrec % 3
                _record_shear(wq, slot)
                if slot == 0:
                    r0 = ts
                elif slot == 1:
                    r1 = ts
                else:
                    r2 = ts
                nrec += 1
                due = 0
            if stage == 0:
                slot = cnt[0] % cap
                buf[slot, 0] = t
                buf[slot, 1] = endf[0, E_T]
                buf[slot, 2] = endf[1, E_T]
                cnt[0] += 1
            if winch:
                L_end = winch_length(prm, L_tick, t0 + (n + 1) * dt, t0, t1) if stage == 2 else 0.0
                winch_update(a, b, dt, Ls, U, U0, dU, prm, L_end)
            else:
                for i in range(nu):
                    Uf[i] = a * U0f[i] + b * (Uf[i] + dt * dUf[i])
            for c in range(3):
                ra[c] = a * ra0[c] + b * (ra[c] + dt * dra[c])
            for end in range(2):
                if has_body(iprm[I_KIND0 + end]):
                    for c in range(bs.shape[1]):
                        bs[end, c] = a * bs0[end, c] + b * (bs[end, c] + dt * dbs[end, c])
        t_new = t0 + (n + 1) * dt
        if kinematic_anchor:
            fill_end_kinematics(bc, iprm, t_new, vbc, bs, bp)
            for c in range(3):
                ra[c] = vbc[anchor, c]
        if implicit and ((n + 1) % every == 0 or n == nsteps - 1):
            fill_end_kinematics(bc, iprm, t_new, vbc, bs, bp)
            m_this = every if (n + 1) % every == 0 else (n + 1) % every  # substeps of the macro step just ended
            m_next = min(every, nsteps - 1 - n)
            _damping(0.5 * dt * (m_this + m_next), A)
        if not _finite_state(Uf, bs):
            out[1] = STATUS_DIVERGED
            return
        out[0] = n + 1
        due += 1
    if K > 1:
        _keep_records(bmr, t1, nrec, due, r0, r1, r2, Uf, ra, bs)


@jit_inline
def _finite_state(Uf, bs):
    """Whether s = sum |U| + sum |body states|, summed in that order, is finite (the divergence check).
    Decided without the sum's chain of dependent additions when every |x| < 1e300: fewer than 1e8 such
    terms cannot overflow, so s is finite; one pass of comparisons without early exit, which the compiler
    vectorises. Otherwise (a NaN, an infinity or a huge value) the sum itself decides, as it always did."""
    big = False
    for i in range(Uf.size):
        big |= not abs(Uf[i]) < 1e300
    for end in range(2):
        for c in range(bs.shape[1]):
            big |= not abs(bs[end, c]) < 1e300
    if not big and Uf.size + bs.size < 100000000:
        return True
    s = 0.0
    for i in range(Uf.size):
        s += abs(Uf[i])
    for end in range(2):
        for c in range(bs.shape[1]):
            s += abs(bs[end, c])
    return math.isfinite(s)


@jit_inline
def _records_carry(bmr, t0, Uf, ra, bs):
    """The carried records (slot bmr) are valid for a call from t0 on this state: the last call ended at t0
    (to 1e-9 s) with bit for bit this U, r_a and body states (compared with !=, over every value without
    early exit: one pass the compiler vectorises)."""
    if bmr[BMR_OK] != 1.0 or abs(t0 - bmr[BMR_T]) > 1e-9:
        return False
    d = False
    k = BMR_STATE
    for i in range(Uf.size):
        d |= bmr[k + i] != Uf[i]
    k += Uf.size
    for c in range(3):
        d |= bmr[k + c] != ra[c]
    k += 3
    for end in range(2):
        for c in range(bs.shape[1]):
            d |= bmr[k + end * bs.shape[1] + c] != bs[end, c]
    return not d


@jit_inline
def _keep_records(bmr, t1, nrec, due, r0, r1, r2, Uf, ra, bs):
    """Save the records' bookkeeping and the end state of this call into bmr (_records_carry reads them)."""
    bmr[BMR_N] = nrec
    bmr[BMR_R] = r0
    bmr[BMR_R + 1] = r1
    bmr[BMR_R + 2] = r2
    bmr[BMR_DUE] = due
    bmr[BMR_T] = t1
    k = BMR_STATE
    for i in range(Uf.size):
        bmr[k + i] = Uf[i]
    k += Uf.size
    for c in range(3):
        bmr[k + c] = ra[c]
    k += 3
    for end in range(2):
        for c in range(bs.shape[1]):
            bmr[k + end * bs.shape[1] + c] = bs[end, c]
    bmr[BMR_OK] = 1.0


@jit_inline
def _extrapolation_weights(prm, t, r0, r1, r2):
    """prm[P_BMR_W + k]: the quadratic Lagrange weights at time t of the records at r0, r1, r2; P_BMR = 1."""
    prm[P_BMR_W] = (t - r1) * (t - r2) / ((r0 - r1) * (r0 - r2))
    prm[P_BMR_W + 1] = (t - r0) * (t - r2) / ((r1 - r0) * (r1 - r2))
    prm[P_BMR_W + 2] = (t - r0) * (t - r1) / ((r2 - r0) * (r2 - r1))
    prm[P_BMR] = 1.0


@jit_inline
def _record_shear(wq, slot):
    """Record slot (0-2) of W_TSH = the bending shear W_TS of the evaluation just made."""
    o = W_TSH + 3 * slot
    for e in range(wq.shape[0]):
        for j in range(wq.shape[1]):
            for c in range(3):
                wq[e, j, o + c] = wq[e, j, W_TS + c]


@jit_inline
def _damping(dt, A):
    """implicit_damping.damping_step of dt on the workspace's arrays (D of the splitting)."""
    damping_step(dt, A[X_U], A[X_VBC], A[X_IDP], A[X_DPRM], A[X_BLK], A[X_BVEC], A[X_V], A[X_PJ], A[X_TR],
                 A[X_TAB_EPS], A[X_TAB_T], A[X_WP], A[X_WD], A[X_BAND], A[X_VEC], A[X_DTMP], A[X_DWOOD],
                 A[X_FDAMP])
