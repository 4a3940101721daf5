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

Steps 1-3 are ``tension_scalar``, step 4 the end of ``internal_forces`` (what the outputs need),
step 5 ``momentum_rate`` (vectorised across the elements in soa.py when the cable has no current
and no seabed). Fluxes and end loads: fluxes.py.

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

import inspect
import math
import textwrap

from tether_sim.numerics.jit import jit, jit_inline
from tether_sim.physics.constitutive import (
    LAW_BILINEAR, LAW_LINEAR, LAW_TABLE, axial_tension, compression_cap, tension_slope,
)
from tether_sim.physics.end_conditions import is_kinematic
from tether_sim.physics.hydrodynamics import current_at, morison_drag, surface_drag, wave_inertia, wetted_fraction
from tether_sim.physics.seabed import seabed_force
from tether_sim.physics.waves import wave_kinematics
from tether_sim.solvers.dg.elementops import strong_derivative
from tether_sim.solvers.dg.layout import (
    B_F, B_P0, B_P1, B_T0, B_T1, B_V0, B_V1, F_NU, F_Q, F_V,
    I_ANCHOR, I_AXDAMP, I_BENDING, I_CURRENT, I_KIND0, I_KIND1, I_LAW, I_N, I_NEEDPOS, I_P, I_NWAVE, I_SEABED, I_SURFACE,
    M_DT, M_NUS, M_TV, P_CCRIT, P_CDN, P_CDN_AIR, P_CDT, P_CDT_AIR, P_EA, P_FBZ, P_FBZ_AIR, P_GAMMA0,
    P_HALF_RHO_D, P_HALF_RHO_D_AIR, P_RHO_AH, P_SURF_B, P_TIME, P_WAVE_DEPTH, P_WAVE_STRETCH, P_WAVE_ZCUT, N_PRM,
    P_BMR, P_BMR_W, P_EI, P_EIC, P_KD, P_LAMBDA_BC, P_LAMBDA_FLOOR, P_MN, P_MT, P_MU, P_QPENT, P_RELAX, P_SBZETA, P_VMU, P_ZETA, P_ZG, T_LAM, T_Q,
    T_TV, T_V, W_ACC, W_EDOT, W_I, W_L, W_NUS, W_Q, W_R, W_TE, W_TS, W_TSH, W_TV, W_V, W_WET,
)
from tether_sim.solvers.dg.fluxes import (
    clip_compression, end_outputs, interface_fluxes, shear_traces, tension_jump_penalty, velocity_fluxes,
)
from tether_sim.solvers.dg.ldg import ldg_shear_force
from tether_sim.solvers.dg.soa import momentum_rate_soa, soa_momentum_applies


@jit_inline
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
def local_speed(prm, law, q0, q1, q2, tab_eps, tab_T, pc):
    """lambda = sqrt(dT/deps / gamma0) at a trace [PE2020 Eq. 25], floored by P_LAMBDA_FLOOR; pc: the
    compression cap of the element (physics/constitutive.py)."""
    eps = math.sqrt(q0 * q0 + q1 * q1 + q2 * q2) - 1.0
    lam = math.sqrt(tension_slope(law, eps, prm[P_EA], tab_eps, tab_T, pc) / prm[P_GAMMA0])
    return lam if lam > prm[P_LAMBDA_FLOOR] else prm[P_LAMBDA_FLOOR]


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


@jit_inline
def dg_rhs(U, ra, prm, iprm, h, V, Pj, D, Lf, Tr, Iq, tab_eps, tab_T, cz, cx, cy, bc, vbc,
           wq, wm, tr, fl, rs, tmp, dU, dra, endf, internal=True):
    """du/dt of the DG cable [PE2020 Eq. 23] into dU; anchor velocity into dra; end loads into endf.
    internal = False: internal_forces of these inputs are already in the work arrays (stepper.dg_evaluate)."""
    if internal:
        internal_forces(U, prm, iprm, h, V, Pj, D, Lf, Tr, tab_eps, tab_T, bc, vbc, wq, wm, tr, fl, dU, endf, tmp)
    nq = V.shape[0]
    nm = V.shape[1]
    if nm == 3 and nq == 4:  # the element loops at a size known to the compiler (SIZED, below)
        momentum_rate_3_4(U, ra, prm, iprm, h, V, Pj, D, Lf, Iq, cz, cx, cy, wq, wm, tr, fl, rs, tmp, dU)
    elif nm == 5 and nq == 7:
        momentum_rate_5_7(U, ra, prm, iprm, h, V, Pj, D, Lf, Iq, cz, cx, cy, wq, wm, tr, fl, rs, tmp, dU)
    else:
        momentum_rate(U, ra, prm, iprm, h, V, Pj, D, Lf, Iq, cz, cx, cy, wq, wm, tr, fl, rs, tmp, dU)
    k = iprm[I_ANCHOR] * iprm[I_N]
    for c in range(3):
        dra[c] = fl[k, F_Q + c]


@jit_inline
def internal_forces(U, prm, iprm, h, V, Pj, D, Lf, Tr, tab_eps, tab_T, bc, vbc, wq, wm, tr, fl, dU, endf, tmp):
    """Steps 1-4 of dg_rhs (module docstring): point values, dq/dt into dU[..., 0:3], the tension
    vector (+ bending shear) on the modes and at the traces, all fluxes and the end loads endf.

    Passes over the elements with the element operations written out, one accumulator per
    channel (same sums, same order as elementops.py), point values consumed where they are made.
    """
    N = iprm[I_N]
    g0 = prm[P_GAMMA0]
    law = iprm[I_LAW]
    k0 = iprm[I_KIND0]
    k1 = iprm[I_KIND1]
    nq = V.shape[0]
    nm = V.shape[1]
    if nm == 3 and nq == 4:  # the element loops at a size known to the compiler (SIZED, below)
        tension_scalar_3_4(U, prm, iprm, h, V, Pj, D, Lf, Tr, tab_eps, tab_T, bc, vbc, wq, wm, tr, fl, dU)
    elif nm == 5 and nq == 7:
        tension_scalar_5_7(U, prm, iprm, h, V, Pj, D, Lf, Tr, tab_eps, tab_T, bc, vbc, wq, wm, tr, fl, dU)
    else:
        tension_scalar(U, prm, iprm, h, V, Pj, D, Lf, Tr, tab_eps, tab_T, bc, vbc, wq, wm, tr, fl, dU)
    # 4. fluxes of the tension vector, boundary fluxes, end loads
    interface_fluxes(fl, tr, N, F_V, T_V, T_TV, 1.0, 1.0)
    lam0 = max(tr[0, 0, T_LAM], prm[P_LAMBDA_BC])
    lam1 = max(tr[N - 1, 1, T_LAM], prm[P_LAMBDA_BC])
    for c in range(3):
        if not is_kinematic(k0):
            fl[0, F_V + c] = -bc[0, B_F + c]
        else:  # n = -1
            fl[0, F_V + c] = tr[0, 0, T_TV + c] - lam0 * (g0 * vbc[0, 3 + c] - tr[0, 0, T_V + c])
        if not is_kinematic(k1):
            fl[N, F_V + c] = bc[1, B_F + c]
        else:  # n = +1
            fl[N, F_V + c] = tr[N - 1, 1, T_TV + c] + lam1 * (g0 * vbc[1, 3 + c] - tr[N - 1, 1, T_V + c])
    if law != LAW_LINEAR:
        # at a velocity end the clip leaves the bending shear trace out (fluxes.clip_compression); a force
        # end's flux is the applied force alone
        shear0 = iprm[I_BENDING] != 0 and is_kinematic(k0)
        shear1 = iprm[I_BENDING] != 0 and is_kinematic(k1)
        if shear0:
            shear_traces(Pj, Tr, wq, tr, 0, 0)
        if shear1:
            shear_traces(Pj, Tr, wq, tr, N - 1, 1)
        clip_compression(fl, tr, 0, 0, 0, compression_cap(law, prm[P_EIC], iprm[I_P], h[0]), shear0)
        clip_compression(fl, tr, N, N - 1, 1, compression_cap(law, prm[P_EIC], iprm[I_P], h[N - 1]), shear1)
    end_outputs(N, tr, fl, endf, k0, k1, bc)


@jit
def tension_scalar(U, prm, iprm, h, V, Pj, D, Lf, Tr, tab_eps, tab_T, bc, vbc, wq, wm, tr, fl, dU):
    """Steps 1-3 of dg_rhs element by element (any law, bending): values, fluxes of F_q, dq/dt,
    strain rate, tension vector (+ T_s) projected on the modes and its traces.

    Longer than the project's ~80 lines on purpose: split into three compiled steps (point values,
    dq/dt per element, tension per element; plain or IR-inlined calls) it measured 8-18 % slower
    per 50 Hz tick at L = 1730 m, N = 6, P = 2 and 2-6 % at 200 m (2026-11-24, bench_vs_moordyn
    --baseline, bit-identical results), on the path the MoorDyn comparison times; 2026-11-25,
    without reference counts: inlined whole into its caller it measured the same as a call)."""
    N = iprm[I_N]
    nq = V.shape[0]
    nm = V.shape[1]
    g0 = prm[P_GAMMA0]
    ig0 = 1.0 / g0
    law = iprm[I_LAW]
    bending = iprm[I_BENDING] != 0
    lam_taut = math.sqrt(prm[P_EA] / g0)  # = local_speed of a taut trace for the (bi)linear laws
    lam_floor = prm[P_LAMBDA_FLOOR]
    EA = prm[P_EA]
    # 1. q, v at the Gauss points and traces; tangent, elongation, local wave speed. The two
    # six-channel sums below are written out on purpose: one helper returning a 6-tuple measured
    # 41-43 us per substep against 35-36 us (ROPOS N = 20, P = 4, bench_dg_kernel.py).
    for e in range(N):
        pc = compression_cap(law, prm[P_EIC], iprm[I_P], h[e])  # 0 without bending: Eq. 22 as printed
        for j in range(nq):
            s0 = 0.0
            s1 = 0.0
            s2 = 0.0
            s3 = 0.0
            s4 = 0.0
            s5 = 0.0
            for k in range(nm):
                a = V[j, k]
                s0 += a * U[e, k, 0]
                s1 += a * U[e, k, 1]
                s2 += a * U[e, k, 2]
                s3 += a * U[e, k, 3]
                s4 += a * U[e, k, 4]
                s5 += a * U[e, k, 5]
            wq[e, j, W_Q] = s0
            wq[e, j, W_Q + 1] = s1
            wq[e, j, W_Q + 2] = s2
            wq[e, j, W_V] = s3
            wq[e, j, W_V + 1] = s4
            wq[e, j, W_V + 2] = s5
            l = math.sqrt(s0 * s0 + s1 * s1 + s2 * s2)
            wq[e, j, W_L] = l
            il = 1.0 / l if l > 1e-300 else 0.0
            wq[e, j, W_I] = s0 * il
            wq[e, j, W_I + 1] = s1 * il
            wq[e, j, W_I + 2] = s2 * il
        for side in range(2):
            s0 = 0.0
            s1 = 0.0
            s2 = 0.0
            s3 = 0.0
            s4 = 0.0
            s5 = 0.0
            for k in range(nm):
                a = Tr[side, k]
                s0 += a * U[e, k, 0]
                s1 += a * U[e, k, 1]
                s2 += a * U[e, k, 2]
                s3 += a * U[e, k, 3]
                s4 += a * U[e, k, 4]
                s5 += a * U[e, k, 5]
            tr[e, side, T_Q] = s0
            tr[e, side, T_Q + 1] = s1
            tr[e, side, T_Q + 2] = s2
            tr[e, side, T_V] = s3
            tr[e, side, T_V + 1] = s4
            tr[e, side, T_V + 2] = s5
            if law == LAW_TABLE:
                lam = local_speed(prm, law, s0, s1, s2, tab_eps, tab_T, pc)
            else:  # local_speed written out: the slope is EA (taut, capped compression, linear law) or 0
                lam = lam_taut
                if law == LAW_BILINEAR:
                    el = math.sqrt(s0 * s0 + s1 * s1 + s2 * s2) - 1.0
                    if el < 0.0 and not EA * el > -pc:
                        lam = 0.0
                lam = lam if lam > lam_floor else lam_floor
            tr[e, side, T_LAM] = lam
    # 2. fluxes of F_q = v / gamma0 (and of the strain-rate gradient)
    velocity_fluxes(prm, iprm, vbc, tr, fl)
    zeta = prm[P_ZETA]
    damped = iprm[I_AXDAMP] != 0
    qtens = prm[P_QPENT] != 0.0
    for e in range(N):
        # dq/dt = d(v/gamma0)/ds with the Lax-Friedrichs fluxes; the strain-rate gradient shares
        # the volume term and differs only in the (central) interface fluxes
        hb = 1.0 / h[e]
        asc = (2.0 / h[e]) * ig0
        pc = compression_cap(law, prm[P_EIC], iprm[I_P], h[e])
        jr0 = fl[e + 1, F_Q] - ig0 * tr[e, 1, T_V]
        jr1 = fl[e + 1, F_Q + 1] - ig0 * tr[e, 1, T_V + 1]
        jr2 = fl[e + 1, F_Q + 2] - ig0 * tr[e, 1, T_V + 2]
        jl0 = fl[e, F_Q] - ig0 * tr[e, 0, T_V]
        jl1 = fl[e, F_Q + 1] - ig0 * tr[e, 0, T_V + 1]
        jl2 = fl[e, F_Q + 2] - ig0 * tr[e, 0, T_V + 2]
        kr0 = fl[e + 1, F_NU] - ig0 * tr[e, 1, T_V]
        kr1 = fl[e + 1, F_NU + 1] - ig0 * tr[e, 1, T_V + 1]
        kr2 = fl[e + 1, F_NU + 2] - ig0 * tr[e, 1, T_V + 2]
        kl0 = fl[e, F_NU] - ig0 * tr[e, 0, T_V]
        kl1 = fl[e, F_NU + 1] - ig0 * tr[e, 0, T_V + 1]
        kl2 = fl[e, F_NU + 2] - ig0 * tr[e, 0, T_V + 2]
        for l in range(nm):
            s0 = 0.0
            s1 = 0.0
            s2 = 0.0
            for m in range(l + 1, nm):
                d = D[l, m]
                s0 += d * U[e, m, 3]
                s1 += d * U[e, m, 4]
                s2 += d * U[e, m, 5]
            l1 = Lf[1, l]
            l0 = Lf[0, l]
            dU[e, l, 0] = asc * s0 + hb * (l1 * jr0 - l0 * jl0)
            dU[e, l, 1] = asc * s1 + hb * (l1 * jr1 - l0 * jl1)
            dU[e, l, 2] = asc * s2 + hb * (l1 * jr2 - l0 * jl2)
            if damped:
                wm[e, l, M_NUS] = asc * s0 + hb * (l1 * kr0 - l0 * kl0)
                wm[e, l, M_NUS + 1] = asc * s1 + hb * (l1 * kr1 - l0 * kl1)
                wm[e, l, M_NUS + 2] = asc * s2 + hb * (l1 * kr2 - l0 * kl2)
        # 3. strain rate and axial tension at the Gauss points
        for j in range(nq):
            i0 = wq[e, j, W_I]
            i1 = wq[e, j, W_I + 1]
            i2 = wq[e, j, W_I + 2]
            edot = 0.0
            if damped:
                s0 = 0.0
                s1 = 0.0
                s2 = 0.0
                for k in range(nm):
                    a = V[j, k]
                    s0 += a * wm[e, k, M_NUS]
                    s1 += a * wm[e, k, M_NUS + 1]
                    s2 += a * wm[e, k, M_NUS + 2]
                wq[e, j, W_NUS] = s0
                wq[e, j, W_NUS + 1] = s1
                wq[e, j, W_NUS + 2] = s2
                edot = i0 * s0 + i1 * s1 + i2 * s2
            wq[e, j, W_EDOT] = edot
            eps = wq[e, j, W_L] - 1.0
            if law == LAW_TABLE:
                T = axial_tension(law, eps, edot, EA, zeta, tab_eps, tab_T, pc)
            else:  # axial_tension written out for the linear and bilinear laws [Eq. 22, compression cap pc]
                T = EA * eps + zeta * edot
                if law == LAW_BILINEAR:
                    if pc > 0.0:
                        if EA * eps <= -pc:  # buckled below the mesh scale: the push fades with the chord
                            T = -pc * (1.0 + eps) / (1.0 - pc / EA)
                        elif not T > -pc:
                            T = -pc
                    elif eps <= 0.0 or not T > 0.0:
                        T = 0.0
            wq[e, j, W_TV] = T * i0
            wq[e, j, W_TV + 1] = T * i1
            wq[e, j, W_TV + 2] = T * i2
            if qtens:  # elastic part alone, for the q-equation penalty (fluxes.tension_jump_penalty)
                Te = axial_tension(law, eps, 0.0, EA, 0.0, tab_eps, tab_T, pc)
                wq[e, j, W_TE] = Te * i0
                wq[e, j, W_TE + 1] = Te * i1
                wq[e, j, W_TE + 2] = Te * i2
        if not bending:
            _project_tension(Pj, Tr, wq, wm, tr, e, nm, nq)
    if bending:
        if prm[P_BMR] != 0.0:  # bending multirate: T_s extrapolated from the records (stepper.py)
            held_shear_force(prm, wq, N, nq)
        else:
            ldg_shear_force(prm, iprm, h, V, Pj, D, Lf, Tr, bc, wq, wm, tr, fl)
        for e in range(N):
            _project_tension(Pj, Tr, wq, wm, tr, e, nm, nq)
    if qtens:
        tension_jump_penalty(prm, iprm, h, Pj, Tr, Lf, wq, tr, fl, dU)


@jit_inline
def held_shear_force(prm, wq, N, nq):
    """T_s = sum_k w_k R_k (W_TS) added to the tension vector W_TV: the bending shear extrapolated from
    the records R_k (W_TSH) of the last three nested-LDG evaluations with the weights w_k (P_BMR_W) that
    the stepper set for this stage's time (stepper.py, bending multirate)."""
    w0 = prm[P_BMR_W]
    w1 = prm[P_BMR_W + 1]
    w2 = prm[P_BMR_W + 2]
    for e in range(N):
        for j in range(nq):
            for c in range(3):
                t = w0 * wq[e, j, W_TSH + c] + w1 * wq[e, j, W_TSH + 3 + c] + w2 * wq[e, j, W_TSH + 6 + c]
                wq[e, j, W_TS + c] = t
                wq[e, j, W_TV + c] += t


@jit_inline
def momentum_rate(U, ra, prm, iprm, h, V, Pj, D, Lf, Iq, cz, cx, cy, wq, wm, tr, fl, rs, tmp, dU):
    """Step 5 of dg_rhs: dT/ds, drag, weight, seabed, added mass; dv/dt projected into dU[..., 3:6].

    Free surface (I_SURFACE): each Gauss point is wetted by the fraction phi (physics/hydrodynamics.
    wetted_fraction) over a band of half-width max(L_s / 2, |dz/ds| h / (2 Q)), the vertical half-extent
    of the arc h / Q it stands for; buoyancy, added mass and water drag scale with phi, air buoyancy
    and air drag with 1 - phi."""
    N = iprm[I_N]
    nq = V.shape[0]
    nm = V.shape[1]
    needpos = iprm[I_NEEDPOS] != 0
    if soa_momentum_applies(iprm, V, tmp):
        momentum_rate_soa(prm, iprm, h, V, Pj, D, Lf, wq, wm, tr, fl, tmp, dU)
        return
    g0 = prm[P_GAMMA0]
    ig0 = 1.0 / g0
    current = iprm[I_CURRENT] != 0
    seabed = iprm[I_SEABED] != 0
    if needpos:
        element_positions(U, ra, h, iprm, rs)
    fbz = prm[P_FBZ]
    relax = prm[P_RELAX]
    hrd = prm[P_HALF_RHO_D]
    cdt = prm[P_CDT]
    cdn = prm[P_CDN]
    ct = g0 / (g0 + prm[P_MT])  # added mass: (gamma0 + m) a = F per direction [Eq. 13]
    cn = g0 / (g0 + prm[P_MN])
    u0 = 0.0
    u1 = 0.0
    u2 = 0.0
    surface = iprm[I_SURFACE] != 0
    nw = iprm[I_NWAVE]
    o = N_PRM  # wave components (layout.py): amp, omega, k, cos, sin, phase
    wamp, wom, wk = prm[o:o + nw], prm[o + nw:o + 2 * nw], prm[o + 2 * nw:o + 3 * nw]
    wc, ws, wph = prm[o + 3 * nw:o + 4 * nw], prm[o + 4 * nw:o + 5 * nw], prm[o + 5 * nw:o + 6 * nw]
    uw = tmp[3:6]
    aw = tmp[6:9]
    for e in range(N):
        hq = h[e] / nq  # arc per Gauss point (free surface band)
        strong_derivative(h[e], D, Lf, wm, e, M_TV, 1.0, tr, T_TV, fl, F_V, wm, M_DT, 3)
        if needpos:
            for j in range(nq):
                for c in range(3):
                    s = 0.0
                    for k in range(nm):
                        s += Iq[j, k] * U[e, k, c]
                    wq[e, j, W_R + c] = rs[e, c] + 0.5 * h[e] * s
        for j in range(nq):
            d0 = 0.0
            d1 = 0.0
            d2 = 0.0
            for k in range(nm):
                a = V[j, k]
                d0 += a * wm[e, k, M_DT]
                d1 += a * wm[e, k, M_DT + 1]
                d2 += a * wm[e, k, M_DT + 2]
            l = wq[e, j, W_L]
            i0 = wq[e, j, W_I]
            i1 = wq[e, j, W_I + 1]
            i2 = wq[e, j, W_I + 2]
            v0 = wq[e, j, W_V]
            v1 = wq[e, j, W_V + 1]
            v2 = wq[e, j, W_V + 2]
            n0 = v0 * ig0
            n1 = v1 * ig0
            n2 = v2 * ig0
            if current:
                current_at(wq[e, j, W_R + 2], cz, cx, cy, tmp)
                u0 = tmp[0]
                u1 = tmp[1]
                u2 = tmp[2]
            eta = 0.0
            wave = nw > 0 and wq[e, j, W_R + 2] > prm[P_WAVE_ZCUT]
            if wave:  # wave particle velocity (drag) and acceleration (inertia below), elevation (surface)
                eta = wave_kinematics(wq[e, j, W_R], wq[e, j, W_R + 1], wq[e, j, W_R + 2], prm[P_TIME], wamp, wom, wk,
                                      wc, ws, wph, prm[P_WAVE_DEPTH], int(prm[P_WAVE_STRETCH]), uw, aw)
                u0 += uw[0]
                u1 += uw[1]
                u2 += uw[2]
            phi = 1.0
            fb = fbz
            if surface:  # wetted fraction over the band max(L_s / 2, vertical half-extent of the point's arc)
                b = max(prm[P_SURF_B], 0.5 * hq * abs(wq[e, j, W_Q + 2]))
                phi, _ = wetted_fraction(wq[e, j, W_R + 2], eta, b)
                wq[e, j, W_WET] = phi
                fx, fy, fz = surface_drag(i0, i1, i2, l, n0, n1, n2, u0, u1, u2, phi, hrd, cdt, cdn,
                                          prm[P_HALF_RHO_D_AIR], prm[P_CDT_AIR], prm[P_CDN_AIR])
                fb = prm[P_FBZ_AIR] + phi * (fbz - prm[P_FBZ_AIR])
                ct = g0 / (g0 + phi * prm[P_MT])
                cn = g0 / (g0 + phi * prm[P_MN])
            else:
                fx, fy, fz = morison_drag(i0, i1, i2, l, u0 - n0, u1 - n1, u2 - n2, hrd, cdt, cdn)
            if wave:  # Froude-Krylov + fluid-side added mass of the wave acceleration (docs/waves.md)
                wx, wy, wz = wave_inertia(i0, i1, i2, aw[0], aw[1], aw[2], prm[P_RHO_AH], prm[P_MT], prm[P_MN])
                fx += phi * wx
                fy += phi * wy
                fz += phi * wz
            if wave or current:
                u0 = 0.0
                u1 = 0.0
                u2 = 0.0
            fx += d0
            fy += d1
            fz += d2 + fb
            if seabed:
                sx, sy, sz = seabed_force(wq[e, j, W_R + 2], n0, n1, n2, l, prm[P_ZG], prm[P_KD], prm[P_CCRIT],
                                          prm[P_SBZETA], prm[P_MU], prm[P_VMU], fb)
                fx += sx
                fy += sy
                fz += sz
            ft = fx * i0 + fy * i1 + fz * i2
            p0 = ft * i0
            p1 = ft * i1
            p2 = ft * i2
            wq[e, j, W_ACC] = (ct * p0 + cn * (fx - p0)) - relax * v0
            wq[e, j, W_ACC + 1] = (ct * p1 + cn * (fy - p1)) - relax * v1
            wq[e, j, W_ACC + 2] = (ct * p2 + cn * (fz - p2)) - relax * v2
        for l in range(nm):
            s0 = 0.0
            s1 = 0.0
            s2 = 0.0
            for j in range(nq):
                a = Pj[l, j]
                s0 += a * wq[e, j, W_ACC]
                s1 += a * wq[e, j, W_ACC + 1]
                s2 += a * wq[e, j, W_ACC + 2]
            dU[e, l, 3] = s0
            dU[e, l, 4] = s1
            dU[e, l, 5] = s2


@jit_inline
def _project_tension(Pj, Tr, wq, wm, tr, e, nm, nq):
    """Tension vector of element e: Gauss points -> modes (M_TV) -> traces (T_TV)."""
    for l in range(nm):
        s0 = 0.0
        s1 = 0.0
        s2 = 0.0
        for j in range(nq):
            a = Pj[l, j]
            s0 += a * wq[e, j, W_TV]
            s1 += a * wq[e, j, W_TV + 1]
            s2 += a * wq[e, j, W_TV + 2]
        wm[e, l, M_TV] = s0
        wm[e, l, M_TV + 1] = s1
        wm[e, l, M_TV + 2] = s2
    for side in range(2):
        s0 = 0.0
        s1 = 0.0
        s2 = 0.0
        for k in range(nm):
            a = Tr[side, k]
            s0 += a * wm[e, k, M_TV]
            s1 += a * wm[e, k, M_TV + 1]
            s2 += a * wm[e, k, M_TV + 2]
        tr[e, side, T_TV] = s0
        tr[e, side, T_TV + 1] = s1
        tr[e, side, T_TV + 2] = s2


# ------------------------------------------------------------------------------ the loops at fixed sizes
# tension_scalar and momentum_rate with the modes per element nm = P + 1 and the Gauss points nq made
# constants, for the (nm, nq) of the live meshes (1730 m: P = 2, Q = 4; 200 m and the paper's meshes: P = 4,
# Q = 7): the same source with its two lines "nq = V.shape[0]", "nm = V.shape[1]" replaced by the numbers,
# so the same operations in the same order (the same bits: test/solvers/dg/test_sized_kernels.py), while
# the compiler unrolls the short loops over modes and points. internal_forces and dg_rhs pick one by
# V's shape. Measured at the 1730 m live mesh (N = 6, P = 2), us per call: tension_scalar 0.79 -> 0.67,
# momentum_rate 0.59 -> 0.52 (benchmarks/probes/substep_parts.py; docs/performance.md, "the substep by part at
# the 1730 m live mesh").
SIZED = ((3, 4), (5, 7))


def sized_source(fn, nm, nq):
    """The source of the compiled function fn with nm and nq constants, named <name>_<nm>_<nq>."""
    py = getattr(fn, "py_func", fn)
    lines = textwrap.dedent(inspect.getsource(py)).splitlines()
    # the decorator a blank line, and as many blank lines before: the line numbers are this file's
    out = "\n" * (py.__code__.co_firstlineno - 1) + "\n".join("" if ln.startswith("@") else ln for ln in lines) + "\n"
    for old, new in (("    nq = V.shape[0]\n", f"    nq = {nq}\n"), ("    nm = V.shape[1]\n", f"    nm = {nm}\n"),
                     (f"def {fn.__name__}(", f"def {fn.__name__}_{nm}_{nq}(")):
        if out.count(old) != 1:
            raise ValueError(f"sized_source: {fn.__name__} has {out.count(old)} lines {old.strip()!r}, needs one")
        out = out.replace(old, new)
    return out


def _define_sized(namespace):
    """<name>_<nm>_<nq> for tension_scalar (a call) and momentum_rate (inlined) at every size of SIZED,
    compiled from this file's name (numba caches them beside the rest)."""
    for nm, nq in SIZED:
        for fn, deco in ((tension_scalar, jit), (momentum_rate, jit_inline)):
            exec(compile(sized_source(fn, nm, nq), __file__, "exec"), namespace)
            name = f"{fn.__name__}_{nm}_{nq}"
            namespace[name] = deco(namespace[name])


_define_sized(globals())
