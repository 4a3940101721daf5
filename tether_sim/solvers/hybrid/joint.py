"""Spherical joint between a catenary and a rod zone [GP Sec. 2.3, Eq. 12-14].

Nine equations at t_{n+1}, L_r the rod node's frame (world -> body):
    kappa_r = 0                     (moment free)          [GP Eq. 12]
    v_r - L_r v_c = 0               (continuous velocity)  [GP Eq. 13]
    f_r - L_r t_c T_c = 0           (continuous force)     [GP Eq. 14]
The catenary tangent need not equal the rod tangent at the joint (GP Sec. 2.3).
"""

import numpy as np

from tether_sim.numerics.jit import jit_alloc
from tether_sim.solvers.hybrid.kernels import P_DT
from tether_sim.solvers.hybrid.rod import frame_at


@jit_alloc
def joint_residual(Yc, Yr, Ynr, Lnr, P, out):
    """The 9 joint equations [GP Eq. 12-14]; Yc catenary node, Yr/Ynr/Lnr rod node."""
    L1 = np.empty((3, 3))
    frame_at(Yr, Ynr, Lnr, P[P_DT], L1)
    T = Yc[3]
    for i in range(3):
        vc = L1[i, 0] * Yc[0] + L1[i, 1] * Yc[1] + L1[i, 2] * Yc[2]
        fc = T * (L1[i, 0] * Yc[4] + L1[i, 1] * Yc[5] + L1[i, 2] * Yc[6])
        out[i] = Yr[6 + i]
        out[3 + i] = Yr[i] - vc
        out[6 + i] = Yr[9 + i] - fc
