"""Shared point kernels of the hybrid solver: parameter layout, environment forces, alpha levels.

Environment forces are those of the DG solver [PE2020 Eq. 12-17] so that both solvers see the same
water and seabed (physics/seabed.py, PE2020 Eq. 15-16): buoyant weight A g (rho_f - rho_c) z with A = gamma0/rho_c [PE2020 Eq. 14, GP Eq. 21],
Morison drag with sqrt(1+eps) [PE2020 Eq. 17; GP Eq. 19 with C_t -> C_dt/pi], added mass
rho_f A (C_mn a_perp + C_mt a_par) [PE2020 Eq. 13; GP Eq. 20], depth-varying current, and waves:
the wave particle velocity in the drag, the wave acceleration in the Froude-Krylov and fluid-side
added-mass load of physics/hydrodynamics.wave_inertia (docs/waves.md), the wetted part following eta.
All per unit unstretched length, world (ENU) components.

Parameter vector P (float64) and node states Y: the column tables of layout.py.
"""

import math

import numpy as np

from tether_sim.numerics.jit import jit_alloc
from tether_sim.physics.hydrodynamics import current_at, wave_inertia, wetted_fraction
from tether_sim.physics.seabed import seabed_force
from tether_sim.physics.waves import wave_kinematics
from tether_sim.solvers.hybrid.layout import (HP_AF, HP_AM, HP_AREA, HP_B0, HP_CCRIT, HP_CDN, HP_CDN_A, HP_CDT,
                                              HP_CDT_A, HP_CK, HP_CMN, HP_CMT, HP_D, HP_DT, HP_EA, HP_FBZ, HP_FS,
                                              HP_FSB, HP_G, HP_GAM, HP_I0, HP_KD, HP_M, HP_MU, HP_NW, HP_RHOA, HP_RHOF,
                                              HP_SBZETA, HP_SEABED, HP_SIZE, HP_SOFT, HP_TIME, HP_TW, HP_VMU, HP_WDEPTH,
                                              HP_WSTRETCH, HP_WZCUT, HP_ZETA, HP_ZG)


def pack_parameters(cable, env, dt, alpha_m, alpha_f, gamma, bend, tors, inertia_b, inertia_t, compression_factor=1.0,
                    compression_width=1.0, segment=0.0, waves=None):
    """P vector of the kernels from CableProperties/Environment and the step coefficients; segment: the
    node spacing (the free-surface ramp is at least one segment wide, so that the wetted length of the
    node sum does not jump as a node crosses the surface); waves: physics/waves.WaveComponents or None
    (their arrays are appended)."""
    P = np.zeros(HP_SIZE)
    P[HP_M] = cable.gamma0
    P[HP_CK] = 1.0 / cable.EA if cable.EA > 0 else 0.0
    P[HP_G] = env.g
    P[HP_RHOF] = env.fluid_density
    P[HP_AREA] = cable.area
    P[HP_D] = cable.diameter
    P[HP_CDN], P[HP_CDT], P[HP_CMN], P[HP_CMT] = cable.Cdn, cable.Cdt, cable.Cmn, cable.Cmt
    P[HP_B0:HP_B0 + 3] = (tors, bend, bend)
    P[HP_I0:HP_I0 + 3] = (inertia_t, inertia_b, inertia_b)
    P[HP_DT], P[HP_AM], P[HP_AF], P[HP_GAM] = dt, alpha_m, alpha_f, gamma
    P[HP_SOFT] = compression_factor if cable.material in ("bilinear", "table") else 1.0
    P[HP_TW] = compression_width
    P[HP_EA] = cable.EA
    P[HP_ZETA] = cable.damping
    # seabed contact, the DG solver's parameters [PE2020 Eq. 15-16]
    P[HP_SEABED] = 1.0 if env.seabed else 0.0
    P[HP_ZG] = env.seabed_z
    P[HP_KD] = env.seabed_stiffness * cable.diameter
    P[HP_CCRIT] = 2.0 * math.sqrt(P[HP_KD] * cable.gamma0)
    P[HP_SBZETA] = env.seabed_damping
    P[HP_MU] = env.seabed_friction
    P[HP_VMU] = env.seabed_friction_speed
    P[HP_FBZ] = -(cable.gamma0 - env.fluid_density * cable.area) * env.g
    P[HP_FS] = 1.0 if env.free_surface else 0.0
    P[HP_RHOA], P[HP_CDN_A], P[HP_CDT_A] = env.air_density, env.air_Cdn, env.air_Cdt
    P[HP_FSB] = 0.5 * max(env.surface_smoothing, segment)
    P[HP_WZCUT] = math.inf
    if waves is None or waves.n == 0:
        return P
    P[HP_NW] = waves.n
    P[HP_WDEPTH] = waves.depth
    P[HP_WSTRETCH] = waves.stretch
    P[HP_WZCUT] = wave_cut_height(waves)
    return np.ascontiguousarray(np.concatenate([P] + [np.asarray(x, float) for x in waves.arrays()]))


def wave_cut_height(comps):
    """Height below which the wave kinematics are < 1e-4 of their surface value (skipped); -inf when the
    longest component reaches the bottom (finite depth, k d < ln 1e4)."""
    amp = np.abs(np.asarray(comps.amp, float))
    kmin = float(np.min(np.asarray(comps.k, float)))
    if kmin <= 0.0 or (math.isfinite(comps.depth) and kmin * comps.depth < math.log(1e4)):
        return -math.inf
    return -float(amp.sum()) - math.log(1e4) / kmin


@jit_alloc
def _softplus(x):
    return x + math.log1p(math.exp(-x)) if x > 0.0 else math.log1p(math.exp(x))


@jit_alloc
def _sigmoid(x):
    return 1.0 / (1.0 + math.exp(-x)) if x > -700.0 else 0.0


@jit_alloc
def tension_only(x, P):
    """Smooth no-compression map Phi of the visco-elastic tension x = EA eps + zeta deps/dt
    [PE2020 Eq. 22: T = max(x, 0)]: Phi(x) = x/s + (1 - 1/s) W (softplus(x/W) - ln 2), i.e. slope 1
    in tension and 1/s in compression (s = compression softening), switching over the width W around
    x = 0; Phi(0) = 0, offset -W ln 2 for x >> W, compression floor ~ -W ln 2 + x/s."""
    s = P[HP_SOFT]
    if s == 1.0:
        return x
    w = P[HP_TW]
    return x / s + (1.0 - 1.0 / s) * w * (_softplus(x / w) - math.log(2.0))


@jit_alloc
def tension_only_slope(x, P):
    """dPhi/dx, between 1/s (compression) and 1 (tension)."""
    s = P[HP_SOFT]
    if s == 1.0:
        return 1.0
    return 1.0 / s + (1.0 - 1.0 / s) * _sigmoid(x / P[HP_TW])


@jit_alloc
def law_residual(T, eps, eps_rate, P):
    """Constitutive equation of one node at t_{n+1}: T - Phi(EA eps + zeta deps/dt) = 0
    [PE2020 Eq. 22, GP Eq. 1 with c_k = 1/EA]; for EA = 0 (c_k = 0, inextensible) eps = 0."""
    if P[HP_EA] <= 0.0:
        return eps
    return T - tension_only(P[HP_EA] * eps + P[HP_ZETA] * eps_rate, P)


@jit_alloc
def elastic_strain(T, P):
    """Static strain carrying tension T (inverse of Phi(EA eps), deps/dt = 0; 0 if inextensible)."""
    if P[HP_EA] <= 0.0:
        return 0.0
    x = T
    for _ in range(60):  # Newton on the monotone Phi, slope in [1/s, 1]
        f = tension_only(x, P) - T
        if abs(f) <= 1e-13 * (abs(T) + P[HP_TW]):
            break
        x -= f / tension_only_slope(x, P)
    return x / P[HP_EA]


@jit_alloc
def coordinate_at_alpha_f(v, rn, P, c):
    """Coordinate c of the position at t_{n+alpha_f} of a point with alpha_f-level velocity v: the
    position is a generalized-alpha variable of dr/dt = v (rate r' with r'_{n+alpha_m} = v_{n+alpha_f});
    rn = (r_n, r'_n). Its derivative by v[c] is alpha_f dt gamma / alpha_m."""
    am = P[HP_AM]
    g = P[HP_GAM]
    rdot = (v[c] - (1.0 - am) * rn[3 + c]) / am
    x1 = rn[c] + P[HP_DT] * ((1.0 - g) * rn[3 + c] + g * rdot)
    return (1.0 - P[HP_AF]) * rn[c] + P[HP_AF] * x1


@jit_alloc
def height_at_alpha_f(v, rn, P):
    """z at t_{n+alpha_f} (coordinate_at_alpha_f, c = 2)."""
    return coordinate_at_alpha_f(v, rn, P, 2)


@jit_alloc
def wave_state(v, rn, z, P, uw, aw):
    """Wave particle velocity uw and local acceleration aw (3,) at the alpha_f-level position and time
    t_n + alpha_f dt (physics/waves.wave_kinematics, P's components); returns eta there (0 without waves)."""
    for k in range(3):
        uw[k] = 0.0
        aw[k] = 0.0
    nw = int(P[HP_NW])
    if nw == 0 or z <= P[HP_WZCUT]:
        return 0.0 if nw == 0 else wave_elevation_at(v, rn, P)
    o = HP_SIZE
    return wave_kinematics(coordinate_at_alpha_f(v, rn, P, 0), coordinate_at_alpha_f(v, rn, P, 1), z,
                           P[HP_TIME] + P[HP_AF] * P[HP_DT], P[o:o + nw], P[o + nw:o + 2 * nw],
                           P[o + 2 * nw:o + 3 * nw],
                           P[o + 3 * nw:o + 4 * nw], P[o + 4 * nw:o + 5 * nw], P[o + 5 * nw:o + 6 * nw],
                           P[HP_WDEPTH], int(P[HP_WSTRETCH]), uw, aw)


@jit_alloc
def wave_elevation_at(v, rn, P):
    """eta at the alpha_f-level horizontal position and time (deep points: the surface for phi only)."""
    nw = int(P[HP_NW])
    o = HP_SIZE
    x = coordinate_at_alpha_f(v, rn, P, 0)
    y = coordinate_at_alpha_f(v, rn, P, 1)
    t = P[HP_TIME] + P[HP_AF] * P[HP_DT]
    eta = 0.0
    for n in range(nw):
        eta += P[o + n] * math.cos(P[o + 2 * nw + n] * (x * P[o + 3 * nw + n] + y * P[o + 4 * nw + n])
                                   - P[o + nw + n] * t + P[o + 5 * nw + n])
    return eta


@jit_alloc
def fluid_force(v, tu, a, uc, le, rho, cdt, cdn, cmn, cmt, P, out):
    """out = Morison drag (relative velocity uc - v) + added-mass reaction to the acceleration a
    (relative to the fluid's) + buoyancy rho A g z_hat of a fluid of density rho, per unstretched metre
    [PE2020 Eq. 13, 14, 17]; tu: unit tangent."""
    vr0 = uc[0] - v[0]
    vr1 = uc[1] - v[1]
    vr2 = uc[2] - v[2]
    vrt = vr0 * tu[0] + vr1 * tu[1] + vr2 * tu[2]
    vn0 = vr0 - vrt * tu[0]
    vn1 = vr1 - vrt * tu[1]
    vn2 = vr2 - vrt * tu[2]
    vnn = math.sqrt(vn0 * vn0 + vn1 * vn1 + vn2 * vn2)
    cdrag = 0.5 * P[HP_D] * rho * math.sqrt(le)
    at = a[0] * tu[0] + a[1] * tu[1] + a[2] * tu[2]
    ma = rho * P[HP_AREA]
    out[0] = cdrag * (cdt * abs(vrt) * vrt * tu[0] + cdn * vnn * vn0) - ma * (cmn * (a[0] - at * tu[0]) + cmt * at * tu[0])
    out[1] = cdrag * (cdt * abs(vrt) * vrt * tu[1] + cdn * vnn * vn1) - ma * (cmn * (a[1] - at * tu[1]) + cmt * at * tu[1])
    out[2] = cdrag * (cdt * abs(vrt) * vrt * tu[2] + cdn * vnn * vn2) - ma * (cmn * (a[2] - at * tu[2]) + cmt * at * tu[2])
    out[2] += ma * P[HP_G]


@jit_alloc
def external_force(v, t, a, rn, eps, P, cz, cx, cy, out):
    """Distributed force F (N/m, world) on a cable point [PE2020 Eq. 13-17; GP Eq. 19-22].

    v: velocity, t: tangent (normalised here), a: inertial acceleration (all at the alpha levels),
    rn: position and its rate at t_n (the height at t_{n+alpha_f} follows from v, so that the seabed
    spring is implicit), eps: strain. Waves: the particle velocity joins the current, the added mass acts
    on the acceleration relative to the wave's, and rho_f A a_w (Froude-Krylov) is added: together the
    load of hydrodynamics.wave_inertia with m = rho_f A C_m. Free surface (HP_FS): the water part is
    weighted by the wetted fraction phi(z - eta) (physics/hydrodynamics.wetted_fraction, half-width
    HP_FSB), the air part (air density and drag coefficients, no added mass, still air) by 1 - phi.
    """
    z = height_at_alpha_f(v, rn, P)
    nt = math.sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2])
    tu = np.empty(3)
    for k in range(3):
        tu[k] = t[k] / nt
    uc = np.empty(3)
    current_at(z, cz, cx, cy, uc)
    le = 1.0 + eps
    if le < 0.0:
        le = 0.0
    uw = np.empty(3)
    aw = np.empty(3)
    eta = wave_state(v, rn, z, P, uw, aw)
    ar = np.empty(3)
    for k in range(3):
        uc[k] += uw[k]
        ar[k] = a[k] - aw[k]
    fluid_force(v, tu, ar, uc, le, P[HP_RHOF], P[HP_CDT], P[HP_CDN], P[HP_CMN], P[HP_CMT], P, out)
    if aw[0] != 0.0 or aw[1] != 0.0 or aw[2] != 0.0:  # Froude-Krylov (the added mass is in ar)
        ma = P[HP_RHOF] * P[HP_AREA]
        fx, fy, fz = wave_inertia(tu[0], tu[1], tu[2], aw[0], aw[1], aw[2], ma, 0.0, 0.0)
        out[0] += fx
        out[1] += fy
        out[2] += fz
    if P[HP_FS] > 0.0:
        phi, _ = wetted_fraction(z, eta, P[HP_FSB])
        if phi < 1.0:
            air = np.empty(3)
            uc[0] = 0.0
            uc[1] = 0.0
            uc[2] = 0.0
            fluid_force(v, tu, a, uc, le, P[HP_RHOA], P[HP_CDT_A], P[HP_CDN_A], 0.0, 0.0, P, air)
            for k in range(3):
                out[k] = phi * out[k] + (1.0 - phi) * air[k]
    out[2] -= P[HP_M] * P[HP_G]
    if P[HP_SEABED] > 0.0:  # the DG solver's contact law [PE2020 Eq. 15-16], l = 1 + eps
        # its damping term jumps from 0 to zeta c_crit |v_z| at first contact: a discontinuity an implicit
        # Newton solve cannot converge across, so it is ramped in over the static penetration -F_bz/K_d
        ramp = 1.0
        d_static = -P[HP_FBZ] / P[HP_KD] if P[HP_KD] > 0.0 else 0.0
        if d_static > 0.0:
            ramp = min(max((P[HP_ZG] - z) / d_static, 0.0), 1.0)
        fx, fy, fz = seabed_force(z, v[0], v[1], v[2], le, P[HP_ZG], P[HP_KD], P[HP_CCRIT], ramp * P[HP_SBZETA],
                                  P[HP_MU], P[HP_VMU], P[HP_FBZ])
        out[0] += fx
        out[1] += fy
        out[2] += fz


@jit_alloc
def alpha_levels(Y, Yn, Ytn, nslot, P, Yf, Ym):
    """Y at t_{n+alpha_f} and dY/dt at t_{n+alpha_m} from the gamma relation [GP Sec. 3]."""
    dt = P[HP_DT]
    am = P[HP_AM]
    af = P[HP_AF]
    g = P[HP_GAM]
    for k in range(nslot):
        ydot = ((Y[k] - Yn[k]) / dt - (1.0 - g) * Ytn[k]) / g
        Yf[k] = (1.0 - af) * Yn[k] + af * Y[k]
        Ym[k] = (1.0 - am) * Ytn[k] + am * ydot


@jit_alloc
def cross(a, b, out):
    """out = a x b."""
    out[0] = a[1] * b[2] - a[2] * b[1]
    out[1] = a[2] * b[0] - a[0] * b[2]
    out[2] = a[0] * b[1] - a[1] * b[0]
