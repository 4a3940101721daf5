"""Index constants and geometry-free block operators of the implicit damping step
(implicit_damping.py): the DG derivative blocks of G (velocity gradient), Div (tension divergence),
Kdot and Tau (nested LDG) per neighbour pair, precomputed at set-up with numpy.
"""

import math

import numpy as np

MODE_EXPLICIT = 0
MODE_AXIAL = 1
MODE_GENERAL = 2

# block operators blk[op, e, d, :, :] acting on element e + d - 2 (d = 0..4)
OP_G = 0  # v modes -> d(v/gamma0)/ds at the Gauss points (columns 0:P+1)
OP_GP = 1  # G Pj: point values -> gradient at points
OP_DIV = 2  # tension vector at points -> dT/ds at points
OP_KDOT = 3  # i-dot at points -> kappa-dot at points (flux bias +beta)
OP_TAU = 4  # M* at points -> tau at points (flux bias -beta)
OP_H = 5  # GP Div (reach 2)
N_OP = 6

# float parameters dprm[...]
DP_ZETA = 0
DP_ZETAB = 1
DP_G0 = 2
DP_AT = 3  # gamma0 / (gamma0 + m_t)
DP_AN = 4  # gamma0 / (gamma0 + m_n)
DP_EA = 5
DP_LAMBDA = 6  # upwind speed of velocity-end fluxes (kernels: max(c, lambda_floor))
DP_TC0 = 7  # (3 + 3) constant damping flux of released ends (runtime, see release_ends)
DP_IP0 = 13  # (3 + 3) trace tangent i+ of released ends (runtime)
DP_LU_H = 19  # gamma h of the stored LU
N_DP = 20

# int parameters idp[...]
ID_MODE = 0
ID_LAW = 1
ID_KIND0 = 2
ID_KIND1 = 3
ID_REACH = 4  # elements coupled by f_d on each side (2 axial, 4 with bending damping)
ID_KL = 5  # half bandwidth of the banded system
ID_REL0 = 6  # (2) velocity end released for this step (no-compression clip of the end flux active)
ID_LU_AGE = 8  # steps since the LU of the strain-rate system was computed (-1: none)
ID_RELF0 = 9  # (2) released flags when it was computed
N_ID = 11
LU_MAX_AGE = 64  # refactor at least this often
LU_TOL = 1e-4  # defect correction accepted if |correction| <= LU_TOL |solution|

# per-point work wp[e, j, ...]
WP_I = 0
WP_L = 3
WP_Z = 4
WP_NUS = 5
WP_TV = 8
WP_R = 11
WP_IDOT = 14
WP_KDOT = 17
WP_MB = 20
WP_TAU = 23
WP_E0 = 26
WP_E1 = 27
WP_E2 = 28
WP_X = 29
WP_TC = 30  # constant damping tension of points where the no-compression clip is active
WP_BC0 = 31  # strain rate caused by that constant force
WP_ZF = 32  # Z when the LU of the strain-rate system was computed
WP_KX = 33  # K x (defect correction): input x
WP_KY = 34  # and output
NWP = 35

# modal work wd[e, k, ...]
WD_F = 0
WD_K1 = 3
WD_Y = 6
WD_P = 9
NWD = 12

# boundary vectors bvec[...]: 0/1 = gradient lift of v_BC at s = 0 / L, 2/3 = trace of the projection
N_BVEC = 4

GAMMA_SDIRK = 1.0 - 1.0 / math.sqrt(2.0)


# ----------------------------------------------------------------------------------- set-up (numpy)
def strong_blocks(ops, h, w_left, w_right, left, right):
    """(N, 3, P+1, P+1) blocks of the modal strong derivative (elementops.strong_derivative) for the
    neighbours d = -1, 0, +1, with interior flux w_left u_L + w_right u_R and end rules
    "trace" (flux = own trace) or "zero" (flux = 0, i.e. a prescribed value moved to the right side)."""
    D, Lf, Tr = np.triu(ops.derivative, 1), ops.lift, ops.trace
    N, nm = len(h), D.shape[0]
    out = np.zeros((N, 3, nm, nm))
    for e in range(N):
        b = 1.0 / h[e]
        out[e, 1] = 2.0 * b * D
        if e < N - 1:
            out[e, 1] += b * (w_left - 1.0) * np.outer(Lf[1], Tr[1])
            out[e, 2] += b * w_right * np.outer(Lf[1], Tr[0])
        elif right == "zero":
            out[e, 1] -= b * np.outer(Lf[1], Tr[1])
        if e > 0:
            out[e, 1] -= b * (w_right - 1.0) * np.outer(Lf[0], Tr[0])
            out[e, 0] -= b * w_left * np.outer(Lf[0], Tr[1])
        elif left == "zero":
            out[e, 1] += b * np.outer(Lf[0], Tr[0])
    return out


def build_operators(ops, h, kinds, gamma0, beta):
    """Geometry-free block operators blk (N_OP, N, 5, Q, Q) and boundary vectors bvec (4, Q)."""
    V, Pj, Tr, Lf = ops.vandermonde, ops.projection, ops.trace, ops.lift
    N, nq, nm = len(h), V.shape[0], V.shape[1]
    force = [k in ("free", "force") for k in kinds]
    clamped = [k == "clamped" for k in kinds]
    vel_rule = ["trace" if f else "zero" for f in force]  # gradient of v: v_BC moved to bvec
    div_rule = ["zero" if f else "trace" for f in force]
    kdot_rule = ["zero" if c else "trace" for c in clamped]
    tau_rule = ["trace" if c else "zero" for c in clamped]
    blk = np.zeros((N_OP, N, 5, nq, nq))
    S = strong_blocks(ops, h, 0.5, 0.5, *vel_rule)
    for e in range(N):
        for d in range(3):
            blk[OP_G, e, d + 1, :, :nm] = V @ S[e, d] / gamma0
            blk[OP_GP, e, d + 1] = V @ S[e, d] @ Pj / gamma0
    for op, wl, wr, rule in ((OP_DIV, 0.5, 0.5, div_rule), (OP_KDOT, 0.5 - beta, 0.5 + beta, kdot_rule),
                             (OP_TAU, 0.5 + beta, 0.5 - beta, tau_rule)):
        S = strong_blocks(ops, h, wl, wr, *rule)
        for e in range(N):
            for d in range(3):
                blk[op, e, d + 1] = V @ S[e, d] @ Pj
    for e in range(N):
        for d1 in (-1, 0, 1):
            e1 = e + d1
            if 0 <= e1 < N:
                for d2 in (-1, 0, 1):
                    if 0 <= e1 + d2 < N:
                        blk[OP_H, e, d1 + d2 + 2] += blk[OP_GP, e, d1 + 2] @ blk[OP_DIV, e1, d2 + 2]
    bvec = np.zeros((N_BVEC, nq))
    if not force[0]:
        bvec[0] = -(V @ Lf[0]) / h[0]
    if not force[1]:
        bvec[1] = (V @ Lf[1]) / h[-1]
    bvec[2] = Tr[0] @ Pj
    bvec[3] = Tr[1] @ Pj
    return np.ascontiguousarray(blk), bvec
