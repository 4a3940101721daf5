"""Outputs of the DG solver: positions, sampled state, end loads and body state (a mixin of
DGCableSolver; the sampling kernel is sampling.py, the evaluation it reads tick.outputs_now)."""

import numpy as np

from tether_sim.numerics.polys import legendre_integral_at
from tether_sim.physics.bodies import body_acceleration
from tether_sim.physics.hydrodynamics import current_at
from tether_sim.solvers.base import BodyState, EndForces, SolverState, end_index
from tether_sim.solvers.dg import layout as Y
from tether_sim.solvers.dg.sampling import (
    NS, S_CURV, S_MOMENT, S_MVEC, S_POS, S_SHEAR, S_STRAIN, S_TENSION, S_TV, S_VEL, SamplingPlan, sample_state,
)


class OutputsMixin:
    """state(), end_forces(), body_state(), positions_at() of DGCableSolver."""

    def _locate(self, s):
        s = np.clip(np.atleast_1d(np.asarray(s, float)), 0.0, self.L)
        e = np.clip(np.searchsorted(self.s_edges, s, side="right") - 1, 0, self.N - 1)
        xi = np.clip(2.0 * (s - self.s_edges[e]) / self.h[e] - 1.0, -1.0, 1.0)
        return s, e, xi

    def positions_at(self, arc_lengths):
        """r(s) (n, 3) from the anchor and int q ds."""
        s, e, xi = self._locate(arc_lengths)
        starts = np.empty((self.N, 3))
        if self.iprm[Y.I_ANCHOR] == 0:
            starts[:] = self.ra + np.concatenate(([np.zeros(3)], np.cumsum(self.h[:, None] * self.U[:, 0, 0:3], axis=0)[:-1]))
        else:
            tail = np.cumsum((self.h[:, None] * self.U[:, 0, 0:3])[::-1], axis=0)[::-1]
            starts[:] = self.ra - tail
        I = legendre_integral_at(self.P, xi)
        return starts[e] + 0.5 * self.h[e][:, None] * np.einsum("nk,nkc->nc", I, self.U[e, :, 0:3])

    def _plan(self, arc_lengths):
        """Sampling plan of these arc lengths (cached: a node asks for the same points every tick)."""
        if arc_lengths is None:
            key = None
        else:
            arr = np.asarray(arc_lengths, float)
            key = (arr.shape, arr.tobytes())
        plan = self._plans.get(key)
        if plan is None:
            if arc_lengths is None:
                arr = np.linspace(0.0, self.L, self.config.node.output_points)
            plan = SamplingPlan(arr, self.s_edges, self.h, self.P)
            if len(self._plans) >= 16:
                self._plans.clear()
            self._plans[key] = plan
        return plan

    def state(self, arc_lengths=None) -> SolverState:
        """Position, velocity, strain, tension, curvature and bending moment at arc lengths s
        (one compiled sampling kernel, sampling.py)."""
        self._evaluate_outputs()
        plan = self._plan(arc_lengths)
        o = np.empty((NS, plan.s.size))
        sample_state(self.U, self.ra, self._wm, self.h, self.iprm, self.config.cable.gamma0, self.law.code,
                     self.law.EA, self.law.zeta, self.prm[Y.P_EIC], self.law.tab_eps, self.law.tab_T, plan.elem, plan.phi, plan.iphi,
                     plan.starts, o)
        vec = lambda c0: o[c0:c0 + 3].T.copy()  # noqa: E731  (n, 3) C-contiguous
        extra = {"moment_vector": vec(S_MVEC), "shear_force": vec(S_SHEAR), "tension_vector": vec(S_TV)}
        return SolverState(time=self.time, arc_length=plan.s.copy(), position=vec(S_POS),
                           velocity=vec(S_VEL), tension=o[S_TENSION], strain=o[S_STRAIN],
                           curvature=o[S_CURV], bending_moment=o[S_MOMENT], time_step=self._substep(),
                           extra=extra)

    def end_forces(self) -> EndForces:
        """Force (and moment) BY the cable ON each end: -n T_hat at the boundary fluxes."""
        self._evaluate_outputs()
        f = self._endf
        return EndForces(ship_force=f[0, Y.E_F:Y.E_F + 3].copy(), vehicle_force=f[1, Y.E_F:Y.E_F + 3].copy(),
                         ship_moment=f[0, Y.E_M:Y.E_M + 3].copy(), vehicle_moment=f[1, Y.E_M:Y.E_M + 3].copy(),
                         ship_tension=float(f[0, Y.E_T]), vehicle_tension=float(f[1, Y.E_T]))

    def body_state(self, end):
        """State of the rigid body at a "body" end (None for other kinds)."""
        e = end_index(end)
        if self.ends[e].position != "body":
            return None
        self._evaluate_outputs()
        b = self._bs[e]
        acc = np.zeros(3)
        uc = np.zeros(3)
        if self.cz.size:
            current_at(b[2], self.cz, self.cx, self.cy, uc)
        body_acceleration(b, self._bp[e], self._endf[e, Y.E_F:Y.E_F + 3].copy(), uc, acc)
        return BodyState(position=b[0:3].copy(), orientation=b[3:7].copy(), velocity=b[7:10].copy(),
                         angular_velocity=b[10:13].copy(), acceleration=acc)

