"""Spherical joint between a catenary and a rod zone [GP Sec. 2.3, Eq. 12-14].

Nine equations at t_{n+1}, L_r the rod node's frame (world -> body):
    kappa_r = 0                     (moment free)          [GP Eq. 12]
    v_r - L_r v_c = 0               (continuous velocity)  [GP Eq. 13]
    f_r - L_r t_c T_c = 0           (continuous force)     [GP Eq. 14]
The catenary tangent need not equal the rod tangent at the joint (GP Sec. 2.3).
"""

import numpy as np

from tether_sim.numerics.jit import jit_alloc
from tether_sim.solvers.hybrid.layout import CAT_T, CAT_TAN, CAT_V, HP_DT, ROD_F, ROD_KAPPA, ROD_V
from tether_sim.solvers.hybrid.rod import frame_at


@jit_alloc
def joint_residual(Yc, Yr, Ynr, Lnr, P, out):
    """The 9 joint equations [GP Eq. 12-14]; Yc catenary node, Yr/Ynr/Lnr rod node."""
    L1 = np.empty((3, 3))
    frame_at(Yr, Ynr, Lnr, P[HP_DT], L1)
    T = Yc[CAT_T]
    for i in range(3):
        vc = L1[i, 0] * Yc[CAT_V] + L1[i, 1] * Yc[CAT_V + 1] + L1[i, 2] * Yc[CAT_V + 2]
        fc = T * (L1[i, 0] * Yc[CAT_TAN] + L1[i, 1] * Yc[CAT_TAN + 1] + L1[i, 2] * Yc[CAT_TAN + 2])
        out[i] = Yr[ROD_KAPPA + i]
        out[3 + i] = Yr[ROD_V + i] - vc
        out[6 + i] = Yr[ROD_F + i] - fc
