"""Analytic derivatives of the distributed environment force of kernels.external_force [PE2020 Eq. 13-17]:
buoyant weight (constant), Morison drag with sqrt(1+eps), added mass, depth-varying current (through the
alpha_f-level height z(v), kernels.height_at_alpha_f), seabed contact [PE2020 Eq. 15-16] and the free
surface (wetted fraction phi(z(v) - eta) blending water and air) and waves (kernels.wave_state).

The wave kinematics (u_w, a_w, eta) are taken at the alpha_f-level position, which moves with v; their
spatial gradient times that motion (k u_w alpha_f dt gamma / alpha_m: ~1e-4 of the drag's own slope at
k = 0.1 1/m, dt = 0.01 s) is left out of dF/dv. Newton then solves the same residual with a Jacobian
that is off by that much (docs/hybrid_solver.md "Waves").

external_force_jac gives F and dF/dv, dF/dt, dF/da (3x3) and dF/deps (3) at one point. At the kinks of
|x|, max(.,0) and of the piecewise-linear current table it takes the derivative of the branch that the
point is on (a forward difference takes the branch on the side of its step; the two differ only on a
set of measure zero). Tested against forward differences in test/solvers/hybrid/test_jacobian.py.
"""

import math

import numpy as np

from tether_sim.numerics.jit import jit_alloc
from tether_sim.physics.hydrodynamics import current_at
from tether_sim.physics.hydrodynamics import wetted_fraction
from tether_sim.physics.hydrodynamics import wave_inertia
from tether_sim.solvers.hybrid.kernels import height_at_alpha_f, wave_state
from tether_sim.solvers.hybrid.layout import (HP_AF, HP_AM, HP_AREA, HP_CCRIT, HP_CDN, HP_CDN_A, HP_CDT, HP_CDT_A,
                                              HP_CMN, HP_CMT, HP_D, HP_DT, HP_FBZ, HP_FS, HP_FSB, HP_G, HP_GAM, HP_KD,
                                              HP_M, HP_MU, HP_RHOA, HP_RHOF, HP_SBZETA, HP_SEABED, HP_VMU, HP_ZG)


@jit_alloc
def current_slope(z, cz, cx, cy, out):
    """d(current)/dz of the piecewise-linear table (0 beyond it); the segment containing z."""
    out[0] = 0.0
    out[1] = 0.0
    out[2] = 0.0
    n = cz.shape[0]
    if n < 2 or z <= cz[0] or z >= cz[n - 1]:
        return
    for k in range(1, n):
        if z < cz[k]:
            h = cz[k] - cz[k - 1]
            out[0] = (cx[k] - cx[k - 1]) / h
            out[1] = (cy[k] - cy[k - 1]) / h
            return


@jit_alloc
def _drag_jac(vr, dvr_dv, tu, Pt, cd, dcd, cdt, cdn, F, Jv, Jt, Je, W):
    """Morison drag cd (Cdt |vrt| vrt tu + Cdn |vn| vn) and its derivatives (added to F, Jv, Jt, Je);
    W: scratch (>= 33), so that no array is allocated per point."""
    vrt = vr[0] * tu[0] + vr[1] * tu[1] + vr[2] * tu[2]
    vn = W[0:3]
    for k in range(3):
        vn[k] = vr[k] - vrt * tu[k]
    vnn = math.sqrt(vn[0] * vn[0] + vn[1] * vn[1] + vn[2] * vn[2])
    dvrt_dv = W[3:6]
    dvrt_dt = W[6:9]
    for j in range(3):
        dvrt_dv[j] = 0.0
        dvrt_dt[j] = 0.0
        for k in range(3):
            dvrt_dv[j] += tu[k] * dvr_dv[k, j]
            dvrt_dt[j] += vr[k] * Pt[k, j]
    dvn_dv = W[9:18].reshape(3, 3)
    dvn_dt = W[18:27].reshape(3, 3)
    for i in range(3):
        for j in range(3):
            dvn_dv[i, j] = dvr_dv[i, j] - tu[i] * dvrt_dv[j]
            dvn_dt[i, j] = -tu[i] * dvrt_dt[j] - vrt * Pt[i, j]
    avrt = abs(vrt)
    for i in range(3):
        F[i] += cd * (cdt * avrt * vrt * tu[i] + cdn * vnn * vn[i])
        Je[i] += dcd * (cdt * avrt * vrt * tu[i] + cdn * vnn * vn[i])
    wv = W[27:30]  # vn^T dvn / |vn|
    wt = W[30:33]
    for j in range(3):
        wv[j] = 0.0
        wt[j] = 0.0
    if vnn > 0.0:
        for j in range(3):
            for k in range(3):
                wv[j] += vn[k] * dvn_dv[k, j] / vnn
                wt[j] += vn[k] * dvn_dt[k, j] / vnn
    for i in range(3):
        for j in range(3):
            Jv[i, j] += cd * (cdt * 2.0 * avrt * tu[i] * dvrt_dv[j] + cdn * (vnn * dvn_dv[i, j] + vn[i] * wv[j]))
            Jt[i, j] += cd * (cdt * (2.0 * avrt * tu[i] * dvrt_dt[j] + avrt * vrt * Pt[i, j])
                              + cdn * (vnn * dvn_dt[i, j] + vn[i] * wt[j]))


@jit_alloc
def _seabed_jac(z, dz_dv2, v, le, P, F, Jv, Je):
    """Seabed force [PE2020 Eq. 15-16, damping ramped in over the static penetration] and derivatives."""
    delta = P[HP_ZG] - z
    if delta <= 0.0:
        return
    sl = math.sqrt(le) if le > 0.0 else 0.0
    dsl = 0.5 / sl if sl > 0.0 else 0.0
    d_static = -P[HP_FBZ] / P[HP_KD] if P[HP_KD] > 0.0 else 0.0
    ramp = 1.0
    dramp_dz = 0.0
    if d_static > 0.0:
        x = delta / d_static
        if x < 1.0:
            ramp = x
            dramp_dz = -1.0 / d_static
    zc = P[HP_SBZETA] * P[HP_CCRIT]
    Kd_term = P[HP_KD] * delta - ramp * zc * v[2]
    if sl * Kd_term > 0.0:
        F[2] += sl * Kd_term
        Jv[2, 2] += sl * (-P[HP_KD] * dz_dv2 - dramp_dz * dz_dv2 * zc * v[2] - ramp * zc)
        Je[2] += dsl * Kd_term
    vh = math.sqrt(v[0] * v[0] + v[1] * v[1])
    mu = P[HP_MU]
    if mu > 0.0 and vh > 0.0 and P[HP_FBZ] < 0.0:
        c = math.pi / P[HP_VMU]
        th = math.tanh(c * vh)
        gfun = th / vh
        dg = (c * (1.0 - th * th) - gfun) / vh
        k0 = sl * mu * P[HP_FBZ]
        for i in range(2):
            F[i] += k0 * gfun * v[i]
            Je[i] += dsl * mu * P[HP_FBZ] * gfun * v[i]
            for j in range(2):
                Jv[i, j] += k0 * ((gfun if i == j else 0.0) + v[i] * dg * v[j] / vh)


@jit_alloc
def _fluid_jac(rho, cdt, cdn, cmn, cmt, vr, dvr_dv, tu, Pt, a, le, P, F, Jv, Jt, Ja, Je, W):
    """kernels.fluid_force (drag, added mass, buoyancy of a fluid of density rho) and its derivatives
    into F, Jv, Jt, Ja, Je (overwritten); W: scratch (>= 66; 33:63 untouched)."""
    for i in range(3):
        F[i] = 0.0
        Je[i] = 0.0
        for j in range(3):
            Jv[i, j] = 0.0
            Jt[i, j] = 0.0
    half = 0.5 * P[HP_D] * rho
    sl = math.sqrt(le)
    _drag_jac(vr, dvr_dv, tu, Pt, half * sl, half * 0.5 / sl if sl > 0.0 else 0.0, cdt, cdn, F, Jv, Jt, Je, W)
    ma = rho * P[HP_AREA]
    dcm = cmt - cmn
    at = a[0] * tu[0] + a[1] * tu[1] + a[2] * tu[2]
    dat_dt = W[63:66]
    for j in range(3):
        dat_dt[j] = 0.0
        for k in range(3):
            dat_dt[j] += a[k] * Pt[k, j]
    for i in range(3):
        F[i] -= ma * (cmn * a[i] + dcm * at * tu[i])
        for j in range(3):
            Ja[i, j] = -ma * ((cmn if i == j else 0.0) + dcm * tu[i] * tu[j])
            Jt[i, j] -= ma * dcm * (tu[i] * dat_dt[j] + at * Pt[i, j])
    F[2] += ma * P[HP_G]


@jit_alloc
def _blend_air(z, eta, dz_dv2, v, tu, Pt, a, le, P, F, Jv, Jt, Ja, Je):
    """Free surface: F = phi F_water + (1 - phi) F_air with the wetted fraction phi(z - eta) and its z
    derivative through z(v_z) (kernels.external_force); the air part is allocated only here."""
    phi, dphi = wetted_fraction(z, eta, P[HP_FSB])
    if phi >= 1.0:
        return
    Fa = np.zeros(3)
    Jva = np.zeros((3, 3))
    Jta = np.zeros((3, 3))
    Jaa = np.zeros((3, 3))
    Jea = np.zeros(3)
    Wa = np.empty(66)
    vra = np.empty(3)
    dvra = np.zeros((3, 3))
    for k in range(3):
        vra[k] = -v[k]
        dvra[k, k] = -1.0
    _fluid_jac(P[HP_RHOA], P[HP_CDT_A], P[HP_CDN_A], 0.0, 0.0, vra, dvra, tu, Pt, a, le, P, Fa, Jva, Jta, Jaa, Jea, Wa)
    for i in range(3):
        d = dphi * dz_dv2 * (F[i] - Fa[i])
        F[i] = phi * F[i] + (1.0 - phi) * Fa[i]
        Je[i] = phi * Je[i] + (1.0 - phi) * Jea[i]
        for j in range(3):
            Jv[i, j] = phi * Jv[i, j] + (1.0 - phi) * Jva[i, j]
            Jt[i, j] = phi * Jt[i, j] + (1.0 - phi) * Jta[i, j]
            Ja[i, j] = phi * Ja[i, j] + (1.0 - phi) * Jaa[i, j]
        Jv[i, 2] += d


@jit_alloc
def external_force_jac(v, t, a, rn, eps, P, cz, cx, cy, F, Jv, Jt, Ja, Je, W):
    """F of kernels.external_force at (v, t, a, eps) and its derivatives: Jv, Jt, Ja (3x3), Je (3,).
    The height z(v) is the alpha_f-level height (dz/dv_z = alpha_f dt gamma / alpha_m). W: scratch
    (>= 128 floats; 70:119 untouched)."""
    dz_dv2 = P[HP_AF] * P[HP_DT] * P[HP_GAM] / P[HP_AM]
    z = height_at_alpha_f(v, rn, P)
    nt = math.sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2])
    tu = W[33:36]
    for k in range(3):
        tu[k] = t[k] / nt
    Pt = W[36:45].reshape(3, 3)  # d tu / d t
    for i in range(3):
        for j in range(3):
            Pt[i, j] = ((1.0 if i == j else 0.0) - tu[i] * tu[j]) / nt
    uc = W[45:48]
    current_at(z, cz, cx, cy, uc)
    duc = W[48:51]
    current_slope(z, cz, cx, cy, duc)
    vr = W[51:54]
    dvr_dv = W[54:63].reshape(3, 3)
    dvr_dv[:, :] = 0.0
    for k in range(3):
        vr[k] = uc[k] - v[k]
        dvr_dv[k, k] = -1.0
        dvr_dv[k, 2] += duc[k] * dz_dv2
    le = 1.0 + eps
    if le < 0.0:
        le = 0.0
    uw = W[119:122]  # 66:119 are the caller's (jacobian.catenary_node_jac)
    aw = W[122:125]
    ar = W[125:128]
    eta = wave_state(v, rn, z, P, uw, aw)
    for k in range(3):
        vr[k] += uw[k]
        ar[k] = a[k] - aw[k]
    _fluid_jac(P[HP_RHOF], P[HP_CDT], P[HP_CDN], P[HP_CMN], P[HP_CMT], vr, dvr_dv, tu, Pt, ar, le, P, F, Jv, Jt, Ja,
               Je, W)
    if aw[0] != 0.0 or aw[1] != 0.0 or aw[2] != 0.0:  # Froude-Krylov: no dependence on v, t, a, eps
        fx, fy, fz = wave_inertia(tu[0], tu[1], tu[2], aw[0], aw[1], aw[2], P[HP_RHOF] * P[HP_AREA], 0.0, 0.0)
        F[0] += fx
        F[1] += fy
        F[2] += fz
    if P[HP_FS] > 0.0:
        _blend_air(z, eta, dz_dv2, v, tu, Pt, a, le, P, F, Jv, Jt, Ja, Je)
    F[2] -= P[HP_M] * P[HP_G]
    if P[HP_SEABED] > 0.0:
        _seabed_jac(z, dz_dv2, v, le, P, F, Jv, Je)
