"""The compiled substep loop: SSP-RK3 [PE2020 Eq. 31-33] over the DG state, the position anchor and
rigid bodies at "body" ends (Table 1 last row: v_hat = v_RB at P, the body feels -n T_hat at P),
with the per-substep end-tension ring buffer. The loop itself allocates nothing.

With ``dg.damping: implicit`` the loop is the Strang splitting D(dt/2) E(dt) D(dt/2) (consecutive
half steps merged into one D(dt)): E is the SSP-RK3 step of the right-hand side without the
damping terms (the caller passes prm/iprm with zeta = zeta_b = 0), D the implicit damping step of
``implicit_damping.py``. The damping end forces of the latest D (fdamp) are added to the end loads
of every E stage (bodies feel them; the recorded end tension includes them).
"""

import math

from tether_sim.numerics.jit import jit
from tether_sim.physics.bodies import body_attachment_kinematics, body_derivatives
from tether_sim.physics.hydrodynamics import current_at
from tether_sim.solvers.dg.implicit_damping import MODE_EXPLICIT, damping_step
from tether_sim.solvers.dg.kernels import dg_rhs, hermite_end
from tether_sim.solvers.dg.layout import E_F, E_T, I_ANCHOR, I_CURRENT, I_KIND0, K_BODY, K_FORCE, K_FREE, P_RELAX

STATUS_OK = 0
STATUS_DIVERGED = 1


@jit
def fill_end_kinematics(bc, iprm, t, vbc, bs, bp):
    """vbc[end] = (position, velocity) of every kinematic end at time t (Hermite segment or body P)."""
    for end in range(2):
        kind = iprm[I_KIND0 + end]
        if kind == K_BODY:
            body_attachment_kinematics(bs[end], bp[end], vbc[end, 0:3], vbc[end, 3:6])
        elif kind != K_FREE and kind != K_FORCE:
            hermite_end(bc, end, t, vbc[end])


@jit
def dg_evaluate(t, U, ra, prm, iprm, h, V, Pj, D, Lf, Tr, Iq, tab_eps, tab_T, cz, cx, cy, bc, vbc,
                wq, wm, tr, fl, rs, tmp, dU, dra, endf, bs, bp, dbs, fdamp):
    """One right-hand-side evaluation at time t (cable and bodies; also used for outputs).

    fdamp (2, 4): end forces (3) and tensions of implicitly treated damping, added to endf (zeros
    in explicit mode)."""
    fill_end_kinematics(bc, iprm, t, vbc, bs, bp)
    dg_rhs(U, ra, prm, iprm, h, V, Pj, D, Lf, Tr, Iq, tab_eps, tab_T, cz, cx, cy, bc, vbc,
           wq, wm, tr, fl, rs, tmp, dU, dra, endf)
    for end in range(2):
        for c in range(3):
            endf[end, E_F + c] += fdamp[end, c]
        endf[end, E_T] += fdamp[end, 3]
    for end in range(2):
        if iprm[I_KIND0 + end] == K_BODY:
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
def dg_advance(nsteps, t0, dt, U, ra, prm, iprm, h, V, Pj, D, Lf, Tr, Iq, tab_eps, tab_T, cz, cx, cy,
               bc, vbc, wq, wm, tr, fl, rs, tmp, dU, dra, endf, bs, bp, dbs, bs0, U0, ra0, buf, cnt, out,
               idp, dprm, blk, bvec, wp, wd, band, vec, dtmp, fdamp):
    """Take nsteps SSP-RK3 substeps of size dt from t0. out[0] = steps done, out[1] = status.

    The end tensions at the start of every substep (from the first stage, no extra work) go into
    the ring buffer buf (cap, 3) = (t, T_ship, T_vehicle); cnt[0] counts entries ever written.
    idp ... fdamp: arrays of implicit_damping.DampingWork; idp[0] = 0 (explicit) skips the splitting.
    """
    implicit = idp[0] != MODE_EXPLICIT
    if implicit:
        fill_end_kinematics(bc, iprm, t0, vbc, bs, bp)
        damping_step(0.5 * dt, U, vbc, idp, dprm, blk, bvec, V, Pj, Tr, wp, wd, band, vec, dtmp, fdamp)
    cap = buf.shape[0]
    N, nm, nv = U.shape
    anchor = iprm[I_ANCHOR]
    kind_a = iprm[I_KIND0 + anchor]
    kinematic_anchor = kind_a != K_FREE and kind_a != K_FORCE
    out[0] = 0.0
    out[1] = STATUS_OK
    for n in range(nsteps):
        t = t0 + n * dt
        for e in range(N):
            for k in range(nm):
                for c in range(nv):
                    U0[e, k, c] = U[e, k, c]
        for c in range(3):
            ra0[c] = ra[c]
        for end in range(2):
            for c in range(bs.shape[1]):
                bs0[end, c] = bs[end, c]
        for stage in range(3):
            if stage == 0:
                a, b, ts = 0.0, 1.0, t
            elif stage == 1:
                a, b, ts = 0.75, 0.25, t + dt
            else:
                a, b, ts = 1.0 / 3.0, 2.0 / 3.0, t + 0.5 * dt
            dg_evaluate(ts, U, ra, prm, iprm, h, V, Pj, D, Lf, Tr, Iq, tab_eps, tab_T, cz, cx, cy, bc,
                        vbc, wq, wm, tr, fl, rs, tmp, dU, dra, endf, bs, bp, dbs, fdamp)
            if stage == 0:
                slot = cnt[0] % cap
                buf[slot, 0] = t
                buf[slot, 1] = endf[0, E_T]
                buf[slot, 2] = endf[1, E_T]
                cnt[0] += 1
            for e in range(N):
                for k in range(nm):
                    for c in range(nv):
                        U[e, k, c] = a * U0[e, k, c] + b * (U[e, k, c] + dt * dU[e, k, c])
            for c in range(3):
                ra[c] = a * ra0[c] + b * (ra[c] + dt * dra[c])
            for end in range(2):
                if iprm[I_KIND0 + end] == K_BODY:
                    for c in range(bs.shape[1]):
                        bs[end, c] = a * bs0[end, c] + b * (bs[end, c] + dt * dbs[end, c])
        t_new = t0 + (n + 1) * dt
        if kinematic_anchor:
            fill_end_kinematics(bc, iprm, t_new, vbc, bs, bp)
            for c in range(3):
                ra[c] = vbc[anchor, c]
        if implicit:
            fill_end_kinematics(bc, iprm, t_new, vbc, bs, bp)
            damping_step(dt if n < nsteps - 1 else 0.5 * dt, U, vbc, idp, dprm, blk, bvec, V, Pj, Tr, wp, wd,
                         band, vec, dtmp, fdamp)
        s = 0.0
        for e in range(N):
            for k in range(nm):
                for c in range(nv):
                    s += abs(U[e, k, c])
        for end in range(2):
            for c in range(bs.shape[1]):
                s += abs(bs[end, c])
        if not math.isfinite(s):
            out[1] = STATUS_DIVERGED
            return
        out[0] = n + 1
