"""Compiled output sampling of the DG cable at fixed arc lengths (state() of the solver).

The output arc lengths of a node rarely change, so everything that depends only on them (the
element of each point, the Legendre values phi_k(xi) and their integrals int_{-1}^{xi} phi_k) is
computed once (:class:`SamplingPlan`) and one kernel fills every output field per call.

Output block ``out`` (NS, n), one row per scalar field: position r(s) = r_a + int q ds, velocity v / gamma0,
tension (below), strain eps = |q| - 1, curvature |kappa|, bending moment |M| with M = l^2 M*, the moment
vector M, the shear force (1/l) i x tau [Eq. 20] and the tension vector (T i + T_s, modal projection),
from the work arrays that the last right-hand-side evaluation left (layout.py).

Tension: the values the scheme uses, interpolated without leaving their range. The scheme evaluates
the law T(eps, deps/dt) [PE2020 Eq. 22] at the Gauss points only (the strain rate there is the one
the right-hand side used, wq W_EDOT) and transmits the numerical flux T_hat between elements and to
the ends [Eq. 23-24, Table 1]. Per element the nodes are its Gauss points and its two interfaces:
at s = 0 and s = L the end loads' axial tension E_T (exactly the value end_forces(), the end-tension
fields and the snap detector read), at an interior interface the flux's axial part T_hat . i_hat
(i_hat the normalised mean of the two trace tangents) limited to the range of the two Gauss values
beside it (the Lax-Friedrichs penalty and the traces of the projected tension vector take it
outside the law's range at a snap front: -137 N where both neighbours read 0). Between the nodes:
the polynomial through the element's nodes, clipped to the range of their values, so the state
never reads a tension above or below every value the scheme used in that element. T(eps(q(s)))
between the Gauss points is no value of the scheme: in a kinked slack element the polynomial q
overshoots |q| = 1 there and read tens of kN where the scheme carried tens of N; a projection of
the tension (the modal F~ of Eq. 23) oscillates across a snap front and reads negative tension
(docs/dg_solver.md, "Sampled tension").
"""

import numpy as np

from tether_sim.numerics.jit import jit
from tether_sim.numerics.polys import lagrange_at, legendre_at, legendre_integral_at
from tether_sim.physics.constitutive import axial_tension, compression_cap
from tether_sim.solvers.dg.kernels import internal_forces
from tether_sim.solvers.dg.layout import (
    E_T, F_V, I_ANCHOR, I_BENDING, I_P, M_KAP, M_MS, M_TAU, M_TV, T_Q, W_EDOT, W_L,
)
from tether_sim.solvers.dg.stepper import fill_end_kinematics
from tether_sim.solvers.dg.winch import winch_active, winch_end_velocity
from tether_sim.solvers.dg.workspace import (
    X_BC, X_BP, X_BS, X_D, X_DU, X_ENDF, X_FL, X_H, X_IPRM, X_LF, X_PJ, X_PRM, X_TAB_EPS, X_TAB_T, X_TMP, X_TR, X_TRC, X_U,
    X_V, X_VBC, X_WM, X_WQ, bind,
)

S_POS = 0
S_VEL = 3
S_TENSION = 6
S_STRAIN = 7
S_CURV = 8
S_MOMENT = 9
S_MVEC = 10
S_SHEAR = 13
S_TV = 16
NS = 19

NODE_SNAP = 2e-9  # in xi: 1e-9 of the element's length


class SamplingPlan:
    """Element index, Legendre values and integrals at fixed arc lengths (clipped to [0, L]), and the
    Lagrange basis of the element's tension nodes (xi = -1, the Gauss points ``points``, +1) there;
    ``tnodes`` (N, Q + 2) holds the node values per call."""

    def __init__(self, arc_lengths, s_edges, h, order, points):
        N = h.size
        L = float(s_edges[-1])
        s = np.clip(np.atleast_1d(np.asarray(arc_lengths, float)), 0.0, L)
        e = np.clip(np.searchsorted(s_edges, s, side="right") - 1, 0, N - 1)
        xi = np.clip(2.0 * (s - s_edges[e]) / h[e] - 1.0, -1.0, 1.0)
        self.s = s
        self.elem = np.ascontiguousarray(e, dtype=np.int64)
        self.phi = np.ascontiguousarray(legendre_at(order, xi))
        self.iphi = np.ascontiguousarray(legendre_integral_at(order, xi))
        # a point within NODE_SNAP of an interface (in xi) is on it: the interpolant then takes the interface value
        # exactly (the end load at s = 0 and s = L, despite the round-off of s_edges)
        xt = np.where(xi <= -1.0 + NODE_SNAP, -1.0, np.where(xi >= 1.0 - NODE_SNAP, 1.0, xi))
        self.lag = np.ascontiguousarray(lagrange_at(np.concatenate(([-1.0], points, [1.0])), xt))
        self.starts = np.zeros((N, 3))
        self.tnodes = np.zeros((N, np.size(points) + 2))


@jit
def evaluate_outputs(t, F, I, S):
    """The part of a right-hand-side evaluation at time t the outputs read (end loads endf, the
    modal work channels of wm) on the workspace of the arenas F, I and the spec S (workspace.bind,
    bound here: a call passes three arrays, not the tuple of every view) with the full parameters
    (slots prm, iprm): end kinematics and kernels.internal_forces, no momentum rate."""
    A = bind(F, I, S)
    U, bc, vbc, Tr, prm, iprm = A[X_U], A[X_BC], A[X_VBC], A[X_TR], A[X_PRM], A[X_IPRM]
    fill_end_kinematics(bc, iprm, t, vbc, A[X_BS], A[X_BP])
    if winch_active(prm, iprm):
        winch_end_velocity(U, prm, iprm, Tr, vbc)
    internal_forces(U, prm, iprm, A[X_H], A[X_V], A[X_PJ], A[X_D], A[X_LF], Tr, A[X_TAB_EPS], A[X_TAB_T], bc, vbc,
                    A[X_WQ], A[X_WM], A[X_TRC], A[X_FL], A[X_DU], A[X_ENDF], A[X_TMP])


@jit
def element_starts(U, ra, h, iprm, starts):
    """r at the left end of every element: r_a + cumulative sums of h int q (from the anchor end)."""
    N = U.shape[0]
    if iprm[I_ANCHOR] == 0:
        for c in range(3):
            acc = 0.0
            for e in range(N):
                starts[e, c] = ra[c] + acc
                acc += h[e] * U[e, 0, c]
    else:
        for c in range(3):
            acc = 0.0
            for e in range(N - 1, -1, -1):
                acc += h[e] * U[e, 0, c]
                starts[e, c] = ra[c] - acc


@jit
def _at3(w, p, arr, e, col):
    """sum_k w[p, k] arr[e, k, col + c] for c = 0, 1, 2: a three-component channel of element e at
    point p from its modes (w = phi for values, iphi for integrals)."""
    a0 = 0.0
    a1 = 0.0
    a2 = 0.0
    for k in range(arr.shape[1]):
        a = w[p, k]
        a0 += a * arr[e, k, col]
        a1 += a * arr[e, k, col + 1]
        a2 += a * arr[e, k, col + 2]
    return a0, a1, a2


@jit
def sample_state(U, ra, wq, wm, tr, fl, endf, h, iprm, g0, law, EA, zeta, EI, tab_eps, tab_T, elem, phi, iphi, lag,
                 starts, tnodes, out):
    """Fill out (NS, n) at the points of a sampling plan (module docstring)."""
    element_starts(U, ra, h, iprm, starts)
    tension_nodes(wq, tr, fl, endf, h, iprm, law, EA, zeta, EI, tab_eps, tab_T, tnodes)
    bending = iprm[I_BENDING] != 0
    ig0 = 1.0 / g0
    for p in range(elem.shape[0]):
        e = elem[p]
        q0, q1, q2 = _at3(phi, p, U, e, 0)
        v0, v1, v2 = _at3(phi, p, U, e, 3)
        r0, r1, r2 = _at3(iphi, p, U, e, 0)
        hh = 0.5 * h[e]
        out[S_POS, p] = starts[e, 0] + hh * r0
        out[S_POS + 1, p] = starts[e, 1] + hh * r1
        out[S_POS + 2, p] = starts[e, 2] + hh * r2
        out[S_VEL, p] = v0 * ig0
        out[S_VEL + 1, p] = v1 * ig0
        out[S_VEL + 2, p] = v2 * ig0
        l = np.sqrt(q0 * q0 + q1 * q1 + q2 * q2)
        il = 1.0 / l if l > 0.0 else 1.0
        i0 = q0 * il
        i1 = q1 * il
        i2 = q2 * il
        out[S_STRAIN, p] = l - 1.0
        out[S_TENSION, p] = node_interpolant(lag, p, tnodes, e)
        out[S_TV, p], out[S_TV + 1, p], out[S_TV + 2, p] = _at3(phi, p, wm, e, M_TV)
        for c in range(S_CURV, S_SHEAR + 3):
            out[c, p] = 0.0
        if bending:
            _bending_at(phi, p, wm, e, l, il, i0, i1, i2, out)


@jit
def tension_nodes(wq, tr, fl, endf, h, iprm, law, EA, zeta, EI, tab_eps, tab_T, tnodes):
    """Tension at every element's nodes into tnodes (N, Q + 2): column 0 the left interface, 1 ... Q the
    law at the Gauss points (strain |q| - 1 and strain rate as the right-hand side used them), Q + 1
    the right interface; an interface's value is shared by the two elements at it (module docstring)."""
    N = tnodes.shape[0]
    nq = tnodes.shape[1] - 2
    for e in range(N):
        pc = compression_cap(law, EI, iprm[I_P], h[e])
        for j in range(nq):
            tnodes[e, 1 + j] = axial_tension(law, wq[e, j, W_L] - 1.0, wq[e, j, W_EDOT], EA, zeta, tab_eps, tab_T, pc)
    tnodes[0, 0] = endf[0, E_T]
    tnodes[N - 1, nq + 1] = endf[1, E_T]
    for k in range(1, N):
        a0, a1, a2 = _unit(tr[k - 1, 1, T_Q], tr[k - 1, 1, T_Q + 1], tr[k - 1, 1, T_Q + 2])
        b0, b1, b2 = _unit(tr[k, 0, T_Q], tr[k, 0, T_Q + 1], tr[k, 0, T_Q + 2])
        m0, m1, m2 = _unit(a0 + b0, a1 + b1, a2 + b2)
        f = fl[k, F_V] * m0 + fl[k, F_V + 1] * m1 + fl[k, F_V + 2] * m2
        lo = tnodes[k - 1, nq]
        hi = tnodes[k, 1]
        if lo > hi:
            lo, hi = hi, lo
        f = f if f > lo else lo
        f = f if f < hi else hi
        tnodes[k - 1, nq + 1] = f
        tnodes[k, 0] = f


@jit
def node_interpolant(lag, p, tnodes, e):
    """sum_j lag[p, j] tnodes[e, j], clipped to the range of the element's node values."""
    v = 0.0
    lo = tnodes[e, 0]
    hi = tnodes[e, 0]
    for j in range(tnodes.shape[1]):
        t = tnodes[e, j]
        v += lag[p, j] * t
        lo = t if t < lo else lo
        hi = t if t > hi else hi
    v = v if v > lo else lo
    return v if v < hi else hi


@jit
def _unit(x0, x1, x2):
    """x / |x| (0 for x = 0)."""
    n = np.sqrt(x0 * x0 + x1 * x1 + x2 * x2)
    if n <= 1e-300:
        return 0.0, 0.0, 0.0
    return x0 / n, x1 / n, x2 / n


@jit
def _bending_at(phi, p, wm, e, l, il, i0, i1, i2, out):
    """Curvature |kappa|, bending moment |M| and M = l^2 M*, shear force (1/l) i x tau at point p."""
    k0, k1, k2 = _at3(phi, p, wm, e, M_KAP)
    m0, m1, m2 = _at3(phi, p, wm, e, M_MS)
    u0, u1, u2 = _at3(phi, p, wm, e, M_TAU)
    l2 = l * l
    m0 *= l2
    m1 *= l2
    m2 *= l2
    out[S_CURV, p] = np.sqrt(k0 * k0 + k1 * k1 + k2 * k2)
    out[S_MOMENT, p] = np.sqrt(m0 * m0 + m1 * m1 + m2 * m2)
    out[S_MVEC, p] = m0
    out[S_MVEC + 1, p] = m1
    out[S_MVEC + 2, p] = m2
    out[S_SHEAR, p] = (i1 * u2 - i2 * u1) * il
    out[S_SHEAR + 1, p] = (i2 * u0 - i0 * u2) * il
    out[S_SHEAR + 2, p] = (i0 * u1 - i1 * u0) * il
