"""Compiled right-hand side of the DG cable equations [PE2020 Eq. 10-17, 23-25] and its pieces.

Shapes and channel indices: see ``layout.py``. The right-hand side is evaluated as:

1. q, v at the Gauss points and element traces; tangent i = q / |q| and l_eps = |q|.
2. Lax-Friedrichs fluxes of F_q = v / gamma0 [Eq. 24-25]; dq/dt by the strong form [Eq. 9, 23].
3. deps/dt = i . d(v/gamma0)/ds at the Gauss points, the gradient taken with central fluxes (an
   LDG auxiliary variable: using dq/dt itself would feed the Lax-Friedrichs penalty on the jumps
   of q into zeta deps/dt, a force that does work unrelated to dissipation and destabilises
   curved damped cables); T(eps, deps/dt) [Eq. 22]; T_vec = T i (+ T_s, ldg.py).
4. T_vec projected on the modes; Lax-Friedrichs fluxes of F_v = T_vec; dT/ds by the strong form.
5. Per Gauss point: R = dT/ds + f_b + f_d + f_c, and the added-mass system solved per point
   (dv/dt = gamma0 a); projected on the modes [Eq. 4, 12-17].

Boundary fluxes (rows of Table 1): velocity ends (prescribed, fixed, clamped, body) take
v_hat = v_BC and T_hat = T+ + n lambda (gamma0 v_BC - v+); force ends (free, force) take
T_hat = n F_BC and v_hat = v+. The lambda term is the upwind (exact Riemann) correction of the
linear axial problem, which vanishes when the interior agrees with the boundary value. At the ends
lambda is the taut wave speed c even where the end is slack: with the local lambda = 0 of a slack
trace the end velocity would not be enforced in the momentum equation at all, the trace velocity
drifts from v_BC, and the jump is released as a spurious spike when the end re-tensions. For laws
without compression the axial part of a velocity end's T_hat is clipped at zero (a slack end can
be pulled taut, never pushed).
"""

import math

from tether_sim.numerics.jit import jit
from tether_sim.physics.constitutive import LAW_LINEAR, axial_tension, tension_slope
from tether_sim.physics.hydrodynamics import added_mass_rate, current_at, morison_drag
from tether_sim.physics.seabed import seabed_force
from tether_sim.solvers.dg.elementops import eval_points, eval_traces, project_points, strong_derivative
from tether_sim.solvers.dg.layout import (
    B_F, B_M, B_P0, B_P1, B_T0, B_T1, B_V0, B_V1, E_F, E_M, E_T, E_VHAT, F_MS, F_NU, F_Q, F_V,
    I_ANCHOR, I_AXDAMP, I_BENDING, I_CURRENT, I_KIND0, I_KIND1, I_LAW, I_N, I_NEEDPOS, I_SEABED, K_CLAMPED,
    K_FORCE, K_FREE, M_DT, M_NUS, M_TV, P_CCRIT, P_CDN, P_CDT, P_EA, P_FBZ, P_GAMMA0, P_HALF_RHO_D,
    P_KD, P_LAMBDA_BC, P_LAMBDA_FLOOR, P_QPEN, P_MN, P_MT, P_MU, P_RELAX, P_SBZETA, P_VMU, P_ZETA, P_ZG, T_LAM, T_Q,
    T_TV, T_V, W_ACC, W_DT, W_EDOT, W_I, W_L, W_NUS, W_Q, W_R, W_TV, W_V,
)
from tether_sim.solvers.dg.ldg import ldg_shear_force


@jit
def is_force_end(kind):
    """Free and point-force ends prescribe T_hat; all others prescribe v_hat [PE2020 Table 1]."""
    return kind == K_FREE or kind == K_FORCE


@jit
def hermite_end(bc, end, t, out):
    """Position out[0:3] and velocity out[3:6] of an end from its cubic Hermite segment."""
    t0 = bc[end, B_T0]
    t1 = bc[end, B_T1]
    if t1 > t0:
        H = t1 - t0
        x = (t - t0) / H
        x2 = x * x
        x3 = x2 * x
        h00 = 2.0 * x3 - 3.0 * x2 + 1.0
        h10 = (x3 - 2.0 * x2 + x) * H
        h01 = -2.0 * x3 + 3.0 * x2
        h11 = (x3 - x2) * H
        d00 = (6.0 * x2 - 6.0 * x) / H
        d10 = 3.0 * x2 - 4.0 * x + 1.0
        d01 = -d00
        d11 = 3.0 * x2 - 2.0 * x
        for c in range(3):
            p0 = bc[end, B_P0 + c]
            v0 = bc[end, B_V0 + c]
            p1 = bc[end, B_P1 + c]
            v1 = bc[end, B_V1 + c]
            out[c] = h00 * p0 + h10 * v0 + h01 * p1 + h11 * v1
            out[3 + c] = d00 * p0 + d10 * v0 + d01 * p1 + d11 * v1
    else:
        for c in range(3):
            out[c] = bc[end, B_P0 + c] + (t - t0) * bc[end, B_V0 + c]
            out[3 + c] = bc[end, B_V0 + c]


@jit
def local_speed(prm, law, q0, q1, q2, tab_eps, tab_T):
    """lambda = sqrt(dT/deps / gamma0) at a trace [PE2020 Eq. 25], floored by P_LAMBDA_FLOOR."""
    eps = math.sqrt(q0 * q0 + q1 * q1 + q2 * q2) - 1.0
    lam = math.sqrt(tension_slope(law, eps, prm[P_EA], tab_eps, tab_T) / prm[P_GAMMA0])
    return lam if lam > prm[P_LAMBDA_FLOOR] else prm[P_LAMBDA_FLOOR]


@jit
def interface_fluxes(fl, tr, N, c_fl, c_u, c_f, scale_f, penalty):
    """Interior Lax-Friedrichs fluxes F_hat = (F_L + F_R)/2 + penalty lambda/2 (u_R - u_L) [Eq. 24]."""
    for k in range(1, N):
        lam = penalty * max(tr[k - 1, 1, T_LAM], tr[k, 0, T_LAM])
        for c in range(3):
            fl[k, c_fl + c] = 0.5 * scale_f * (tr[k - 1, 1, c_f + c] + tr[k, 0, c_f + c]) \
                + 0.5 * lam * (tr[k, 0, c_u + c] - tr[k - 1, 1, c_u + c])


@jit
def element_positions(U, ra, h, iprm, rs):
    """Position rs[e] of the left end of every element, from the anchor ra by integrating q."""
    N = iprm[I_N]
    if iprm[I_ANCHOR] == 0:
        for c in range(3):
            acc = ra[c]
            for e in range(N):
                rs[e, c] = acc
                acc += h[e] * U[e, 0, c]
    else:
        for c in range(3):
            acc = ra[c]
            for e in range(N - 1, -1, -1):
                acc -= h[e] * U[e, 0, c]
                rs[e, c] = acc


@jit
def dg_rhs(U, ra, prm, iprm, h, V, Pj, D, Lf, Tr, Iq, tab_eps, tab_T, cz, cx, cy, bc, vbc,
           wq, wm, tr, fl, rs, tmp, dU, dra, endf):
    """du/dt of the DG cable [PE2020 Eq. 23] into dU; anchor velocity into dra; end loads into endf."""
    N = iprm[I_N]
    nq = V.shape[0]
    nm = V.shape[1]
    g0 = prm[P_GAMMA0]
    ig0 = 1.0 / g0
    law = iprm[I_LAW]
    k0 = iprm[I_KIND0]
    k1 = iprm[I_KIND1]
    # 1. values at Gauss points and traces
    for e in range(N):
        eval_points(V, U, e, 0, wq, W_Q, 6, 1.0)
        eval_traces(Tr, U, e, 0, tr, T_Q, 6, 1.0)
        for j in range(nq):
            q0 = wq[e, j, W_Q]
            q1 = wq[e, j, W_Q + 1]
            q2 = wq[e, j, W_Q + 2]
            l = math.sqrt(q0 * q0 + q1 * q1 + q2 * q2)
            wq[e, j, W_L] = l
            il = 1.0 / l if l > 1e-300 else 0.0
            wq[e, j, W_I] = q0 * il
            wq[e, j, W_I + 1] = q1 * il
            wq[e, j, W_I + 2] = q2 * il
        for side in range(2):
            tr[e, side, T_LAM] = local_speed(prm, law, tr[e, side, T_Q], tr[e, side, T_Q + 1], tr[e, side, T_Q + 2],
                                             tab_eps, tab_T)
    # 2. fluxes of F_q = v / gamma0 and dq/dt
    interface_fluxes(fl, tr, N, F_Q, T_Q, T_V, ig0, prm[P_QPEN])
    for c in range(3):
        fl[0, F_Q + c] = tr[0, 0, T_V + c] * ig0 if is_force_end(k0) else vbc[0, 3 + c]
        fl[N, F_Q + c] = tr[N - 1, 1, T_V + c] * ig0 if is_force_end(k1) else vbc[1, 3 + c]
    EA = prm[P_EA]
    zeta = prm[P_ZETA]
    damped = iprm[I_AXDAMP] != 0
    if damped:  # central fluxes for the strain-rate gradient of the damping terms (LDG-style)
        for k in range(1, N):
            for c in range(3):
                fl[k, F_NU + c] = 0.5 * (tr[k - 1, 1, T_V + c] + tr[k, 0, T_V + c]) * ig0
        for c in range(3):
            fl[0, F_NU + c] = fl[0, F_Q + c]
            fl[N, F_NU + c] = fl[N, F_Q + c]
    for e in range(N):
        strong_derivative(h[e], D, Lf, U, e, 3, ig0, tr, T_V, fl, F_Q, dU, 0, 3)
        if damped:
            strong_derivative(h[e], D, Lf, U, e, 3, ig0, tr, T_V, fl, F_NU, wm, M_NUS, 3)
            eval_points(V, wm, e, M_NUS, wq, W_NUS, 3, 1.0)
        # 3. strain rate and axial tension at the Gauss points
        for j in range(nq):
            i0 = wq[e, j, W_I]
            i1 = wq[e, j, W_I + 1]
            i2 = wq[e, j, W_I + 2]
            edot = 0.0
            if damped:
                edot = i0 * wq[e, j, W_NUS] + i1 * wq[e, j, W_NUS + 1] + i2 * wq[e, j, W_NUS + 2]
            wq[e, j, W_EDOT] = edot
            T = axial_tension(law, wq[e, j, W_L] - 1.0, edot, EA, zeta, tab_eps, tab_T)
            wq[e, j, W_TV] = T * i0
            wq[e, j, W_TV + 1] = T * i1
            wq[e, j, W_TV + 2] = T * i2
    if iprm[I_BENDING] != 0:
        ldg_shear_force(prm, iprm, h, V, Pj, D, Lf, Tr, bc, wq, wm, tr, fl)
    # 4. tension vector on the modes, fluxes, dT/ds
    for e in range(N):
        project_points(Pj, wq, e, W_TV, wm, M_TV, 3)
        eval_traces(Tr, wm, e, M_TV, tr, T_TV, 3, 1.0)
    interface_fluxes(fl, tr, N, F_V, T_V, T_TV, 1.0, 1.0)
    lam0 = max(tr[0, 0, T_LAM], prm[P_LAMBDA_BC])
    lam1 = max(tr[N - 1, 1, T_LAM], prm[P_LAMBDA_BC])
    for c in range(3):
        if is_force_end(k0):
            fl[0, F_V + c] = -bc[0, B_F + c]
        else:  # n = -1
            fl[0, F_V + c] = tr[0, 0, T_TV + c] - lam0 * (g0 * vbc[0, 3 + c] - tr[0, 0, T_V + c])
        if is_force_end(k1):
            fl[N, F_V + c] = bc[1, B_F + c]
        else:  # n = +1
            fl[N, F_V + c] = tr[N - 1, 1, T_TV + c] + lam1 * (g0 * vbc[1, 3 + c] - tr[N - 1, 1, T_V + c])
    if law != LAW_LINEAR:
        clip_compression(fl, tr, 0, 0, 0)
        clip_compression(fl, tr, N, N - 1, 1)
    end_outputs(N, tr, fl, endf, k0, k1, bc)
    # 5. sources, added mass, projection
    needpos = iprm[I_NEEDPOS] != 0
    current = iprm[I_CURRENT] != 0
    seabed = iprm[I_SEABED] != 0
    if needpos:
        element_positions(U, ra, h, iprm, rs)
    fbz = prm[P_FBZ]
    mt = prm[P_MT]
    mn = prm[P_MN]
    relax = prm[P_RELAX]
    hrd = prm[P_HALF_RHO_D]
    cdt = prm[P_CDT]
    cdn = prm[P_CDN]
    uc = tmp[0:3]
    uc[0] = 0.0
    uc[1] = 0.0
    uc[2] = 0.0
    for e in range(N):
        strong_derivative(h[e], D, Lf, wm, e, M_TV, 1.0, tr, T_TV, fl, F_V, wm, M_DT, 3)
        eval_points(V, wm, e, M_DT, wq, W_DT, 3, 1.0)
        if needpos:
            for j in range(nq):
                for c in range(3):
                    s = 0.0
                    for k in range(nm):
                        s += Iq[j, k] * U[e, k, c]
                    wq[e, j, W_R + c] = rs[e, c] + 0.5 * h[e] * s
        for j in range(nq):
            l = wq[e, j, W_L]
            i0 = wq[e, j, W_I]
            i1 = wq[e, j, W_I + 1]
            i2 = wq[e, j, W_I + 2]
            n0 = wq[e, j, W_V] * ig0
            n1 = wq[e, j, W_V + 1] * ig0
            n2 = wq[e, j, W_V + 2] * ig0
            if current:
                current_at(wq[e, j, W_R + 2], cz, cx, cy, uc)
            fx, fy, fz = morison_drag(i0, i1, i2, l, uc[0] - n0, uc[1] - n1, uc[2] - n2, hrd, cdt, cdn)
            fx += wq[e, j, W_DT]
            fy += wq[e, j, W_DT + 1]
            fz += wq[e, j, W_DT + 2] + fbz
            if seabed:
                sx, sy, sz = seabed_force(wq[e, j, W_R + 2], n0, n1, n2, l, prm[P_ZG], prm[P_KD], prm[P_CCRIT],
                                          prm[P_SBZETA], prm[P_MU], prm[P_VMU], fbz)
                fx += sx
                fy += sy
                fz += sz
            a0, a1, a2 = added_mass_rate(i0, i1, i2, fx, fy, fz, g0, mt, mn)
            wq[e, j, W_ACC] = a0 - relax * wq[e, j, W_V]
            wq[e, j, W_ACC + 1] = a1 - relax * wq[e, j, W_V + 1]
            wq[e, j, W_ACC + 2] = a2 - relax * wq[e, j, W_V + 2]
        project_points(Pj, wq, e, W_ACC, dU, 3, 3)
    a = iprm[I_ANCHOR]
    for c in range(3):
        dra[c] = fl[a * N, F_Q + c]


@jit
def clip_compression(fl, tr, k, e, side):
    """Remove a compressive axial part of the boundary flux T_hat (laws without compression).

    The Riemann solution of a cable that cannot push has T* >= 0: a boundary moving into the cable
    faster than the upwind term allows produces slack, not compression.
    """
    q0 = tr[e, side, T_Q]
    q1 = tr[e, side, T_Q + 1]
    q2 = tr[e, side, T_Q + 2]
    lq = math.sqrt(q0 * q0 + q1 * q1 + q2 * q2)
    if lq <= 1e-300:
        return
    i0 = q0 / lq
    i1 = q1 / lq
    i2 = q2 / lq
    a = fl[k, F_V] * i0 + fl[k, F_V + 1] * i1 + fl[k, F_V + 2] * i2
    if a < 0.0:
        fl[k, F_V] -= a * i0
        fl[k, F_V + 1] -= a * i1
        fl[k, F_V + 2] -= a * i2


@jit
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
