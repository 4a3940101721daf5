"""Nested local DG for the bending shear force [PE2020 Eq. 18-21, 26-30, Table 1].

Given q, l = |q| and d(v/gamma0)/ds at the Gauss points (from kernels.dg_rhs), with the bending tangent
b = q / l_b and l_b = max(l, l_f) (below; l_f = 1 for the laws without compression, 0 for the
linear law):

    db/dt  = (dq/dt - b deps/dt) / l (taut), dq/dt (short chord); dq/dt = d(v/gamma0)/ds
    kappa  = d b / ds        with flux b_hat  [Eq. 26, 29]
    kdot   = d (db/dt) / ds  with flux b_hat-dot [Eq. 27, 29] (only when zeta_b > 0)
    M*     = (b x (EI kappa + zeta_b kdot) + GIp Omega_1 b) / l_b^2   [Eq. 19-21]
    tau    = d M* / ds       with flux M*_hat [Eq. 28, 30]
    T_s    = (1 / l_b) b x tau                                         [Eq. 20]

T_s is added to the tension vector at the Gauss points. Boundary fluxes per Table 1:
clamped ends impose b_hat = i_BC, b_hat-dot = 0 and take M*_hat from the interior; force ends
impose M*_hat = n M_BC; every other end (prescribed, fixed pin, free, body) is moment free
(M*_hat = 0) with b_hat, b_hat-dot from the interior.

**Where the cable is taut or stretched (l >= 1) b = i = q / l and l_b = l: PE2020's equations, bit for
bit.** Where the chord is shorter than the material (l < 1, only possible in slack parts: the law of
Eq. 22 carries no compression), PE2020's stretched-domain factors 1/l, 1/l^2 and the unit tangent q/l
are those of a rod whose material is compressed while its centreline stays smooth. A slack cable does
not shorten its material; a chord shorter than the material means the cable is wavy below the mesh
scale, and its arc length per unstretched metre is still 1. So there b = q and l_b = 1: the bending
of the resolved (mean) line, measured on the material arc length. The two forms meet at l = 1 (b and
l_b continuous, b Lipschitz in q). With the linear law (cable.material: linear) compression is real
material strain and PE2020's form holds at every l (l_f = 0).

Why the stretched form must not be used where the chord is short: as a chord collapses
(l -> 0, the cable folded inside an element) q/l is undefined and flips sign when q passes through
zero, so kappa = d(q/l)/ds becomes a jump of size 2 across the fold, and M* ~ 1/l^2, T_s ~ 1/l^3 turn
it into a force that grows without bound as the fold sharpens (measured on ROPOS 200 m, alpha = 100:
a 1.04 MN "snap" at the cage on N = 20, 10 MN on finer meshes, each rising within one time step;
docs/dg_solver.md, "Slack with bending"). With b = q the bending terms are polynomials in q: a fold
below the mesh scale carries the bending of its mean line and no more, and the force stays bounded
by EI |q|^2 |q''| as the chord passes through zero.
"""

from tether_sim.numerics.jit import jit_inline
from tether_sim.physics.constitutive import chord_floor
from tether_sim.physics.end_conditions import M_APPLIED, M_INTERIOR, holds_direction, moment_rule
from tether_sim.solvers.dg.elementops import eval_points, eval_traces, project_points, strong_derivative
from tether_sim.solvers.dg.layout import (
    B_DIR, B_M, F_I, F_IDOT, F_MS, I_BENDDAMP, I_KIND0, I_KIND1, I_LAW, I_N, M_I,
    M_IDOT, M_KAP, M_KDOT, M_MS, M_TAU, P_BETA, P_EI, P_TORQUE, P_ZETAB, T_I, T_IDOT, T_MS,
    W_B, W_EDOT, W_I, W_IDOT, W_KAP, W_KDOT, W_L, W_MS, W_NUS, W_Q, W_TAU, W_TV,
)


@jit_inline
def _ldg_fluxes(fl, tr, N, c_fl, c_tr, bias):
    """Interior fluxes 0.5 (u_L + u_R) + bias (u_R - u_L) [Eq. 29 with bias = beta, Eq. 30 with -beta]."""
    for k in range(1, N):
        for c in range(3):
            uL = tr[k - 1, 1, c_tr + c]
            uR = tr[k, 0, c_tr + c]
            fl[k, c_fl + c] = 0.5 * (uL + uR) + bias * (uR - uL)


@jit_inline
def bending_tangent(wq, e, j, floor):
    """b = q / max(l, floor) at Gauss point j of element e into wq[e, j, W_B] (the unit tangent i where
    l >= floor; floor = constitutive.chord_floor(law))."""
    if wq[e, j, W_L] >= floor:
        for c in range(3):
            wq[e, j, W_B + c] = wq[e, j, W_I + c]
    else:
        for c in range(3):
            wq[e, j, W_B + c] = wq[e, j, W_Q + c]


@jit_inline
def ldg_shear_force(prm, iprm, h, V, Pj, D, Lf, Tr, bc, wq, wm, tr, fl):
    """Add the bending shear force T_s to wq[..., W_TV] (see module docstring)."""
    N = iprm[I_N]
    nq = V.shape[0]
    EI = prm[P_EI]
    zb = prm[P_ZETAB]
    beta = prm[P_BETA]
    torque = prm[P_TORQUE]
    damp = iprm[I_BENDDAMP] != 0
    k0 = iprm[I_KIND0]
    k1 = iprm[I_KIND1]
    floor = chord_floor(iprm[I_LAW])
    for e in range(N):
        for j in range(nq):
            bending_tangent(wq, e, j, floor)
        project_points(Pj, wq, e, W_B, wm, M_I, 3)
        eval_traces(Tr, wm, e, M_I, tr, T_I, 3, 1.0)
        if damp:
            for j in range(nq):
                l = wq[e, j, W_L]
                for c in range(3):
                    if l >= floor:
                        wq[e, j, W_IDOT + c] = (wq[e, j, W_NUS + c] - wq[e, j, W_B + c] * wq[e, j, W_EDOT]) / l
                    else:
                        wq[e, j, W_IDOT + c] = wq[e, j, W_NUS + c]
            project_points(Pj, wq, e, W_IDOT, wm, M_IDOT, 3)
            eval_traces(Tr, wm, e, M_IDOT, tr, T_IDOT, 3, 1.0)
    _ldg_fluxes(fl, tr, N, F_I, T_I, beta)
    if damp:
        _ldg_fluxes(fl, tr, N, F_IDOT, T_IDOT, beta)
    for c in range(3):
        if holds_direction(k0):
            fl[0, F_I + c] = bc[0, B_DIR + c]
            fl[0, F_IDOT + c] = 0.0
        else:
            fl[0, F_I + c] = tr[0, 0, T_I + c]
            fl[0, F_IDOT + c] = tr[0, 0, T_IDOT + c]
        if holds_direction(k1):
            fl[N, F_I + c] = bc[1, B_DIR + c]
            fl[N, F_IDOT + c] = 0.0
        else:
            fl[N, F_I + c] = tr[N - 1, 1, T_I + c]
            fl[N, F_IDOT + c] = tr[N - 1, 1, T_IDOT + c]
    for e in range(N):
        strong_derivative(h[e], D, Lf, wm, e, M_I, 1.0, tr, T_I, fl, F_I, wm, M_KAP, 3)
        eval_points(V, wm, e, M_KAP, wq, W_KAP, 3, 1.0)
        if damp:
            strong_derivative(h[e], D, Lf, wm, e, M_IDOT, 1.0, tr, T_IDOT, fl, F_IDOT, wm, M_KDOT, 3)
            eval_points(V, wm, e, M_KDOT, wq, W_KDOT, 3, 1.0)
        for j in range(nq):
            b0 = EI * wq[e, j, W_KAP]
            b1 = EI * wq[e, j, W_KAP + 1]
            b2 = EI * wq[e, j, W_KAP + 2]
            if damp:
                b0 += zb * wq[e, j, W_KDOT]
                b1 += zb * wq[e, j, W_KDOT + 1]
                b2 += zb * wq[e, j, W_KDOT + 2]
            i0 = wq[e, j, W_B]
            i1 = wq[e, j, W_B + 1]
            i2 = wq[e, j, W_B + 2]
            lb = max(wq[e, j, W_L], floor)
            il2 = 1.0 / (lb * lb)
            wq[e, j, W_MS] = (i1 * b2 - i2 * b1 + torque * i0) * il2
            wq[e, j, W_MS + 1] = (i2 * b0 - i0 * b2 + torque * i1) * il2
            wq[e, j, W_MS + 2] = (i0 * b1 - i1 * b0 + torque * i2) * il2
        project_points(Pj, wq, e, W_MS, wm, M_MS, 3)
        eval_traces(Tr, wm, e, M_MS, tr, T_MS, 3, 1.0)
    _ldg_fluxes(fl, tr, N, F_MS, T_MS, -beta)
    for c in range(3):
        if moment_rule(k0) == M_INTERIOR:
            fl[0, F_MS + c] = tr[0, 0, T_MS + c]
        elif moment_rule(k0) == M_APPLIED:
            fl[0, F_MS + c] = -bc[0, B_M + c]
        else:
            fl[0, F_MS + c] = 0.0
        if moment_rule(k1) == M_INTERIOR:
            fl[N, F_MS + c] = tr[N - 1, 1, T_MS + c]
        elif moment_rule(k1) == M_APPLIED:
            fl[N, F_MS + c] = bc[1, B_M + c]
        else:
            fl[N, F_MS + c] = 0.0
    for e in range(N):
        strong_derivative(h[e], D, Lf, wm, e, M_MS, 1.0, tr, T_MS, fl, F_MS, wm, M_TAU, 3)
        eval_points(V, wm, e, M_TAU, wq, W_TAU, 3, 1.0)
        for j in range(nq):
            il = 1.0 / max(wq[e, j, W_L], floor)
            i0 = wq[e, j, W_B]
            i1 = wq[e, j, W_B + 1]
            i2 = wq[e, j, W_B + 2]
            t0 = wq[e, j, W_TAU]
            t1 = wq[e, j, W_TAU + 1]
            t2 = wq[e, j, W_TAU + 2]
            wq[e, j, W_TV] += (i1 * t2 - i2 * t1) * il
            wq[e, j, W_TV + 1] += (i2 * t0 - i0 * t2) * il
            wq[e, j, W_TV + 2] += (i0 * t1 - i1 * t0) * il
