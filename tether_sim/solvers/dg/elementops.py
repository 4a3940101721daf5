"""Small compiled element operations of the modal DG method [PE2020 Eq. 23, 26-28].

Every function acts on element ``e`` of 3-D work arrays (element, mode or point, channel) and
``c_*`` select the first of ``nc`` consecutive channels. The arrays are indexed directly (no views
are created: with reference counting, array views cost a count update each; the kernels are now
compiled without it, numerics/jit.py, and the direct indexing stays). See numerics/operators.py.

The three-channel case (every vector field of the cable) is unrolled by hand: three independent
accumulators per row instead of an inner loop of length 3, the same sums in the same order.
"""

from tether_sim.numerics.jit import jit_inline


@jit_inline
def apply_element_matrix(M, src, e, c_src, dst, c_dst, nc, scale):
    """dst[e, i, c_dst + c] = scale * sum_k M[i, k] src[e, k, c_src + c] for one element e.

    With M = V (modes -> Gauss points), Pj (Gauss points -> modes, L2 projection) or Tr (modes ->
    the traces at xi = -1, +1) this is every change of representation the DG operators need.
    """
    ni, nk = M.shape
    if nc == 3:
        for i in range(ni):
            s0 = 0.0
            s1 = 0.0
            s2 = 0.0
            for k in range(nk):
                m = M[i, k]
                s0 += m * src[e, k, c_src]
                s1 += m * src[e, k, c_src + 1]
                s2 += m * src[e, k, c_src + 2]
            dst[e, i, c_dst] = scale * s0
            dst[e, i, c_dst + 1] = scale * s1
            dst[e, i, c_dst + 2] = scale * s2
        return
    for i in range(ni):
        for c in range(nc):
            s = 0.0
            for k in range(nk):
                s += M[i, k] * src[e, k, c_src + c]
            dst[e, i, c_dst + c] = scale * s


eval_points = apply_element_matrix  # V: modes -> Gauss points
eval_traces = apply_element_matrix  # Tr: modes -> traces (side 0: xi = -1, side 1: xi = +1)


@jit_inline
def project_points(Pj, src, e, c_src, dst, c_dst, nc):
    """Gauss points -> modes (L2 projection with Pj)."""
    apply_element_matrix(Pj, src, e, c_src, dst, c_dst, nc, 1.0)


@jit_inline
def strong_derivative(h, D, Lf, src, e, c_src, scale, tr, c_tr, fl, c_fl, dst, c_dst, nc):
    """Strong-form DG derivative of F = scale * src on element e [PE2020 Eq. 23] with numerical fluxes.

    dst[e, l] = (2/h) sum_m D[l, m] F_m + (1/h) (Lf[1, l] (F_hat_R - F_R) - Lf[0, l] (F_hat_L - F_L)),
    with traces F_L, F_R = scale * tr[e, 0|1, c_tr + c] and F_hat = fl[e | e + 1, c_fl + c].
    """
    nm = D.shape[0]
    a = 2.0 / h
    b = 1.0 / h
    if nc == 3:
        jr0 = fl[e + 1, c_fl] - scale * tr[e, 1, c_tr]
        jr1 = fl[e + 1, c_fl + 1] - scale * tr[e, 1, c_tr + 1]
        jr2 = fl[e + 1, c_fl + 2] - scale * tr[e, 1, c_tr + 2]
        jl0 = fl[e, c_fl] - scale * tr[e, 0, c_tr]
        jl1 = fl[e, c_fl + 1] - scale * tr[e, 0, c_tr + 1]
        jl2 = fl[e, c_fl + 2] - scale * tr[e, 0, c_tr + 2]
        asc = a * scale
        for l in range(nm):
            s0 = 0.0
            s1 = 0.0
            s2 = 0.0
            for m in range(l + 1, nm):
                d = D[l, m]
                s0 += d * src[e, m, c_src]
                s1 += d * src[e, m, c_src + 1]
                s2 += d * src[e, m, c_src + 2]
            l1 = Lf[1, l]
            l0 = Lf[0, l]
            dst[e, l, c_dst] = asc * s0 + b * (l1 * jr0 - l0 * jl0)
            dst[e, l, c_dst + 1] = asc * s1 + b * (l1 * jr1 - l0 * jl1)
            dst[e, l, c_dst + 2] = asc * s2 + b * (l1 * jr2 - l0 * jl2)
        return
    for c in range(nc):
        jr = fl[e + 1, c_fl + c] - scale * tr[e, 1, c_tr + c]
        jl = fl[e, c_fl + c] - scale * tr[e, 0, c_tr + c]
        for l in range(nm):
            s = 0.0
            for m in range(l + 1, nm):
                s += D[l, m] * src[e, m, c_src + c]
            dst[e, l, c_dst + c] = a * scale * s + b * (Lf[1, l] * jr - Lf[0, l] * jl)
