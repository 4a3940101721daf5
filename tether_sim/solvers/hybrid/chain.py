"""The chain of nodes of one zoning and its equation groups (see assembly.py for the kinds).

Each end is given by its PE2020 Table 1 row (physics/end_conditions.EndKind) and whether its frame
is held (a clamped row, or a force end with hybrid.hold_direction_*: the GP benchmark's right end):
a body's end is tied to the body's node, a kinematic end has v = v_BC, a force end a point force
(a free end: zero load, ``free_ends``); at a rod end rod.rod_end_code picks the condition.
"""

from dataclasses import dataclass

import numpy as np

from tether_sim.physics.bodies import BODY_STATE_SIZE
from tether_sim.solvers.hybrid.assembly import (BODY_DYN, CAT_BODY, CAT_CELL, CAT_FORCE, CAT_FREE, CAT_VEL, GROUP_ROWS,
                                                JOINT_CR, JOINT_RC, LAW, ROD_BODY, ROD_CELL, ROD_END, UNIT)
from tether_sim.solvers.hybrid.body import BODY_PAR0, GPAR_SIZE
from tether_sim.solvers.hybrid.layout import CAT_SLOTS, ROD_SLOTS
from tether_sim.solvers.hybrid.rod import rod_end_code
from tether_sim.solvers.hybrid.zoning import ROD, chain_nodes


@dataclass
class Chain:
    """Node and group arrays of one zoning (all int64/float64, ready for the kernels)."""

    grid: np.ndarray  # (K,) grid index of each chain node
    kind: np.ndarray  # (K,) 0 catenary, 1 rod
    s: np.ndarray  # (K,) arc length
    noff: np.ndarray  # (K,) offset of the node's unknowns
    nslot: np.ndarray  # (K,) 7 or 12
    gkind: np.ndarray
    ga: np.ndarray
    gb: np.ndarray
    grow: np.ndarray
    gpar: np.ndarray  # (G, 9)
    end_group: tuple  # group index of the ship and vehicle end conditions
    body_node: tuple  # node index of the body at each end (-1: none); body nodes follow the cable nodes
    n_unknowns: int
    nnz_max: int
    idx_node: np.ndarray  # (n_unknowns,) node of each unknown
    idx_slot: np.ndarray  # (n_unknowns,) slot of each unknown
    kl: int = 0  # lower and upper bandwidth of the Jacobian in this unknown and row order
    ku: int = 0
    low: np.ndarray = None  # (n,) lowest row with a nonzero in each column (band_lu)
    last: np.ndarray = None  # (n,) last nonzero column of each row


def build_chain(zones, s_grid, end_rows, end_held, free_ends, body_params=(None, None)):
    """Chain and groups for element zones; ``end_rows[e]``: the end's Table 1 row, ``end_held[e]``: its
    frame held; ``free_ends[e]`` marks a tension-free catenary end; ``body_params[e]`` (packed rigid-body
    parameters) adds a body node at that end."""
    nodes = chain_nodes(zones)
    K = len(nodes)
    grid = np.array([j for j, _ in nodes], dtype=np.int64)
    kind = np.array([k for _, k in nodes], dtype=np.int64)
    nslot = np.where(kind == ROD, ROD_SLOTS, CAT_SLOTS).astype(np.int64)
    body_node = [-1, -1]
    for e in range(2):
        if body_params[e] is not None:
            body_node[e] = K + sum(1 for x in body_node if x >= 0)
    nslot = np.concatenate([nslot, np.full(sum(1 for x in body_node if x >= 0), BODY_STATE_SIZE)]).astype(np.int64)
    # unknowns in chain order, a ship-end body first and a vehicle-end body last, so that the Jacobian
    # is banded (the rows of each body group sit next to its end's rows)
    order = ([body_node[0]] if body_node[0] >= 0 else []) + list(range(K)) + ([body_node[1]] if body_node[1] >= 0 else [])
    order = np.array(order, dtype=np.int64)
    noff = np.zeros(nslot.size, dtype=np.int64)
    noff[order] = np.concatenate([[0], np.cumsum(nslot[order])[:-1]])
    groups, end_group = _groups(grid, kind, body_node, end_rows, free_ends)
    gkind = np.array([g[0] for g in groups], dtype=np.int64)
    rows = GROUP_ROWS[gkind]
    grow = np.concatenate([[0], np.cumsum(rows)[:-1]]).astype(np.int64)
    n_unknowns = int(nslot.sum())
    if int(rows.sum()) != n_unknowns:
        raise AssertionError(f"hybrid chain: {int(rows.sum())} equations for {n_unknowns} unknowns")
    ga = np.array([g[1] for g in groups], dtype=np.int64)
    gb = np.array([g[2] for g in groups], dtype=np.int64)
    nnz = 0
    for g, (k, a, b) in enumerate(groups):
        nnz += GROUP_ROWS[k] * (nslot[a] + (nslot[b] if b >= 0 else 0))
    gpar = _group_parameters(groups, gkind, end_group, kind, body_node, end_rows, end_held, body_params)
    idx_node = np.repeat(order, nslot[order])
    idx_slot = np.concatenate([np.arange(nslot[n]) for n in order]).astype(np.int64)
    kl, ku, low, last = _band(groups, grow, noff, nslot, n_unknowns)
    return Chain(grid, kind, s_grid[grid].astype(float), noff, nslot, gkind, ga, gb, grow, gpar, tuple(end_group),
                 tuple(body_node), n_unknowns, int(nnz), idx_node, idx_slot, kl, ku, low, last)


def _groups(grid, kind, body_node, end_rows, free_ends):
    """Equation groups (kind, node a, node b or -1) in node order -- ship end, then per node its
    unit-tangent row, its law and the link to the next node, then the vehicle end -- so that the
    Jacobian is banded in this row order; and the indices of the two end groups."""
    K = len(grid)
    links = []
    for c in range(K - 1):
        if grid[c] == grid[c + 1]:
            links.append((JOINT_CR if kind[c] != ROD else JOINT_RC, c, c + 1))
        else:
            links.append((ROD_CELL if kind[c] == ROD else CAT_CELL, c, c + 1))
    ends = []
    for e, (node, neighbour) in enumerate(((0, 1), (K - 1, K - 2))):
        if body_node[e] >= 0:
            ends.append((ROD_BODY if kind[node] == ROD else CAT_BODY, node, body_node[e]))
        elif kind[node] == ROD:
            ends.append((ROD_END, node, -1))
        elif end_rows[e].kinematic:
            ends.append((CAT_VEL, node, -1))
        elif free_ends[e]:
            ends.append((CAT_FREE, node, neighbour))
        else:
            ends.append((CAT_FORCE, node, -1))
    groups = [ends[0]]
    if body_node[0] >= 0:
        groups.append((BODY_DYN, body_node[0], 0))
    for c in range(K):
        if kind[c] != ROD:
            groups.append((UNIT, c, -1))
        groups.append((LAW, c, -1))
        if c < K - 1:
            groups.append(links[c])
    groups.append(ends[1])
    end_group = [0, len(groups) - 1]
    if body_node[1] >= 0:
        groups.append((BODY_DYN, body_node[1], K - 1))
    return groups, end_group


def _group_parameters(groups, gkind, end_group, kind, body_node, end_rows, end_held, body_params):
    """Per group parameters: the rod end kind, the law's rod flag, the body's end and parameters."""
    gpar = np.zeros((len(groups), GPAR_SIZE))
    for e in range(2):
        g = end_group[e]
        if gkind[g] == ROD_END:
            gpar[g, 0] = rod_end_code(end_rows[e], end_held[e])
    for g, (k, a, b) in enumerate(groups):
        if k == LAW:
            gpar[g, 0] = float(kind[a] == ROD)
        if k in (BODY_DYN, CAT_BODY, ROD_BODY):
            e = body_node.index(a if k == BODY_DYN else b)
            gpar[g, 0] = e
            gpar[g, 1] = float(kind[b if k == BODY_DYN else a] == ROD)
            gpar[g, BODY_PAR0:] = body_params[e]
    return gpar


def _band(groups, grow, noff, nslot, n_unknowns):
    """Lower and upper bandwidths of the Jacobian, the lowest row with a nonzero in each column
    (band_lu's ``low``) and the last nonzero column of each row."""
    kl = ku = 0
    first = np.zeros(n_unknowns, dtype=np.int64)  # structural first and last column of each row
    last = np.zeros(n_unknowns, dtype=np.int64)
    for g, (k, a, b) in enumerate(groups):
        lo = min(noff[x] for x in (a, b) if x >= 0)
        hi = max(noff[x] + nslot[x] - 1 for x in (a, b) if x >= 0)
        kl = max(kl, int(grow[g] + GROUP_ROWS[k] - 1 - lo))
        ku = max(ku, int(hi - grow[g]))
        first[grow[g]:grow[g] + GROUP_ROWS[k]] = lo
        last[grow[g]:grow[g] + GROUP_ROWS[k]] = hi
    by_first = np.argsort(first, kind="stable")  # low[j] = max{i : first[i] <= j}
    pos = np.searchsorted(first[by_first], np.arange(n_unknowns), side="right") - 1
    low = np.maximum.accumulate(by_first)[pos].astype(np.int64)
    return kl, ku, low, last


def rod_blocks(chain):
    """(first, last) chain indices of each run of rod nodes joined by rod cells."""
    out = []
    K = chain.grid.size
    c = 0
    while c < K:
        if chain.kind[c] != ROD:
            c += 1
            continue
        first = c
        while c + 1 < K and chain.kind[c + 1] == ROD and chain.grid[c + 1] != chain.grid[c]:
            c += 1
        out.append((first, c))
        c += 1
    return out
