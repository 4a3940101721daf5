"""Outputs of the DG solver as functions of the workspace: positions, the sampled state, end loads and
body state (DGCableSolver calls these after the evaluation they read, tick.outputs_now; the sampling
kernel is sampling.py). No compiled code here."""

import numpy as np

from tether_sim.numerics.polys import legendre_integral_at
from tether_sim.physics.bodies import body_acceleration
from tether_sim.physics.hydrodynamics import current_at
from tether_sim.solvers.base import BodyState, EndForces, SolverState
from tether_sim.solvers.dg import layout as Y
from tether_sim.solvers.dg.sampling import (
    NS, S_CURV, S_MOMENT, S_MVEC, S_POS, S_SHEAR, S_STRAIN, S_TENSION, S_TV, S_VEL, SamplingPlan, sample_state,
)

PLANS_KEPT = 16  # sampling plans cached per solver (a node asks for the same points every tick)


def locate(s_edges, h, L, arc_lengths):
    """(s clipped to [0, L], element, xi in [-1, 1]) of every arc length."""
    N = h.size
    s = np.clip(np.atleast_1d(np.asarray(arc_lengths, float)), 0.0, L)
    e = np.clip(np.searchsorted(s_edges, s, side="right") - 1, 0, N - 1)
    xi = np.clip(2.0 * (s - s_edges[e]) / h[e] - 1.0, -1.0, 1.0)
    return s, e, xi


def positions_at(ws, P, s_edges, L, arc_lengths):
    """r(s) (n, 3) from the anchor r_a and int q ds (the anchor is end iprm[I_ANCHOR])."""
    U, h, ra = ws.U, ws.h, ws.ra
    s, e, xi = locate(s_edges, h, L, arc_lengths)
    starts = np.empty((h.size, 3))
    if ws.iprm[Y.I_ANCHOR] == 0:
        starts[:] = ra + np.concatenate(([np.zeros(3)], np.cumsum(h[:, None] * U[:, 0, 0:3], axis=0)[:-1]))
    else:
        tail = np.cumsum((h[:, None] * U[:, 0, 0:3])[::-1], axis=0)[::-1]
        starts[:] = ra - tail
    I = legendre_integral_at(P, xi)
    return starts[e] + 0.5 * h[e][:, None] * np.einsum("nk,nkc->nc", I, U[e, :, 0:3])


def plan(plans, arc_lengths, s_edges, h, P, L, output_points, points):
    """Sampling plan of these arc lengths (None: output_points evenly spaced on [0, L]), cached in plans;
    points: the Gauss points of the element (its tension nodes, sampling.py)."""
    if arc_lengths is None:
        key = None
    else:
        arr = np.asarray(arc_lengths, float)
        key = (arr.shape, arr.tobytes())
    found = plans.get(key)
    if found is None:
        if arc_lengths is None:
            arr = np.linspace(0.0, L, output_points)
        found = SamplingPlan(arr, s_edges, h, P, points)
        if len(plans) >= PLANS_KEPT:
            plans.clear()
        plans[key] = found
    return found


def _sample(ws, plan, law, gamma0, o):
    """The sampling kernel on the workspace, the law and the plan (sampling.sample_state)."""
    sample_state(ws.U, ws.ra, ws.wq, ws.wm, ws.trc, ws.fl, ws.endf, ws.h, ws.iprm, gamma0, law.code, law.EA,
                 law.zeta, ws.prm[Y.P_EIC], law.tab_eps, law.tab_T, plan.elem, plan.phi, plan.iphi, plan.lag,
                 plan.starts, plan.tnodes, o)


def sampled_state(ws, plan, law, gamma0, time, time_step) -> SolverState:
    """Position, velocity, strain, tension, curvature and bending moment at the plan's arc lengths
    (one compiled sampling kernel, sampling.py)."""
    o = np.empty((NS, plan.s.size))
    _sample(ws, plan, law, gamma0, o)
    vec = lambda c0: o[c0:c0 + 3].T.copy()  # noqa: E731  (n, 3) C-contiguous
    extra = {"moment_vector": vec(S_MVEC), "shear_force": vec(S_SHEAR), "tension_vector": vec(S_TV)}
    return SolverState(time=time, arc_length=plan.s.copy(), position=vec(S_POS), velocity=vec(S_VEL),
                       tension=o[S_TENSION], strain=o[S_STRAIN], curvature=o[S_CURV], bending_moment=o[S_MOMENT],
                       time_step=time_step, extra=extra)


def sampled_kinematics(ws, plan, law, gamma0):
    """(positions (n, 3), velocities (n, 3)) at the plan's arc lengths: those of :func:`sampled_state`
    (the same kernel), without building the rest of the state."""
    o = np.empty((NS, plan.s.size))
    _sample(ws, plan, law, gamma0, o)
    return o[S_POS:S_POS + 3].T, o[S_VEL:S_VEL + 3].T


def end_forces(ws) -> EndForces:
    """Force (and moment) BY the cable ON each end: -n T_hat at the boundary fluxes (the endf slot)."""
    f = ws.endf
    return EndForces(ship_force=f[0, Y.E_F:Y.E_F + 3].copy(), vehicle_force=f[1, Y.E_F:Y.E_F + 3].copy(),
                     ship_moment=f[0, Y.E_M:Y.E_M + 3].copy(), vehicle_moment=f[1, Y.E_M:Y.E_M + 3].copy(),
                     ship_tension=float(f[0, Y.E_T]), vehicle_tension=float(f[1, Y.E_T]))


def body_state(ws, e) -> BodyState:
    """State of the rigid body at end e, with its acceleration under the end load and the current."""
    b = ws.bs[e]
    acc = np.zeros(3)
    uc = np.zeros(3)
    if ws.cz.size:
        current_at(b[2], ws.cz, ws.cx, ws.cy, uc)
    body_acceleration(b, ws.bp[e], ws.endf[e, Y.E_F:Y.E_F + 3].copy(), uc, acc)
    return BodyState(position=b[0:3].copy(), orientation=b[3:7].copy(), velocity=b[7:10].copy(),
                     angular_velocity=b[10:13].copy(), acceleration=acc)
