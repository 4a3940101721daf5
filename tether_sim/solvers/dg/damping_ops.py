"""Compiled pieces of the linear damping operator f_d of implicit_damping.py [PE2020 Eq. 19, 22]:
frozen geometry, strain rates e = i . G v, axial and bending-damping tension vectors, their
divergence through the added mass, end forces, the no-compression clip and released ends.
"""

import math

from tether_sim.numerics.jit import jit
from tether_sim.physics.constitutive import LAW_LINEAR, buckled, chord_floor, elastic_tension
from tether_sim.physics.end_conditions import is_kinematic
from tether_sim.solvers.dg.damping_layout import (
    DP_AN, DP_AT, DP_EA, DP_G0, DP_IP0, DP_LAMBDA, DP_TC0, DP_ZETA, DP_ZETAB, ID_KIND0, ID_LAW, ID_REL0, OP_DIV,
    OP_G, OP_KDOT, OP_TAU, WP_E0, WP_I, WP_IDOT, WP_KDOT, WP_L, WP_MB, WP_NUS, WP_PC, WP_R, WP_TAU, WP_TC, WP_TV,
    WP_X, WP_Z,
)
from tether_sim.solvers.dg.fluxes import unit_tangent
from tether_sim.solvers.dg.ldg import short_chord_jt, short_chord_map


@jit
def damping_geometry(U, V, idp, dprm, wp, tab_eps, tab_T):
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
            # the material is strained where taut, or in capped compression short of the cap
            strained = linear or not buckled(idp[ID_LAW], l - 1.0, dprm[DP_EA], tab_eps, tab_T, wp[e, j, WP_PC])
            wp[e, j, WP_Z] = zeta if strained else 0.0


@jit
def clip_set(idp, dprm, wp, tab_eps, tab_T):
    """No-compression laws [Eq. 22]: T = max(-p_c, T_el + zeta e) (p_c = WP_PC, the compression cap, 0 without
    bending). Where the strain rate e at the start of the step (WP_E0) would take the total below -p_c, the
    damping tension is the constant -p_c - T_el (total -p_c) for the step: Z = 0 there and T_c = -p_c - T_el
    (WP_TC). Returns the number of such points."""
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
                pc = wp[e, j, WP_PC]
                tel = elastic_tension(idp[ID_LAW], wp[e, j, WP_L] - 1.0, dprm[DP_EA], tab_eps, tab_T, pc)
                if tel + zeta * wp[e, j, WP_E0] < -pc:
                    wp[e, j, WP_Z] = 0.0
                    wp[e, j, WP_TC] = -pc - tel
                    nclip += 1
    return nclip


@jit
def release_ends(U, vbc, idp, dprm, bvec, Tr, wp, tab_eps, tab_T):
    """Velocity ends whose total flux T_el+ + T_d+ + n lambda (gamma0 v_BC - v+) would be compressive
    at the start of the step (fluxes.clip_compression clips it to zero in the explicit scheme) are
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
        if not is_kinematic(idp[ID_KIND0 + end]) or idp[ID_LAW] == LAW_LINEAR:
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
        i0, i1, i2, ok = unit_tangent(q0, q1, q2)
        if not ok:
            continue
        a_el = 0.0
        a_d = 0.0
        for j in range(nq):
            t_el = elastic_tension(idp[ID_LAW], wp[e, j, WP_L] - 1.0, dprm[DP_EA], tab_eps, tab_T, wp[e, j, WP_PC])
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
        pc = wp[e, 0, WP_PC]
        if a_el + a_d < -pc:
            idp[ID_REL0 + end] = 1
            nrel += 1
            a = -(a_el + pc) if a_el > -pc else 0.0  # the elastic flux is clipped at -pc by dg_rhs
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
def bending_shear_points(blk, idp, dprm, wp, c_e):
    """Add the bending-damping shear to WP_TV with the bending tangent b of ldg.py: where taut (l >= l_f)
    PE2020's (1/l) b x tau, tau = d/ds(zeta_b b x kdot / l^2), b = i; where the chord is short b = g q,
    g = 2 / (1 + l^2), db/dt = J dq/dt and the shear -J Y, Y = d/ds(zeta_b kdot), J = g I + g' l i i^T
    (ldg.py's energy form; Y with the fluxes of M*, as ldg._short_chord_shear)."""
    N, nq = wp.shape[0], wp.shape[1]
    zb = dprm[DP_ZETAB]
    floor = chord_floor(idp[ID_LAW])
    short = False
    for e in range(N):
        for j in range(nq):
            l = wp[e, j, WP_L]
            if l >= floor:
                il = 1.0 / l
                for c in range(3):
                    wp[e, j, WP_IDOT + c] = (wp[e, j, WP_NUS + c] - wp[e, j, WP_I + c] * wp[e, j, c_e]) * il
            else:  # db/dt = g dq/dt + g' l (i . dq/dt) i, i . dq/dt = the strain rate
                short = True
                g, gl = short_chord_map(l)
                for c in range(3):
                    wp[e, j, WP_IDOT + c] = g * wp[e, j, WP_NUS + c] + gl * wp[e, j, c_e] * wp[e, j, WP_I + c]
    apply_block_op(blk, OP_KDOT, 1, nq, wp, WP_IDOT, 1.0, wp, WP_KDOT)
    for e in range(N):
        for j in range(nq):
            l = wp[e, j, WP_L]
            f = 1.0 if l >= floor else 2.0 * l / (1.0 + l * l)  # |b|
            i0 = wp[e, j, WP_I] * f
            i1 = wp[e, j, WP_I + 1] * f
            i2 = wp[e, j, WP_I + 2] * f
            lb = max(l, floor)
            s = zb / (lb * lb)
            k0 = wp[e, j, WP_KDOT]
            k1 = wp[e, j, WP_KDOT + 1]
            k2 = wp[e, j, WP_KDOT + 2]
            wp[e, j, WP_MB] = s * (i1 * k2 - i2 * k1)
            wp[e, j, WP_MB + 1] = s * (i2 * k0 - i0 * k2)
            wp[e, j, WP_MB + 2] = s * (i0 * k1 - i1 * k0)
    apply_block_op(blk, OP_TAU, 1, nq, wp, WP_MB, 1.0, wp, WP_TAU)
    for e in range(N):
        for j in range(nq):
            l = wp[e, j, WP_L]
            if l < floor:
                continue
            il = 1.0 / l
            i0 = wp[e, j, WP_I]
            i1 = wp[e, j, WP_I + 1]
            i2 = wp[e, j, WP_I + 2]
            t0 = wp[e, j, WP_TAU]
            t1 = wp[e, j, WP_TAU + 1]
            t2 = wp[e, j, WP_TAU + 2]
            wp[e, j, WP_TV] += (i1 * t2 - i2 * t1) * il
            wp[e, j, WP_TV + 1] += (i2 * t0 - i0 * t2) * il
            wp[e, j, WP_TV + 2] += (i0 * t1 - i1 * t0) * il
    if not short:
        return
    for e in range(N):  # X = zeta_b kdot into WP_MB, Y = dX/ds into WP_TAU (the same operator as tau)
        for j in range(nq):
            for c in range(3):
                wp[e, j, WP_MB + c] = zb * wp[e, j, WP_KDOT + c]
    apply_block_op(blk, OP_TAU, 1, nq, wp, WP_MB, 1.0, wp, WP_TAU)
    for e in range(N):
        for j in range(nq):
            l = wp[e, j, WP_L]
            if l >= floor:
                continue
            u0, u1, u2 = short_chord_jt(l, wp[e, j, WP_I], wp[e, j, WP_I + 1], wp[e, j, WP_I + 2],
                                        wp[e, j, WP_TAU], wp[e, j, WP_TAU + 1], wp[e, j, WP_TAU + 2])
            wp[e, j, WP_TV] -= u0
            wp[e, j, WP_TV + 1] -= u1
            wp[e, j, WP_TV + 2] -= u2


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
        if not is_kinematic(idp[ID_KIND0 + end]):
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
        bending_shear_points(blk, idp, dprm, wp, WP_X)
    tension_divergence(blk, Pj, bvec, idp, dprm, wp, dst, c_dst, with_bc)
