"""Catenary elements [GP Sec. 2.1, Eq. 1-5, Appendix 2 Eq. 24-26].

Field variables per node (world components): v (0:3), T (3), unit tangent t (4:7).

GP parameterise t by two spherical angles (Eq. 4); that chart is singular where the tangent is
along its pole, and a vertical tether is our normal case. We use the unit tangent itself as three
unknowns plus the algebraic constraint |t|^2 = 1 at every node ("direct unit-tangent variables"):
no chart, no singularity, and Eq. 2-3 stay linear in t. The constraint replaces the one equation
that the angles would have saved, so counts balance (6 cell equations + 1 node equation per node).

Discretisation: box scheme in s (generalized-alpha with rho_s = 1) at t_{n+alpha_f}, generalized-
alpha in time for the rates [GP Sec. 3]:
    (v_b - v_a)/ds - mean_{a,b}[ c_k dT/dt t + (1 + c_k T) dt/dt ]           = 0   [GP Eq. 2]
    ((T t)_b - (T t)_a)/ds + mean_{a,b}[ F - m dv/dt ]                         = 0   [GP Eq. 3]
(T t)_b - (T t)_a = Tbar (t_b - t_a) + tbar (T_b - T_a) exactly, i.e. the K_c ds-term of Eq. 25.
"""

import math

import numpy as np

from tether_sim.numerics.jit import jit
from tether_sim.solvers.hybrid.kernels import CAT_SLOTS, P_CK, P_M, alpha_levels, external_force


@jit
def catenary_node_terms(Y, Yn, Ytn, zn, P, cz, cx, cy, out_rate, out_load, out_tension_vec):
    """Per-node terms of the cell equations: d((1+eps) t)/dt, F - m dv/dt, and T t (alpha levels)."""
    Yf = np.empty(CAT_SLOTS)
    Ym = np.empty(CAT_SLOTS)
    alpha_levels(Y, Yn, Ytn, CAT_SLOTS, P, Yf, Ym)
    ck = P[P_CK]
    T = Yf[3]
    for k in range(3):
        out_rate[k] = ck * Ym[3] * Yf[4 + k] + (1.0 + ck * T) * Ym[4 + k]
        out_tension_vec[k] = T * Yf[4 + k]
    F = np.empty(3)
    external_force(Yf[0:3], Yf[4:7], Ym[0:3], zn, ck * T, P, cz, cx, cy, F)
    for k in range(3):
        out_load[k] = F[k] - P[P_M] * Ym[k]
    # spatial differences use the alpha_f level values: return them through Y-slots
    return Yf[0], Yf[1], Yf[2]


@jit
def catenary_cell_residual(Ya, Yna, Ytna, za, Yb, Ynb, Ytnb, zb, ds, P, cz, cx, cy, out):
    """The 6 box equations of one catenary cell [GP Eq. 2-3, 5]."""
    ra = np.empty(3)
    la = np.empty(3)
    ta = np.empty(3)
    rb = np.empty(3)
    lb = np.empty(3)
    tb = np.empty(3)
    va0, va1, va2 = catenary_node_terms(Ya, Yna, Ytna, za, P, cz, cx, cy, ra, la, ta)
    vb0, vb1, vb2 = catenary_node_terms(Yb, Ynb, Ytnb, zb, P, cz, cx, cy, rb, lb, tb)
    out[0] = (vb0 - va0) / ds - 0.5 * (ra[0] + rb[0])
    out[1] = (vb1 - va1) / ds - 0.5 * (ra[1] + rb[1])
    out[2] = (vb2 - va2) / ds - 0.5 * (ra[2] + rb[2])
    for k in range(3):
        out[3 + k] = (tb[k] - ta[k]) / ds + 0.5 * (la[k] + lb[k])


@jit
def unit_tangent_residual(Y, out):
    """|t|^2 - 1 = 0 at a catenary node (replaces the angle chart of GP Eq. 4)."""
    out[0] = Y[4] * Y[4] + Y[5] * Y[5] + Y[6] * Y[6] - 1.0


@jit
def catenary_velocity_bc(Y, vbc, out):
    """Prescribed/fixed/body end: v = v_BC (3 equations)."""
    for k in range(3):
        out[k] = Y[k] - vbc[k]


@jit
def catenary_force_bc(Y, force, out):
    """Point-force end: T t = force on the internal-force convention (sign set by the caller)."""
    for k in range(3):
        out[k] = Y[3] * Y[4 + k] - force[k]


@jit
def catenary_free_bc(Y, Ynb, p1, p2, tscale, out):
    """Tension-free end: T = 0; the end tangent follows its neighbour across the plane (p1, p2) normal to it."""
    out[0] = Y[3] / tscale
    d0 = Y[4] - Ynb[4]
    d1 = Y[5] - Ynb[5]
    d2 = Y[6] - Ynb[6]
    out[1] = d0 * p1[0] + d1 * p1[1] + d2 * p1[2]
    out[2] = d0 * p2[0] + d1 * p2[1] + d2 * p2[2]


def tangent_normals(t):
    """Two unit vectors normal to t (for catenary_free_bc)."""
    t = np.asarray(t, dtype=float) / max(math.sqrt(float(np.dot(t, t))), 1e-300)
    trial = np.array([1.0, 0.0, 0.0]) if abs(t[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    p1 = np.cross(t, trial)
    p1 /= np.linalg.norm(p1)
    return p1, np.cross(t, p1)
