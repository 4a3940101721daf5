"""Nested local DG for the bending shear force [PE2020 Eq. 18-21, 26-30, Table 1].

Given q, l = |q| and d(v/gamma0)/ds at the Gauss points (from kernels.dg_rhs), with the bending tangent b
(below; l_f = 1 for the laws without compression, 0 for the linear law):

    b      = q / l (taut, l >= l_f),  2 q / (1 + l^2) (short chord, l < l_f)
    db/dt  = (dq/dt - b deps/dt) / l (taut), J dq/dt (short chord); dq/dt = d(v/gamma0)/ds
    kappa  = d b / ds        with flux b_hat  [Eq. 26, 29]
    kdot   = d (db/dt) / ds  with flux b_hat-dot [Eq. 27, 29] (only when zeta_b > 0)
    taut:  M* = (b x (EI kappa + zeta_b kdot) + GIp Omega_1 b) / l^2   [Eq. 19-21]
           tau = d M* / ds with flux M*_hat [Eq. 28, 30];  T_s = (1 / l) b x tau   [Eq. 20]
    short: X = EI kappa + zeta_b kdot, Y = dX/ds with flux X_hat (bias -beta, the rules of M*_hat);
           T_s = -J Y,  J = db/dq = g I + g' l i i^T,  g = 2 / (1 + l^2)

T_s is added to the tension vector at the Gauss points. Boundary fluxes per Table 1:
clamped ends impose b_hat = i_BC, b_hat-dot = 0 and take M*_hat (X_hat) from the interior; force ends
impose M*_hat = n M_BC (X_hat = (M*_hat x b) / |b|^2); every other end (prescribed, fixed pin, free, body)
is moment free (M*_hat = 0, X_hat = 0) with b_hat, b_hat-dot from the interior.

**Where the cable is taut or stretched (l >= 1) b = i = q / l: PE2020's equations, bit for bit.**

**Where the chord is shorter than the material** (l < 1, only in slack parts: Eq. 22 carries no
compression), PE2020's stretched form -- the unit tangent q / l and the factors 1/l^2, 1/l -- flips with q
as a chord passes through zero and turns the flip into a force ~ 1/l^3 (a 1.04 MN "snap" at the cage of the
Sec. 6.2 case on N = 20). So there the bending acts on b = g(l) q, a tangent that shrinks with the chord
and meets i at l = 1 with its derivative (g(1) = 1, d(g l)/dl = 0 at l = 1: b is C^1 in q). The shear is
the gradient of the bending energy of b, int EI |b_s|^2 / 2 ds: with T_s = -J^T Y (J symmetric), the work
of T_s on dq/dt is exactly the rate of that energy, on the discrete operators too (the LDG derivatives of
b and X are adjoint with these fluxes), so the bending of a short chord stores and returns energy and
creates none (test_slack_bending.py: dE/dt = 0 to round-off for a slack cable with free ends). At l = 1,
J = I - i i^T and T_s = -(I - i i^T) Y, PE2020's shear to within the l' terms of its 1/l^2 factors.

Why not PE2020's cross-product form with b = q (used until 2026-11-27): b x tau with |b| != 1 is not the
gradient of an energy. Linearised about a straight slack line b = a(s) e_z with a sideways offset w it gives
gamma w_tt = -(EI a^2 w^(3))' + (EI a a_ss w')', i.e. an effective tension EI a a_ss -- a compression wherever the
chord has a maximum or, at a fold, passes through zero (a a_ss < 0). At the cage of the Sec. 6.2 case on
N = 40, where the slack cable falls onto the slower cage and its end chord passes through zero, that was
a push EI a a_ss = -113 kN (EI = 262 kN m^2, a = -0.41, a_ss = 1.06 / m^2 at 6.86 s) on a column whose bending
stiffness there is EI a^2 = 44 kN m^2: the buckling rate P / (2 sqrt(EI a^2 gamma_n)) = 139 1/s (gamma_n =
3.73 kg/m with added mass), e-fold 7.2 ms; measured: the sideways velocity grew e-fold every 7-8 ms (0.03 ->
18 m/s in 48 ms) and the cage recorded a 2.8 MN one-step event (docs/dg_solver.md, "Slack with bending").
The energy form has no such term: for the same offset it gives gamma w_tt = -(EI w_ss)_ss + lower-order terms of g, and a chord that varies along the
line stores energy EI |b_s|^2 / 2 instead of feeding the transverse waves; near l = 1 |b| = 2 l / (1 + l^2)
stays within 1 % of 1 for l > 0.87, so only a collapsing chord feels it.

The torque term (GIp Omega_1) acts where taut only.
"""

from tether_sim.numerics.jit import jit_inline
from tether_sim.physics.constitutive import chord_floor
from tether_sim.physics.end_conditions import M_APPLIED, M_INTERIOR, holds_direction, moment_rule
from tether_sim.solvers.dg.elementops import eval_points, eval_traces, project_points, strong_derivative
from tether_sim.solvers.dg.layout import (
    B_DIR, B_M, F_I, F_IDOT, F_MS, F_SX, I_BENDDAMP, I_KIND0, I_KIND1, I_LAW, I_N, M_I,
    M_IDOT, M_KAP, M_KDOT, M_MS, M_SX, M_SY, M_TAU, P_BETA, P_EI, P_TORQUE, P_ZETAB, T_I, T_IDOT, T_MS, T_SX,
    W_B, W_EDOT, W_I, W_IDOT, W_KAP, W_KDOT, W_L, W_MS, W_NUS, W_Q, W_SY, W_TAU, W_TS, W_TV,
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
def short_chord_map(l):
    """(g, l g'(l)) of the short-chord bending tangent b = g(l) q, g = 2 / (1 + l^2) (module docstring):
    db/dt = J dq/dt with J = g I + l g'(l) i i^T."""
    g = 2.0 / (1.0 + l * l)
    return g, -4.0 * l * l / ((1.0 + l * l) * (1.0 + l * l))


@jit_inline
def short_chord_jt(l, i0, i1, i2, y0, y1, y2):
    """J^T y = g y + l g'(l) (i . y) i for the short-chord map (J symmetric): the bending shear there is
    -J^T Y with Y = d/ds(EI b_s) (module docstring)."""
    g, gl = short_chord_map(l)
    a = gl * (i0 * y0 + i1 * y1 + i2 * y2)
    return g * y0 + a * i0, g * y1 + a * i1, g * y2 + a * i2


@jit_inline
def bending_tangent(wq, e, j, floor):
    """The bending tangent b at Gauss point j of element e into wq[e, j, W_B]: the unit tangent i where
    l >= floor (floor = constitutive.chord_floor(law)), b = g(l) q with g = 2 / (1 + l^2) where the chord is
    short (module docstring); returns True where short."""
    if wq[e, j, W_L] >= floor:
        for c in range(3):
            wq[e, j, W_B + c] = wq[e, j, W_I + c]
        return False
    g, _ = short_chord_map(wq[e, j, W_L])
    for c in range(3):
        wq[e, j, W_B + c] = g * wq[e, j, W_Q + c]
    return True


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
    short = False
    for e in range(N):
        for j in range(nq):
            if bending_tangent(wq, e, j, floor):
                short = True
        project_points(Pj, wq, e, W_B, wm, M_I, 3)
        eval_traces(Tr, wm, e, M_I, tr, T_I, 3, 1.0)
        if damp:
            for j in range(nq):
                l = wq[e, j, W_L]
                if l >= floor:
                    for c in range(3):
                        wq[e, j, W_IDOT + c] = (wq[e, j, W_NUS + c] - wq[e, j, W_B + c] * wq[e, j, W_EDOT]) / l
                else:  # db/dt = J dq/dt, J = g I + g' l i i^T; i . dq/dt = deps/dt
                    g, gl = short_chord_map(l)
                    for c in range(3):
                        wq[e, j, W_IDOT + c] = g * wq[e, j, W_NUS + c] + gl * wq[e, j, W_EDOT] * wq[e, j, W_I + c]
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
    if short:
        _short_chord_shear(iprm, h, V, D, Lf, Tr, bc, wq, wm, tr, fl, EI, zb, damp, beta)
    for e in range(N):
        strong_derivative(h[e], D, Lf, wm, e, M_MS, 1.0, tr, T_MS, fl, F_MS, wm, M_TAU, 3)
        eval_points(V, wm, e, M_TAU, wq, W_TAU, 3, 1.0)
        for j in range(nq):
            l = wq[e, j, W_L]
            if l < floor:  # short chord: T_s = -J^T Y, J = g I + g' l i i^T (module docstring)
                u0, u1, u2 = short_chord_jt(l, wq[e, j, W_I], wq[e, j, W_I + 1], wq[e, j, W_I + 2],
                                            wq[e, j, W_SY], wq[e, j, W_SY + 1], wq[e, j, W_SY + 2])
                t0 = -u0
                t1 = -u1
                t2 = -u2
            else:
                il = 1.0 / l
                i0 = wq[e, j, W_B]
                i1 = wq[e, j, W_B + 1]
                i2 = wq[e, j, W_B + 2]
                u0 = wq[e, j, W_TAU]
                u1 = wq[e, j, W_TAU + 1]
                u2 = wq[e, j, W_TAU + 2]
                t0 = (i1 * u2 - i2 * u1) * il
                t1 = (i2 * u0 - i0 * u2) * il
                t2 = (i0 * u1 - i1 * u0) * il
            wq[e, j, W_TS] = t0
            wq[e, j, W_TS + 1] = t1
            wq[e, j, W_TS + 2] = t2
            wq[e, j, W_TV] += t0
            wq[e, j, W_TV + 1] += t1
            wq[e, j, W_TV + 2] += t2


@jit_inline
def _short_chord_shear(iprm, h, V, D, Lf, Tr, bc, wq, wm, tr, fl, EI, zb, damp, beta):
    """Y = d/ds (EI kappa + zeta_b dkappa/dt) at the Gauss points (W_SY), the shear of the bending energy
    int EI |b'|^2 / 2 ds (module docstring), with the LDG flux of bias -beta (as M*) and the boundary rules of
    M*: moment free ends 0, clamped ends the interior trace, applied moments M_BC = b x X, i.e.
    X_hat = (M*_hat x b) / |b|^2 with b the end's trace of the bending tangent."""
    N = iprm[I_N]
    nm = D.shape[0]
    k0 = iprm[I_KIND0]
    k1 = iprm[I_KIND1]
    for e in range(N):
        for m in range(nm):
            for c in range(3):
                x = EI * wm[e, m, M_KAP + c]
                if damp:
                    x += zb * wm[e, m, M_KDOT + c]
                wm[e, m, M_SX + c] = x
        eval_traces(Tr, wm, e, M_SX, tr, T_SX, 3, 1.0)
    _ldg_fluxes(fl, tr, N, F_SX, T_SX, -beta)
    for end in range(2):
        k = end * N
        e = end * (N - 1)
        rule = moment_rule(k0 if end == 0 else k1)
        if rule == M_INTERIOR:
            for c in range(3):
                fl[k, F_SX + c] = tr[e, end, T_SX + c]
        elif rule == M_APPLIED:
            b0 = tr[e, end, T_I]
            b1 = tr[e, end, T_I + 1]
            b2 = tr[e, end, T_I + 2]
            m0 = fl[k, F_MS]
            m1 = fl[k, F_MS + 1]
            m2 = fl[k, F_MS + 2]
            bb = b0 * b0 + b1 * b1 + b2 * b2
            ib = 1.0 / bb if bb > 1e-300 else 0.0
            fl[k, F_SX] = (m1 * b2 - m2 * b1) * ib
            fl[k, F_SX + 1] = (m2 * b0 - m0 * b2) * ib
            fl[k, F_SX + 2] = (m0 * b1 - m1 * b0) * ib
        else:
            for c in range(3):
                fl[k, F_SX + c] = 0.0
    for e in range(N):
        strong_derivative(h[e], D, Lf, wm, e, M_SX, 1.0, tr, T_SX, fl, F_SX, wm, M_SY, 3)
        eval_points(V, wm, e, M_SY, wq, W_SY, 3, 1.0)
