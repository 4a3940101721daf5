"""Seabed contact: bilinear spring-damper normal force and tanh-regularised friction [PE2020 Eq. 15-16]."""

import math

from tether_sim.numerics.jit import jit


@jit
def seabed_force(z, n0, n1, n2, l, z_g, Kd, c_crit, zeta, mu, v_mu, fbz):
    """Scalar form of :func:`add_seabed_force` for velocity (n0, n1, n2); returns (fx, fy, fz)."""
    delta = z_g - z
    if delta <= 0.0:
        return 0.0, 0.0, 0.0
    sl = math.sqrt(l) if l > 0.0 else 0.0
    fz = sl * (Kd * delta - zeta * c_crit * n2)
    if fz < 0.0:
        fz = 0.0
    fx = 0.0
    fy = 0.0
    vh = math.sqrt(n0 * n0 + n1 * n1)
    if mu > 0.0 and vh > 0.0 and fbz < 0.0:
        f = sl * mu * math.tanh(math.pi * vh / v_mu) * fbz / vh
        fx = f * n0
        fy = f * n1
    return fx, fy, fz


@jit
def add_seabed_force(z, nu, l, z_g, Kd, c_crit, zeta, mu, v_mu, fbz, out):
    """out += f_c for a point at height z with velocity nu (3,) and elongation l.

    Kd = K_g d (N/m^2), c_crit = 2 sqrt(K_g d gamma0), fbz = vertical net buoyancy per metre
    (negative for a sinking cable). Only acts when the penetration delta = z_g - z > 0:
    f_z = sqrt(l) (Kd delta - zeta c_crit nu_z) [Eq. 15] (never pulling the cable down),
    f_xy = sqrt(l) mu tanh(pi |nu_xy| / v_mu) nu_xy / |nu_xy| min(fbz, 0) [Eq. 16].
    """
    fx, fy, fz = seabed_force(z, nu[0], nu[1], nu[2], l, z_g, Kd, c_crit, zeta, mu, v_mu, fbz)
    out[0] += fx
    out[1] += fy
    out[2] += fz
