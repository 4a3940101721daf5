"""Catenary elements [GP Sec. 2.1, Eq. 1-5, Appendix 2 Eq. 24-26].

Field variables per node (world components): v (0:3), T (3), unit tangent t (4:7), strain eps (7).
T and eps are linked by the node's constitutive equation (kernels.law_residual, PE2020 Eq. 22).

GP parameterise t by two spherical angles (Eq. 4); that chart is singular where the tangent is
along its pole, and a vertical tether is our normal case. We use the unit tangent itself as three
unknowns plus the algebraic constraint |t|^2 = 1 at every node ("direct unit-tangent variables"):
no chart, no singularity, and Eq. 2-3 stay linear in t. The constraint replaces the one equation
that the angles would have saved, so counts balance (6 cell equations + 1 node equation per node).

Discretisation: box scheme in s (generalized-alpha with rho_s = 1), generalized-alpha in time
[GP Sec. 3]. Eq. 2 is used in its time-integrated (position) form at t_{n+1}, with node positions
advanced as generalized-alpha variables of dr/dt = v (rate r' with r'_{n+a_m} = v_{n+a_f}):
    (r_b - r_a)/ds - mean_{a,b}[ (1 + c_k T) t ]                                = 0   [GP Eq. 2]
    ((T t)_b - (T t)_a)/ds + mean_{a,b}[ F - m dv/dt ]   at the alpha levels    = 0   [GP Eq. 3]
For rho_inf = 1 the first line is exactly the box form of Eq. 2 summed over steps; for rho_inf < 1
it keeps positions, tangents and strain consistent (the rate form lets the length drift by the
truncation error, which a taut tether turns into a tension error).
(T t)_b - (T t)_a = Tbar (t_b - t_a) + tbar (T_b - T_a) exactly, i.e. the K_c ds-term of Eq. 25.
"""

import math

import numpy as np

from tether_sim.numerics.jit import jit_alloc
from tether_sim.solvers.hybrid.kernels import alpha_levels, external_force
from tether_sim.solvers.hybrid.layout import (CAT_EPS, CAT_SLOTS, CAT_T, CAT_TAN, CAT_V, HP_AF, HP_AM, HP_DT, HP_GAM,
                                              HP_M)


@jit_alloc
def catenary_node_terms(Y, Yn, Ytn, rn, P, cz, cx, cy, out_pos, out_q, out_load, out_tension_vec):
    """rn = (r_n, r'_n) (6,). Per-node terms: r_{n+1}, (1+eps) t at t_{n+1}; F - m dv/dt and T t at the alpha levels."""
    Yf = np.empty(CAT_SLOTS)
    Ym = np.empty(CAT_SLOTS)
    alpha_levels(Y, Yn, Ytn, CAT_SLOTS, P, Yf, Ym)
    dt = P[HP_DT]
    g = P[HP_GAM]
    am = P[HP_AM]
    af = P[HP_AF]
    e1 = Y[CAT_EPS]
    for k in range(3):
        # r is a generalized-alpha variable with dr/dt = v collocated at the alpha levels
        rdot = ((1.0 - af) * Yn[CAT_V + k] + af * Y[CAT_V + k] - (1.0 - am) * rn[3 + k]) / am
        out_pos[k] = rn[k] + dt * ((1.0 - g) * rn[3 + k] + g * rdot)
        out_q[k] = (1.0 + e1) * Y[CAT_TAN + k]
        out_tension_vec[k] = Yf[CAT_T] * Yf[CAT_TAN + k]
    F = np.empty(3)
    external_force(Yf[CAT_V:CAT_V + 3], Yf[CAT_TAN:CAT_TAN + 3], Ym[CAT_V:CAT_V + 3], rn, Yf[CAT_EPS], P, cz, cx, cy,
                   F)
    for k in range(3):
        out_load[k] = F[k] - P[HP_M] * Ym[CAT_V + k]


@jit_alloc
def catenary_cell_residual(Ya, Yna, Ytna, rna, Yb, Ynb, Ytnb, rnb, ds, P, cz, cx, cy, out):
    """The 6 box equations of one catenary cell [GP Eq. 2-3, 5] (Eq. 2 in its position form)."""
    pa = np.empty(3)
    qa = np.empty(3)
    la = np.empty(3)
    ta = np.empty(3)
    pb = np.empty(3)
    qb = np.empty(3)
    lb = np.empty(3)
    tb = np.empty(3)
    catenary_node_terms(Ya, Yna, Ytna, rna, P, cz, cx, cy, pa, qa, la, ta)
    catenary_node_terms(Yb, Ynb, Ytnb, rnb, P, cz, cx, cy, pb, qb, lb, tb)
    for k in range(3):
        out[k] = (pb[k] - pa[k]) / ds - 0.5 * (qa[k] + qb[k])
        out[3 + k] = (tb[k] - ta[k]) / ds + 0.5 * (la[k] + lb[k])


@jit_alloc
def unit_tangent_residual(Y, out):
    """|t|^2 - 1 = 0 at a catenary node (replaces the angle chart of GP Eq. 4)."""
    out[0] = unit_tangent_value(Y[CAT_TAN], Y[CAT_TAN + 1], Y[CAT_TAN + 2])


@jit_alloc
def unit_tangent_value(t0, t1, t2):
    """|t|^2 - 1 of a tangent's components."""
    return t0 * t0 + t1 * t1 + t2 * t2 - 1.0


@jit_alloc
def catenary_velocity_bc(Y, vbc, out):
    """Prescribed/fixed/body end: v = v_BC (3 equations)."""
    for k in range(3):
        out[k] = Y[CAT_V + k] - vbc[k]


@jit_alloc
def catenary_force_bc(Y, force, out):
    """Point-force end: T t = force on the internal-force convention (sign set by the caller)."""
    for k in range(3):
        out[k] = Y[CAT_T] * Y[CAT_TAN + k] - force[k]


@jit_alloc
def catenary_free_bc(Y, Ynb, p1, p2, tscale, out):
    """Tension-free end: T = 0; the end tangent follows its neighbour across the plane (p1, p2) normal to it."""
    out[0] = Y[CAT_T] / tscale
    d0 = Y[CAT_TAN] - Ynb[CAT_TAN]
    d1 = Y[CAT_TAN + 1] - Ynb[CAT_TAN + 1]
    d2 = Y[CAT_TAN + 2] - Ynb[CAT_TAN + 2]
    out[1] = d0 * p1[0] + d1 * p1[1] + d2 * p1[2]
    out[2] = d0 * p2[0] + d1 * p2[1] + d2 * p2[2]


def tangent_normals(t):
    """Two unit vectors normal to t (for catenary_free_bc)."""
    t = np.asarray(t, dtype=float) / max(math.sqrt(float(np.dot(t, t))), 1e-300)
    trial = np.array([1.0, 0.0, 0.0]) if abs(t[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    p1 = np.cross(t, trial)
    p1 /= np.linalg.norm(p1)
    return p1, np.cross(t, p1)
