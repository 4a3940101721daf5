"""Compiled Newton iteration of one implicit step with the analytic band Jacobian (hybrid.jacobian: analytic).

The same algorithm as the Python loop of solver._step that drives the forward-difference twin (modified
Newton, row equilibration, tangent damping, backtracking line search after each fresh Jacobian, the same
stopping test), moved into one compiled function so that a step costs no Python per iteration. The
linear solver is a banded LU with partial pivoting (the algorithm of LAPACK dgbtf2/dgbtrs) in the
LAPACK band storage A[i, j] -> ab[kl + ku + i - j, j].
"""

import numpy as np

from tether_sim.numerics.jit import jit_alloc
from tether_sim.solvers.hybrid.assembly import assemble_residual
from tether_sim.solvers.hybrid.jacobian import assemble_band_jacobian, scale_band_rows

LINE_SEARCH_HALVINGS = 6  # as newton.LINE_SEARCH_HALVINGS
# largest update (relative to its variable's scale) the stopping test takes for stagnation at round-off
# when the tolerance itself is not met: 1000 x the default newton_tolerance. As a multiple of a loose
# tolerance (1e-3) a stagnating iteration was accepted 5 scales away from the converged step.
STAGNATION = 1e-6
FAIL_RESIDUAL, FAIL_SINGULAR, FAIL_UPDATE, FAIL_ITERATIONS = -1, -2, -3, -4


@jit_alloc
def band_lu(ab, n, kl, ku, low, last, ipiv):
    """In-place LU with partial pivoting of the band matrix (the algorithm of LAPACK dgbtf2), skipping the
    structural zeros inside the band: low[j] is the lowest row with a nonzero in column j (no fill-in
    goes below it), last (work, length n) starts as each row's last nonzero column and follows the
    fill-in to the right. Returns 0, or j + 1 if pivot j is zero."""
    kv = kl + ku
    for j in range(n):
        km = min(low[j], n - 1) - j
        p = 0
        big = abs(ab[kv, j])
        for i in range(1, km + 1):
            if abs(ab[kv + i, j]) > big:
                big = abs(ab[kv + i, j])
                p = i
        ipiv[j] = j + p
        if big == 0.0:
            return j + 1
        if p != 0:
            for c in range(j, max(last[j], last[j + p]) + 1):
                tmp = ab[kv + j - c, c]
                ab[kv + j - c, c] = ab[kv + j + p - c, c]
                ab[kv + j + p - c, c] = tmp
            tmp = last[j]
            last[j] = last[j + p]
            last[j + p] = tmp
        inv = 1.0 / ab[kv, j]
        for i in range(1, km + 1):
            ab[kv + i, j] *= inv
        lj = last[j]
        for c in range(j + 1, lj + 1):
            u = ab[kv + j - c, c]
            if u != 0.0:
                for i in range(1, km + 1):
                    ab[kv + j + i - c, c] -= ab[kv + i, j] * u
        for i in range(1, km + 1):
            if ab[kv + i, j] != 0.0 and last[j + i] < lj:
                last[j + i] = lj
    return 0


@jit_alloc
def band_solve(ab, n, kl, ku, low, ipiv, b):
    """Solve A x = b in place with the factors of band_lu (dgbtrs, no transpose)."""
    kv = kl + ku
    for j in range(n - 1):
        p = ipiv[j]
        if p != j:
            tmp = b[p]
            b[p] = b[j]
            b[j] = tmp
        bj = b[j]
        for i in range(1, min(low[j], n - 1) - j + 1):
            b[j + i] -= ab[kv + i, j] * bj
    for j in range(n - 1, -1, -1):
        b[j] /= ab[kv, j]
        bj = b[j]
        for i in range(max(0, j - kv), j):
            b[i] -= ab[kv + i - j, j] * bj


@jit_alloc
def _scaled_norm2(rs, R, n):
    acc = 0.0
    for i in range(n):
        acc += (rs[i] * R[i]) ** 2
    return acc


@jit_alloc
def _all_finite(x, n):
    for i in range(n):
        if not np.isfinite(x[i]):
            return False
    return True


@jit_alloc
def _apply(Y, Ybase, idx_node, idx_slot, dx, lam, n):
    for i in range(n):
        Y[idx_node[i], idx_slot[i]] = Ybase[idx_node[i], idx_slot[i]] - lam * dx[i]


@jit_alloc
def _line_search(ch, Y, Ytry, dx, lam, rs, R, Rt, n, Yn, Ytn, Ln, rn, s, P, cz, cx, cy, counts):
    """Backtracking on the scaled residual norm after a fresh Jacobian (as NewtonMixin._line_search). Returns
    (lam, accepted): when accepted, Rt holds the residual at Y - lam dx (the next iteration's, bit for bit)."""
    gkind, ga, gb, grow, gpar, noff, nslot, idx_node, idx_slot = ch
    f0 = _scaled_norm2(rs, R, n)
    Ytry[:, :] = Y
    for _ in range(LINE_SEARCH_HALVINGS):
        _apply(Ytry, Y, idx_node, idx_slot, dx, lam, n)
        assemble_residual(gkind, ga, gb, grow, gpar, Ytry, Yn, Ytn, Ln, rn, s, P, cz, cx, cy, Rt)
        if _all_finite(Rt, n) and _scaled_norm2(rs, Rt, n) <= (1.0 - 1e-4 * lam) * f0:
            return lam, True
        lam *= 0.5
    counts[1] += 1
    return (lam * 2.0 ** LINE_SEARCH_HALVINGS if f0 > 0.0 else lam), False


@jit_alloc
def newton_band(ch, kl, ku, low, last, tangent, scale, Y, Yn, Ytn, Ln, rn, s, P, cz, cx, cy, max_it, tol, max_turn, ab,
                ipiv, rs, held, counts):
    """Newton iterations of one step on Y (in place). ch = (gkind, ga, gb, grow, gpar, noff, nslot,
    idx_node, idx_slot); low, last: the structure of band_lu; tangent: bool mask of the catenary tangent unknowns; scale: per-unknown scales
    of the stopping test; ab, ipiv, rs: the factorised, row-equilibrated iteration matrix and its row scales.
    held[0] = 1 on entry: they hold the factorisation of an earlier step of this chain and step size, and the
    step starts with it (simplified Newton across steps, refactorised by the same rule as within a step); if
    that attempt fails, the step starts again from the same Y with a fresh Jacobian, as without it. On return
    held[0] = 1 if they hold a factorisation. Returns the iteration count, or a FAIL_* code. counts[0] += fresh
    Jacobians, counts[1] += exhausted line searches, counts[2] += steps started again after a failed attempt with a
    kept factorisation."""
    if held[0] == 1:
        Y0 = Y.copy()
        it = _iterate(ch, kl, ku, low, last, tangent, scale, Y, Yn, Ytn, Ln, rn, s, P, cz, cx, cy, max_it, tol,
                      max_turn, ab, ipiv, rs, True, counts)
        if it > 0:
            return it
        counts[2] += 1
        Y[:, :] = Y0
    it = _iterate(ch, kl, ku, low, last, tangent, scale, Y, Yn, Ytn, Ln, rn, s, P, cz, cx, cy, max_it, tol,
                  max_turn, ab, ipiv, rs, False, counts)
    held[0] = 1 if it > 0 else 0
    return it


@jit_alloc
def _iterate(ch, kl, ku, low, last, tangent, scale, Y, Yn, Ytn, Ln, rn, s, P, cz, cx, cy, max_it, tol, max_turn, ab,
             ipiv, rs, kept, counts):
    """The iterations of newton_band, starting with the kept factorisation in ab, ipiv, rs if kept, else with a
    fresh Jacobian. Stagnation at round-off is accepted only with a Jacobian of this step."""
    gkind, ga, gb, grow, gpar, noff, nslot, idx_node, idx_slot = ch
    n = idx_node.shape[0]
    R = np.empty(n)
    Rt = np.empty(n)
    dx = np.empty(n)
    Ytry = np.empty_like(Y)
    have_lu = kept
    own = False  # the factorisation is of a Jacobian of this step
    res_prev = np.inf
    err_prev = np.inf
    known = False  # R already holds the residual at Y (the line search's accepted point)
    for it in range(1, max_it + 1):
        if not known:
            assemble_residual(gkind, ga, gb, grow, gpar, Y, Yn, Ytn, Ln, rn, s, P, cz, cx, cy, R)
            if not _all_finite(R, n):
                return FAIL_RESIDUAL
        known = False
        res = np.inf
        if have_lu:
            res = 0.0
            for i in range(n):
                res = max(res, abs(rs[i] * R[i]))
        fresh = (not have_lu) or res > 0.1 * res_prev
        if fresh:
            assemble_band_jacobian(gkind, ga, gb, grow, gpar, noff, nslot, Y, Yn, Ytn, Ln, rn, s, P, cz, cx, cy,
                                   kl, ku, ab)
            scale_band_rows(ab, kl, ku, n, rs)
            lastw = last.copy()
            if band_lu(ab, n, kl, ku, low, lastw, ipiv) != 0:
                return FAIL_SINGULAR
            have_lu = True
            own = True
            counts[0] += 1
            res = 0.0
            for i in range(n):
                res = max(res, abs(rs[i] * R[i]))
        res_prev = res
        for i in range(n):
            dx[i] = rs[i] * R[i]
        band_solve(ab, n, kl, ku, low, ipiv, dx)
        if not _all_finite(dx, n):
            return FAIL_UPDATE
        # a catenary tangent turns at most max_turn per iteration (no jump to the mirror branch (-T, -t))
        turn = 0.0
        for i in range(n):
            if tangent[i]:
                turn = max(turn, abs(dx[i]))
        lam = min(1.0, max_turn / turn) if turn > 0.0 else 1.0
        if fresh:
            lam, known = _line_search(ch, Y, Ytry, dx, lam, rs, R, Rt, n, Yn, Ytn, Ln, rn, s, P, cz, cx, cy, counts)
        err = 0.0
        for i in range(n):
            Y[idx_node[i], idx_slot[i]] -= lam * dx[i]
            err = max(err, abs(dx[i]) / scale[i])
        err /= tol
        if lam == 1.0 and (err <= 1.0 or (own and err <= 1e3 and err * tol <= STAGNATION and err >= 0.5 * err_prev)):
            return it
        err_prev = err
        if known:  # Y is now Ytry (the same operation, Y - lam dx): its residual is Rt
            R[:] = Rt
    return FAIL_ITERATIONS
