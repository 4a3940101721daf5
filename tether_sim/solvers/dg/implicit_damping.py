"""Implicit treatment of the material damping terms of the DG cable (IMEX by Strang splitting).

The axial damping zeta deps/dt [PE2020 Eq. 22] and the bending damping zeta_b kappa-dot [Eq. 19]
are linear in the velocity once the geometry (tangent i, stretch l_eps) is frozen:

    dv/dt|_damp = f_d(v) = Pj AM Div[ Z (i . G v) i  +  (1/l) i x Tau( zeta_b i x Kdot(Pi G v) / l^2 ) ]

with G the DG derivative of v/gamma0 with central fluxes (the boundary velocity at velocity ends),
Pi = (I - i i^T)/l, Kdot and Tau the nested-LDG derivatives (beta-weighted fluxes, Table 1),
Div the strong derivative of the tension vector with the central part of the Lax-Friedrichs
flux, AM the per-point added-mass solve and Z = zeta where the law transmits tension (eps > 0 for
laws without compression, everywhere for the linear law). These are exactly the terms dg_rhs
adds when zeta, zeta_b > 0, so f_elastic(u; zeta = 0) + f_d(u) = f(u) (tested).

The stepper (stepper.py) alternates D(dt/2) E(dt) D(dt/2) with E the explicit SSP-RK3 of the
elastic part and D a step of dv/dt = f_d(v) (consecutive half steps merged). D is the 2-stage,
L-stable, stiffly accurate SDIRK2 (gamma = 1 - 1/sqrt 2): second order, and the unresolved stiff
damping modes are removed (|R(-inf)| = 0) instead of ringing as with the trapezoidal rule.

Two linear-algebra paths (docs/dg_solver.md):

* ``MODE_AXIAL`` (zeta_b = 0): Z (i . G v) is a scalar per Gauss point, so by Woodbury the system
  is solved for the strain rates e (N Q unknowns, block-pentadiagonal Q x Q blocks) instead of v
  (3 (P+1) N unknowns): (I - gamma h K) e = e_0, K = i^T G Pj AM Div Z i assembled analytically
  from precomputed geometry-free block operators.
* ``MODE_GENERAL`` (bending damping): the v-system with block bandwidth 4 elements, assembled by
  probing f_d with coloured unit vectors.

Both use a banded LU without pivoting (the matrix is I plus a dissipative operator times dt).
Boundary conditions: velocity ends (prescribed, fixed, clamped, body) supply v_BC in G, their
damping tension flux is the interior trace; force ends (free, force) carry no damping flux (the
prescribed force is the total); clamped ends have i_hat-dot = 0 and M*_hat = M*+.
"""

import math

import numpy as np

from tether_sim.numerics.jit import jit
from tether_sim.physics.constitutive import LAW_LINEAR, elastic_tension
from tether_sim.solvers.dg.layout import K_FORCE, K_FREE

MODE_EXPLICIT = 0
MODE_AXIAL = 1
MODE_GENERAL = 2

# block operators blk[op, e, d, :, :] acting on element e + d - 2 (d = 0..4)
OP_G = 0  # v modes -> d(v/gamma0)/ds at the Gauss points (columns 0:P+1)
OP_GP = 1  # G Pj: point values -> gradient at points
OP_DIV = 2  # tension vector at points -> dT/ds at points
OP_KDOT = 3  # i-dot at points -> kappa-dot at points (flux bias +beta)
OP_TAU = 4  # M* at points -> tau at points (flux bias -beta)
OP_H = 5  # GP Div (reach 2)
N_OP = 6

# float parameters dprm[...]
DP_ZETA = 0
DP_ZETAB = 1
DP_G0 = 2
DP_AT = 3  # gamma0 / (gamma0 + m_t)
DP_AN = 4  # gamma0 / (gamma0 + m_n)
DP_EA = 5
DP_LAMBDA = 6  # upwind speed of velocity-end fluxes (kernels: max(c, lambda_floor))
DP_TC0 = 7  # (3 + 3) constant damping flux of released ends (runtime, see release_ends)
DP_IP0 = 13  # (3 + 3) trace tangent i+ of released ends (runtime)
DP_LU_H = 19  # gamma h of the stored LU
N_DP = 20

# int parameters idp[...]
ID_MODE = 0
ID_LAW = 1
ID_KIND0 = 2
ID_KIND1 = 3
ID_REACH = 4  # elements coupled by f_d on each side (2 axial, 4 with bending damping)
ID_KL = 5  # half bandwidth of the banded system
ID_REL0 = 6  # (2) velocity end released for this step (no-compression clip of the end flux active)
ID_LU_AGE = 8  # steps since the LU of the strain-rate system was computed (-1: none)
ID_RELF0 = 9  # (2) released flags when it was computed
N_ID = 11
LU_MAX_AGE = 64  # refactor at least this often
LU_TOL = 1e-4  # defect correction accepted if |correction| <= LU_TOL |solution|

# per-point work wp[e, j, ...]
WP_I = 0
WP_L = 3
WP_Z = 4
WP_NUS = 5
WP_TV = 8
WP_R = 11
WP_IDOT = 14
WP_KDOT = 17
WP_MB = 20
WP_TAU = 23
WP_E0 = 26
WP_E1 = 27
WP_E2 = 28
WP_X = 29
WP_TC = 30  # constant damping tension of points where the no-compression clip is active
WP_BC0 = 31  # strain rate caused by that constant force
WP_ZF = 32  # Z when the LU of the strain-rate system was computed
WP_KX = 33  # K x (defect correction): input x
WP_KY = 34  # and output
NWP = 35

# modal work wd[e, k, ...]
WD_F = 0
WD_K1 = 3
WD_Y = 6
WD_P = 9
NWD = 12

# boundary vectors bvec[...]: 0/1 = gradient lift of v_BC at s = 0 / L, 2/3 = trace of the projection
N_BVEC = 4

GAMMA_SDIRK = 1.0 - 1.0 / math.sqrt(2.0)


# ----------------------------------------------------------------------------------- set-up (numpy)
def strong_blocks(ops, h, w_left, w_right, left, right):
    """(N, 3, P+1, P+1) blocks of the modal strong derivative (elementops.strong_derivative) for the
    neighbours d = -1, 0, +1, with interior flux w_left u_L + w_right u_R and end rules
    "trace" (flux = own trace) or "zero" (flux = 0, i.e. a prescribed value moved to the right side)."""
    D, Lf, Tr = np.triu(ops.derivative, 1), ops.lift, ops.trace
    N, nm = len(h), D.shape[0]
    out = np.zeros((N, 3, nm, nm))
    for e in range(N):
        b = 1.0 / h[e]
        out[e, 1] = 2.0 * b * D
        if e < N - 1:
            out[e, 1] += b * (w_left - 1.0) * np.outer(Lf[1], Tr[1])
            out[e, 2] += b * w_right * np.outer(Lf[1], Tr[0])
        elif right == "zero":
            out[e, 1] -= b * np.outer(Lf[1], Tr[1])
        if e > 0:
            out[e, 1] -= b * (w_right - 1.0) * np.outer(Lf[0], Tr[0])
            out[e, 0] -= b * w_left * np.outer(Lf[0], Tr[1])
        elif left == "zero":
            out[e, 1] += b * np.outer(Lf[0], Tr[0])
    return out


def build_operators(ops, h, kinds, gamma0, beta):
    """Geometry-free block operators blk (N_OP, N, 5, Q, Q) and boundary vectors bvec (4, Q)."""
    V, Pj, Tr, Lf = ops.vandermonde, ops.projection, ops.trace, ops.lift
    N, nq, nm = len(h), V.shape[0], V.shape[1]
    force = [k in ("free", "force") for k in kinds]
    clamped = [k == "clamped" for k in kinds]
    vel_rule = ["trace" if f else "zero" for f in force]  # gradient of v: v_BC moved to bvec
    div_rule = ["zero" if f else "trace" for f in force]
    kdot_rule = ["zero" if c else "trace" for c in clamped]
    tau_rule = ["trace" if c else "zero" for c in clamped]
    blk = np.zeros((N_OP, N, 5, nq, nq))
    S = strong_blocks(ops, h, 0.5, 0.5, *vel_rule)
    for e in range(N):
        for d in range(3):
            blk[OP_G, e, d + 1, :, :nm] = V @ S[e, d] / gamma0
            blk[OP_GP, e, d + 1] = V @ S[e, d] @ Pj / gamma0
    for op, wl, wr, rule in ((OP_DIV, 0.5, 0.5, div_rule), (OP_KDOT, 0.5 - beta, 0.5 + beta, kdot_rule),
                             (OP_TAU, 0.5 + beta, 0.5 - beta, tau_rule)):
        S = strong_blocks(ops, h, wl, wr, *rule)
        for e in range(N):
            for d in range(3):
                blk[op, e, d + 1] = V @ S[e, d] @ Pj
    for e in range(N):
        for d1 in (-1, 0, 1):
            e1 = e + d1
            if 0 <= e1 < N:
                for d2 in (-1, 0, 1):
                    if 0 <= e1 + d2 < N:
                        blk[OP_H, e, d1 + d2 + 2] += blk[OP_GP, e, d1 + 2] @ blk[OP_DIV, e1, d2 + 2]
    bvec = np.zeros((N_BVEC, nq))
    if not force[0]:
        bvec[0] = -(V @ Lf[0]) / h[0]
    if not force[1]:
        bvec[1] = (V @ Lf[1]) / h[-1]
    bvec[2] = Tr[0] @ Pj
    bvec[3] = Tr[1] @ Pj
    return np.ascontiguousarray(blk), bvec


class DampingWork:
    """Arrays of the implicit damping step (allocated once; passed to the compiled loop)."""

    def __init__(self, mode, ops, h, kinds, cable, gamma0, m_t, m_n, beta, law_code, kind_codes, lam_bc):
        N, nq, nm = len(h), ops.vandermonde.shape[0], ops.vandermonde.shape[1]
        self.mode = mode
        self.blk, self.bvec = build_operators(ops, h, kinds, gamma0, beta)
        reach = 4 if cable.bending_damping > 0.0 else 2
        if mode == MODE_AXIAL:
            n, kl = N * nq, 3 * nq - 1
        elif mode == MODE_GENERAL:
            n, kl = N * 3 * nm, (reach + 1) * 3 * nm - 1
        else:
            n, kl = 1, 0
        kl = min(kl, n - 1)
        self.dprm = np.zeros(N_DP)
        self.dprm[DP_ZETA], self.dprm[DP_ZETAB], self.dprm[DP_G0] = cable.damping, cable.bending_damping, gamma0
        self.dprm[DP_AT], self.dprm[DP_AN] = gamma0 / (gamma0 + m_t), gamma0 / (gamma0 + m_n)
        self.dprm[DP_EA] = cable.EA
        self.dprm[DP_LAMBDA] = lam_bc
        self.idp = np.zeros(N_ID, dtype=np.int64)
        self.idp[ID_MODE], self.idp[ID_LAW] = mode, law_code
        self.idp[ID_KIND0], self.idp[ID_KIND1] = kind_codes
        self.idp[ID_REACH], self.idp[ID_KL] = reach, kl
        self.idp[ID_LU_AGE] = -1
        self.wp = np.zeros((N, nq, NWP))
        self.wd = np.zeros((N, nm, NWD))
        self.band = np.zeros((n, 2 * kl + 1))
        self.vec = np.zeros((4, max(n, kl + 1)))
        self.tmp = np.zeros((2, N, 3, nq, nq))
        self.fdamp = np.zeros((2, 4))


# ----------------------------------------------------------------------------------- kernels
@jit
def is_force_kind(kind):
    return kind == K_FREE or kind == K_FORCE


@jit
def damping_geometry(U, V, idp, dprm, wp):
    """Frozen geometry at the Gauss points: tangent i, stretch l, damping coefficient Z."""
    N, nm = U.shape[0], U.shape[1]
    nq = V.shape[0]
    zeta = dprm[DP_ZETA]
    linear = idp[ID_LAW] == LAW_LINEAR
    for e in range(N):
        for j in range(nq):
            q0 = 0.0
            q1 = 0.0
            q2 = 0.0
            for k in range(nm):
                q0 += V[j, k] * U[e, k, 0]
                q1 += V[j, k] * U[e, k, 1]
                q2 += V[j, k] * U[e, k, 2]
            l = math.sqrt(q0 * q0 + q1 * q1 + q2 * q2)
            il = 1.0 / l if l > 1e-300 else 0.0
            wp[e, j, WP_I] = q0 * il
            wp[e, j, WP_I + 1] = q1 * il
            wp[e, j, WP_I + 2] = q2 * il
            wp[e, j, WP_L] = l
            wp[e, j, WP_Z] = zeta if (linear or l > 1.0) else 0.0


@jit
def clip_set(idp, dprm, wp, tab_eps, tab_T):
    """No-compression laws [Eq. 22]: T = max(0, T_el + zeta e). Where the strain rate e at the start
    of the step (WP_E0) would make the total compressive, the damping tension is the constant -T_el
    (total 0) for the step: Z = 0 there and T_c = -T_el (WP_TC). Returns the number of such points."""
    N, nq = wp.shape[0], wp.shape[1]
    nclip = 0
    if idp[ID_LAW] == LAW_LINEAR:
        for e in range(N):
            for j in range(nq):
                wp[e, j, WP_TC] = 0.0
        return 0
    zeta = dprm[DP_ZETA]
    for e in range(N):
        for j in range(nq):
            wp[e, j, WP_TC] = 0.0
            if wp[e, j, WP_Z] > 0.0:
                tel = elastic_tension(idp[ID_LAW], wp[e, j, WP_L] - 1.0, dprm[DP_EA], tab_eps, tab_T)
                if tel + zeta * wp[e, j, WP_E0] < 0.0:
                    wp[e, j, WP_Z] = 0.0
                    wp[e, j, WP_TC] = -tel
                    nclip += 1
    return nclip


@jit
def release_ends(U, vbc, idp, dprm, bvec, Tr, wp, tab_eps, tab_T):
    """Velocity ends whose total flux T_el+ + T_d+ + n lambda (gamma0 v_BC - v+) would be compressive
    at the start of the step (kernels.clip_compression clips it to zero in the explicit scheme) are
    released for the step: their damping flux is the constant -max(a_el, 0) i+ (DP_TC), so that
    elastic (clipped by dg_rhs) + damping flux has no axial part, instead of the trace of the
    damping tension (whose stiff impulse would otherwise enforce v_BC on a slack end).
    Uses WP_E0 and WP_TC (after clip_set). Returns the number of released ends."""
    N, nq = wp.shape[0], wp.shape[1]
    nm = U.shape[1]
    g0 = dprm[DP_G0]
    lam = dprm[DP_LAMBDA]
    nrel = 0
    for end in range(2):
        idp[ID_REL0 + end] = 0
        if is_force_kind(idp[ID_KIND0 + end]) or idp[ID_LAW] == LAW_LINEAR:
            continue
        e = end * (N - 1)
        sgn = 1.0 if end == 0 else -1.0
        q0 = 0.0
        q1 = 0.0
        q2 = 0.0
        for k in range(nm):
            q0 += Tr[end, k] * U[e, k, 0]
            q1 += Tr[end, k] * U[e, k, 1]
            q2 += Tr[end, k] * U[e, k, 2]
        lq = math.sqrt(q0 * q0 + q1 * q1 + q2 * q2)
        if lq <= 1e-300:
            continue
        i0 = q0 / lq
        i1 = q1 / lq
        i2 = q2 / lq
        a_el = 0.0
        a_d = 0.0
        for j in range(nq):
            t_el = elastic_tension(idp[ID_LAW], wp[e, j, WP_L] - 1.0, dprm[DP_EA], tab_eps, tab_T)
            t_d = wp[e, j, WP_Z] * wp[e, j, WP_E0] + wp[e, j, WP_TC]
            ii = wp[e, j, WP_I] * i0 + wp[e, j, WP_I + 1] * i1 + wp[e, j, WP_I + 2] * i2
            a_el += bvec[2 + end, j] * t_el * ii
            a_d += bvec[2 + end, j] * t_d * ii
        vrel = 0.0
        for c in range(3):
            vc = 0.0
            for k in range(nm):
                vc += Tr[end, k] * U[e, k, 3 + c]
            ic = i0 if c == 0 else (i1 if c == 1 else i2)
            vrel += (g0 * vbc[end, 3 + c] - vc) * ic
        a_el -= sgn * lam * vrel
        if a_el + a_d < 0.0:
            idp[ID_REL0 + end] = 1
            nrel += 1
            a = -a_el if a_el > 0.0 else 0.0
            dprm[DP_TC0 + 3 * end] = a * i0
            dprm[DP_TC0 + 3 * end + 1] = a * i1
            dprm[DP_TC0 + 3 * end + 2] = a * i2
            dprm[DP_IP0 + 3 * end] = i0
            dprm[DP_IP0 + 3 * end + 1] = i1
            dprm[DP_IP0 + 3 * end + 2] = i2
    return nrel


@jit
def apply_block_op(blk, op, reach, ncol, src, c_src, scale, dst, c_dst):
    """dst[e, j, c_dst:+3] = scale sum_{|d| <= reach} blk[op, e, d] @ src[e + d, :ncol, c_src:+3]."""
    N, nq = dst.shape[0], dst.shape[1]
    for e in range(N):
        for j in range(nq):
            s0 = 0.0
            s1 = 0.0
            s2 = 0.0
            for d in range(2 - reach, 3 + reach):
                ee = e + d - 2
                if ee < 0 or ee >= N:
                    continue
                for m in range(ncol):
                    a = blk[op, e, d, j, m]
                    s0 += a * src[ee, m, c_src]
                    s1 += a * src[ee, m, c_src + 1]
                    s2 += a * src[ee, m, c_src + 2]
            dst[e, j, c_dst] = scale * s0
            dst[e, j, c_dst + 1] = scale * s1
            dst[e, j, c_dst + 2] = scale * s2


@jit
def strain_rates(src, c_src, with_bc, vbc, blk, bvec, wp, c_out):
    """d(v/gamma0)/ds at the points (WP_NUS) and the strain rate e = i . that (channel c_out)."""
    N, nq = wp.shape[0], wp.shape[1]
    nm = src.shape[1]
    apply_block_op(blk, OP_G, 1, nm, src, c_src, 1.0, wp, WP_NUS)
    if with_bc:
        for j in range(nq):
            for c in range(3):
                wp[0, j, WP_NUS + c] += bvec[0, j] * vbc[0, 3 + c]
                wp[N - 1, j, WP_NUS + c] += bvec[1, j] * vbc[1, 3 + c]
    for e in range(N):
        for j in range(nq):
            wp[e, j, c_out] = (wp[e, j, WP_I] * wp[e, j, WP_NUS] + wp[e, j, WP_I + 1] * wp[e, j, WP_NUS + 1]
                               + wp[e, j, WP_I + 2] * wp[e, j, WP_NUS + 2])


@jit
def axial_tension_points(wp, c_e, with_const):
    """Damping tension vector (Z e + T_c) i at the points (WP_TV); T_c only if with_const."""
    N, nq = wp.shape[0], wp.shape[1]
    for e in range(N):
        for j in range(nq):
            t = wp[e, j, WP_Z] * wp[e, j, c_e]
            if with_const:
                t += wp[e, j, WP_TC]
            for c in range(3):
                wp[e, j, WP_TV + c] = t * wp[e, j, WP_I + c]


@jit
def bending_shear_points(blk, dprm, wp, c_e):
    """Add the bending-damping shear (1/l) i x tau, tau = d/ds(zeta_b i x kdot / l^2), to WP_TV."""
    N, nq = wp.shape[0], wp.shape[1]
    zb = dprm[DP_ZETAB]
    for e in range(N):
        for j in range(nq):
            il = 1.0 / wp[e, j, WP_L]
            for c in range(3):
                wp[e, j, WP_IDOT + c] = (wp[e, j, WP_NUS + c] - wp[e, j, WP_I + c] * wp[e, j, c_e]) * il
    apply_block_op(blk, OP_KDOT, 1, nq, wp, WP_IDOT, 1.0, wp, WP_KDOT)
    for e in range(N):
        for j in range(nq):
            i0 = wp[e, j, WP_I]
            i1 = wp[e, j, WP_I + 1]
            i2 = wp[e, j, WP_I + 2]
            s = zb / (wp[e, j, WP_L] * wp[e, j, WP_L])
            k0 = wp[e, j, WP_KDOT]
            k1 = wp[e, j, WP_KDOT + 1]
            k2 = wp[e, j, WP_KDOT + 2]
            wp[e, j, WP_MB] = s * (i1 * k2 - i2 * k1)
            wp[e, j, WP_MB + 1] = s * (i2 * k0 - i0 * k2)
            wp[e, j, WP_MB + 2] = s * (i0 * k1 - i1 * k0)
    apply_block_op(blk, OP_TAU, 1, nq, wp, WP_MB, 1.0, wp, WP_TAU)
    for e in range(N):
        for j in range(nq):
            il = 1.0 / wp[e, j, WP_L]
            i0 = wp[e, j, WP_I]
            i1 = wp[e, j, WP_I + 1]
            i2 = wp[e, j, WP_I + 2]
            t0 = wp[e, j, WP_TAU]
            t1 = wp[e, j, WP_TAU + 1]
            t2 = wp[e, j, WP_TAU + 2]
            wp[e, j, WP_TV] += (i1 * t2 - i2 * t1) * il
            wp[e, j, WP_TV + 1] += (i2 * t0 - i0 * t2) * il
            wp[e, j, WP_TV + 2] += (i0 * t1 - i1 * t0) * il


@jit
def tension_divergence(blk, Pj, bvec, idp, dprm, wp, dst, c_dst, with_const):
    """dst modes = Pj AM Div(WP_TV): the damping force per metre (dv/dt) from the tension vector.

    At a released velocity end (release_ends) the axial part of the flux is the constant DP_TC (only
    if with_const) instead of the trace: Div gets bvec[end] (flux - (trace . i+) i+) on the end element."""
    N, nq = wp.shape[0], wp.shape[1]
    nm = dst.shape[1]
    at = dprm[DP_AT]
    an = dprm[DP_AN]
    apply_block_op(blk, OP_DIV, 1, nq, wp, WP_TV, 1.0, wp, WP_R)
    for end in range(2):
        if idp[ID_REL0 + end] != 0:
            e = end * (N - 1)
            ta = 0.0  # axial part of the trace (the clip removes only that)
            for c in range(3):
                tr = 0.0
                for m in range(nq):
                    tr += bvec[2 + end, m] * wp[e, m, WP_TV + c]
                ta += tr * dprm[DP_IP0 + 3 * end + c]
            for c in range(3):
                jump = (dprm[DP_TC0 + 3 * end + c] if with_const else 0.0) - ta * dprm[DP_IP0 + 3 * end + c]
                for j in range(nq):
                    wp[e, j, WP_R + c] += bvec[end, j] * jump
    for e in range(N):
        for j in range(nq):
            i0 = wp[e, j, WP_I]
            i1 = wp[e, j, WP_I + 1]
            i2 = wp[e, j, WP_I + 2]
            r0 = wp[e, j, WP_R]
            r1 = wp[e, j, WP_R + 1]
            r2 = wp[e, j, WP_R + 2]
            ft = (at - an) * (r0 * i0 + r1 * i1 + r2 * i2)
            wp[e, j, WP_R] = an * r0 + ft * i0
            wp[e, j, WP_R + 1] = an * r1 + ft * i1
            wp[e, j, WP_R + 2] = an * r2 + ft * i2
        for k in range(nm):
            for c in range(3):
                s = 0.0
                for j in range(nq):
                    s += Pj[k, j] * wp[e, j, WP_R + c]
                dst[e, k, c_dst + c] = s


@jit
def end_damping_forces(idp, dprm, bvec, U, Tr, wp, fdamp):
    """fdamp[end] = (force by the cable on the end (3), axial tension) of the damping tension WP_TV:
    -n T_hat with T_hat the trace of its projection at velocity ends, 0 at force ends."""
    N, nq = wp.shape[0], wp.shape[1]
    nm = U.shape[1]
    for end in range(2):
        for c in range(4):
            fdamp[end, c] = 0.0
        if is_force_kind(idp[ID_KIND0 + end]):
            continue
        e = end * (N - 1)
        sgn = 1.0 if end == 0 else -1.0
        q = 0.0
        ql = 0.0
        for c in range(3):
            s = 0.0
            for j in range(nq):
                s += bvec[2 + end, j] * wp[e, j, WP_TV + c]
            fdamp[end, c] = sgn * s
            qc = 0.0
            for k in range(nm):
                qc += Tr[end, k] * U[e, k, c]
            q += s * qc
            ql += qc * qc
        fdamp[end, 3] = q / math.sqrt(ql) if ql > 0.0 else 0.0
        if idp[ID_REL0 + end] != 0:  # released: axial part replaced by the constant flux
            ta = 0.0
            for c in range(3):
                ta += sgn * fdamp[end, c] * dprm[DP_IP0 + 3 * end + c]
            for c in range(3):
                ic = dprm[DP_IP0 + 3 * end + c]
                fdamp[end, c] += sgn * (dprm[DP_TC0 + 3 * end + c] - ta * ic)
            fdamp[end, 3] = 0.0
            for c in range(3):
                fdamp[end, 3] += sgn * fdamp[end, c] * dprm[DP_IP0 + 3 * end + c]


@jit
def damping_force(src, c_src, with_bc, vbc, idp, dprm, blk, bvec, Pj, wp, dst, c_dst):
    """f_d(v) on the modes for v = src[..., c_src:+3] with the frozen geometry in wp (see module doc);
    with_bc = False gives the homogeneous part (v_BC = 0, no clip constant) used to build the matrix."""
    strain_rates(src, c_src, with_bc, vbc, blk, bvec, wp, WP_X)
    axial_tension_points(wp, WP_X, with_bc)
    if dprm[DP_ZETAB] > 0.0:
        bending_shear_points(blk, dprm, wp, WP_X)
    tension_divergence(blk, Pj, bvec, idp, dprm, wp, dst, c_dst, with_bc)


@jit
def band_factor(A, n, kl, row):
    """In-place LU (no pivoting) of the band matrix A[i, j - i + kl], half bandwidth kl (row: work
    vector of length >= kl + 1 holding the pivot row, so that the update loop vectorises)."""
    for k in range(n - 1):
        inv = 1.0 / A[k, kl]
        last = min(n - 1, k + kl)
        m = last - k
        for j in range(m):
            row[j] = A[k, kl + 1 + j]
        for i in range(k + 1, last + 1):
            li = A[i, k - i + kl] * inv
            A[i, k - i + kl] = li
            o = k + 1 - i + kl
            for j in range(m):
                A[i, o + j] -= li * row[j]


@jit
def band_solve(A, n, kl, x, col):
    """Solve (LU) y = x[col] in place with the factors of band_factor."""
    for i in range(n):
        s = x[col, i]
        for j in range(max(0, i - kl), i):
            s -= A[i, j - i + kl] * x[col, j]
        x[col, i] = s
    for i in range(n - 1, -1, -1):
        s = x[col, i]
        for j in range(i + 1, min(n, i + kl + 1)):
            s -= A[i, j - i + kl] * x[col, j]
        x[col, i] = s / A[i, kl]


@jit
def _dot_i(wp, e, j, e2, j2):
    return (wp[e, j, WP_I] * wp[e2, j2, WP_I] + wp[e, j, WP_I + 1] * wp[e2, j2, WP_I + 1]
            + wp[e, j, WP_I + 2] * wp[e2, j2, WP_I + 2])


@jit
def assemble_axial(blk, bvec, idp, dprm, wp, gh, A, kl, tmp):
    """A = I - gh K with K = i^T G Pj AM Div Z i on the strain rates at the points (e, j):

        K = a_n (H o i_j . i_jj) Z_jj + (a_t - a_n) X Y,
        X[(e,j), (e1,m)] = GP[e,e1][j,m] i_j . i_m,   Y[(e1,m), (e2,jj)] = Div[e1,e2][m,jj] i_m . i_jj Z_jj

    (AM = a_n I + (a_t - a_n) i i^T; H = GP Div precomputed). tmp (2, N, 3, Q, Q) holds X and Y."""
    N, nq = wp.shape[0], wp.shape[1]
    at = dprm[DP_AT]
    an = dprm[DP_AN]
    aniso = at != an
    for r in range(A.shape[0]):
        for c in range(A.shape[1]):
            A[r, c] = 0.0
    for e in range(N):
        for d in range(5):
            e2 = e + d - 2
            if e2 < 0 or e2 >= N:
                continue
            for j in range(nq):
                o = e2 * nq - (e * nq + j) + kl
                for jj in range(nq):
                    A[e * nq + j, o + jj] = -gh * an * _dot_i(wp, e, j, e2, jj) * blk[OP_H, e, d, j, jj] * wp[e2, jj, WP_Z]
        if aniso:
            for d in range(1, 4):
                e2 = e + d - 2
                if e2 < 0 or e2 >= N:
                    continue
                for j in range(nq):
                    for m in range(nq):
                        tmp[0, e, d - 1, j, m] = -gh * (at - an) * blk[OP_GP, e, d, j, m] * _dot_i(wp, e, j, e2, m)
                        tmp[1, e, d - 1, j, m] = blk[OP_DIV, e, d, j, m] * _dot_i(wp, e, j, e2, m) * wp[e2, m, WP_Z]
    if aniso:
        for e in range(N):
            for d1 in range(3):
                e1 = e + d1 - 1
                if e1 < 0 or e1 >= N:
                    continue
                for d2 in range(3):
                    e2 = e1 + d2 - 1
                    if e2 < 0 or e2 >= N:
                        continue
                    for j in range(nq):
                        r = e * nq + j
                        o = e2 * nq - r + kl
                        for m in range(nq):
                            x = tmp[0, e, d1, j, m]
                            if x != 0.0:
                                for jj in range(nq):
                                    A[r, o + jj] += x * tmp[1, e1, d2, m, jj]
    for end in range(2):
        if idp[ID_REL0 + end] != 0:
            release_correction(blk, bvec, dprm, wp, gh, A, kl, end)
    for r in range(A.shape[0]):
        A[r, kl] += 1.0


@jit
def release_correction(blk, bvec, dprm, wp, gh, A, kl, end):
    """K of a released end: Div of the end element loses the axial part of the trace flux, a rank-one
    change; K += -GP[e, e_end] (i_j^T AM_m i+) (i+ . i_jj) bvec[end]_m bvec[2 + end]_jj Z_jj."""
    N, nq = wp.shape[0], wp.shape[1]
    at = dprm[DP_AT]
    an = dprm[DP_AN]
    ee = end * (N - 1)
    for e in range(max(0, ee - 1), min(N, ee + 2)):
        d = ee - e + 2
        for j in range(nq):
            r = e * nq + j
            o = ee * nq - r + kl
            for jj in range(nq):
                p0 = dprm[DP_IP0 + 3 * end]
                p1 = dprm[DP_IP0 + 3 * end + 1]
                p2 = dprm[DP_IP0 + 3 * end + 2]
                zt = wp[ee, jj, WP_Z] * bvec[2 + end, jj] * (
                    p0 * wp[ee, jj, WP_I] + p1 * wp[ee, jj, WP_I + 1] + p2 * wp[ee, jj, WP_I + 2])
                if zt == 0.0:
                    continue
                dj = wp[e, j, WP_I] * p0 + wp[e, j, WP_I + 1] * p1 + wp[e, j, WP_I + 2] * p2
                s = 0.0
                for m in range(nq):
                    gb = blk[OP_GP, e, d, j, m] * bvec[end, m]
                    mp = wp[ee, m, WP_I] * p0 + wp[ee, m, WP_I + 1] * p1 + wp[ee, m, WP_I + 2] * p2
                    s += gb * (an * dj + (at - an) * _dot_i(wp, e, j, ee, m) * mp)
                A[r, o + jj] += gh * s * zt


@jit
def axial_step(hs, U, vbc, idp, dprm, blk, bvec, V, Pj, Tr, tab_eps, tab_T, wp, wd, band, vec, tmp, fdamp):
    """SDIRK2 step of size hs of dv/dt = f_d(v) = C (Z e(v) + T_c) (axial damping only), solved for
    the strain rates e at the points (see module doc; T_c: clip_set)."""
    N, nq = wp.shape[0], wp.shape[1]
    nm = U.shape[1]
    kl = idp[ID_KL]
    g = GAMMA_SDIRK
    damping_geometry(U, V, idp, dprm, wp)
    strain_rates(U, 3, True, vbc, blk, bvec, wp, WP_E0)
    nclip = clip_set(idp, dprm, wp, tab_eps, tab_T)
    nclip += release_ends(U, vbc, idp, dprm, bvec, Tr, wp, tab_eps, tab_T)
    if nclip > 0:  # strain rate per unit time of the constant force: B c0 (WP_BC0)
        for e in range(N):
            for j in range(nq):
                for c in range(3):
                    wp[e, j, WP_TV + c] = wp[e, j, WP_TC] * wp[e, j, WP_I + c]
        tension_divergence(blk, Pj, bvec, idp, dprm, wp, wd, WD_P, True)
        strain_rates(wd, WD_P, False, vbc, blk, bvec, wp, WP_BC0)
    else:
        for e in range(N):
            for j in range(nq):
                wp[e, j, WP_BC0] = 0.0
    gh = g * hs
    exact = not _lu_valid(idp, dprm, wp, gh)
    if exact:
        _refactor(blk, bvec, idp, dprm, wp, gh, band, kl, tmp, vec)
    _rhs_stage1(wp, gh, vec)
    if not _stage_solve(0, exact, gh, Pj, vbc, idp, dprm, blk, bvec, wp, wd, band, kl, vec):
        exact = True
        _refactor(blk, bvec, idp, dprm, wp, gh, band, kl, tmp, vec)
        _rhs_stage1(wp, gh, vec)
        _stage_solve(0, True, gh, Pj, vbc, idp, dprm, blk, bvec, wp, wd, band, kl, vec)
    for e in range(N):
        for j in range(nq):
            wp[e, j, WP_E1] = vec[0, e * nq + j]
    _rhs_stage2(wp, hs, g, vec)
    if not _stage_solve(1, exact, gh, Pj, vbc, idp, dprm, blk, bvec, wp, wd, band, kl, vec):
        _refactor(blk, bvec, idp, dprm, wp, gh, band, kl, tmp, vec)
        _rhs_stage2(wp, hs, g, vec)
        _stage_solve(1, True, gh, Pj, vbc, idp, dprm, blk, bvec, wp, wd, band, kl, vec)
    idp[ID_LU_AGE] += 1
    for e in range(N):
        for j in range(nq):
            wp[e, j, WP_E2] = vec[1, e * nq + j]
            wp[e, j, WP_X] = (1.0 - g) * wp[e, j, WP_E1] + g * wp[e, j, WP_E2]
    axial_tension_points(wp, WP_X, True)
    tension_divergence(blk, Pj, bvec, idp, dprm, wp, wd, WD_F, True)
    for e in range(N):
        for k in range(nm):
            for c in range(3):
                U[e, k, 3 + c] += hs * wd[e, k, WD_F + c]
    axial_tension_points(wp, WP_E2, True)  # stiffly accurate: E2 is the strain rate of the new state
    end_damping_forces(idp, dprm, bvec, U, Tr, wp, fdamp)


@jit
def _lu_valid(idp, dprm, wp, gh):
    """The stored LU was built for this step size, active set and released ends, recently enough."""
    if idp[ID_LU_AGE] < 0 or idp[ID_LU_AGE] >= LU_MAX_AGE or dprm[DP_LU_H] != gh:
        return False
    if idp[ID_REL0] != idp[ID_RELF0] or idp[ID_REL0 + 1] != idp[ID_RELF0 + 1]:
        return False
    N, nq = wp.shape[0], wp.shape[1]
    for e in range(N):
        for j in range(nq):
            if wp[e, j, WP_Z] != wp[e, j, WP_ZF]:
                return False
    return True


@jit
def _refactor(blk, bvec, idp, dprm, wp, gh, band, kl, tmp, vec):
    """Assemble and factor I - gh K for the present geometry; remember what it was built for."""
    N, nq = wp.shape[0], wp.shape[1]
    assemble_axial(blk, bvec, idp, dprm, wp, gh, band, kl, tmp)
    band_factor(band, N * nq, kl, vec[2])
    dprm[DP_LU_H] = gh
    idp[ID_RELF0] = idp[ID_REL0]
    idp[ID_RELF0 + 1] = idp[ID_REL0 + 1]
    idp[ID_LU_AGE] = 0
    for e in range(N):
        for j in range(nq):
            wp[e, j, WP_ZF] = wp[e, j, WP_Z]


@jit
def _rhs_stage1(wp, gh, vec):
    N, nq = wp.shape[0], wp.shape[1]
    for e in range(N):
        for j in range(nq):
            vec[0, e * nq + j] = wp[e, j, WP_E0] + gh * wp[e, j, WP_BC0]


@jit
def _rhs_stage2(wp, hs, g, vec):
    N, nq = wp.shape[0], wp.shape[1]
    c1 = (1.0 - g) / g
    for e in range(N):
        for j in range(nq):
            e0 = wp[e, j, WP_E0]
            bc0 = wp[e, j, WP_BC0]
            vec[1, e * nq + j] = e0 + hs * bc0 + c1 * (wp[e, j, WP_E1] - e0 - g * hs * bc0)


@jit
def _stage_solve(col, exact, gh, Pj, vbc, idp, dprm, blk, bvec, wp, wd, band, kl, vec):
    """vec[col]: right-hand side -> solution of (I - gh K) x = rhs with the stored LU. If that LU is
    not exact for the present geometry, one defect correction with K applied matrix-free (K x =
    i . G Pj AM Div(Z x i)); returns False when the correction exceeds LU_TOL of the solution."""
    N, nq = wp.shape[0], wp.shape[1]
    n = N * nq
    for r in range(n):
        vec[3, r] = vec[col, r]
    band_solve(band, n, kl, vec, col)
    if exact:
        return True
    for e in range(N):
        for j in range(nq):
            wp[e, j, WP_KX] = vec[col, e * nq + j]
    axial_tension_points(wp, WP_KX, False)
    tension_divergence(blk, Pj, bvec, idp, dprm, wp, wd, WD_P, False)
    strain_rates(wd, WD_P, False, vbc, blk, bvec, wp, WP_KY)
    for e in range(N):
        for j in range(nq):
            r = e * nq + j
            vec[3, r] = vec[3, r] - vec[col, r] + gh * wp[e, j, WP_KY]
    band_solve(band, n, kl, vec, 3)
    nd = 0.0
    nx = 0.0
    for r in range(n):
        vec[col, r] += vec[3, r]
        nd = max(nd, abs(vec[3, r]))
        nx = max(nx, abs(vec[col, r]))
    return nd <= LU_TOL * nx


@jit
def general_step(hs, U, vbc, idp, dprm, blk, bvec, V, Pj, Tr, tab_eps, tab_T, wp, wd, band, vec, fdamp):
    """SDIRK2 step of size hs of dv/dt = f_d(v) (axial and bending damping) on the v-system,
    its matrix built by probing f_d with unit vectors coloured every 2 reach + 1 elements."""
    N, nm = U.shape[0], U.shape[1]
    b = 3 * nm
    n = N * b
    kl = idp[ID_KL]
    reach = idp[ID_REACH]
    period = 2 * reach + 1
    g = GAMMA_SDIRK
    gh = g * hs
    damping_geometry(U, V, idp, dprm, wp)
    strain_rates(U, 3, True, vbc, blk, bvec, wp, WP_E0)
    clip_set(idp, dprm, wp, tab_eps, tab_T)
    release_ends(U, vbc, idp, dprm, bvec, Tr, wp, tab_eps, tab_T)
    for r in range(band.shape[0]):
        for c in range(band.shape[1]):
            band[r, c] = 0.0
    for colour in range(min(period, N)):
        for c in range(3):
            for k in range(nm):
                for e in range(N):
                    for kk in range(nm):
                        for cc in range(3):
                            wd[e, kk, WD_P + cc] = 0.0
                for e in range(colour, N, period):
                    wd[e, k, WD_P + c] = 1.0
                damping_force(wd, WD_P, False, vbc, idp, dprm, blk, bvec, Pj, wp, wd, WD_F)
                for e in range(colour, N, period):
                    col = e * b + c * nm + k
                    for ee in range(max(0, e - reach), min(N, e + reach + 1)):
                        for cc in range(3):
                            for kk in range(nm):
                                row = ee * b + cc * nm + kk
                                band[row, col - row + kl] = -gh * wd[ee, kk, WD_F + cc]
    for r in range(n):
        band[r, kl] += 1.0
    band_factor(band, n, kl, vec[2])
    damping_force(U, 3, True, vbc, idp, dprm, blk, bvec, Pj, wp, wd, WD_F)
    for e in range(N):
        for c in range(3):
            for k in range(nm):
                vec[0, e * b + c * nm + k] = wd[e, k, WD_F + c]
    band_solve(band, n, kl, vec, 0)
    for e in range(N):
        for c in range(3):
            for k in range(nm):
                k1 = vec[0, e * b + c * nm + k]
                wd[e, k, WD_K1 + c] = k1
                wd[e, k, WD_Y + c] = U[e, k, 3 + c] + (1.0 - g) * hs * k1
    damping_force(wd, WD_Y, True, vbc, idp, dprm, blk, bvec, Pj, wp, wd, WD_F)
    for e in range(N):
        for c in range(3):
            for k in range(nm):
                vec[1, e * b + c * nm + k] = wd[e, k, WD_F + c]
    band_solve(band, n, kl, vec, 1)
    for e in range(N):
        for c in range(3):
            for k in range(nm):
                U[e, k, 3 + c] += hs * ((1.0 - g) * wd[e, k, WD_K1 + c] + g * vec[1, e * b + c * nm + k])
    damping_force(U, 3, True, vbc, idp, dprm, blk, bvec, Pj, wp, wd, WD_F)
    end_damping_forces(idp, dprm, bvec, U, Tr, wp, fdamp)


@jit
def damping_step(hs, U, vbc, idp, dprm, blk, bvec, V, Pj, Tr, tab_eps, tab_T, wp, wd, band, vec, tmp, fdamp):
    """One implicit step of size hs of the damping terms (nothing in explicit mode)."""
    mode = idp[ID_MODE]
    if mode == MODE_AXIAL:
        axial_step(hs, U, vbc, idp, dprm, blk, bvec, V, Pj, Tr, tab_eps, tab_T, wp, wd, band, vec, tmp, fdamp)
    elif mode == MODE_GENERAL:
        general_step(hs, U, vbc, idp, dprm, blk, bvec, V, Pj, Tr, tab_eps, tab_T, wp, wd, band, vec, fdamp)
