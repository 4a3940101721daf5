"""The compiled substep loop: SSP-RK3 [PE2020 Eq. 31-33] over the DG state, the position anchor and
the end kinematics, with the per-substep end-tension ring buffer. Nothing here allocates.
"""

import math

from tether_sim.numerics.jit import jit
from tether_sim.solvers.dg.kernels import dg_rhs, hermite_end
from tether_sim.solvers.dg.layout import E_T, I_ANCHOR, I_KIND0, I_KIND1, K_FORCE, K_FREE

STATUS_OK = 0
STATUS_DIVERGED = 1


@jit
def fill_end_kinematics(bc, iprm, t, vbc):
    """vbc[end] = (position, velocity) of every kinematic end at time t (Hermite segment)."""
    for end in range(2):
        kind = iprm[I_KIND0 + end]
        if kind != K_FREE and kind != K_FORCE:
            hermite_end(bc, end, t, vbc[end])


@jit
def dg_evaluate(t, U, ra, prm, iprm, h, V, Pj, D, Lf, Tr, Iq, tab_eps, tab_T, cz, cx, cy, bc, vbc,
                wq, wm, tr, fl, rs, tmp, dU, dra, endf):
    """One right-hand-side evaluation at time t (fills the work arrays; used for outputs)."""
    fill_end_kinematics(bc, iprm, t, vbc)
    dg_rhs(U, ra, prm, iprm, h, V, Pj, D, Lf, Tr, Iq, tab_eps, tab_T, cz, cx, cy, bc, vbc,
           wq, wm, tr, fl, rs, tmp, dU, dra, endf)


@jit
def dg_advance(nsteps, t0, dt, U, ra, prm, iprm, h, V, Pj, D, Lf, Tr, Iq, tab_eps, tab_T, cz, cx, cy,
               bc, vbc, wq, wm, tr, fl, rs, tmp, dU, dra, endf, U0, ra0, buf, cnt, out):
    """Take nsteps SSP-RK3 substeps of size dt from t0. out[0] = steps done, out[1] = status.

    The end tensions at the start of every substep (from the first stage, no extra work) go into
    the ring buffer buf (cap, 3) = (t, T_ship, T_vehicle); cnt[0] counts entries ever written.
    """
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
        for stage in range(3):
            if stage == 0:
                a, b, ts = 0.0, 1.0, t
            elif stage == 1:
                a, b, ts = 0.75, 0.25, t + dt
            else:
                a, b, ts = 1.0 / 3.0, 2.0 / 3.0, t + 0.5 * dt
            dg_evaluate(ts, U, ra, prm, iprm, h, V, Pj, D, Lf, Tr, Iq, tab_eps, tab_T, cz, cx, cy, bc,
                        vbc, wq, wm, tr, fl, rs, tmp, dU, dra, endf)
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
        t_new = t0 + (n + 1) * dt
        if kinematic_anchor:
            fill_end_kinematics(bc, iprm, t_new, vbc)
            for c in range(3):
                ra[c] = vbc[anchor, c]
        s = 0.0
        for e in range(N):
            for k in range(nm):
                for c in range(nv):
                    s += abs(U[e, k, c])
        if not math.isfinite(s):
            out[1] = STATUS_DIVERGED
            return
        out[0] = n + 1
