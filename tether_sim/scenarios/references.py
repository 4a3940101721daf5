"""Closed-form reference solutions used to verify the cable solvers [PE2020 Sec. 2, 4, 5].

Conventions (match ``tether_sim.solvers.base``): s is the unstretched arc length from the ship end
(s = 0); T(s) is the force the part beyond s exerts on the part before s, so the force the cable
exerts on the ship end is +T(0) and on the vehicle end -T(L). z is up. "Weight" w is the submerged
weight per unstretched metre, w = g (gamma0 - rho_f A) with the material area A = gamma0 / rho_c
[PE2020 Eq. 14]. Hydrodynamic area for added mass: A_d = pi d^2 / 4 with d the hydrodynamic
diameter ``cable.diameter`` (the area Eq. 13 multiplies; for a solid cable both areas coincide).
"""

from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq, fsolve


# ---------------------------------------------------------------- loads, speeds, frequencies
def submerged_weight(gamma0, density, fluid_density, g=9.81):
    """Net weight per unstretched metre w = g (gamma0 - rho_f gamma0 / rho_c) [PE2020 Eq. 14]."""
    return g * (gamma0 - fluid_density * gamma0 / density)


def axial_wave_speed(EA, gamma0):
    """Axial (snap) wave speed c = sqrt(EA / gamma0) in material coordinates [PE2020 Eq. 25]."""
    return np.sqrt(EA / gamma0)


def axial_arrival_time(length, EA, gamma0):
    """Time for an axial front to cross the cable, L / c (independent of a uniform pre-strain)."""
    return length / axial_wave_speed(EA, gamma0)


def longitudinal_return_period(length, EA, gamma0):
    """Return period of longitudinal waves T_r = 2 L / c [PE2020 Sec. 5, Fig. 3d]."""
    return 2.0 * axial_arrival_time(length, EA, gamma0)


def hydrodynamic_area(diameter):
    """A_d = pi d^2 / 4, the area that multiplies rho_f C_m in the added mass [PE2020 Eq. 13]."""
    return 0.25 * np.pi * diameter**2


def normal_added_mass(fluid_density, diameter, Cmn):
    """Normal added mass per unstretched metre rho_f A_d C_m,perp (strain-independent, Eq. 13)."""
    return fluid_density * hydrodynamic_area(diameter) * Cmn


def taut_string_frequency(mode, length, tension, gamma0, strain=0.0, added_mass=0.0):
    """Angular frequency of transverse mode n of a taut string pinned at both ends.

    In material coordinates the linearised equation is (gamma0 + m_a) y_tt = (T/l_eps) y_ss, so
    omega_n = (n pi / L) sqrt(T / (l_eps (gamma0 + m_a))) with L unstretched and l_eps = 1 + strain.
    """
    return mode * np.pi / length * np.sqrt(tension / ((1.0 + strain) * (gamma0 + added_mass)))


def terminal_velocity(weight, fluid_density, diameter, Cd, strain=0.0):
    """Speed at which Morison drag balances the weight w [PE2020 Eq. 17]:

    w = 0.5 rho_f d sqrt(l_eps) Cd v^2  ->  v = sqrt(2 w / (rho_f d Cd sqrt(l_eps))).
    """
    return np.sqrt(2.0 * weight / (fluid_density * diameter * Cd * np.sqrt(1.0 + strain)))


def seabed_sink_depth(weight, K_g, diameter, strain=0.0):
    """Static penetration delta = w / (sqrt(l_eps) K_g d) of a resting cable [PE2020 Eq. 15]."""
    return weight / (np.sqrt(1.0 + strain) * K_g * diameter)


def seabed_friction_force(velocity_xy, weight, mu, v_mu, strain=0.0):
    """Friction per unstretched metre [PE2020 Eq. 16]; opposes the horizontal velocity.

    f = -sqrt(l_eps) mu tanh(pi |v|/v_mu) w v/|v| (Eq. 16 with min(f_b^z, 0) = -w for w > 0).
    """
    v = np.asarray(velocity_xy, dtype=float)
    speed = np.linalg.norm(v)
    if speed == 0.0 or weight <= 0.0:
        return np.zeros_like(v)
    return -np.sqrt(1.0 + strain) * mu * np.tanh(np.pi * speed / v_mu) * weight * v / speed


def snap_front_speed(EA, gamma0, pull_speed, slack_strain=0.0):
    """Material speed S of the front that snaps a slack, resting cable (bilinear law, Eq. 22).

    Ahead of the front: strain -a <= 0, T = 0, at rest; behind: strain e1 > 0, speed V. The jump
    conditions of Eq. 10, S [q] = -[v/gamma0] and S gamma0 [nu] = -[T], give
    e1 (e1 + a) = (V/c)^2 and S = V / (e1 + a); S -> c as a -> 0.  Returns (S, e1).
    """
    c = axial_wave_speed(EA, gamma0)
    a = -min(slack_strain, 0.0)
    m = pull_speed / c
    e1 = 0.5 * (-a + np.sqrt(a * a + 4.0 * m * m))
    return pull_speed / (e1 + a), e1


# ---------------------------------------------------------------- statics
@dataclass
class ElasticCatenary:
    """Elastic catenary [Irvine]: T(s) = (H, V0 + w s) in the vertical plane through both ends."""

    length: float
    EA: float
    w: float
    H: float  # horizontal tension component, N
    V0: float  # vertical component of T at s = 0, N (negative when the cable leaves s=0 downwards)

    def tension_vector(self, s):
        """(horizontal, vertical) components of T(s), shape (n, 2)."""
        s = np.asarray(s, dtype=float)
        return np.stack([np.full_like(s, self.H), self.V0 + self.w * s], axis=-1)

    def tension(self, s):
        return np.linalg.norm(self.tension_vector(s), axis=-1)

    def shape(self, s):
        """(horizontal, vertical) offset of r(s) from the s = 0 end: dr/ds = T/|T| + T/EA."""
        s = np.asarray(s, dtype=float)
        H, V0, w, EA = self.H, self.V0, self.w, self.EA
        V = V0 + w * s
        x = H * s / EA + (H / w) * (np.arcsinh(V / H) - np.arcsinh(V0 / H))
        z = (V0 * s + 0.5 * w * s * s) / EA + (np.hypot(H, V) - np.hypot(H, V0)) / w
        return np.stack([x, z], axis=-1)

    def sag(self, n=2001):
        """Largest vertical distance of the cable below the chord between its ends."""
        s = np.linspace(0.0, self.length, n)
        xz = self.shape(s)
        dx, dz = xz[-1]
        chord_z = dz * xz[:, 0] / dx
        return float(np.max(chord_z - xz[:, 1]))


def elastic_catenary(length, EA, w, span, rise):
    """Solve the elastic catenary hanging from s = 0 (origin) to s = L at (span, rise), span > 0."""
    if span <= 0.0 or w <= 0.0:
        raise ValueError("elastic_catenary needs span > 0 and a positive weight w")

    def residual(p):
        cat = ElasticCatenary(length, EA, w, np.exp(p[0]), p[1])
        return cat.shape(np.array([length]))[0] - np.array([span, rise])

    # Start from the inextensible parabola-like guess: H ~ w L^2 / (8 sag), V0 ~ -w L / 2.
    chord = np.hypot(span, rise)
    slack = max(length - chord, 1e-3 * length)
    H0 = w * length**2 / (8.0 * np.sqrt(3.0 * slack * length / 8.0))
    sol, info, ok, msg = fsolve(residual, [np.log(H0), -0.5 * w * length], full_output=True, xtol=1e-13)
    cat = ElasticCatenary(length, EA, w, float(np.exp(sol[0])), float(sol[1]))
    if np.max(np.abs(residual(sol))) > 1e-9 * length:
        raise RuntimeError(f"elastic catenary did not converge: {msg}")
    return cat


def vertical_hanging_cable(s, length, EA, w, bottom_load=0.0):
    """Cable hanging straight down from s = 0 with a downward point load at s = L.

    T(s) = w (L - s) + F_b; depth below the top: s + (w (L s - s^2/2) + F_b s) / EA.
    Returns (depth (n,), tension (n,)).
    """
    s = np.asarray(s, dtype=float)
    tension = w * (length - s) + bottom_load
    depth = s + (w * (length * s - 0.5 * s * s) + bottom_load * s) / EA
    return depth, tension


# ---------------------------------------------------------------- axial pulse (smooth exact)
def gaussian_pulse(t, amplitude, centre, width):
    """g(t) = a exp(-((t - t0)/sigma)^2) and its derivative g'(t)."""
    x = (np.asarray(t, dtype=float) - centre) / width
    g = amplitude * np.exp(-x * x)
    return g, -2.0 * x / width * g


def axial_pulse_solution(s, t, length, c, amplitude, centre, width, n_images=8):
    """Exact axial displacement u, velocity u_t and strain u_s for u_tt = c^2 u_ss on [0, L],
    u(0, t) = g(t) (Gaussian pulse), u(L, t) = 0 (fixed end), at rest at t = 0, by images:
    u = sum_k g(t - (2kL + s)/c) - g(t - (2(k+1)L - s)/c).
    """
    s = np.asarray(s, dtype=float)
    u = np.zeros_like(s)
    ut = np.zeros_like(s)
    us = np.zeros_like(s)
    for k in range(n_images):
        g1, d1 = gaussian_pulse(t - (2 * k * length + s) / c, amplitude, centre, width)
        g2, d2 = gaussian_pulse(t - (2 * (k + 1) * length - s) / c, amplitude, centre, width)
        u += g1 - g2
        ut += d1 - d2
        us += -d1 / c - d2 / c
    return u, ut, us


# ---------------------------------------------------------------- cantilever [PE2020 Eq. 41-46]
def cantilever_root(i):
    """i-th root (i = 1, 2, ...) of 1 + cos(x) cosh(x) = 0, x = Omega_i L [PE2020 Eq. 44]."""
    f = lambda x: np.cos(x) + 1.0 / np.cosh(x)  # same roots, well scaled
    guess = (i - 0.5) * np.pi
    return brentq(f, guess - 0.5 * np.pi + 1e-9 if i > 1 else 1.0, guess + 0.5 * np.pi - 1e-9, xtol=1e-15)


def cantilever_omega(i, EI, m, length):
    """omega_i = (Omega_i L)^2 sqrt(EI / (m L^4)) [PE2020 Eq. 45]."""
    return cantilever_root(i) ** 2 * np.sqrt(EI / (m * length**4))


def cantilever_mode(s, i, length, derivative=0):
    """Phi_i (Eq. 41-42) or its derivative (0..3) at s; |Phi_i(L)| = 1 (tip amplitude A)."""
    W = cantilever_root(i) / length
    x = W * np.asarray(s, dtype=float)
    bl = W * length
    D = (np.cos(bl) + np.cosh(bl)) / (np.sin(bl) + np.sinh(bl))
    c, ch, sn, sh = np.cos(x), np.cosh(x), np.sin(x), np.sinh(x)
    terms = {
        0: c - ch + D * (sh - sn),
        1: -sn - sh + D * (ch - c),
        2: -c - ch + D * (sh + sn),
        3: sn - sh + D * (ch + c),
    }
    return 0.5 * W**derivative * terms[derivative]


def cantilever_envelopes(s, i, EI, length, amplitude):
    """Analytic envelopes max_t |.| of deflection A Phi, moment EI A Phi'' and shear EI A Phi'''."""
    return (np.abs(amplitude * cantilever_mode(s, i, length)),
            np.abs(EI * amplitude * cantilever_mode(s, i, length, 2)),
            np.abs(EI * amplitude * cantilever_mode(s, i, length, 3)))


# ---------------------------------------------------------------- ring beam [PE2020 Sec. 4.1]
def ring_beam_shape(s, radius=1.0):
    """Beam clamped at the origin along +x, bent by an end moment +y into a circle of radius
    R = EI/M centred at (0, 0, -R): r(s) = (R sin(s/R), 0, -R (1 - cos(s/R)))."""
    th = np.asarray(s, dtype=float) / radius
    return np.stack([radius * np.sin(th), np.zeros_like(th), -radius * (1.0 - np.cos(th))], axis=-1)


def relative_l2_error(s, r, r_exact):
    """Eq. 34: sqrt(int |r - r_ana|^2 ds / int |r_ana|^2 ds) by the trapezoidal rule on s."""
    d = np.sum((np.asarray(r) - r_exact) ** 2, axis=-1)
    n = np.sum(np.asarray(r_exact) ** 2, axis=-1)
    return float(np.sqrt(np.trapezoid(d, s) / np.trapezoid(n, s)))


def convergence_rates(errors, refinement=2.0):
    """Eq. 36 rates between successive meshes (DOFs multiplied by ``refinement``), positive when
    the error falls: alpha = -(log e_{i+1} - log e_i) / log(refinement)."""
    e = np.asarray(errors, dtype=float)
    return -np.diff(np.log(e)) / np.log(refinement)


def gauss_points(n_elements, order_points, length):
    """Gauss-Legendre points and weights on a uniform mesh of [0, L] (for integrals of DG fields)."""
    xg, wg = np.polynomial.legendre.leggauss(order_points)
    h = length / n_elements
    left = h * np.arange(n_elements)
    s = (left[:, None] + 0.5 * h * (xg[None, :] + 1.0)).ravel()
    w = np.tile(0.5 * h * wg, n_elements)
    return s, w
