"""Kirchhoff rod elements [GP Sec. 2.2, Eq. 6-11, Appendix 2 Eq. 27-29].

Field variables per node, body-frame components (layout.py): v, omega, kappa, f, and
the axial strain eps, tied to the tension f_1 by the node's constitutive equation
(kernels.law_residual, PE2020 Eq. 22), so Eq. 7 below is linear in deps/dt.
Body axis 0 is the tangent (torsion axis), axes 1-2 the bending axes; B = diag(GJ, EI, EI),
I = diag(I_t, I_b, I_b). The frame L (world -> body) of each node is advanced in time by the
incremental rotation theta = dt (omega_n + omega_{n+1})/2 [GP Eq. 15-18]; the alpha_f-level frame
used to express gravity/drag/current in body components is exp(-alpha_f theta~) L_n.

GP's rod is inextensible; ours stretches with the catenary's law f_1 = Phi(EA eps + zeta deps/dt)
(f_1 = f . t, the tension), so that a rod zone in a tether can neither carry compression stiffly nor change the axial
wave speed: r' = (1 + eps) t gives Eq. 7 the terms (1 + eps) omega x t + deps/dt t and Eq. 9 the
moment arm (1 + eps). With c_k = 0 (GP benchmark) the equations are exactly GP's.

Box scheme in s at t_{n+alpha_f}, generalized-alpha rates at t_{n+alpha_m} [GP Sec. 3]:
    dv/ds + kappa x v - (1 + eps) omega x t - deps/dt t             = 0   [GP Eq. 7]
    domega/ds + kappa x omega - dkappa/dt                           = 0   [GP Eq. 8]
    B dkappa/ds + kappa x B kappa - I domega/dt - omega x I omega
                - (1 + eps) f x t + Q                                = 0   [GP Eq. 9, q = B kappa]
    df/ds + kappa x f - m (dv/dt + omega x v) + F                   = 0   [GP Eq. 10]
"""

import numpy as np

from tether_sim.numerics.jit import jit_alloc
from tether_sim.numerics.rotations import rotate_frame
from tether_sim.solvers.hybrid.kernels import alpha_levels, cross, external_force
from tether_sim.solvers.hybrid.layout import (HP_AF, HP_B0, HP_DT, HP_I0, HP_M, ROD_EPS, ROD_F, ROD_KAPPA, ROD_OMEGA,
                                              ROD_SLOTS, ROD_V)


@jit_alloc
def frame_at(Y, Yn, Ln, frac, out):
    """Frame at t_n + frac*dt: exp(-frac*theta~) L_n, theta = dt (omega_n + omega_{n+1})/2 [GP Eq. 15-16]."""
    th = np.empty(3)
    for k in range(3):
        th[k] = frac * 0.5 * (Yn[ROD_OMEGA + k] + Y[ROD_OMEGA + k])
    rotate_frame(Ln, th, out)


@jit_alloc
def rod_node_terms(Y, Yn, Ytn, Ln, rn, P, cz, cx, cy, Yf, Ym, Fb):
    """Alpha-level values (Yf, Ym) and the body-frame external load Fb (N/m) of one rod node."""
    alpha_levels(Y, Yn, Ytn, ROD_SLOTS, P, Yf, Ym)
    La = np.empty((3, 3))
    frame_at(Y, Yn, Ln, P[HP_AF] * P[HP_DT], La)
    acc_b = np.empty(3)
    cross(Yf[ROD_OMEGA:ROD_OMEGA + 3], Yf[ROD_V:ROD_V + 3], acc_b)
    for k in range(3):
        acc_b[k] += Ym[ROD_V + k]
    vw = np.zeros(3)
    tw = np.zeros(3)
    aw = np.zeros(3)
    for i in range(3):
        tw[i] = La[0, i]
        for k in range(3):
            vw[i] += La[k, i] * Yf[ROD_V + k]
            aw[i] += La[k, i] * acc_b[k]
    Fw = np.empty(3)
    external_force(vw, tw, aw, rn, Yf[ROD_EPS], P, cz, cx, cy, Fw)
    for k in range(3):
        Fb[k] = La[k, 0] * Fw[0] + La[k, 1] * Fw[1] + La[k, 2] * Fw[2]


@jit_alloc
def rod_cell_residual(Ya, Yna, Ytna, La, ra, Yb, Ynb, Ytnb, Lb, rb, ds, P, cz, cx, cy, out):
    """The 12 box equations of one rod cell [GP Eq. 7-11]."""
    Yfa = np.empty(ROD_SLOTS)
    Yma = np.empty(ROD_SLOTS)
    Yfb = np.empty(ROD_SLOTS)
    Ymb = np.empty(ROD_SLOTS)
    Fa = np.empty(3)
    Fb = np.empty(3)
    rod_node_terms(Ya, Yna, Ytna, La, ra, P, cz, cx, cy, Yfa, Yma, Fa)
    rod_node_terms(Yb, Ynb, Ytnb, Lb, rb, P, cz, cx, cy, Yfb, Ymb, Fb)
    rod_cell_from_terms(Yfa, Yma, Fa, Yfb, Ymb, Fb, ds, P, out)


@jit_alloc
def rod_cell_from_terms(Yfa, Yma, Fa, Yfb, Ymb, Fb, ds, P, out):
    """The 12 box equations from the two nodes' rod_node_terms (alpha-level values and loads)."""
    Y = np.empty(ROD_SLOTS)
    Yd = np.empty(ROD_SLOTS)
    for k in range(ROD_SLOTS):
        Y[k] = 0.5 * (Yfa[k] + Yfb[k])
        Yd[k] = 0.5 * (Yma[k] + Ymb[k])
    v = Y[ROD_V:ROD_V + 3]
    om = Y[ROD_OMEGA:ROD_OMEGA + 3]
    ka = Y[ROD_KAPPA:ROD_KAPPA + 3]
    f = Y[ROD_F:ROD_F + 3]
    B = P[HP_B0:HP_B0 + 3]
    II = P[HP_I0:HP_I0 + 3]
    c = np.empty(3)
    Bk = np.empty(3)
    Iw = np.empty(3)
    for k in range(3):
        Bk[k] = B[k] * ka[k]
        Iw[k] = II[k] * om[k]
    # Eq. 7 (extensible): dv/ds + kappa x v - (1 + eps) omega x e1 - deps/dt e1 (eps: node unknown)
    le = 1.0 + Y[ROD_EPS]
    edot = Yd[ROD_EPS]
    cross(ka, v, c)
    out[0] = (Yfb[ROD_V] - Yfa[ROD_V]) / ds + c[0] - edot
    out[1] = (Yfb[ROD_V + 1] - Yfa[ROD_V + 1]) / ds + c[1] - le * om[2]
    out[2] = (Yfb[ROD_V + 2] - Yfa[ROD_V + 2]) / ds + c[2] + le * om[1]
    # Eq. 8: domega/ds + kappa x omega - dkappa/dt
    cross(ka, om, c)
    for k in range(3):
        out[3 + k] = (Yfb[ROD_OMEGA + k] - Yfa[ROD_OMEGA + k]) / ds + c[k] - Yd[ROD_KAPPA + k]
    # Eq. 9: B dkappa/ds + kappa x B kappa - I domega/dt - omega x I omega - f x e1 (+ Q = 0)
    cross(ka, Bk, c)
    w = np.empty(3)
    cross(om, Iw, w)
    fxt = np.empty(3)
    fxt[0] = 0.0
    fxt[1] = le * f[2]
    fxt[2] = -le * f[1]
    for k in range(3):
        out[6 + k] = (B[k] * (Yfb[ROD_KAPPA + k] - Yfa[ROD_KAPPA + k]) / ds + c[k] - II[k] * Yd[ROD_OMEGA + k] - w[k]
                      - fxt[k])
    # Eq. 10: df/ds + kappa x f - m (dv/dt + omega x v) + F
    cross(ka, f, c)
    cross(om, v, w)
    m = P[HP_M]
    for k in range(3):
        out[9 + k] = (Yfb[ROD_F + k] - Yfa[ROD_F + k]) / ds + c[k] - m * (Yd[ROD_V + k] + w[k]) + 0.5 * (Fa[k] + Fb[k])


# rod end conditions (rod_end_residual's kind), from the end's PE2020 Table 1 row
ROD_END_PINNED, ROD_END_CLAMPED, ROD_END_FORCE, ROD_END_FORCE_HELD = range(4)


def rod_end_code(row, held):
    """The rod end condition of an end with Table 1 row ``row`` (physics/end_conditions.EndKind; not a
    body's) whose frame is ``held`` (a clamped row, or a force end with hybrid.hold_direction_*)."""
    return (ROD_END_CLAMPED if held else ROD_END_PINNED) if row.kinematic else \
        (ROD_END_FORCE_HELD if held else ROD_END_FORCE)


@jit_alloc
def rod_end_residual(kind, Y, Yn, Ln, P, vec_a, vec_b, out):
    """Six end conditions of a rod end at t_{n+1}; vectors in world components.

    ROD_END_PINNED (0): v = vec_a, kappa = 0 (prescribed, fixed)
    ROD_END_CLAMPED (1): v = vec_a, omega = 0 (clamped: frame held)
    ROD_END_FORCE (2): f = vec_a, B kappa = vec_b (force: point force and moment; free: both 0)
    ROD_END_FORCE_HELD (3): f = vec_a, omega = 0 (point force with the end frame held, GP benchmark right end)
    """
    L1 = np.empty((3, 3))
    frame_at(Y, Yn, Ln, P[HP_DT], L1)
    a = np.empty(3)
    b = np.empty(3)
    for i in range(3):
        a[i] = L1[i, 0] * vec_a[0] + L1[i, 1] * vec_a[1] + L1[i, 2] * vec_a[2]
        b[i] = L1[i, 0] * vec_b[0] + L1[i, 1] * vec_b[1] + L1[i, 2] * vec_b[2]
    if kind == ROD_END_PINNED or kind == ROD_END_CLAMPED:
        for k in range(3):
            out[k] = Y[ROD_V + k] - a[k]
    else:
        for k in range(3):
            out[k] = Y[ROD_F + k] - a[k]
    for k in range(3):
        if kind == ROD_END_PINNED:
            out[3 + k] = Y[ROD_KAPPA + k]
        elif kind == ROD_END_FORCE:
            out[3 + k] = P[HP_B0 + k] * Y[ROD_KAPPA + k] - b[k]
        else:
            out[3 + k] = Y[ROD_OMEGA + k]
