"""Step 5 of the DG right-hand side (kernels.momentum_rate) vectorised across the elements.

The per-element kernels work on 5-7 modes or points at a time, too few for SIMD. Here the
quantities of step 5 are held "structure of arrays" in the scratch part of ``tmp`` (flat, element
index innermost: one row of N contiguous values per channel and mode or point), so that each
operation is a loop over the N elements that the compiler vectorises; the gain is in the point
loads (two square roots, drag, added mass per point, four at a time). Every element sees exactly
the operations of the scalar path in the same order (no reassociation; IEEE sqrt and division), so
both paths give the same bits (test_twins.py). Used when the cable has no current and no seabed (no
table look-ups or contact branches) and at least SOA_MIN_ELEMENTS elements (below that the loops
over N are too short to pay for the transposition); ``tmp`` must hold
``TMP_HEAD + soa_scratch_size(N, P+1, Q)``. The same
layout for steps 1-3 was measured slower (8.1 vs 6.0 us): their cost is in the small matrix
products, which the element-wise kernels already keep in registers.
"""

import math

import numpy as np

from tether_sim.numerics.jit import jit
from tether_sim.solvers.dg.layout import (
    F_V, I_N, I_NEEDPOS, M_TV, P_CDN, P_CDT, P_FBZ, P_GAMMA0, P_HALF_RHO_D, P_MN, P_MT, P_RELAX, T_TV, W_I, W_L, W_V,
)

TMP_HEAD = 16  # tmp[0:16] belongs to the scalar kernels and the stepper
# Fewer elements than this: the element-wise path is cheaper (each SoA row loop is only N long; ROPOS
# P = 4, thread CPU per right-hand side, 2026-11-23: N = 2 / 3 / 5 element-wise 0.8 / 1.6 / 1.7 us,
# SoA 2.4 / 3.1 / 2.7 us; N = 8 / 12: element-wise 3.9 / 4.2 us, SoA 2.2 / 3.2 us). On 2026-11-25, after
# the kernels lost their reference counts and their small helpers were inlined (numerics/jit.py),
# the element-wise path won up to N = 20 (us per 50 Hz tick, ROPOS, bending off / on, 2026-11-25,
# load ~1, SoA from 7 elements vs never: N = 8 P = 2 59.6 / 86.1 vs 51.2 / 82.6; N = 12 P = 2
# 63.1 / 91.7 vs 56.9 / 89.9; N = 20 P = 4 81.2 / 128.6 vs 79.7 / 123.0 at 1730 m; N = 32 P = 2
# 36.4 / 59.0 vs 37.5 / 58.8) and lost at N = 24, P = 4 (253 / 434 vs 274 / 436 at 975 m).
SOA_MIN_ELEMENTS = 24
# Unsigned indices: numba adds a negative-index wrap-around check to every signed index computed at
# run time, which keeps the compiler from vectorising the element loops (measured x3).
U64 = np.uint64


@jit
def _offsets(N, nm, nq):
    """Start of every scratch region in tmp (rows of N values; see the comments)."""
    o_a = TMP_HEAD  # 2 / h (1 row), 1 / h (1 row)
    o_b = o_a + N
    o_tv = o_b + N  # tension vector modes (3, nm)
    o_dt = o_tv + 3 * nm * N  # dT/ds modes (3, nm)
    o_dq = o_dt + 3 * nm * N  # dT/ds at the points (3, nq)
    o_pt = o_dq + 3 * nq * N  # point values l, i (3), v (3): (7, nq)
    o_j = o_pt + 7 * nq * N  # flux jumps (3 right, 3 left)
    o_acc = o_j + 6 * N  # dv/dt at the points (3, nq)
    o_am = o_acc + 3 * nq * N  # dv/dt modes (3, nm)
    end = o_am + 3 * nm * N
    return o_a, o_b, o_tv, o_dt, o_dq, o_pt, o_j, o_acc, o_am, end


@jit
def soa_scratch_size(N, nm, nq):
    """Length of the scratch area after TMP_HEAD."""
    return _offsets(N, nm, nq)[-1] - TMP_HEAD


@jit
def soa_momentum_applies(iprm, V, tmp):
    """Step 5 vectorised: no current and no seabed, enough elements, and the scratch is there."""
    N = iprm[I_N]
    return (iprm[I_NEEDPOS] == 0 and N >= SOA_MIN_ELEMENTS
            and tmp.shape[0] >= TMP_HEAD + soa_scratch_size(N, V.shape[1], V.shape[0]))


@jit
def _matrix_rows(M, tmp, o_src, o_dst, nc, N):
    """dst[c, i, :] = sum_k M[i, k] src[c, k, :] (rows of N), summed in k order from 0."""
    ni, nk = M.shape
    for c in range(nc):
        for i in range(ni):
            d = o_dst + (c * ni + i) * N
            for e in range(N):
                tmp[U64(d + e)] = 0.0
            for k in range(nk):
                a = M[i, k]
                s = o_src + (c * nk + k) * N
                for e in range(N):
                    tmp[U64(d + e)] += a * tmp[U64(s + e)]


@jit
def momentum_rate_soa(prm, iprm, h, V, Pj, D, Lf, wq, wm, tr, fl, tmp, dU):
    """dv/dt into dU[..., 3:6] without current and seabed (same result as kernels.momentum_rate)."""
    N = iprm[I_N]
    nq = V.shape[0]
    nm = V.shape[1]
    g0 = prm[P_GAMMA0]
    ig0 = 1.0 / g0
    fbz = prm[P_FBZ]
    relax = prm[P_RELAX]
    hrd = prm[P_HALF_RHO_D]
    cdt = prm[P_CDT]
    cdn = prm[P_CDN]
    ct = g0 / (g0 + prm[P_MT])
    cn = g0 / (g0 + prm[P_MN])
    o_a, o_b, o_tv, o_dt, o_dq, o_pt, o_j, o_acc, o_am = _offsets(N, nm, nq)[:9]
    for e in range(N):
        tmp[U64(o_a + e)] = 2.0 / h[e]
        tmp[U64(o_b + e)] = 1.0 / h[e]
        for c in range(3):
            for k in range(nm):
                tmp[U64(o_tv + (c * nm + k) * N + e)] = wm[e, k, M_TV + c]
            tmp[U64(o_j + c * N + e)] = fl[e + 1, F_V + c] - 1.0 * tr[e, 1, T_TV + c]
            tmp[U64(o_j + (3 + c) * N + e)] = fl[e, F_V + c] - 1.0 * tr[e, 0, T_TV + c]
        for j in range(nq):
            tmp[U64(o_pt + j * N + e)] = wq[e, j, W_L]
            for c in range(3):
                tmp[U64(o_pt + ((1 + c) * nq + j) * N + e)] = wq[e, j, W_I + c]
                tmp[U64(o_pt + ((4 + c) * nq + j) * N + e)] = wq[e, j, W_V + c]
    # strong derivative of the tension vector (elementops.strong_derivative, scale 1)
    for c in range(3):
        jr = o_j + c * N
        jl = o_j + (3 + c) * N
        for l in range(nm):
            d = o_dt + (c * nm + l) * N
            for e in range(N):
                tmp[U64(d + e)] = 0.0
            for m in range(l + 1, nm):
                a = D[l, m]
                s = o_tv + (c * nm + m) * N
                for e in range(N):
                    tmp[U64(d + e)] += a * tmp[U64(s + e)]
            l1 = Lf[1, l]
            l0 = Lf[0, l]
            for e in range(N):
                tmp[U64(d + e)] = (tmp[U64(o_a + e)] * 1.0) * tmp[U64(d + e)] + tmp[U64(o_b + e)] * (l1 * tmp[U64(jr + e)] - l0 * tmp[U64(jl + e)])
    _matrix_rows(V, tmp, o_dt, o_dq, 3, N)
    # point loads: Morison drag [Eq. 17] in still water, weight, added mass [Eq. 13]
    for j in range(nq):
        pl = o_pt + j * N
        p0 = o_pt + (1 * nq + j) * N
        p1 = o_pt + (2 * nq + j) * N
        p2 = o_pt + (3 * nq + j) * N
        pv0 = o_pt + (4 * nq + j) * N
        pv1 = o_pt + (5 * nq + j) * N
        pv2 = o_pt + (6 * nq + j) * N
        q0 = o_dq + j * N
        q1 = o_dq + (nq + j) * N
        q2 = o_dq + (2 * nq + j) * N
        a0 = o_acc + j * N
        a1 = o_acc + (nq + j) * N
        a2 = o_acc + (2 * nq + j) * N
        for e in range(N):
            l = tmp[U64(pl + e)]
            i0 = tmp[U64(p0 + e)]
            i1 = tmp[U64(p1 + e)]
            i2 = tmp[U64(p2 + e)]
            v0 = tmp[U64(pv0 + e)]
            v1 = tmp[U64(pv1 + e)]
            v2 = tmp[U64(pv2 + e)]
            w0 = 0.0 - v0 * ig0
            w1 = 0.0 - v1 * ig0
            w2 = 0.0 - v2 * ig0
            wt = w0 * i0 + w1 * i1 + w2 * i2
            m0 = w0 - wt * i0
            m1 = w1 - wt * i1
            m2 = w2 - wt * i2
            wn = math.sqrt(m0 * m0 + m1 * m1 + m2 * m2)
            sl = math.sqrt(l if l > 0.0 else 0.0)
            f = hrd * sl if l > 0.0 else 0.0
            ft = f * cdt * abs(wt) * wt
            fn = f * cdn * wn
            fx = ft * i0 + fn * m0
            fy = ft * i1 + fn * m1
            fz = ft * i2 + fn * m2
            fx += tmp[U64(q0 + e)]
            fy += tmp[U64(q1 + e)]
            fz += tmp[U64(q2 + e)] + fbz
            fa = fx * i0 + fy * i1 + fz * i2
            r0 = fa * i0
            r1 = fa * i1
            r2 = fa * i2
            tmp[U64(a0 + e)] = (ct * r0 + cn * (fx - r0)) - relax * v0
            tmp[U64(a1 + e)] = (ct * r1 + cn * (fy - r1)) - relax * v1
            tmp[U64(a2 + e)] = (ct * r2 + cn * (fz - r2)) - relax * v2
    _matrix_rows(Pj, tmp, o_acc, o_am, 3, N)
    for e in range(N):
        for l in range(nm):
            for c in range(3):
                dU[e, l, 3 + c] = tmp[U64(o_am + (c * nm + l) * N + e)]

