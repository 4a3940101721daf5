"""Index constants and geometry-free block operators of the implicit damping step
(implicit_damping.py): the DG derivative blocks of G (velocity gradient), Div (tension divergence),
Kdot and Tau (nested LDG) per neighbour pair, precomputed at set-up with numpy.
"""

import math

import numpy as np

from tether_sim.physics.end_conditions import end_kind
from tether_sim.solvers.columns import define

MODE_EXPLICIT = 0
MODE_AXIAL = 1
MODE_GENERAL = 2
MODE_RKL2 = 3  # axial damping only, by RKL2 super-time-stepping (rkl_damping.py)

# block operators blk[op, e, d, :, :] acting on element e + d - 2 (d = 0..4)
OP_G = 0  # v modes -> d(v/gamma0)/ds at the Gauss points (columns 0:P+1)
OP_GP = 1  # G Pj: point values -> gradient at points
OP_DIV = 2  # tension vector at points -> dT/ds at points
OP_KDOT = 3  # i-dot at points -> kappa-dot at points (flux bias +beta)
OP_TAU = 4  # M* at points -> tau at points (flux bias -beta)
OP_H = 5  # GP Div (reach 2)
N_OP = 6

# strain-rate LUs kept (damping_update.select_lu): the active one and LU_SLOTS - 1 parked, one per step size and
# released ends (the splitting's half and merged steps; an end released for a step or not)
LU_SLOTS = 4
LU_INTS = 20  # the ints describing an LU: ID_LU_AGE, ID_RELF0 (2), ID_NCH, ID_CH0 (8), ID_PV0 (8)

# The columns of the implicit damping step's arrays, named once (solvers/columns.py; layout.py has the rest)
define(globals(), "dprm", [
    ("DP_ZETA", 1, "zeta", "N s", "axial material damping"),
    ("DP_ZETAB", 1, "zeta_b", "N m^2 s", "bending damping"),
    ("DP_G0", 1, "gamma0", "kg/m", "mass per unstretched metre"),
    ("DP_AT", 1, "a_t", "-", "gamma0 / (gamma0 + m_t)"),
    ("DP_AN", 1, "a_n", "-", "gamma0 / (gamma0 + m_n)"),
    ("DP_EA", 1, "EA", "N", "axial stiffness"),
    ("DP_LAMBDA", 1, "lambda", "m/s", "upwind speed of velocity-end fluxes (max(c, lambda_floor))"),
    ("DP_TC0", 6, "-a_el i+", "N", "constant damping flux of released ends, 3 per end (runtime, release_ends)"),
    ("DP_IP0", 6, "i+", "-", "trace tangent of released ends, 3 per end (runtime)"),
    ("DP_LU_H", 1, "gamma h", "s", "gamma dt of the stored LU"),
    ("DP_RHO", 1, "rho_b", "1/s", "bound of the damping operator's spectral radius (MODE_RKL2: its stage count)"),
    ("DP_PARK_H", LU_SLOTS - 1, "gamma h", "s", "gamma dt of the parked LUs (damping_update.select_lu)"),
], "N_DP")

define(globals(), "idp", [
    ("ID_MODE", 1, "-", "-", "MODE_EXPLICIT / MODE_AXIAL / MODE_GENERAL / MODE_RKL2"),
    ("ID_LAW", 1, "-", "-", "tension law code"),
    ("ID_KIND0", 1, "-", "-", "end kind code at s = 0"),
    ("ID_KIND1", 1, "-", "-", "end kind code at s = L"),
    ("ID_REACH", 1, "-", "-", "elements coupled by f_d on each side (2 axial, 4 with bending damping)"),
    ("ID_KL", 1, "-", "-", "half bandwidth of the banded system"),
    ("ID_REL0", 2, "-", "-", "velocity end released for this step, per end (no-compression clip active)"),
    ("ID_LU_AGE", 1, "-", "-", "steps since the strain-rate LU was computed (-1: none)"),
    ("ID_RELF0", 2, "-", "-", "released flags when it was computed"),
    ("ID_NCH", 1, "k", "-", "points whose Z differs from the LU's, carried by the low-rank update (damping_update.py)"),
    ("ID_CH0", 8, "p", "-", "their point indices e Q + j (at most MAX_CHANGED)"),
    ("ID_PV0", 8, "-", "-", "row permutation of the capacitance matrix's LU"),
    ("ID_NSTEPS", 1, "-", "-", "strain-rate steps taken (counter, for benchmarks)"),
    ("ID_NFACT", 1, "-", "-", "of which with a new LU (counter)"),
    ("ID_NUPD", 1, "-", "-", "of which with the low-rank update of changed points (counter)"),
    ("ID_NWHY", 5, "-", "-", "new LUs by reason WHY_* (counters)"),
    ("ID_PARK0", (LU_SLOTS - 1) * LU_INTS, "-", "-", "the parked LUs' ID_LU_AGE .. ID_PV0, LU_INTS each"),
    ("ID_EVERY", 1, "-", "-", "substeps per damping step (stepper.dg_advance)"),
    ("ID_DEFECT", 1, "-", "-", "1: defect correction of a stored LU's stage solves"),
], "N_ID")
assert ID_PV0 + 8 - ID_LU_AGE == LU_INTS
# why a step computed a new LU (counters ID_NWHY + WHY_*): none for this step size (none yet, or the step size
# changed and no parked LU is for it), released ends changed, LU_MAX_AGE reached, the low-rank update
# refused (more than MAX_CHANGED points or a small pivot), a stage's defect correction above LU_TOL
WHY_STEP, WHY_ENDS, WHY_AGE, WHY_POINTS, WHY_TOL = range(5)
LU_MAX_AGE = 64  # refactor at least this often
LU_TOL = 1e-4  # defect correction accepted if |correction| <= LU_TOL |solution|
MAX_CHANGED = 8  # more points with a changed Z than this: refactor instead of the low-rank update
PIVOT_MIN = 1e-8  # a capacitance pivot below this (the updated matrix near singular there): refactor

define(globals(), "wp", [
    ("WP_I", 3, "i", "-", "frozen tangent"),
    ("WP_L", 1, "l", "-", "frozen stretch"),
    ("WP_Z", 1, "Z", "N s", "damping coefficient where the law transmits tension"),
    ("WP_NUS", 3, "G v", "1/s", "velocity gradient d(v/gamma0)/ds"),
    ("WP_TV", 3, "T_d i + T_s,d", "N", "damping tension vector (axial + bending-damping shear)"),
    ("WP_R", 3, "f_d", "N/m", "damping momentum rate at the point (divergence through the added mass)"),
    ("WP_IDOT", 3, "di/dt", "1/s", "tangent rate (bending damping)"),
    ("WP_KDOT", 3, "dkappa/dt", "1/(m s)", "curvature rate"),
    ("WP_MB", 3, "M*_d", "N m", "bending-damping moment / l^2"),
    ("WP_TAU", 3, "tau_d", "N", "its derivative"),
    ("WP_E0", 1, "e_0", "1/s", "strain rate at the start of the step"),
    ("WP_E1", 1, "e_1", "1/s", "SDIRK stage 1 strain rate"),
    ("WP_E2", 1, "e_2", "1/s", "SDIRK stage 2 strain rate"),
    ("WP_X", 1, "e", "1/s", "strain rate the damping tension is evaluated at"),
    ("WP_TC", 1, "T_c", "N", "constant damping tension of points where the no-compression clip is active"),
    ("WP_BC0", 1, "e_c", "1/s", "strain rate caused by that constant force"),
    ("WP_PC", 1, "p_c", "N", "compression cap of the point's element (constitutive.compression_cap; set once: h is fixed)"),
    ("WP_ZF", 1, "Z_LU", "N s", "Z when the strain-rate LU was computed"),
    ("WP_ZP", LU_SLOTS - 1, "Z_LU'", "N s", "the same for the parked LUs"),
    ("WP_KX", 1, "x", "1/s", "K x (defect correction): input"),
    ("WP_KY", 1, "K x", "1/s^2", "and output"),
], "NWP")

define(globals(), "wd", [
    ("WD_F", 3, "f_d", "N/m", "damping momentum rate, modal (output of damping_force)"),
    ("WD_K1", 3, "k_1", "N/m", "SDIRK stage 1 rate, modal (MODE_GENERAL); RKL2: v at the step start"),
    ("WD_Y", 3, "v_1", "kg/s", "SDIRK stage value, modal (MODE_GENERAL); RKL2: the stage before the last"),
    ("WD_P", 3, "p", "kg/s or N/m", "probe vector (matrix assembly) or rate of the constant clip tension, modal; RKL2: f_d at the step start"),
], "NWD")

# rows of the low-rank update's array (wood, (2 WOOD_ROWS, max(N Q, MAX_CHANGED))): A_LU^-1 u_p of each carried
# point, the LU of the capacitance matrix I + E^T W, the Z change each column was made for, a k-vector of scratch;
# rows s WOOD_ROWS.. the same for the parked LU s = 1 .. LU_SLOTS - 1
WOOD_W = 0
WOOD_C = MAX_CHANGED
WOOD_DZ = 2 * MAX_CHANGED
WOOD_Z = 2 * MAX_CHANGED + 1
WOOD_ROWS = 2 * MAX_CHANGED + 2

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
    force = [not end_kind(k).kinematic for k in kinds]
    clamped = [end_kind(k).direction == "held" for k in kinds]
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
