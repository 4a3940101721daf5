"""Analytic Jacobian of one implicit step, written straight into LAPACK band storage (docs/hybrid_solver.md,
"Jacobian"). The forward-difference Jacobian of assembly.py stays as the plain twin (hybrid.jacobian:
finite_difference) and the reference of test/solvers/hybrid/test_jacobian.py.

Per group kind:
* catenary cell [GP Eq. 2-3]: analytic; the cell is linear in per-node terms (position, (1+eps) t, load,
  T t), so each node's 12x8 term derivative is formed once per cell side and combined;
* rod cell [GP Eq. 7-10]: analytic for every term except the body-frame environment load F_b, whose
  derivative (through the alpha_f-level frame, i.e. through omega) is a node-local forward difference
  (7 evaluations of rod_node_terms per node instead of 26 cell evaluations);
* unit tangent, tension-strain law, catenary end conditions: analytic;
* joints, rod ends and rigid-body groups (a handful per chain): group-local forward differences.
Band storage: A[i, j] -> ab[kl + ku + i - j, j] (LAPACK dgbtrf with kl extra rows for the pivoting).
"""

import numpy as np

from tether_sim.numerics.jit import jit_alloc
from tether_sim.solvers.hybrid.assembly import (CAT_CELL, CAT_FORCE, CAT_FREE, CAT_VEL, GROUP_ROWS, LAW, ROD_CELL, UNIT,
                                                group_residual)
from tether_sim.solvers.hybrid.jac_env import external_force_jac
from tether_sim.solvers.hybrid.kernels import alpha_levels, tension_only_slope
from tether_sim.solvers.hybrid.layout import (CAT_EPS, CAT_SLOTS, CAT_T, CAT_TAN, CAT_V, HP_AF, HP_AM, HP_B0, HP_DT,
                                              HP_EA, HP_GAM, HP_I0, HP_M, HP_ZETA, ROD_EPS, ROD_F, ROD_KAPPA, ROD_OMEGA,
                                              ROD_SLOTS, ROD_V)
from tether_sim.solvers.hybrid.rod import rod_node_terms

FD_STEP = 1e-7  # relative forward-difference step of the FD parts (same as assembly.assemble_jacobian)


@jit_alloc
def _put(ab, kl, ku, i, j, val):
    ab[kl + ku + i - j, j] += val


@jit_alloc
def catenary_node_jac(Y, Yn, Ytn, rn, P, cz, cx, cy, D, W):
    """D (12, 8): derivatives of the node terms of catenary.catenary_node_terms (rows: r_{n+1} 0:3,
    (1+eps) t 3:6, F - m dv/dt 6:9, T t 9:12) with respect to the node's unknowns. W: scratch (>= 130)."""
    Yf = W[70:78]
    Ym = W[78:86]
    alpha_levels(Y, Yn, Ytn, CAT_SLOTS, P, Yf, Ym)
    af = P[HP_AF]
    cm = P[HP_AM] / (P[HP_GAM] * P[HP_DT])  # d(rate at alpha_m)/dY
    D[:, :] = 0.0
    F = W[86:89]
    Jv = W[89:98].reshape(3, 3)
    Jt = W[98:107].reshape(3, 3)
    Ja = W[107:116].reshape(3, 3)
    Je = W[116:119]
    external_force_jac(Yf[CAT_V:CAT_V + 3], Yf[CAT_TAN:CAT_TAN + 3], Ym[CAT_V:CAT_V + 3], rn, Yf[CAT_EPS], P, cz, cx,
                       cy, F, Jv, Jt, Ja, Je, W)
    dpos = P[HP_DT] * P[HP_GAM] * af / P[HP_AM]
    e1 = Y[CAT_EPS]
    for k in range(3):
        D[k, CAT_V + k] = dpos
        D[3 + k, CAT_TAN + k] = 1.0 + e1
        D[3 + k, CAT_EPS] = Y[CAT_TAN + k]
        D[9 + k, CAT_T] = af * Yf[CAT_TAN + k]
        D[9 + k, CAT_TAN + k] = af * Yf[CAT_T]
        for j in range(3):
            D[6 + k, CAT_V + j] = af * Jv[k, j] + cm * Ja[k, j]
            D[6 + k, CAT_TAN + j] = af * Jt[k, j]
        D[6 + k, CAT_V + k] -= P[HP_M] * cm
        D[6 + k, CAT_EPS] = af * Je[k]


@jit_alloc
def catenary_cell_jac(r0, ca, cb, Da, Db, ds, ab, kl, ku):
    """The 6 rows of catenary.catenary_cell_residual into the band, from the node-term derivatives Da, Db
    (catenary_node_jac) of its two nodes (columns ca, cb: node offsets)."""
    for side in range(2):
        D = Da if side == 0 else Db
        sg = -1.0 if side == 0 else 1.0
        c0 = ca if side == 0 else cb
        for k in range(3):
            for j in range(CAT_SLOTS):
                v1 = sg * D[k, j] / ds - 0.5 * D[3 + k, j]
                v2 = sg * D[9 + k, j] / ds + 0.5 * D[6 + k, j]
                if v1 != 0.0:
                    _put(ab, kl, ku, r0 + k, c0 + j, v1)
                if v2 != 0.0:
                    _put(ab, kl, ku, r0 + 3 + k, c0 + j, v2)


@jit_alloc
def rod_load_jac(Y, Yn, Ytn, Ln, rn, P, cz, cx, cy, DF):
    """DF (3, 13): forward-difference derivative of the body-frame load F_b of rod.rod_node_terms (it
    depends on v, omega and eps only)."""
    Yf = np.empty(ROD_SLOTS)
    Ym = np.empty(ROD_SLOTS)
    F0 = np.empty(3)
    F1 = np.empty(3)
    rod_node_terms(Y, Yn, Ytn, Ln, rn, P, cz, cx, cy, Yf, Ym, F0)
    DF[:, :] = 0.0
    Yp = Y.copy()
    for slot in (ROD_V, ROD_V + 1, ROD_V + 2, ROD_OMEGA, ROD_OMEGA + 1, ROD_OMEGA + 2, ROD_EPS):
        y0 = Y[slot]
        yp = y0 + FD_STEP * (1.0 + abs(y0))
        Yp[slot] = yp
        rod_node_terms(Yp, Yn, Ytn, Ln, rn, P, cz, cx, cy, Yf, Ym, F1)
        Yp[slot] = y0
        h = yp - y0
        for k in range(3):
            DF[k, slot] = (F1[k] - F0[k]) / h


@jit_alloc
def _skew_into(M, r, c, x, sign):
    """M[r:r+3, c:c+3] += sign * x~ (x~ y = x cross y)."""
    M[r + 0, c + 1] -= sign * x[2]
    M[r + 0, c + 2] += sign * x[1]
    M[r + 1, c + 0] += sign * x[2]
    M[r + 1, c + 2] -= sign * x[0]
    M[r + 2, c + 0] -= sign * x[1]
    M[r + 2, c + 1] += sign * x[0]


@jit_alloc
def rod_mean_jac(M, P, JM):
    """JM (12, 13): derivative of the rod cell rows [GP Eq. 7-10] with respect to the cell-mean alpha_f
    values M (v, omega, kappa, f, eps), excluding the s-differences, the rates and the load."""
    JM[:, :] = 0.0
    v = M[ROD_V:ROD_V + 3]
    om = M[ROD_OMEGA:ROD_OMEGA + 3]
    ka = M[ROD_KAPPA:ROD_KAPPA + 3]
    f = M[ROD_F:ROD_F + 3]
    le = 1.0 + M[ROD_EPS]
    B = P[HP_B0:HP_B0 + 3]
    II = P[HP_I0:HP_I0 + 3]
    Bk = np.empty(3)
    Iw = np.empty(3)
    for k in range(3):
        Bk[k] = B[k] * ka[k]
        Iw[k] = II[k] * om[k]
    # rows: the equations [GP Eq. 7, 8, 9, 10] at 0, 3, 6, 9; columns: the slots
    _skew_into(JM, 0, ROD_KAPPA, v, -1.0)  # kappa x v
    _skew_into(JM, 0, ROD_V, ka, 1.0)
    JM[1, ROD_OMEGA + 2] -= le  # -(1+eps) omega x e1
    JM[1, ROD_EPS] -= om[2]
    JM[2, ROD_OMEGA + 1] += le
    JM[2, ROD_EPS] += om[1]
    _skew_into(JM, 3, ROD_KAPPA, om, -1.0)  # kappa x omega
    _skew_into(JM, 3, ROD_OMEGA, ka, 1.0)
    _skew_into(JM, 6, ROD_KAPPA, Bk, -1.0)  # kappa x B kappa
    _skew_into(JM, 6, ROD_OMEGA, Iw, 1.0)  # -omega x I omega
    for i in range(3):
        for j in range(3):
            JM[6 + i, ROD_KAPPA + j] += ((ka[(i + 1) % 3] * (j == (i + 2) % 3) - ka[(i + 2) % 3] * (j == (i + 1) % 3))
                                         * B[j])
            JM[6 + i, ROD_OMEGA + j] -= ((om[(i + 1) % 3] * (j == (i + 2) % 3) - om[(i + 2) % 3] * (j == (i + 1) % 3))
                                         * II[j])
    JM[7, ROD_F + 2] -= le  # -(1+eps) f x e1 = -(0, le f2, -le f1)
    JM[7, ROD_EPS] -= f[2]
    JM[8, ROD_F + 1] += le
    JM[8, ROD_EPS] += f[1]
    _skew_into(JM, 9, ROD_KAPPA, f, -1.0)  # kappa x f
    _skew_into(JM, 9, ROD_F, ka, 1.0)
    m = P[HP_M]
    _skew_into(JM, 9, ROD_OMEGA, v, m)  # -m omega x v
    _skew_into(JM, 9, ROD_V, om, -m)


@jit_alloc
def rod_cell_jac(r0, ca, cb, Ya, Yna, Ytna, Yb, Ynb, Ytnb, DFa, DFb, ds, P, ab, kl, ku):
    """The 12 rows of rod.rod_cell_residual into the band (columns ca, cb: node offsets; DFa, DFb: the
    load derivatives of rod_load_jac)."""
    af = P[HP_AF]
    cm = P[HP_AM] / (P[HP_GAM] * P[HP_DT])
    Yfa = np.empty(ROD_SLOTS)
    Yma = np.empty(ROD_SLOTS)
    Yfb = np.empty(ROD_SLOTS)
    Ymb = np.empty(ROD_SLOTS)
    alpha_levels(Ya, Yna, Ytna, ROD_SLOTS, P, Yfa, Yma)
    alpha_levels(Yb, Ynb, Ytnb, ROD_SLOTS, P, Yfb, Ymb)
    M = 0.5 * (Yfa + Yfb)
    JM = np.empty((12, ROD_SLOTS))
    rod_mean_jac(M, P, JM)
    II = P[HP_I0:HP_I0 + 3]
    m = P[HP_M]
    Jn = np.empty((12, ROD_SLOTS))
    for side in range(2):
        DF = DFa if side == 0 else DFb
        sd = -af / ds if side == 0 else af / ds
        c0 = ca if side == 0 else cb
        for i in range(12):
            for j in range(ROD_SLOTS):
                Jn[i, j] = 0.5 * af * JM[i, j]
        for i in range(12):  # s-differences
            Jn[i, i] += sd * (P[HP_B0 + i - 6] if 6 <= i < 9 else 1.0)
        Jn[0, ROD_EPS] -= 0.5 * cm  # rates at alpha_m
        for k in range(3):
            Jn[3 + k, ROD_KAPPA + k] -= 0.5 * cm
            Jn[6 + k, ROD_OMEGA + k] -= 0.5 * cm * II[k]
            Jn[9 + k, ROD_V + k] -= 0.5 * cm * m
            for j in range(ROD_SLOTS):
                Jn[9 + k, j] += 0.5 * DF[k, j]
        for i in range(12):
            for j in range(ROD_SLOTS):
                if Jn[i, j] != 0.0:
                    _put(ab, kl, ku, r0 + i, c0 + j, Jn[i, j])


@jit_alloc
def _group_fd(k, a, b, gp, noff, nslot, r0, Y, Yn, Ytn, Ln, rn, s, P, cz, cx, cy, ab, kl, ku):
    """Group-local forward differences (as assembly.assemble_jacobian) into the band."""
    nr = GROUP_ROWS[k]
    base = np.empty(13)
    pert = np.empty(13)
    group_residual(k, a, b, gp, Y, Yn, Ytn, Ln, rn, s, P, cz, cx, cy, base)
    for which in range(2):
        node = a if which == 0 else b
        if node < 0 or (which == 1 and b == a):
            continue
        for slot in range(nslot[node]):
            y0 = Y[node, slot]
            yp = y0 + FD_STEP * (1.0 + abs(y0))
            Y[node, slot] = yp
            group_residual(k, a, b, gp, Y, Yn, Ytn, Ln, rn, s, P, cz, cx, cy, pert)
            Y[node, slot] = y0
            hinv = 1.0 / (yp - y0)
            for r in range(nr):
                d = (pert[r] - base[r]) * hinv
                if d != 0.0:
                    _put(ab, kl, ku, r0 + r, noff[node] + slot, d)


@jit_alloc
def assemble_band_jacobian(gkind, ga, gb, grow, gpar, noff, nslot, Y, Yn, Ytn, Ln, rn, s, P, cz, cx, cy, kl, ku, ab):
    """Jacobian of assembly.assemble_residual into ab (2 kl + ku + 1, n) (zeroed here)."""
    ab[:, :] = 0.0
    g_ = P[HP_GAM]
    dt = P[HP_DT]
    K = Y.shape[0]
    D = np.empty((K, 12, ROD_SLOTS))  # per-node derivatives, each computed once (shared by two cells)
    have = np.zeros(K, dtype=np.bool_)
    W = np.empty(130)
    for g in range(gkind.shape[0]):
        k = gkind[g]
        a = ga[g]
        b = gb[g]
        r0 = grow[g]
        if k == CAT_CELL or k == ROD_CELL:
            for c in (a, b):
                if not have[c]:
                    if k == CAT_CELL:
                        catenary_node_jac(Y[c], Yn[c], Ytn[c], rn[c], P, cz, cx, cy, D[c, :, 0:CAT_SLOTS], W)
                    else:
                        rod_load_jac(Y[c], Yn[c], Ytn[c], Ln[c], rn[c], P, cz, cx, cy, D[c, 0:3, :])
                    have[c] = True
            if k == CAT_CELL:
                catenary_cell_jac(r0, noff[a], noff[b], D[a, :, 0:CAT_SLOTS], D[b, :, 0:CAT_SLOTS], s[b] - s[a],
                                  ab, kl, ku)
            else:
                rod_cell_jac(r0, noff[a], noff[b], Y[a], Yn[a], Ytn[a], Y[b], Yn[b], Ytn[b], D[a, 0:3, :],
                             D[b, 0:3, :], s[b] - s[a], P, ab, kl, ku)
        elif k == UNIT:
            for j in range(3):
                _put(ab, kl, ku, r0, noff[a] + CAT_TAN + j, 2.0 * Y[a, CAT_TAN + j])
        elif k == LAW:
            is_rod = gpar[g, 0] > 0.5
            ie = ROD_EPS if is_rod else CAT_EPS
            if P[HP_EA] <= 0.0:
                _put(ab, kl, ku, r0, noff[a] + ie, 1.0)
            else:
                rate = ((Y[a, ie] - Yn[a, ie]) / dt - (1.0 - g_) * Ytn[a, ie]) / g_
                x = P[HP_EA] * Y[a, ie] + P[HP_ZETA] * rate
                _put(ab, kl, ku, r0, noff[a] + (ROD_F if is_rod else CAT_T), 1.0)
                _put(ab, kl, ku, r0, noff[a] + ie, -tension_only_slope(x, P) * (P[HP_EA] + P[HP_ZETA] / (g_ * dt)))
        elif k == CAT_VEL:
            for j in range(3):
                _put(ab, kl, ku, r0 + j, noff[a] + CAT_V + j, 1.0)
        elif k == CAT_FORCE:
            for j in range(3):
                _put(ab, kl, ku, r0 + j, noff[a] + CAT_T, Y[a, CAT_TAN + j])
                _put(ab, kl, ku, r0 + j, noff[a] + CAT_TAN + j, Y[a, CAT_T])
        elif k == CAT_FREE:
            _put(ab, kl, ku, r0, noff[a] + CAT_T, 1.0 / gpar[g, 6])
            for j in range(3):
                _put(ab, kl, ku, r0 + 1, noff[a] + CAT_TAN + j, gpar[g, j])
                _put(ab, kl, ku, r0 + 1, noff[b] + CAT_TAN + j, -gpar[g, j])
                _put(ab, kl, ku, r0 + 2, noff[a] + CAT_TAN + j, gpar[g, 3 + j])
                _put(ab, kl, ku, r0 + 2, noff[b] + CAT_TAN + j, -gpar[g, 3 + j])
        else:  # joints, rod ends, rigid-body groups
            _group_fd(k, a, b, gpar[g], noff, nslot, r0, Y, Yn, Ytn, Ln, rn, s, P, cz, cx, cy, ab, kl, ku)


@jit_alloc
def scale_band_rows(ab, kl, ku, n, rs):
    """rs[i] = 1 / max_j |A[i, j]| and A <- diag(rs) A, in the band storage (equilibrated rows)."""
    for i in range(n):
        rs[i] = 0.0
    for j in range(n):
        for i in range(max(0, j - ku), min(n, j + kl + 1)):
            a = abs(ab[kl + ku + i - j, j])
            if a > rs[i]:
                rs[i] = a
    for i in range(n):
        rs[i] = 1.0 / rs[i] if rs[i] > 0.0 else 1.0
    for j in range(n):
        for i in range(max(0, j - ku), min(n, j + kl + 1)):
            ab[kl + ku + i - j, j] *= rs[i]
