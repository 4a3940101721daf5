"""Small compiled element operations of the modal DG method [PE2020 Eq. 23, 26-28].

Every function acts on one element; arrays are 2-D views (row = mode or point, column = channel)
and ``c_*`` select the first of ``nc`` consecutive channels. See ``numerics/operators.py``.
"""

from tether_sim.numerics.jit import jit


@jit
def eval_points(V, src, c_src, dst, c_dst, nc, scale):
    """dst[j, c_dst + c] = scale * sum_k V[j, k] src[k, c_src + c] (modes -> Gauss points)."""
    nq, nm = V.shape
    for j in range(nq):
        for c in range(nc):
            s = 0.0
            for k in range(nm):
                s += V[j, k] * src[k, c_src + c]
            dst[j, c_dst + c] = scale * s


@jit
def project_points(Pj, src, c_src, dst, c_dst, nc):
    """dst[k, c_dst + c] = sum_j Pj[k, j] src[j, c_src + c] (Gauss points -> modes, L2 projection)."""
    nm, nq = Pj.shape
    for k in range(nm):
        for c in range(nc):
            s = 0.0
            for j in range(nq):
                s += Pj[k, j] * src[j, c_src + c]
            dst[k, c_dst + c] = s


@jit
def eval_traces(Tr, src, c_src, dst, c_dst, nc, scale):
    """dst[side, c_dst + c] = scale * u(xi = -1 | +1) for side 0 | 1."""
    nm = Tr.shape[1]
    for side in range(2):
        for c in range(nc):
            s = 0.0
            for k in range(nm):
                s += Tr[side, k] * src[k, c_src + c]
            dst[side, c_dst + c] = scale * s


@jit
def strong_derivative(h, D, Lf, src, c_src, scale, trace, c_tr, flux_left, flux_right, c_fl, dst, c_dst, nc):
    """Strong-form DG derivative of F = scale * src [PE2020 Eq. 23] with numerical fluxes.

    dst[l] = (2/h) sum_m D[l, m] F_m + (1/h) (Lf[1, l] (F_hat_R - F_R) - Lf[0, l] (F_hat_L - F_L)),
    with the element traces F_L, F_R = scale * trace[0|1, c_tr + c] and F_hat from the fluxes.
    """
    nm = D.shape[0]
    a = 2.0 / h
    b = 1.0 / h
    for c in range(nc):
        jr = flux_right[c_fl + c] - scale * trace[1, c_tr + c]
        jl = flux_left[c_fl + c] - scale * trace[0, c_tr + c]
        for l in range(nm):
            s = 0.0
            for m in range(l + 1, nm):
                s += D[l, m] * src[m, c_src + c]
            dst[l, c_dst + c] = a * scale * s + b * (Lf[1, l] * jr - Lf[0, l] * jl)
