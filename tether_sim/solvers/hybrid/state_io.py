"""Hybrid solver state in world terms: end motion, positions, per-node fields, zone conversion."""

import numpy as np

from tether_sim.solvers.hybrid import zoning
from tether_sim.solvers.hybrid.layout import CAT_EPS, CAT_T, CAT_TAN, CAT_V, ROD_F, ROD_KAPPA, ROD_V


class EndMotion:
    """Commanded state of one end; cubic Hermite from the current state to the target of advance_to."""

    def __init__(self, position):
        self.p = np.asarray(position, dtype=float).copy()
        self.v = np.zeros(3)
        self.target = None
        self.t0 = self.t1 = 0.0
        self.active = False

    def set_target(self, position, velocity):
        self.target = (np.asarray(position, dtype=float).copy(), np.asarray(velocity, dtype=float).copy())

    def begin(self, t0, t1):
        self.t0, self.t1 = t0, t1
        if self.target is None:
            self.target = (self.p.copy(), self.v.copy()) if float(np.abs(self.v).max()) <= 1e-8 else \
                (self.p + self.v * (t1 - t0), self.v.copy())
        self.active = t1 > t0

    def _hermite(self, t):
        h = self.t1 - self.t0
        x = min(max((t - self.t0) / h, 0.0), 1.0)
        p1, v1 = self.target
        h00, h10, h01, h11 = 2 * x**3 - 3 * x**2 + 1, x**3 - 2 * x**2 + x, -2 * x**3 + 3 * x**2, x**3 - x**2
        d00, d10, d01, d11 = 6 * x**2 - 6 * x, 3 * x**2 - 4 * x + 1, -6 * x**2 + 6 * x, 3 * x**2 - 2 * x
        pos = h00 * self.p + h10 * h * self.v + h01 * p1 + h11 * h * v1
        vel = (d00 * self.p + d01 * p1) / h + d10 * self.v + d11 * v1
        return pos, vel

    def position_at(self, t):
        return self._hermite(t)[0] if self.active else self.p.copy()

    def velocity_at(self, t):
        return self._hermite(t)[1] if self.active else self.v.copy()

    def finish(self, t):
        if self.active:
            self.p, self.v = self.target[0].copy(), self.target[1].copy()
        self.target = None
        self.active = False
        self.t0 = self.t1 = t

    def reset_time(self, t):
        self.t0 = self.t1 = t
        self.v[:] = 0.0
        self.active = False


def _node_tangent_strain(solver, c):
    if solver.chain.kind[c] == zoning.ROD:
        return solver.Lf[c][0], solver._node_strain(c)
    t = solver.Y[c, CAT_TAN:CAT_TAN + 3]
    return t / np.linalg.norm(t), solver._node_strain(c)


def reconstruct_positions(solver):
    """r(s) by integrating dr/ds = (1 + eps) t from the ship end (trapezoid on the chain)."""
    ch = solver.chain
    K = ch.grid.size
    r = np.empty((K, 3))
    r[0] = solver.r0
    ta, ea = _node_tangent_strain(solver, 0)
    for c in range(1, K):
        tb, eb = _node_tangent_strain(solver, c)
        if ch.grid[c] == ch.grid[c - 1]:
            r[c] = r[c - 1]
        else:
            r[c] = r[c - 1] + (ch.s[c] - ch.s[c - 1]) * 0.5 * ((1.0 + ea) * ta + (1.0 + eb) * tb)
        ta, ea = tb, eb
    return r


def node_profile(solver):
    """Per chain node: s, position, velocity, tension, strain, force (world), shear, moment, curvature."""
    ch = solver.chain
    K = ch.grid.size
    Y, Lf = solver.Y, solver.Lf
    B = np.array([solver.GJ, solver.EI, solver.EI])
    out = {k: np.zeros(K) for k in ("tension", "strain", "shear", "moment", "torsion", "curvature")}
    out["velocity"] = np.zeros((K, 3))
    out["force"] = np.zeros((K, 3))
    out["moment_vec"] = np.zeros((K, 3))
    rod = ch.kind == zoning.ROD
    for c in range(K):
        if rod[c]:
            L = Lf[c]
            out["velocity"][c] = L.T @ Y[c, ROD_V:ROD_V + 3]
            out["force"][c] = L.T @ Y[c, ROD_F:ROD_F + 3]
            out["tension"][c] = Y[c, ROD_F]
            out["strain"][c] = solver._node_strain(c)
            out["shear"][c] = np.hypot(Y[c, ROD_F + 1], Y[c, ROD_F + 2])
            q = B * Y[c, ROD_KAPPA:ROD_KAPPA + 3]
            out["moment_vec"][c] = L.T @ q
            out["moment"][c] = np.hypot(q[1], q[2])
            out["torsion"][c] = q[0]
            out["curvature"][c] = np.hypot(Y[c, ROD_KAPPA + 1], Y[c, ROD_KAPPA + 2])
        else:
            t = Y[c, CAT_TAN:CAT_TAN + 3] / np.linalg.norm(Y[c, CAT_TAN:CAT_TAN + 3])
            out["velocity"][c] = Y[c, CAT_V:CAT_V + 3]
            out["force"][c] = Y[c, CAT_T] * t
            out["tension"][c] = Y[c, CAT_T]
            out["strain"][c] = solver._node_strain(c)
    cat_idx = np.nonzero(~rod)[0]
    for c in cat_idx:  # geometric curvature of the catenary (no moment carried)
        a = c - 1 if c > 0 and not rod[c - 1] and ch.grid[c - 1] != ch.grid[c] else c
        b = c + 1 if c < K - 1 and not rod[c + 1] and ch.grid[c + 1] != ch.grid[c] else c
        if b != a:
            ta = Y[a, CAT_TAN:CAT_TAN + 3] / np.linalg.norm(Y[a, CAT_TAN:CAT_TAN + 3])
            tb = Y[b, CAT_TAN:CAT_TAN + 3] / np.linalg.norm(Y[b, CAT_TAN:CAT_TAN + 3])
            out["curvature"][c] = np.linalg.norm(tb - ta) / (ch.s[b] - ch.s[a])
    out["s"] = ch.s
    out["position"] = solver.positions
    out["zone"] = ch.kind.copy()
    return out


def convert_state(solver, new_zones):
    """(Y, Yt, Lf, positions, position rates) on the chain of ``new_zones``, converting nodes whose model changed [GP Eq. 13-14]."""
    old = solver.chain
    nodes = zoning.chain_nodes(new_zones)
    K = len(nodes)
    Y = np.zeros((K, 13))
    Yt = np.zeros((K, 13))
    Lf = np.zeros((K, 3, 3))
    pos = np.zeros((K, 3))
    rdot = np.zeros((K, 3))
    src = []
    for j, kind in nodes:
        cands = np.nonzero(old.grid == j)[0]
        same = [c for c in cands if old.kind[c] == kind]
        src.append((same[0], True) if same else (cands[0], False))
    for n, ((j, kind), (c, same)) in enumerate(zip(nodes, src)):
        Lf[n] = solver.Lf[c]
        pos[n] = solver.positions[c]
        rdot[n] = solver.rdot[c]
        if same or kind == zoning.CATENARY:
            if same:
                Y[n], Yt[n] = solver.Y[c], solver.Yt[c]
            else:
                Y[n], Yt[n] = zoning.rod_to_cat(solver.Y[c], solver.Yt[c], solver.Lf[c])
    for n, m in _runs(nodes, zoning.ROD):  # rod blocks: frames by minimal rotation from kept frames, then variables
        block = range(n, m + 1)
        keep = [src[i][1] for i in block]
        tang = [solver.Lf[src[i][0]][0] if keep[k] else solver.Y[src[i][0], 4:7] / np.linalg.norm(
            solver.Y[src[i][0], 4:7]) for k, i in enumerate(block)]
        frames = zoning.rod_block_frames(tang, [Lf[i] for i in block], keep)
        ds = solver.cell_lengths()[[nodes[i][0] for i in block[:-1]]]  # element k joins block nodes k, k + 1
        for k, i in enumerate(block):
            if keep[k]:
                continue
            Lf[i] = frames[k]
            Y[i], Yt[i] = zoning.cat_to_rod(solver.Y[src[i][0]], solver.Yt[src[i][0]], frames[k])
            kap = []
            if k > 0:
                kap.append(zoning.curvature_between(frames[k - 1], frames[k], ds[k - 1]))
            if k < len(frames) - 1:
                kap.append(zoning.curvature_between(frames[k], frames[k + 1], ds[k]))
            if kap:
                Y[i, ROD_KAPPA:ROD_KAPPA + 3] = np.mean(kap, axis=0)
    _anchor_new_catenary(solver, nodes, src, Y, pos)
    return Y, Yt, Lf, pos, rdot


def _anchor_new_catenary(solver, nodes, src, Y, pos):
    """Positions of nodes that became catenary, from the catenary's own geometry.

    A rod zone's positions are integrated from its tangents after each step; nothing in the rod's
    equations ties that shape to the point its far end is held at (its compatibility equation is in
    rate form), so a rod block's integrated end misses a held end or a joint by the drift of its
    shape (tens of mm on a 30 m slack line with bending). The catenary's cell equation is in position
    form, (r_b - r_a) / ds = mean((1 + eps) t): a catenary zone taking over that shape from the rod
    would close the miss through the strain of one cell in one step (EA x miss / ds, 100 kN and more
    for a stiff line), and Newton does not converge. So a new catenary stretch is integrated with its
    own cell equation from a node whose position is authoritative (a catenary node kept from the old
    chain, or a held end: fixed, or driven at its commanded position); the miss stays at the joint
    with the remaining rod zone, whose equations do not use positions. Held on both sides, the miss is
    spread along the stretch in proportion to arc length.
    """
    K = len(nodes)
    held = [None] * K
    for e, n in ((0, 0), (1, K - 1)):
        if nodes[n][1] != zoning.CATENARY:
            continue
        where = solver.end_kinds[e].position
        if where == "fixed":
            held[n] = np.asarray(solver.ends[e].position, dtype=float)
        elif where == "motion":
            held[n] = solver.end_motion[e].position_at(solver.time)
    s_grid = solver.s_grid
    for n, m in _runs(nodes, zoning.CATENARY):
        run = list(range(n, m + 1))
        converted = [not src[i][1] for i in run]
        if not any(converted):
            continue
        anchor = [held[i] is not None or not converted[k] for k, i in enumerate(run)]
        for i in run:
            if held[i] is not None:
                pos[i] = held[i]
        k = 0
        while k < len(run):  # stretches of converted nodes between anchors
            if anchor[k]:
                k += 1
                continue
            a = k
            while k < len(run) and not anchor[k]:
                k += 1
            left = a - 1 if a > 0 else None
            right = k if k < len(run) else None
            if left is None and right is None:
                continue  # nothing authoritative in this run: the rod's shape stays
            idx = [run[j] for j in range(a if left is None else left, (k - 1 if right is None else right) + 1)]
            step = [0.5 * (s_grid[nodes[q][0]] - s_grid[nodes[p][0]]) * (
                (1.0 + Y[p, CAT_EPS]) * _unit(Y[p, CAT_TAN:CAT_TAN + 3])
                + (1.0 + Y[q, CAT_EPS]) * _unit(Y[q, CAT_TAN:CAT_TAN + 3])) for p, q in zip(idx[:-1], idx[1:])]
            if left is not None:
                new = [pos[idx[0]]]
                for d in step:
                    new.append(new[-1] + d)
                if right is not None:  # held on both sides: spread the miss by arc length
                    miss = pos[idx[-1]] - new[-1]
                    s0, s1 = s_grid[nodes[idx[0]][0]], s_grid[nodes[idx[-1]][0]]
                    for j, i in enumerate(idx):
                        new[j] = new[j] + miss * (s_grid[nodes[i][0]] - s0) / max(s1 - s0, 1e-300)
                for j, i in enumerate(idx[1:-1] if right is not None else idx[1:]):
                    pos[i] = new[j + 1]
            else:
                new = [pos[idx[-1]]]
                for d in reversed(step):
                    new.append(new[-1] - d)
                for j, i in enumerate(reversed(idx[:-1])):
                    pos[i] = new[j + 1]


def _runs(nodes, kind):
    """(first, last) of each run of consecutive chain nodes of ``kind`` (a joint's two nodes share a grid
    point and end one run, start another)."""
    K = len(nodes)
    n = 0
    while n < K:
        if nodes[n][1] != kind:
            n += 1
            continue
        m = n
        while m + 1 < K and nodes[m + 1][1] == kind and nodes[m + 1][0] != nodes[m][0]:
            m += 1
        yield n, m
        n = m + 1


def _unit(t):
    return t / np.linalg.norm(t)
