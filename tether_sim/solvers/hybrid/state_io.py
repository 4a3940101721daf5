"""Hybrid solver state in world terms: end motion, positions, per-node fields, zone conversion."""

import numpy as np

from tether_sim.numerics.jit import jit_alloc
from tether_sim.numerics.rotations import minimal_rotation, rotate_frame
from tether_sim.physics.bodies import body_attachment_kinematics
from tether_sim.solvers.hybrid import zoning
from tether_sim.solvers.hybrid.layout import (CAT_EPS, CAT_T, CAT_TAN, CAT_V, ROD_EPS, ROD_F, ROD_KAPPA, ROD_OMEGA,
                                              ROD_V)

CLOSE_TOLERANCE = 1e-7  # a re-closed rod shape ends this close to its target, per metre of block (close_rod_blocks)
CLOSE_ITERATIONS = 8  # Gauss-Newton iterations of the closing correction at most
CLOSE_RCOND = 1e-6  # directions of the bending correction with less than this share of the largest compliance are left
CLOSE_KEEP = 1e-5  # at a zone evaluation without changes, a rod block ending this close to its target (per metre) is kept


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


def _norms(x):
    """Row norms of a (k, 3) array, each the number np.linalg.norm gives for the row (sqrt of the row's BLAS dot
    product with itself: a stacked matmul takes the same dot per row; a sum of squares rounds differently)."""
    return np.sqrt(np.matmul(x[:, None, :], x[:, :, None])[:, 0, 0])


def node_profile(solver):
    """Per chain node: s, position, velocity, tension, strain, force (world), shear, moment, curvature.

    Array operations, each node's numbers those of the same operations on the node alone (the unit tangent
    t / |t|, L^T y per rod node, the hypot of two components): the profile the node loop gave, bit for bit."""
    ch = solver.chain
    K = ch.grid.size
    Y, Lf = solver.Y[:K], solver.Lf[:K]
    out = {k: np.zeros(K) for k in ("tension", "strain", "shear", "moment", "torsion", "curvature")}
    velocity, force, moment_vec = np.zeros((K, 3)), np.zeros((K, 3)), np.zeros((K, 3))
    rod = ch.kind == zoning.ROD
    cat = ~rod
    has_rod = bool(rod.any())
    if has_rod:
        Yr = Y[rod]
        LT = np.swapaxes(Lf[rod], 1, 2)
        velocity[rod] = np.matmul(LT, Yr[:, ROD_V:ROD_V + 3, None])[:, :, 0]
        force[rod] = np.matmul(LT, Yr[:, ROD_F:ROD_F + 3, None])[:, :, 0]
        q = np.array([solver.GJ, solver.EI, solver.EI]) * Yr[:, ROD_KAPPA:ROD_KAPPA + 3]
        moment_vec[rod] = np.matmul(LT, q[:, :, None])[:, :, 0]
        out["tension"][rod] = Yr[:, ROD_F]
        out["strain"][rod] = Yr[:, ROD_EPS]
        out["shear"][rod] = np.hypot(Yr[:, ROD_F + 1], Yr[:, ROD_F + 2])
        out["moment"][rod] = np.hypot(q[:, 1], q[:, 2])
        out["torsion"][rod] = q[:, 0]
        out["curvature"][rod] = np.hypot(Yr[:, ROD_KAPPA + 1], Yr[:, ROD_KAPPA + 2])
    if not has_rod:  # all catenary (a live file's usual chain): the same operations on whole columns, no gathers
        unit = Y[:, CAT_TAN:CAT_TAN + 3] / _norms(Y[:, CAT_TAN:CAT_TAN + 3])[:, None]
        velocity = Y[:, CAT_V:CAT_V + 3].copy()
        force = Y[:, CAT_T, None] * unit
        out["tension"] = Y[:, CAT_T].copy()
        out["strain"] = Y[:, CAT_EPS].copy()
    elif cat.any():
        Yc = Y[cat]
        tan = Yc[:, CAT_TAN:CAT_TAN + 3]
        unit = np.zeros((K, 3))
        unit[cat] = tan / _norms(tan)[:, None]
        velocity[cat] = Yc[:, CAT_V:CAT_V + 3]
        force[cat] = Yc[:, CAT_T, None] * unit[cat]
        out["tension"][cat] = Yc[:, CAT_T]
        out["strain"][cat] = Yc[:, CAT_EPS]
    if cat.any():
        # geometric curvature of the catenary (no moment carried): the turn of the unit tangent between the
        # node's catenary neighbours on other grid points (the node itself at a zone end or joint)
        c = np.arange(K)
        grid = ch.grid
        a, b = c.copy(), c.copy()
        a[1:] = np.where(cat[:-1] & (grid[:-1] != grid[1:]), c[:-1], c[1:])
        b[:-1] = np.where(cat[1:] & (grid[1:] != grid[:-1]), c[1:], c[:-1])
        use = cat & (a != b)
        if use.any():
            a, b = a[use], b[use]
            out["curvature"][use] = _norms(unit[b] - unit[a]) / (ch.s[b] - ch.s[a])
    out["velocity"], out["force"], out["moment_vec"] = velocity, force, moment_vec
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
    if solver.opt.zoning == "adaptive" and solver.opt.close_rod_shapes != "off" and solver.opt.frames_from_curvature:
        close_rod_blocks(solver, nodes, src, Y, Yt, Lf, pos)
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


def end_target(solver, e):
    """Where a line's end is: a body's attachment point, a driven end's commanded position, a fixed point; None for a
    force or free end (nothing holds its position)."""
    where = solver.end_kinds[e].position
    if where == "body":
        x = getattr(solver, "body_x", (None, None))[e]
        if x is None:
            return None  # the initial state: the body is placed at the line's end after it
        p, v = np.empty(3), np.empty(3)
        body_attachment_kinematics(x, solver.body_params[e], p, v)
        return p
    if where == "motion":
        return solver.end_motion[e].position_at(solver.time)
    if where == "fixed":
        return np.asarray(solver.ends[e].position, dtype=float)
    return None


@jit_alloc
def frames_along(L0, kappa, ds):
    """Frames of a rod block from its first frame and its node curvatures, L_b = exp(-kappa_ab~ ds) L_a with
    kappa_ab the mean of the two nodes' (the recursion of the solver's frame re-derivation, same arithmetic)."""
    n = kappa.shape[0]
    out = np.empty((n, 3, 3))
    out[0] = L0
    th = np.empty(3)
    for k in range(1, n):
        for i in range(3):
            th[i] = 0.5 * (kappa[k, i] + kappa[k - 1, i]) * ds[k - 1]
        rotate_frame(out[k - 1], th, out[k])
    return out


@jit_alloc
def shape_along(r0, frames, eps, ds):
    """Positions of a rod block integrated from r0 along (1 + eps) t (trapezoid, as after every step)."""
    n = frames.shape[0]
    r = np.empty((n, 3))
    r[0] = r0
    for k in range(1, n):
        a = 1.0 + eps[k - 1]
        b = 1.0 + eps[k]
        for i in range(3):
            r[k, i] = r[k - 1, i] + 0.5 * ds[k - 1] * (a * frames[k - 1, 0, i] + b * frames[k, 0, i])
    return r


def close_rod_block(L0, kappa, free, eps, ds, r0, target, turn=True):
    """First frame and node curvatures of a rod block whose frames (frames_along) integrate to a shape (shape_along)
    from r0 that ends at ``target``. Returns (kappa, frames, positions, iterations).

    Two corrections, alternated: (1) with ``turn`` (a moment-free start: a spherical joint [GP Eq. 12-14] or a
    pinned or body end), the block turns rigidly about its start so that its chord points at the target, which costs
    no bending; (2) the ``free`` nodes' curvatures change by the correction of least bending energy that brings the
    end onto the target, min sum EI |d kappa|^2 ds: linearised, a rotation phi_e = ds_e d kappa_e (world components)
    of element e moves the end by phi_e x (r_end - r_e), so the minimiser is d kappa_c = (r_end - r_c) x lambda (the
    curvature a point force at the end gives a cantilever, lambda its size over EI), with J lambda = -gap,
    J = sum_e ds_e (|R_e|^2 I - R_e R_e^T); it is what changes the chord's length, and a straight block cannot
    change it (J singular along the chord: the least-squares solution leaves that part)."""
    kappa = np.array(kappa, dtype=float)
    L0 = np.array(L0, dtype=float)
    frames = frames_along(L0, kappa, ds)
    r = shape_along(r0, frames, eps, ds)
    if target is None:
        return kappa, frames, r, 0
    length = float(np.sum(ds))
    tol = CLOSE_TOLERANCE * max(length, 1.0)
    m = free.astype(float)
    size = float(np.linalg.norm(r[-1] - target))
    it = 0
    while it < CLOSE_ITERATIONS and size > tol:
        it += 1
        if turn and float(np.linalg.norm(target - r0)) > tol:
            L0 = L0 @ minimal_rotation(r[-1] - r0, target - r0).T  # tangents t -> Q t
            frames = frames_along(L0, kappa, ds)
            r = shape_along(r0, frames, eps, ds)
            size = float(np.linalg.norm(r[-1] - target))
            if size <= tol or not np.any(free):
                continue
        gap = r[-1] - target
        R = r[-1] - r  # lever arms to the end
        Rm = 0.5 * (R[1:] + R[:-1])
        w = ds[:, None, None] * (np.einsum("e,ij->eij", np.einsum("ei,ei->e", Rm, Rm), np.eye(3))
                                 - np.einsum("ei,ej->eij", Rm, Rm))
        J = 0.5 * (np.einsum("e,eij->ij", m[:-1], w) + np.einsum("e,eij->ij", m[1:], w))  # element: mean of its nodes
        lam = np.linalg.lstsq(J, -gap, rcond=CLOSE_RCOND)[0]
        dk = np.einsum("kij,kj->ki", frames, np.cross(R, lam) * m[:, None])
        for _ in range(8):  # backtracking: the shape is nonlinear in kappa
            k_try = kappa + dk
            f_try = frames_along(L0, k_try, ds)
            r_try = shape_along(r0, f_try, eps, ds)
            s_try = float(np.linalg.norm(r_try[-1] - target))
            if s_try < size:
                break
            dk = 0.5 * dk
        else:
            break  # no decrease along this direction: keep the best shape so far
        stalled = s_try > 0.9 * size  # what is left is along a straight chord, which bending barely shortens
        kappa, frames, r, size = k_try, f_try, r_try, s_try
        if stalled:
            break
    return kappa, frames, r, it


def close_rod_blocks(solver, nodes, src, Y, Yt, Lf, pos, every=False):
    """Rod blocks after a conversion whose frames, re-derived from their curvature, end where their far end is.

    After each step the frames of a rod block are re-derived from kappa along s from the block's first frame and
    its shape is integrated from its tangents (solver._integrate_frames, _commit); the kinematic conditions at its
    far end hold the velocity only. A conversion sets the frames of new rod nodes from the catenary's tangents and
    their kappa from the frame differences averaged over the two neighbouring elements; the element means of those
    node values are not the frames' differences (an odd-even recursion would be: it forces a node-to-node zigzag of
    kappa, a spurious bending moment), and the joint and a moment-free end have kappa = 0 from the next step on. So
    the shape the next step re-derives is not the converted one, and its end moves off the body or driven end it
    belongs to by centimetres a conversion (0.4-1 m over an L = 200 m slack phase). Here each rod block touched by
    the conversion gets kappa = 0 where its conditions will impose it, frames re-derived from its kappa exactly as
    the next step will (so that step keeps them), and the least-bending-energy correction of its kappa that brings
    its integrated shape onto its far end (close_rod_block: the body's attachment point, the commanded or fixed
    end, or the catenary node of its far joint). World velocities, angular velocities and internal forces of its
    nodes are kept (their body components re-expressed in the new frames); strains are not touched."""
    K = len(nodes)
    s_grid = solver.s_grid
    held = solver.end_held
    kinds = solver.end_kinds
    old = solver.chain
    Kold = old.grid.size
    for first, last in _runs(nodes, zoning.ROD):
        if last == K - 1 and held[1] and not (first == 0 and held[0]):
            continue  # frames anchored at the held end (solver._integrate_frames): nothing to close on
        block = list(range(first, last + 1))
        converted = [not src[i][1] for i in block]
        c0, c1 = src[first][0], src[last][0]
        shrunk = (src[first][1] and c0 > 0 and old.kind[c0 - 1] == zoning.ROD and old.grid[c0 - 1] != old.grid[c0]) or \
            (src[last][1] and c1 < Kold - 1 and old.kind[c1 + 1] == zoning.ROD and old.grid[c1 + 1] != old.grid[c1])
        if last < K - 1:
            target = pos[last + 1]  # the catenary node of the far joint
        else:
            target = end_target(solver, 1)
        ds = np.array([s_grid[nodes[i + 1][0]] - s_grid[nodes[i][0]] for i in block[:-1]])
        if not (any(converted) or shrunk):
            if not every or target is None or np.linalg.norm(pos[last] - target) <= CLOSE_KEEP * max(ds.sum(), 1.0):
                continue
        kappa = Y[block, ROD_KAPPA:ROD_KAPPA + 3].copy()
        free = np.ones(len(block), dtype=bool)
        # kappa = 0 at a joint [GP Eq. 12] and at a moment-free (pinned or body) line end; a force end keeps its own
        if first > 0 or (kinds[0].kinematic and not held[0]):
            kappa[0] = 0.0
        if last < K - 1 or (kinds[1].kinematic and not held[1]):
            kappa[-1] = 0.0
        free[0] = free[-1] = False
        r0 = pos[first - 1] if first > 0 else pos[first]
        eps = Y[block, ROD_EPS]
        turn = not held[0] if first == 0 else True
        kappa, frames, r, it = close_rod_block(Lf[first], kappa, free, eps, ds, r0, target, turn)
        for k, i in enumerate(block):
            rot = frames[k] @ Lf[i].T  # old body components -> new
            for a in (ROD_V, ROD_OMEGA, ROD_F):
                Y[i, a:a + 3] = rot @ Y[i, a:a + 3]
                Yt[i, a:a + 3] = rot @ Yt[i, a:a + 3]
            Y[i, ROD_KAPPA:ROD_KAPPA + 3] = kappa[k]
            Lf[i] = frames[k]
            pos[i] = r[k]
        st = solver.stats
        st["closures"] = st.get("closures", 0) + 1


def close_rod_shapes(solver):
    """At a zone evaluation without changes: the solver's rod blocks whose shape has drifted off their far end
    (more than CLOSE_KEEP per metre) closed again, in place (close_rod_blocks)."""
    ch = solver.chain
    nodes = list(zip(ch.grid.tolist(), ch.kind.tolist()))
    src = [(c, True) for c in range(len(nodes))]
    close_rod_blocks(solver, nodes, src, solver.Y, solver.Yt, solver.Lf, solver.positions, every=True)


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
