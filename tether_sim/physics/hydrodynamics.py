"""Hydrodynamic and gravity loads on a cable point [PE2020 Eq. 12-14, 17].

All kernels act on one point: tangent ``i`` (3,), elongation ``l = 1 + eps``, cable velocity
``nu`` (3,), current ``uc`` (3,). Forces are per unstretched metre (N/m).
"""

import math

import numpy as np

from tether_sim.numerics.jit import jit


@jit
def current_at(z, cz, cx, cy, out):
    """Depth-varying current (piecewise linear in z, constant beyond the table); out (3,)."""
    n = cz.shape[0]
    out[0] = 0.0
    out[1] = 0.0
    out[2] = 0.0
    if n == 0:
        return
    if z <= cz[0]:
        out[0] = cx[0]
        out[1] = cy[0]
        return
    if z >= cz[n - 1]:
        out[0] = cx[n - 1]
        out[1] = cy[n - 1]
        return
    for k in range(1, n):
        if z <= cz[k]:
            a = (z - cz[k - 1]) / (cz[k] - cz[k - 1])
            out[0] = cx[k - 1] + a * (cx[k] - cx[k - 1])
            out[1] = cy[k - 1] + a * (cy[k] - cy[k - 1])
            return


@jit
def morison_drag(i0, i1, i2, l, w0, w1, w2, half_rho_d, Cdt, Cdn):
    """f_d = 0.5 rho_f d sqrt(l) (Cdt |v_t*| v_t* + Cdn |v_n*| v_n*) [PE2020 Eq. 17] for the relative
    flow velocity v* = (w0, w1, w2) = u_current - nu and tangent (i0, i1, i2); returns (fx, fy, fz)."""
    wt = w0 * i0 + w1 * i1 + w2 * i2
    n0 = w0 - wt * i0
    n1 = w1 - wt * i1
    n2 = w2 - wt * i2
    wn = math.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
    f = half_rho_d * math.sqrt(l) if l > 0.0 else 0.0
    ft = f * Cdt * abs(wt) * wt
    fn = f * Cdn * wn
    return ft * i0 + fn * n0, ft * i1 + fn * n1, ft * i2 + fn * n2


@jit
def add_morison_drag(i, l, nu, uc, half_rho_d, Cdt, Cdn, out):
    """out += f_d [PE2020 Eq. 17] with v* = uc - nu (array form of :func:`morison_drag`)."""
    fx, fy, fz = morison_drag(i[0], i[1], i[2], l, uc[0] - nu[0], uc[1] - nu[1], uc[2] - nu[2], half_rho_d, Cdt, Cdn)
    out[0] += fx
    out[1] += fy
    out[2] += fz


@jit
def wave_inertia(i0, i1, i2, a0, a1, a2, rho_a, m_t, m_n):
    """Load per metre of the fluid acceleration a_w = (a0, a1, a2) on a wetted point with tangent i:

        f_w = rho_f A a_w + m_n a_w,perp + m_t a_w,par        [DNV-RP-C205 Eq. 6.1-6.2, slender member]

    rho_a = rho_f A: Froude-Krylov, the undisturbed pressure gradient on the displaced volume, in every
    direction (also along the axis); m_n = rho_f A_h C_mn, m_t = rho_f A_h C_mt: the fluid side of the
    added mass (its structure side, -m a, is solved with the cable's inertia: added_mass_rate).
    PE2020 Eq. 13 keeps only the normal part rho_f A a_w,perp of the first term (docs/waves.md).
    Returns (fx, fy, fz)."""
    at = a0 * i0 + a1 * i1 + a2 * i2
    p0 = at * i0
    p1 = at * i1
    p2 = at * i2
    return (rho_a * a0 + m_n * (a0 - p0) + m_t * p0, rho_a * a1 + m_n * (a1 - p1) + m_t * p1,
            rho_a * a2 + m_n * (a2 - p2) + m_t * p2)


@jit
def solve_added_mass(i, force, gamma0, m_t, m_n, out):
    """Momentum rate dv/dt = gamma0 * a from (gamma0 + m_t) a_par = F_par, (gamma0 + m_n) a_perp = F_perp.

    ``force`` (3,) is every load except the added-mass reaction (N/m); m_t = rho_f A_h Cmt and
    m_n = rho_f A_h Cmn are the added masses per metre [PE2020 Eq. 13, a_w = 0 in a steady current].
    The cable acceleration appears on both sides of Eq. 4 + Eq. 13; splitting along the tangent
    solves it exactly per point.
    """
    out[0], out[1], out[2] = added_mass_rate(i[0], i[1], i[2], force[0], force[1], force[2], gamma0, m_t, m_n)


@jit
def added_mass_rate(i0, i1, i2, f0, f1, f2, gamma0, m_t, m_n):
    """Scalar form of :func:`solve_added_mass`: returns dv/dt = gamma0 a (3 floats)."""
    ft = f0 * i0 + f1 * i1 + f2 * i2
    ct = gamma0 / (gamma0 + m_t)
    cn = gamma0 / (gamma0 + m_n)
    p0 = ft * i0
    p1 = ft * i1
    p2 = ft * i2
    return ct * p0 + cn * (f0 - p0), ct * p1 + cn * (f1 - p1), ct * p2 + cn * (f2 - p2)


@jit
def wetted_fraction(z, eta, b):
    """Wetted fraction phi of a point at height z under a surface at eta, and dphi/dz.

    phi = x^2 (3 - 2 x) with x = (eta - z + b) / (2 b) clipped to [0, 1]: 1 at z <= eta - b, 0 at
    z >= eta + b, C1 in z. The ramp is odd about eta (phi(eta + y) = 1 - phi(eta - y)), so a straight
    cable crossing the band gets exactly the wetted length of the sharp interface.
    """
    x = (eta - z + b) / (2.0 * b)
    if x >= 1.0:
        return 1.0, 0.0
    if x <= 0.0:
        return 0.0, 0.0
    return x * x * (3.0 - 2.0 * x), -6.0 * x * (1.0 - x) / (2.0 * b)


@jit
def surface_drag(i0, i1, i2, l, n0, n1, n2, u0, u1, u2, phi, hrd, cdt, cdn, hra, cdta, cdna):
    """Drag of a point with wetted fraction phi: phi f_d(water, v* = u - nu) + (1 - phi) f_d(air, v* = -nu)
    [PE2020 Eq. 17 with the air density and air coefficients above the surface]; returns (fx, fy, fz)."""
    fx = 0.0
    fy = 0.0
    fz = 0.0
    if phi > 0.0:
        wx, wy, wz = morison_drag(i0, i1, i2, l, u0 - n0, u1 - n1, u2 - n2, hrd, cdt, cdn)
        fx = phi * wx
        fy = phi * wy
        fz = phi * wz
    if phi < 1.0 and hra > 0.0:
        ax, ay, az = morison_drag(i0, i1, i2, l, -n0, -n1, -n2, hra, cdta, cdna)
        fx += (1.0 - phi) * ax
        fy += (1.0 - phi) * ay
        fz += (1.0 - phi) * az
    return fx, fy, fz


def net_weight_per_length(cable, env) -> float:
    """Submerged weight per unstretched metre w = g (gamma0 - rho_f A) (N/m), > 0 sinks [PE2020 Eq. 14]."""
    return env.g * (cable.gamma0 - env.fluid_density * cable.area)


def air_weight_per_length(cable, env) -> float:
    """Weight per unstretched metre in air w_air = g (gamma0 - rho_air A) (N/m) (free surface on)."""
    return env.g * (cable.gamma0 - env.air_density * cable.area)


def buoyancy_vector(cable, env) -> np.ndarray:
    """f_b = A g (rho_f - rho_c) z_hat with A = gamma0 / rho_c [PE2020 Eq. 14]."""
    return np.array([0.0, 0.0, -net_weight_per_length(cable, env)])


def added_mass_per_length(cable, env):
    """(m_t, m_n) = rho_f (pi d^2 / 4) (Cmt, Cmn) (kg/m) [PE2020 Eq. 13]."""
    a_h = math.pi * cable.diameter**2 / 4.0
    return env.fluid_density * a_h * cable.Cmt, env.fluid_density * a_h * cable.Cmn


def current_table(env):
    """(cz, cx, cy) contiguous arrays of the current profile, validated."""
    cz = np.asarray(env.current_z, float)
    cx = np.asarray(env.current_x, float)
    cy = np.asarray(env.current_y, float)
    if not (cz.size == cx.size == cy.size):
        raise ValueError("environment.current_z/current_x/current_y must have the same length")
    if cz.size > 1 and np.any(np.diff(cz) <= 0.0):
        raise ValueError("environment.current_z must be strictly increasing")
    return np.ascontiguousarray(cz), np.ascontiguousarray(cx), np.ascontiguousarray(cy)
