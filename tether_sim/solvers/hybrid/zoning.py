"""Rod/catenary zoning: which element uses which model, the chain of nodes, state conversion.

Criterion (adaptive zoning)
---------------------------
A catenary neglects the bending moment EI kappa and the shear force EI d(kappa)/ds. Bending acts
over the bending length l_b = sqrt(EI/T); it matters where l_b is not small against the radius of
curvature 1/kappa of the line, or where the shear force is not small against the tension:

    chi = max( sqrt(EI/T) max(w/T, kappa),  sqrt(|f_shear| / T) )

(w: net distributed load per length; kappa and f_shear the element's own bending curvature and, in
a rod element, shear force). Along a static catenary kappa = w/T and the shear EI kappa' = EI w^2/T^2,
so both terms are sqrt(EI w^2 / T^3), the criterion of the weight alone. A moving line can be bent
and sheared far more than its weight does it (a slack rod zone under a jerk carries shear forces of
the size of its tension): a rod element keeps them until the tension dominates. The shear term is
what the spherical joint needs [GP Eq. 14]: there the catenary's tangent takes the direction of the
rod's whole internal force, so a joint placed where the rod's shear is of the size of its tension
kinks the catenary by tens of degrees within one step, and Newton does not converge.

An element becomes rod when chi > chi_on (T below T_on = (EI w^2/chi_on^2)^(1/3), including T <= 0)
and returns to catenary only when chi < chi_off < chi_on (hysteresis: T must rise by the factor
(chi_on/chi_off)^(2/3)). Zones shorter than ``min_zone_elements`` are absorbed into rod (a short
catenary gap) or dropped (a short rod island), so joints do not chatter. Ends whose condition
carries a moment or holds the tangent (clamped, held direction) keep a rod zone of at least
``end_rod_length``. The criterion is evaluated after every accepted step.
"""

import math

import numpy as np

from tether_sim.numerics.jit import jit
from tether_sim.numerics.rotations import frame_with_tangent, minimal_rotation, rotation_vector
from tether_sim.solvers.hybrid.layout import (CAT_EPS, CAT_T, CAT_TAN, CAT_V, N_SLOTS, ROD_EPS, ROD_F, ROD_KAPPA, ROD_OMEGA,
                                              ROD_V)

CATENARY, ROD = 0, 1


def tension_ratio(T_elem, EI, w, kappa_elem=None, shear_elem=None):
    """chi per element (module docstring; inf where T <= 0); without kappa_elem and shear_elem the
    static catenary's sqrt(EI w^2 / T^3)."""
    T = np.asarray(T_elem, dtype=float)
    chi = np.full(T.shape, np.inf)
    pos = T > 0
    kap = w / T[pos]
    if kappa_elem is not None:
        kap = np.maximum(kap, np.asarray(kappa_elem, dtype=float)[pos])
    chi[pos] = np.sqrt(EI / T[pos]) * kap
    if shear_elem is not None:
        chi[pos] = np.maximum(chi[pos], np.sqrt(np.asarray(shear_elem, dtype=float)[pos] / T[pos]))
    return chi


def grid_ends(grid):
    """(first, last) chain node of each grid point: one node per grid point, two at a joint (chain_nodes)."""
    change = np.flatnonzero(grid[1:] != grid[:-1])
    return np.concatenate(([0], change + 1)), np.concatenate((change, [grid.size - 1]))


def _to_elements(node_values, ends):
    """Per element the largest value of its nodes (a node belongs to the elements on both sides), at least 0."""
    first, last = ends
    at_grid = np.maximum(node_values[first], node_values[last])
    return np.maximum(np.maximum(at_grid[:-1], at_grid[1:]), 0.0)


def element_bending(kind, Y, grid, s, n_elements, ends=None):
    """(|kappa|, |f_shear|) per element from the chain's state: at a rod node the bending components
    of kappa and of the internal force f, across a catenary cell the turn of its unit tangents over
    the cell (a catenary carries no shear); each element takes the largest of its nodes and cells.
    ``ends``: grid_ends(grid), if known."""
    ends = grid_ends(grid) if ends is None else ends
    assert ends[0].size == n_elements + 1
    rod = kind == ROD
    kap_node = np.zeros(len(kind))
    shear_node = np.zeros(len(kind))
    kap_node[rod] = np.hypot(Y[rod, ROD_KAPPA + 1], Y[rod, ROD_KAPPA + 2])
    shear_node[rod] = np.hypot(Y[rod, ROD_F + 1], Y[rod, ROD_F + 2])
    out = _to_elements(kap_node, ends)
    shear = _to_elements(shear_node, ends)
    cat = (kind[:-1] == CATENARY) & (kind[1:] == CATENARY) & (grid[1:] > grid[:-1])
    if np.any(cat):
        ta = Y[:-1][cat, CAT_TAN:CAT_TAN + 3]
        tb = Y[1:][cat, CAT_TAN:CAT_TAN + 3]
        ta = ta / np.linalg.norm(ta, axis=1)[:, None]
        tb = tb / np.linalg.norm(tb, axis=1)[:, None]
        turn = 2.0 * np.arcsin(np.clip(0.5 * np.linalg.norm(tb - ta, axis=1), 0.0, 1.0))
        e = grid[:-1][cat]  # one catenary cell per element at most
        out[e] = np.maximum(out[e], turn / (s[1:][cat] - s[:-1][cat]))
    return out, shear


# relative distance of chi from its switching value below which zone_criterion leaves the decision to classify
CRITERION_MARGIN = 1e-9


@jit
def zone_criterion(kind, Y, grid, s, first, last, previous, EI, w, chi_on, chi_off, raw):
    """Each element's zone by the criterion alone, before classify's clean-up: raw[e] as classify computes it from
    the chain's state (the element tensions of solver._rezone, element_bending, tension_ratio and the hysteresis),
    in one pass without temporaries. Returns True if every element's chi is farther than CRITERION_MARGIN
    (relative) from its switching value, so that numpy's chi, equal up to rounding, decides the same; False
    (raw not to be used) otherwise or if a value is not finite. first, last: grid_ends(grid)."""
    n = previous.shape[0]
    for e in range(n):
        T = np.inf
        kap = 0.0
        shear = 0.0
        for j in (e, e + 1):
            for c in (first[j], last[j]):
                if kind[c] == ROD:
                    t = Y[c, ROD_F]
                    kap = max(kap, math.hypot(Y[c, ROD_KAPPA + 1], Y[c, ROD_KAPPA + 2]))
                    shear = max(shear, math.hypot(Y[c, ROD_F + 1], Y[c, ROD_F + 2]))
                else:
                    t = Y[c, CAT_T]
                T = min(T, t)
        c = last[e]  # the element's catenary cell, if both its nodes are catenary nodes
        if kind[c] == CATENARY and kind[c + 1] == CATENARY:
            na = math.sqrt(Y[c, CAT_TAN] ** 2 + Y[c, CAT_TAN + 1] ** 2 + Y[c, CAT_TAN + 2] ** 2)
            nb = math.sqrt(Y[c + 1, CAT_TAN] ** 2 + Y[c + 1, CAT_TAN + 1] ** 2 + Y[c + 1, CAT_TAN + 2] ** 2)
            d = 0.0
            for k in range(3):
                d += (Y[c + 1, CAT_TAN + k] / nb - Y[c, CAT_TAN + k] / na) ** 2
            turn = 2.0 * math.asin(min(max(0.5 * math.sqrt(d), 0.0), 1.0))
            kap = max(kap, turn / (s[c + 1] - s[c]))
        if not (np.isfinite(T) and np.isfinite(kap) and np.isfinite(shear)):
            return False
        rod = previous[e] == ROD
        if T <= 0.0:
            raw[e] = ROD
            continue
        chi = math.sqrt(EI / T) * max(w / T, kap)
        chi = max(chi, math.sqrt(shear / T))
        switch = chi_off if rod else chi_on
        if not abs(chi - switch) > CRITERION_MARGIN * switch:
            return False
        if rod:
            raw[e] = CATENARY if chi < chi_off else ROD
        else:
            raw[e] = ROD if chi > chi_on else CATENARY
    return True


def raw_zones(T_elem, previous, EI, w, chi_on, chi_off, kappa_elem=None, shear_elem=None):
    """Each element's zone by the criterion and its hysteresis alone (classify before its clean-up)."""
    chi = tension_ratio(T_elem, EI, w, kappa_elem, shear_elem)
    prev = np.asarray(previous)
    return np.where(prev == ROD, np.where(chi < chi_off, CATENARY, ROD), np.where(chi > chi_on, ROD, CATENARY))


def classify(T_elem, previous, EI, w, chi_on, chi_off, min_zone, end_rod=(0, 0), kappa_elem=None, shear_elem=None):
    """New element zones from element tensions (curvatures, shear forces) with hysteresis (module docstring)."""
    zones = raw_zones(T_elem, previous, EI, w, chi_on, chi_off, kappa_elem, shear_elem)
    key = (zones.tobytes(), int(min_zone), tuple(end_rod))
    if _LAST[0] == key:  # the rest depends only on these (the zones are re-evaluated after every step)
        return _LAST[1].copy()
    raw = zones
    zones = _clean_runs(zones, min_zone)
    n = zones.size
    if end_rod[0] > 0:  # after the clean-up, so a short held-end zone is kept
        zones[: min(end_rod[0], n)] = ROD
    if end_rod[1] > 0:
        zones[max(n - end_rod[1], 0):] = ROD
    _LAST[:] = [(raw.tobytes(), int(min_zone), tuple(end_rod)), zones.copy()]
    return zones


_LAST = [None, None]  # last (raw classification, clean-up settings) and its result


def _clean_runs(zones, min_zone):
    """Fill catenary gaps shorter than min_zone with rod; drop rod islands shorter than min_zone."""
    zones = zones.copy()
    for target, fill in ((CATENARY, ROD), (ROD, CATENARY)):
        runs = _runs(zones)
        for start, stop, value in runs:
            if value == target and stop - start < min_zone and len(runs) > 1:
                zones[start:stop] = fill
    return zones


def _runs(zones):
    out = []
    start = 0
    for e in range(1, zones.size + 1):
        if e == zones.size or zones[e] != zones[start]:
            out.append((start, e, int(zones[start])))
            start = e
    return out


def chain_nodes(zones):
    """Chain of (grid index, kind): one node per grid point, two at a joint (left zone, right zone)."""
    nodes = [(0, int(zones[0]))]
    for j in range(1, zones.size):
        if zones[j - 1] != zones[j]:
            nodes.append((j, int(zones[j - 1])))
        nodes.append((j, int(zones[j])))
    nodes.append((zones.size, int(zones[-1])))
    return nodes


def cat_to_rod(Yc, Ytc, L):
    """Rod variables (v, omega, kappa=0, f, eps; and rates) of a catenary node in the frame L (axis 0 = t)."""
    tan, v, f, om_ = (slice(c, c + 3) for c in (CAT_TAN, ROD_V, ROD_F, ROD_OMEGA))
    t = Yc[tan] / np.linalg.norm(Yc[tan])
    tdot = Ytc[tan]
    Y = np.zeros(N_SLOTS)
    Yt = np.zeros(N_SLOTS)
    Y[ROD_EPS], Yt[ROD_EPS] = Yc[CAT_EPS], Ytc[CAT_EPS]  # strain
    Y[v] = L @ Yc[CAT_V:CAT_V + 3]
    om = L @ np.cross(t, tdot)
    Y[om_] = om
    Y[f] = L @ (Yc[CAT_T] * t)
    Yt[v] = L @ Ytc[CAT_V:CAT_V + 3] - np.cross(om, Y[v])
    Yt[f] = L @ (Ytc[CAT_T] * t + Yc[CAT_T] * tdot) - np.cross(om, Y[f])
    return Y, Yt


def rod_to_cat(Yr, Ytr, L):
    """Catenary variables (v, T, t, eps; and rates) of a rod node with frame L."""
    v, tan, f = (slice(c, c + 3) for c in (CAT_V, CAT_TAN, ROD_F))
    Y = np.zeros(N_SLOTS)
    Yt = np.zeros(N_SLOTS)
    Y[CAT_EPS], Yt[CAT_EPS] = Yr[ROD_EPS], Ytr[ROD_EPS]  # strain
    om = Yr[ROD_OMEGA:ROD_OMEGA + 3]
    Y[v] = L.T @ Yr[ROD_V:ROD_V + 3]
    Y[CAT_T] = Yr[ROD_F]
    Y[tan] = L[0]
    Yt[v] = L.T @ (Ytr[ROD_V:ROD_V + 3] + np.cross(om, Yr[ROD_V:ROD_V + 3]))
    Yt[CAT_T] = Ytr[ROD_F] + np.cross(om, Yr[f])[0]
    Yt[tan] = L.T @ np.cross(om, [1.0, 0.0, 0.0])
    return Y, Yt


def rod_block_frames(tangents, ref_frames, keep):
    """Frames of a rod block: kept ones stay, new ones follow their neighbour by minimal rotation."""
    n = len(tangents)
    frames = [None] * n
    for i in range(n):
        if keep[i]:
            frames[i] = ref_frames[i]
    if not any(keep):
        frames[0] = frame_with_tangent(tangents[0], ref_frames[0])
    for i in range(1, n):  # forward sweep from known frames
        if frames[i] is None and frames[i - 1] is not None:
            frames[i] = frames[i - 1] @ minimal_rotation(frames[i - 1][0], tangents[i]).T
    for i in range(n - 2, -1, -1):  # backward sweep for a leading gap
        if frames[i] is None:
            frames[i] = frames[i + 1] @ minimal_rotation(frames[i + 1][0], tangents[i]).T
    return frames


def curvature_between(La, Lb, ds):
    """Body components of kappa from two frames ds apart: L_b = exp(-kappa~ ds) L_a."""
    return -rotation_vector(Lb @ La.T) / ds
