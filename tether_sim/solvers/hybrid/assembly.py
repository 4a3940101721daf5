"""Residual and sparse Jacobian of one implicit step of the whole chain (all zones, joints, ends).

The discretised step is one nonlinear system in the unknowns Y_{n+1} of every chain node (a joint
is two chain nodes at the same s, one per zone). Equations come in groups, each touching one or two
neighbouring nodes, so the Jacobian is block-banded; it is built group by group with forward
differences (exact structure, ~1e-8 relative entries) and factorised with a sparse LU.

Group kinds: the table GROUPS (a kind's code is its row). Group parameters gpar (G, GPAR_SIZE) hold
boundary vectors. Node arrays: Y, Yn, Ytn (K, N_SLOTS) (cable nodes, then body nodes; layout.py);
Ln (K, 3, 3) rod frames at t_n; rn (K, 6) positions and their generalized-alpha rates at t_n; s (K,).
"""

import numpy as np

from tether_sim.numerics.jit import jit_alloc
from tether_sim.solvers.hybrid.body import body_dynamics_residual, body_end_residual
from tether_sim.solvers.hybrid.catenary import (catenary_cell_residual, catenary_force_bc, catenary_free_bc,
                                                catenary_node_terms, catenary_velocity_bc, unit_tangent_residual,
                                                unit_tangent_value)
from tether_sim.solvers.hybrid.joint import joint_residual
from tether_sim.solvers.hybrid.kernels import law_residual
from tether_sim.solvers.hybrid.layout import CAT_EPS, CAT_T, CAT_TAN, HP_DT, HP_GAM, ROD_EPS, ROD_F
from tether_sim.solvers.hybrid.rod import rod_cell_from_terms, rod_cell_residual, rod_end_residual, rod_node_terms

# (kind, rows, equations): each kind's code (a module constant, compiled as a constant) is its row
GROUPS = (
    ("CAT_CELL", 6, "catenary cell: position and momentum box equations [GP Eq. 2-3]"),
    ("ROD_CELL", 12, "rod cell box equations [GP Eq. 7-10]"),
    ("JOINT_CR", 9, "spherical joint, catenary node then rod node [GP Eq. 12-14]"),
    ("JOINT_RC", 9, "spherical joint, rod node then catenary node [GP Eq. 12-14]"),
    ("UNIT", 1, "|t|^2 = 1 at a catenary node"),
    ("CAT_VEL", 3, "kinematic catenary end: v = v_BC"),
    ("CAT_FORCE", 3, "force catenary end: T t = F"),
    ("CAT_FREE", 3, "free catenary end: T = 0, tangent follows its neighbour"),
    ("ROD_END", 6, "rod end (rod.rod_end_code)"),
    ("BODY_DYN", 13, "rigid body at an end (physics/bodies.py)"),
    ("CAT_BODY", 3, "catenary end moving with the body's attachment point"),
    ("ROD_BODY", 6, "rod end moving with the body's attachment point, moment free"),
    ("LAW", 1, "the node's tension-strain law"),
)
for _code, (_kind, _rows, _equations) in enumerate(GROUPS):
    globals()[_kind] = _code
GROUP_ROWS = np.array([rows for _, rows, _ in GROUPS], dtype=np.int64)


@jit_alloc
def node_law_value(T, eps, eps_n, eps_rate_n, P):
    """Constitutive equation of one node at t_{n+1} [PE2020 Eq. 22]; deps/dt from the gamma relation."""
    g = P[HP_GAM]
    rate = ((eps - eps_n) / P[HP_DT] - (1.0 - g) * eps_rate_n) / g
    return law_residual(T, eps, rate, P)


@jit_alloc
def node_law_residual(Y, Yn, Ytn, is_rod, P, out):
    """node_law_value of one node's row (tension and strain by the node's kind)."""
    iT = 9 if is_rod else 3
    ie = ROD_EPS if is_rod else CAT_EPS
    out[0] = node_law_value(Y[iT], Y[ie], Yn[ie], Ytn[ie], P)


@jit_alloc
def group_residual(kind, a, b, gp, Y, Yn, Ytn, Ln, rn, s, P, cz, cx, cy, out):
    """Residual of one equation group into out[:rows]."""
    if kind == CAT_CELL:
        catenary_cell_residual(Y[a], Yn[a], Ytn[a], rn[a], Y[b], Yn[b], Ytn[b], rn[b], s[b] - s[a], P, cz, cx, cy, out)
    elif kind == ROD_CELL:
        rod_cell_residual(Y[a], Yn[a], Ytn[a], Ln[a], rn[a], Y[b], Yn[b], Ytn[b], Ln[b], rn[b], s[b] - s[a],
                          P, cz, cx, cy, out)
    elif kind == JOINT_CR:
        joint_residual(Y[a], Y[b], Yn[b], Ln[b], P, out)
    elif kind == JOINT_RC:
        joint_residual(Y[b], Y[a], Yn[a], Ln[a], P, out)
    elif kind == UNIT:
        unit_tangent_residual(Y[a], out)
    elif kind == CAT_VEL:
        catenary_velocity_bc(Y[a], gp[0:3], out)
    elif kind == CAT_FORCE:
        catenary_force_bc(Y[a], gp[0:3], out)
    elif kind == CAT_FREE:
        catenary_free_bc(Y[a], Y[b], gp[0:3], gp[3:6], gp[6], out)
    elif kind == ROD_END:
        rod_end_residual(int(gp[0]), Y[a], Yn[a], Ln[a], P, gp[1:4], gp[4:7], out)
    elif kind == LAW:
        node_law_residual(Y[a], Yn[a], Ytn[a], gp[0] > 0.5, P, out)
    elif kind == BODY_DYN:  # a: body node, b: cable end node (gp[1] = 1 if it is a rod node)
        body_dynamics_residual(Y[a], Yn[a], Ytn[a], Y[b], Yn[b], Ln[b], gp[1] > 0.5, gp, P, cz, cx, cy, out)
    else:  # CAT_BODY / ROD_BODY: a: cable end node, b: body node
        body_end_residual(Y[a], Yn[a], Ln[a], kind == ROD_BODY, Y[b], gp, P, out)


@jit_alloc
def _node_terms(c, is_rod, Y, Yn, Ytn, Ln, rn, P, cz, cx, cy, terms, have):
    """Per-node terms of the cell equations, computed once per node (shared by its two cells)."""
    if have[c]:
        return
    tr = terms[c]
    if is_rod:  # alpha_f values (0:13), alpha_m rates (13:26), body-frame load (26:29)
        rod_node_terms(Y[c], Yn[c], Ytn[c], Ln[c], rn[c], P, cz, cx, cy, tr[0:13], tr[13:26], tr[26:29])
    else:  # r_{n+1} (0:3), (1+eps) t (3:6), load (6:9), T t (9:12)
        catenary_node_terms(Y[c], Yn[c], Ytn[c], rn[c], P, cz, cx, cy, tr[0:3], tr[3:6], tr[6:9], tr[9:12])
    have[c] = True


@jit_alloc
def assemble_residual(gkind, ga, gb, grow, gpar, Y, Yn, Ytn, Ln, rn, s, P, cz, cx, cy, R):
    """R (n_rows,) = all group residuals (cell groups from per-node terms evaluated once per node; the
    same arithmetic as group_residual). The catenary cells, unit-tangent and law rows are written straight into R
    from the node arrays: a call of group_residual passes ~15 array views (with their reference counts), which was
    ~30 % of a residual at the 1730 m live mesh, where these are 3 of every 4 groups."""
    out = np.empty(13)
    K = Y.shape[0]
    terms = np.empty((K, 29))
    have = np.zeros(K, dtype=np.bool_)
    for g in range(gkind.shape[0]):
        k = gkind[g]
        a = ga[g]
        b = gb[g]
        r0 = grow[g]
        if k == CAT_CELL or k == ROD_CELL:
            rod = k == ROD_CELL
            _node_terms(a, rod, Y, Yn, Ytn, Ln, rn, P, cz, cx, cy, terms, have)
            _node_terms(b, rod, Y, Yn, Ytn, Ln, rn, P, cz, cx, cy, terms, have)
            ta = terms[a]
            tb = terms[b]
            ds = s[b] - s[a]
            if rod:
                rod_cell_from_terms(ta[0:13], ta[13:26], ta[26:29], tb[0:13], tb[13:26], tb[26:29], ds, P, out)
            else:
                for j in range(3):
                    R[r0 + j] = (tb[j] - ta[j]) / ds - 0.5 * (ta[3 + j] + tb[3 + j])
                    R[r0 + 3 + j] = (tb[9 + j] - ta[9 + j]) / ds + 0.5 * (ta[6 + j] + tb[6 + j])
                continue
        elif k == UNIT:
            R[r0] = unit_tangent_value(Y[a, CAT_TAN], Y[a, CAT_TAN + 1], Y[a, CAT_TAN + 2])
            continue
        elif k == LAW:
            if gpar[g, 0] > 0.5:
                R[r0] = node_law_value(Y[a, ROD_F], Y[a, ROD_EPS], Yn[a, ROD_EPS], Ytn[a, ROD_EPS], P)
            else:
                R[r0] = node_law_value(Y[a, CAT_T], Y[a, CAT_EPS], Yn[a, CAT_EPS], Ytn[a, CAT_EPS], P)
            continue
        else:
            group_residual(k, a, b, gpar[g], Y, Yn, Ytn, Ln, rn, s, P, cz, cx, cy, out)
        for r in range(GROUP_ROWS[k]):
            R[r0 + r] = out[r]


@jit_alloc
def assemble_jacobian(gkind, ga, gb, grow, gpar, noff, nslot, Y, Yn, Ytn, Ln, rn, s, P, cz, cx, cy,
                      rows, cols, vals):
    """Forward-difference Jacobian in COO form (group by group); returns the number of entries."""
    base = np.empty(13)
    pert = np.empty(13)
    nnz = 0
    for g in range(gkind.shape[0]):
        k = gkind[g]
        nr = GROUP_ROWS[k]
        a = ga[g]
        b = gb[g]
        group_residual(k, a, b, gpar[g], Y, Yn, Ytn, Ln, rn, s, P, cz, cx, cy, base)
        for which in range(2):
            node = a if which == 0 else b
            if node < 0 or (which == 1 and b == a):
                continue
            for slot in range(nslot[node]):
                y0 = Y[node, slot]
                yp = y0 + 1e-7 * (1.0 + abs(y0))
                h = yp - y0
                Y[node, slot] = yp
                group_residual(k, a, b, gpar[g], Y, Yn, Ytn, Ln, rn, s, P, cz, cx, cy, pert)
                Y[node, slot] = y0
                hinv = 1.0 / h
                for r in range(nr):
                    d = (pert[r] - base[r]) * hinv
                    if d != 0.0:
                        rows[nnz] = grow[g] + r
                        cols[nnz] = noff[node] + slot
                        vals[nnz] = d
                        nnz += 1
    return nnz
