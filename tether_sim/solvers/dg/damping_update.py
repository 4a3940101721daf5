"""Low-rank update of the strain-rate LU of the implicit damping step (implicit_damping.py, MODE_AXIAL).

The matrix of a stage is A = I - gamma h K with K = i^T G Pj AM Div Z i: the damping coefficient Z of
point p scales column p of K alone. When the law's switches (no-compression clip, buckled points) change
Z at a few points p_1..p_k since the stored LU of A_LU was computed, the present matrix is

    A = A_LU + U E^T,   u_a = -gamma h K_(Z = dZ_a at p_a only) e_(p_a),   E = [e_(p_1) .. e_(p_k)]

(dZ_a = Z - Z_LU at p_a; u_a is K applied matrix-free to the unit vector e_(p_a), the operator of the
defect correction), and by the Sherman-Morrison-Woodbury identity

    A^-1 b = y - W C^-1 E^T y,   y = A_LU^-1 b,   W = A_LU^-1 U,   C = I_k + E^T W   (k x k).

Each changed point costs one band solve when it changes (its column of W is kept while its Z stays
changed) instead of a new assembly and factorisation of the whole band. More than MAX_CHANGED points,
or a pivot of C below PIVOT_MIN (the updated matrix near singular in those columns), and the caller
refactors. The geometry (i, l) still drifts from the LU's as in the plain reuse: the stage solve keeps
its defect correction with the present K, so the update is a better preconditioner, not a new answer.

Up to LU_SLOTS LUs are kept, one per step size and released ends (select_lu): the splitting's half
steps D(dt/2) at both ends of a call take gamma dt / 2, the merged steps between them gamma dt, and a
velocity end released for a step (release_ends) or not changes K by a rank-one term in its end elements.
Each change refactored before (three step-size changes per call; in the slack phases of the PE2020
Sec. 6.2 case an end's release switches every few steps). The LUs not in use are parked (band rows s N Q..,
wood rows s WOOD_ROWS.., WP_ZP + s - 1, the ints ID_PARK0 + (s - 1) LU_INTS.., DP_PARK_H + s - 1) and
swap_lu exchanges one with the active LU. Every LU ages with the steps (age_lus): a parked one comes back
only while younger than LU_MAX_AGE steps, with the same defect correction as the active one.
"""

from tether_sim.numerics.banded import band_solve
from tether_sim.numerics.jit import jit
from tether_sim.solvers.dg.damping_layout import (
    DP_LU_H, DP_PARK_H, ID_CH0, ID_LU_AGE, ID_NCH, ID_PARK0, ID_PV0, ID_REL0, ID_RELF0, LU_INTS, LU_SLOTS, MAX_CHANGED,
    PIVOT_MIN, WD_P, WOOD_C, WOOD_DZ, WOOD_ROWS, WOOD_W, WOOD_Z, WP_KX, WP_KY, WP_Z, WP_ZF, WP_ZP,
)
from tether_sim.solvers.dg.damping_ops import axial_tension_points, strain_rates, tension_divergence


@jit
def update_columns(gh, Pj, vbc, idp, dprm, blk, bvec, wp, wd, band, kl, wood):
    """Bring the update up to date with the present Z (WP_Z against WP_ZF): drop the carried points whose
    Z went back, add a column of W for each newly changed point, factor C. False: refactor instead."""
    N, nq = wp.shape[0], wp.shape[1]
    n = N * nq
    total = 0
    for e in range(N):
        for j in range(nq):
            if wp[e, j, WP_Z] != wp[e, j, WP_ZF]:
                total += 1
    if total > MAX_CHANGED:
        return False
    k = 0
    for a in range(idp[ID_NCH]):  # keep the columns of points still changed the same way
        p = idp[ID_CH0 + a]
        e = p // nq
        j = p - e * nq
        dz = wp[e, j, WP_Z] - wp[e, j, WP_ZF]
        if dz != 0.0 and dz == wood[WOOD_DZ, a]:
            if k != a:
                idp[ID_CH0 + k] = p
                wood[WOOD_DZ, k] = dz
                for r in range(n):
                    wood[WOOD_W + k, r] = wood[WOOD_W + a, r]
            k += 1
    kept = k
    for e in range(N):
        for j in range(nq):
            dz = wp[e, j, WP_Z] - wp[e, j, WP_ZF]
            if dz == 0.0:
                continue
            p = e * nq + j
            known = False
            for a in range(kept):
                if idp[ID_CH0 + a] == p:
                    known = True
            if known:
                continue
            _solved_column(e, j, dz, gh, Pj, vbc, idp, dprm, blk, bvec, wp, wd, band, kl, wood, WOOD_W + k)
            idp[ID_CH0 + k] = p
            wood[WOOD_DZ, k] = dz
            k += 1
    idp[ID_NCH] = k
    return _factor_capacitance(idp, wood, k)


@jit
def _solved_column(e0, j0, dz, gh, Pj, vbc, idp, dprm, blk, bvec, wp, wd, band, kl, wood, row):
    """wood[row] = A_LU^-1 u with u = -gh K e_p, K taken with Z = dz at p = (e0, j0) and 0 elsewhere."""
    N, nq = wp.shape[0], wp.shape[1]
    for e in range(N):
        for j in range(nq):
            wp[e, j, WP_KX] = 0.0
    wp[e0, j0, WP_KX] = 1.0
    z = wp[e0, j0, WP_Z]
    wp[e0, j0, WP_Z] = dz
    axial_tension_points(wp, WP_KX, False)
    tension_divergence(blk, Pj, bvec, idp, dprm, wp, wd, WD_P, False)
    strain_rates(wd, WD_P, False, vbc, blk, bvec, wp, WP_KY)
    wp[e0, j0, WP_Z] = z
    for e in range(N):
        for j in range(nq):
            wood[row, e * nq + j] = -gh * wp[e, j, WP_KY]
    band_solve(band, N * nq, kl, wood, row)


@jit
def _factor_capacitance(idp, wood, k):
    """LU with partial pivoting of C = I + E^T W (rows WOOD_C.., row order in ID_PV0); False if a pivot
    is below PIVOT_MIN."""
    for a in range(k):
        idp[ID_PV0 + a] = a
        for b in range(k):
            wood[WOOD_C + a, b] = wood[WOOD_W + b, idp[ID_CH0 + a]] + (1.0 if a == b else 0.0)
    for c in range(k):
        best = c
        for a in range(c + 1, k):
            if abs(wood[WOOD_C + a, c]) > abs(wood[WOOD_C + best, c]):
                best = a
        if abs(wood[WOOD_C + best, c]) < PIVOT_MIN:
            return False
        if best != c:
            for b in range(k):
                t = wood[WOOD_C + c, b]
                wood[WOOD_C + c, b] = wood[WOOD_C + best, b]
                wood[WOOD_C + best, b] = t
            t = idp[ID_PV0 + c]
            idp[ID_PV0 + c] = idp[ID_PV0 + best]
            idp[ID_PV0 + best] = t
        inv = 1.0 / wood[WOOD_C + c, c]
        for a in range(c + 1, k):
            f = wood[WOOD_C + a, c] * inv
            wood[WOOD_C + a, c] = f
            for b in range(c + 1, k):
                wood[WOOD_C + a, b] -= f * wood[WOOD_C + c, b]
    return True


@jit
def update_solve(band, n, kl, x, col, wood, idp):
    """x[col] <- A^-1 x[col] with A = A_LU + U E^T (band_solve when no point is carried)."""
    band_solve(band, n, kl, x, col)
    k = idp[ID_NCH]
    if k == 0:
        return
    for a in range(k):  # z = C^-1 E^T y: permuted forward, then back substitution
        s = x[col, idp[ID_CH0 + idp[ID_PV0 + a]]]
        for b in range(a):
            s -= wood[WOOD_C + a, b] * wood[WOOD_Z, b]
        wood[WOOD_Z, a] = s
    for a in range(k - 1, -1, -1):
        s = wood[WOOD_Z, a]
        for b in range(a + 1, k):
            s -= wood[WOOD_C + a, b] * wood[WOOD_Z, b]
        wood[WOOD_Z, a] = s / wood[WOOD_C + a, a]
    for r in range(n):
        s = x[col, r]
        for b in range(k):
            s -= wood[WOOD_W + b, r] * wood[WOOD_Z, b]
        x[col, r] = s



@jit
def _matches(idp, gh, age, h, rel):
    """A stored LU (its age, gamma h and released flags at idp[rel], idp[rel + 1]) is for this step."""
    return age >= 0 and h == gh and idp[rel] == idp[ID_REL0] and idp[rel + 1] == idp[ID_REL0 + 1]


@jit
def select_lu(idp, dprm, wp, band, wood, gh):
    """Make the active LU the one kept for this step size and these released ends (idp ID_REL0) if any;
    otherwise the active one is parked in place of an empty or the oldest parked one, which becomes the
    active one to be refactored. Returns the parked slot swapped in (0: none)."""
    if idp[ID_LU_AGE] < 0 or _matches(idp, gh, idp[ID_LU_AGE], dprm[DP_LU_H], ID_RELF0):
        return 0
    best = 0
    oldest = -1
    for s in range(1, LU_SLOTS):
        o = ID_PARK0 + (s - 1) * LU_INTS
        age = idp[o]
        if _matches(idp, gh, age, dprm[DP_PARK_H + s - 1], o + ID_RELF0 - ID_LU_AGE):
            best = s
            break
        if age < 0:
            age = 1 << 40  # an empty slot is taken first
        if age > oldest:
            oldest = age
            best = s
    swap_lu(idp, dprm, wp, band, wood, best)
    return best


@jit
def swap_lu(idp, dprm, wp, band, wood, s):
    """Exchange the active LU (band rows 0..n-1, wood rows 0..WOOD_ROWS-1, WP_ZF, idp ID_LU_AGE.. and DP_LU_H)
    with the parked one s >= 1 (band rows s n.., wood rows s WOOD_ROWS.., WP_ZP + s - 1, ID_PARK0 + (s - 1) LU_INTS..,
    DP_PARK_H + s - 1); n = N Q."""
    N, nq = wp.shape[0], wp.shape[1]
    n = N * nq
    for r in range(n):
        for c in range(band.shape[1]):
            t = band[r, c]
            band[r, c] = band[s * n + r, c]
            band[s * n + r, c] = t
    for r in range(WOOD_ROWS):
        for c in range(wood.shape[1]):
            t = wood[r, c]
            wood[r, c] = wood[s * WOOD_ROWS + r, c]
            wood[s * WOOD_ROWS + r, c] = t
    for e in range(N):
        for j in range(nq):
            t = wp[e, j, WP_ZF]
            wp[e, j, WP_ZF] = wp[e, j, WP_ZP + s - 1]
            wp[e, j, WP_ZP + s - 1] = t
    o = ID_PARK0 + (s - 1) * LU_INTS
    for a in range(LU_INTS):
        ti = idp[ID_LU_AGE + a]
        idp[ID_LU_AGE + a] = idp[o + a]
        idp[o + a] = ti
    t = dprm[DP_LU_H]
    dprm[DP_LU_H] = dprm[DP_PARK_H + s - 1]
    dprm[DP_PARK_H + s - 1] = t


@jit
def age_lus(idp):
    """One step more for the active and every parked LU (the geometry drifts from all of them)."""
    idp[ID_LU_AGE] += 1
    for s in range(1, LU_SLOTS):
        o = ID_PARK0 + (s - 1) * LU_INTS
        if idp[o] >= 0:
            idp[o] += 1
