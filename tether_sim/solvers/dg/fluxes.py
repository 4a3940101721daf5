"""Numerical fluxes at the element interfaces of the DG cable [PE2020 Eq. 24-25, Table 1] and the
end loads they give (boundary rules: kernels.py module docstring)."""

import math

from tether_sim.numerics.jit import jit, jit_inline
from tether_sim.physics.end_conditions import is_kinematic
from tether_sim.solvers.dg.layout import (
    E_F, E_M, E_T, E_VHAT, F_MS, F_NU, F_Q, F_V, I_AXDAMP, I_KIND0, I_KIND1, I_N, P_GAMMA0, P_QPEN,
    P_QPENT, T_LAM, T_Q, T_TE, T_TS, T_V, W_TE, W_TS,
)


@jit_inline
def interface_fluxes(fl, tr, N, c_fl, c_u, c_f, scale_f, penalty):
    """Interior Lax-Friedrichs fluxes F_hat = (F_L + F_R)/2 + penalty lambda/2 (u_R - u_L) [Eq. 24]."""
    for k in range(1, N):
        lam = penalty * max(tr[k - 1, 1, T_LAM], tr[k, 0, T_LAM])
        for c in range(3):
            fl[k, c_fl + c] = 0.5 * scale_f * (tr[k - 1, 1, c_f + c] + tr[k, 0, c_f + c]) \
                + 0.5 * lam * (tr[k, 0, c_u + c] - tr[k - 1, 1, c_u + c])


@jit_inline
def velocity_fluxes(prm, iprm, vbc, tr, fl):
    """Fluxes of F_q = v / gamma0 [Eq. 24] and, with damping, the central fluxes of the
    strain-rate gradient (an LDG auxiliary variable, module docstring) at every interface."""
    N = iprm[I_N]
    ig0 = 1.0 / prm[P_GAMMA0]
    k0 = iprm[I_KIND0]
    k1 = iprm[I_KIND1]
    interface_fluxes(fl, tr, N, F_Q, T_Q, T_V, ig0, prm[P_QPEN])
    for c in range(3):
        fl[0, F_Q + c] = tr[0, 0, T_V + c] * ig0 if not is_kinematic(k0) else vbc[0, 3 + c]
        fl[N, F_Q + c] = tr[N - 1, 1, T_V + c] * ig0 if not is_kinematic(k1) else vbc[1, 3 + c]
    if iprm[I_AXDAMP] != 0:
        for k in range(1, N):
            for c in range(3):
                fl[k, F_NU + c] = 0.5 * (tr[k - 1, 1, T_V + c] + tr[k, 0, T_V + c]) * ig0
        for c in range(3):
            fl[0, F_NU + c] = fl[0, F_Q + c]
            fl[N, F_NU + c] = fl[N, F_Q + c]


@jit
def tension_jump_penalty(prm, iprm, h, Pj, Tr, Lf, wq, tr, fl, dU):
    """Penalty of the q equation on the jump of the projected elastic tension vector
    (dg.q_penalty_jump = tension, docs/dg_solver.md "q-equation penalty"):

        F_hat_q += a [Pi T_el],   a = q_penalty / (2 gamma0 lambda),   lambda = max of the two traces

    added to the interface flux and lifted into dq/dt (dU[..., 0:3], already holding the central
    or Eq. 24 part). T_el = T(eps) i without damping and bending (wq[..., W_TE]). The energy
    rate of the interface term is -a |[Pi T_el]|^2 <= 0 for any law and geometry (the energy
    tests dq/dt with Pi T_el), where Eq. 24's lambda/2 [q] gives -lambda/2 [q].[Pi T_el], which is
    indefinite when EA/T is large. For a straight cable under a linear law [Pi T_el] = EA [q]
    and the two coincide (the exact upwind flux of the axial waves).
    """
    N = iprm[I_N]
    nm = Pj.shape[0]
    nq = Pj.shape[1]
    for e in range(N):
        for side in range(2):
            s0 = 0.0
            s1 = 0.0
            s2 = 0.0
            for j in range(nq):
                a = 0.0
                for k in range(nm):
                    a += Tr[side, k] * Pj[k, j]
                s0 += a * wq[e, j, W_TE]
                s1 += a * wq[e, j, W_TE + 1]
                s2 += a * wq[e, j, W_TE + 2]
            tr[e, side, T_TE] = s0
            tr[e, side, T_TE + 1] = s1
            tr[e, side, T_TE + 2] = s2
    for k in range(1, N):
        lam = max(tr[k - 1, 1, T_LAM], tr[k, 0, T_LAM])
        if lam <= 0.0:
            continue
        a = 0.5 * prm[P_QPENT] / (prm[P_GAMMA0] * lam)
        hl = 1.0 / h[k - 1]
        hr = 1.0 / h[k]
        for c in range(3):
            p = a * (tr[k, 0, T_TE + c] - tr[k - 1, 1, T_TE + c])
            fl[k, F_Q + c] += p
            for l in range(nm):
                dU[k - 1, l, c] += hl * Lf[1, l] * p
                dU[k, l, c] -= hr * Lf[0, l] * p


@jit_inline
def shear_traces(Pj, Tr, wq, tr, e, side):
    """tr[e, side, T_TS]: the trace of the L2 projection of the bending shear W_TS of element e."""
    nm = Pj.shape[0]
    nq = Pj.shape[1]
    s0 = 0.0
    s1 = 0.0
    s2 = 0.0
    for k in range(nm):
        a0 = 0.0
        a1 = 0.0
        a2 = 0.0
        for j in range(nq):
            p = Pj[k, j]
            a0 += p * wq[e, j, W_TS]
            a1 += p * wq[e, j, W_TS + 1]
            a2 += p * wq[e, j, W_TS + 2]
        t = Tr[side, k]
        s0 += t * a0
        s1 += t * a1
        s2 += t * a2
    tr[e, side, T_TS] = s0
    tr[e, side, T_TS + 1] = s1
    tr[e, side, T_TS + 2] = s2


@jit_inline
def clip_compression(fl, tr, k, e, side, pc, shear):
    """Clip the axial part of the boundary flux T_hat at -pc (laws without compression; pc the element's
    compression cap, physics/constitutive.py: 0 without bending).

    The Riemann solution of a cable that cannot push has T* >= 0: a boundary moving into the cable
    faster than the upwind term allows produces slack, not compression; with bending the cable pushes
    up to the Euler load of the mesh's shortest wave, as inside the cable. shear (a cable with bending):
    the clip acts on the flux without the bending shear trace tr[e, side, T_TS] (shear_traces), which a
    moment-free end transmits whole: the law bounds the axial tension, not the shear, and a clip of a
    shear component is work done at the end on the cable with no sign (docs/dg_solver.md, "Slack with
    bending").
    """
    i0, i1, i2, ok = trace_tangent(tr, e, side)
    if not ok:
        return
    if not shear:
        fl[k, F_V], fl[k, F_V + 1], fl[k, F_V + 2] = axial_clip(fl[k, F_V], fl[k, F_V + 1], fl[k, F_V + 2],
                                                                i0, i1, i2, pc)
        return
    s0 = tr[e, side, T_TS]
    s1 = tr[e, side, T_TS + 1]
    s2 = tr[e, side, T_TS + 2]
    t0, t1, t2 = axial_clip(fl[k, F_V] - s0, fl[k, F_V + 1] - s1, fl[k, F_V + 2] - s2, i0, i1, i2, pc)
    fl[k, F_V] = t0 + s0
    fl[k, F_V + 1] = t1 + s1
    fl[k, F_V + 2] = t2 + s2


@jit_inline
def trace_tangent(tr, e, side):
    """(i = q / |q| of element e's trace at side, whether |q| > 1e-300): the direction of a boundary flux's
    axial part."""
    return unit_tangent(tr[e, side, T_Q], tr[e, side, T_Q + 1], tr[e, side, T_Q + 2])


@jit_inline
def unit_tangent(q0, q1, q2):
    """(q / |q|, whether |q| > 1e-300): the unit tangent of a trace q, the direction in which a law without
    compression clips an end's axial flux (here and in the implicit damping's released ends)."""
    lq = math.sqrt(q0 * q0 + q1 * q1 + q2 * q2)
    if lq <= 1e-300:
        return 0.0, 0.0, 0.0, False
    return q0 / lq, q1 / lq, q2 / lq, True


@jit_inline
def axial_clip(t0, t1, t2, i0, i1, i2, pc):
    """The vector t with its component along the unit vector i raised to -pc when below (a cable that
    cannot push beyond its compression cap pc): t - min(t.i + pc, 0) i."""
    a = t0 * i0 + t1 * i1 + t2 * i2
    if a < -pc:
        d = a + pc
        t0 -= d * i0
        t1 -= d * i1
        t2 -= d * i2
    return t0, t1, t2


@jit_inline
def end_outputs(N, tr, fl, endf, k0, k1, bc):
    """Force and moment by the cable on each end (-n T_hat, -n M_hat), axial end tension, v_hat."""
    for end in range(2):
        k = end * N
        e = end * (N - 1)
        side = end
        sgn = 1.0 if end == 0 else -1.0  # -n
        q0 = tr[e, side, T_Q]
        q1 = tr[e, side, T_Q + 1]
        q2 = tr[e, side, T_Q + 2]
        lq = math.sqrt(q0 * q0 + q1 * q1 + q2 * q2)
        il = 1.0 / lq if lq > 1e-300 else 0.0
        endf[end, E_T] = (fl[k, F_V] * q0 + fl[k, F_V + 1] * q1 + fl[k, F_V + 2] * q2) * il
        for c in range(3):
            endf[end, E_F + c] = sgn * fl[k, F_V + c]
            endf[end, E_M + c] = sgn * fl[k, F_MS + c]
            endf[end, E_VHAT + c] = fl[k, F_Q + c]
