"""Rigid body at a cable end, solved monolithically with the cable in the same Newton system.

The body state x (13: CoG position, quaternion, velocity, angular velocity; CONTRACTS.md) is one
more generalized-alpha variable: dx/dt at t_{n+alpha_m} = body_derivatives(x, F) at t_{n+alpha_f},
with F the force of the cable on the body [PE2020 Table 1 'rigid body connection']. The cable end
moves with the attachment point P: v_end = v_P(x_{n+1}) (moment free, like a pinned end).
Group parameters gp: gp[0] = end (0 ship, 1 vehicle), gp[8:8+BODY_PARAMS_SIZE] = body parameters.
"""

import numpy as np

from tether_sim.numerics.jit import jit_alloc
from tether_sim.physics.bodies import BODY_PARAMS_SIZE, BODY_STATE_SIZE, body_attachment_kinematics, body_derivatives
from tether_sim.solvers.hybrid.kernels import alpha_levels, current_at
from tether_sim.solvers.hybrid.layout import CAT_T, CAT_TAN, CAT_V, HP_AF, HP_DT, ROD_F, ROD_KAPPA, ROD_V
from tether_sim.solvers.hybrid.rod import frame_at

BODY_PAR0 = 8
GPAR_SIZE = BODY_PAR0 + BODY_PARAMS_SIZE


@jit_alloc
def _end_force_world(Yc, Ync, Lnc, is_rod, level_new, P, out):
    """Internal force f (world) at a cable end node, at t_{n+1} (level_new) or t_n."""
    if is_rod:
        L = np.empty((3, 3))
        if level_new:
            frame_at(Yc, Ync, Lnc, P[HP_DT], L)
            f = Yc[ROD_F:ROD_F + 3]
        else:
            L[:, :] = Lnc
            f = Ync[ROD_F:ROD_F + 3]
        for i in range(3):
            out[i] = L[0, i] * f[0] + L[1, i] * f[1] + L[2, i] * f[2]
    else:
        Y = Yc if level_new else Ync
        nt = np.sqrt(Y[CAT_TAN] * Y[CAT_TAN] + Y[CAT_TAN + 1] * Y[CAT_TAN + 1] + Y[CAT_TAN + 2] * Y[CAT_TAN + 2])
        for i in range(3):
            out[i] = Y[CAT_T] * Y[CAT_TAN + i] / nt


@jit_alloc
def body_dynamics_residual(Yb, Ynb, Ytnb, Yc, Ync, Lnc, is_rod, gp, P, cz, cx, cy, out):
    """13 equations: x'_{am} - body_derivatives(x_{af}, F_{af}) (F by the cable on the body)."""
    Yf = np.empty(BODY_STATE_SIZE)
    Ym = np.empty(BODY_STATE_SIZE)
    alpha_levels(Yb, Ynb, Ytnb, BODY_STATE_SIZE, P, Yf, Ym)
    f1 = np.empty(3)
    f0 = np.empty(3)
    _end_force_world(Yc, Ync, Lnc, is_rod, True, P, f1)
    _end_force_world(Yc, Ync, Lnc, is_rod, False, P, f0)
    sign = 1.0 if gp[0] < 0.5 else -1.0  # ship end: the cable pulls with +f(0); vehicle: -f(L)
    af = P[HP_AF]
    F = np.empty(3)
    for i in range(3):
        F[i] = sign * ((1.0 - af) * f0[i] + af * f1[i])
    uc = np.empty(3)
    current_at(Yf[2], cz, cx, cy, uc)
    d = np.empty(BODY_STATE_SIZE)
    body_derivatives(Yf, gp[BODY_PAR0:GPAR_SIZE], F, uc, d)
    for k in range(BODY_STATE_SIZE):
        out[k] = Ym[k] - d[k]


@jit_alloc
def body_end_residual(Yc, Ync, Lnc, is_rod, Yb, gp, P, out):
    """Cable end moves with P: v = v_P(x_{n+1}) (3 rows); a rod end is also moment free (3 more)."""
    pos = np.empty(3)
    vel = np.empty(3)
    body_attachment_kinematics(Yb, gp[BODY_PAR0:GPAR_SIZE], pos, vel)
    if is_rod:
        L = np.empty((3, 3))
        frame_at(Yc, Ync, Lnc, P[HP_DT], L)
        for i in range(3):
            out[i] = Yc[ROD_V + i] - (L[i, 0] * vel[0] + L[i, 1] * vel[1] + L[i, 2] * vel[2])
            out[3 + i] = Yc[ROD_KAPPA + i]
    else:
        for i in range(3):
            out[i] = Yc[CAT_V + i] - vel[i]
