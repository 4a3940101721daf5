"""Small compiled element operations of the modal DG method [PE2020 Eq. 23, 26-28].

Every function acts on element ``e`` of 3-D work arrays (element, mode or point, channel) and
``c_*`` select the first of ``nc`` consecutive channels. The arrays are indexed directly (no views
are created: array views in numba cost a reference-count update each). See numerics/operators.py.
"""

from tether_sim.numerics.jit import jit


@jit
def eval_points(V, src, e, c_src, dst, c_dst, nc, scale):
    """dst[e, j, c_dst + c] = scale * sum_k V[j, k] src[e, k, c_src + c] (modes -> Gauss points)."""
    nq, nm = V.shape
    for j in range(nq):
        for c in range(nc):
            s = 0.0
            for k in range(nm):
                s += V[j, k] * src[e, k, c_src + c]
            dst[e, j, c_dst + c] = scale * s


@jit
def project_points(Pj, src, e, c_src, dst, c_dst, nc):
    """dst[e, k, c_dst + c] = sum_j Pj[k, j] src[e, j, c_src + c] (Gauss points -> modes, L2 projection)."""
    nm, nq = Pj.shape
    for k in range(nm):
        for c in range(nc):
            s = 0.0
            for j in range(nq):
                s += Pj[k, j] * src[e, j, c_src + c]
            dst[e, k, c_dst + c] = s


@jit
def eval_traces(Tr, src, e, c_src, dst, c_dst, nc, scale):
    """dst[e, side, c_dst + c] = scale * u(xi = -1 | +1) for side 0 | 1."""
    nm = Tr.shape[1]
    for side in range(2):
        for c in range(nc):
            s = 0.0
            for k in range(nm):
                s += Tr[side, k] * src[e, k, c_src + c]
            dst[e, side, c_dst + c] = scale * s


@jit
def strong_derivative(h, D, Lf, src, e, c_src, scale, tr, c_tr, fl, c_fl, dst, c_dst, nc):
    """Strong-form DG derivative of F = scale * src on element e [PE2020 Eq. 23] with numerical fluxes.

    dst[e, l] = (2/h) sum_m D[l, m] F_m + (1/h) (Lf[1, l] (F_hat_R - F_R) - Lf[0, l] (F_hat_L - F_L)),
    with traces F_L, F_R = scale * tr[e, 0|1, c_tr + c] and F_hat = fl[e | e + 1, c_fl + c].
    """
    nm = D.shape[0]
    a = 2.0 / h
    b = 1.0 / h
    for c in range(nc):
        jr = fl[e + 1, c_fl + c] - scale * tr[e, 1, c_tr + c]
        jl = fl[e, c_fl + c] - scale * tr[e, 0, c_tr + c]
        for l in range(nm):
            s = 0.0
            for m in range(l + 1, nm):
                s += D[l, m] * src[e, m, c_src + c]
            dst[e, l, c_dst + c] = a * scale * s + b * (Lf[1, l] * jr - Lf[0, l] * jl)
