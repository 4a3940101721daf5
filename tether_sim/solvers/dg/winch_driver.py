"""The winch of the DG solver, driver side (a mixin of DGCableSolver; kernels in winch.py).

API (agreed with the winch controller, physics/winch.py and ros/winch_link.py):

- ``set_pay_out_rate(rate)``: unstretched pay-out rate dL/dt (m/s; > 0 pays out, < 0 hauls in) at
  the winch end; the rate ramps linearly from the current rate to ``rate`` over the next
  ``advance_to`` (or ``step``) interval, then stays;
- ``unstretched_length``: L(t), the unstretched length in the domain (m);
- ``pay_out_rate``: the rate reached at the current time (m/s).

Enabled by ``winch.enabled`` (``winch.end``: ship or vehicle), read defensively so that a
configuration without the section builds a fixed-length solver. The winch end must be kinematic
(its point is the sheave); ``dg.damping: implicit`` is refused (its block operators are built for
fixed element sizes). While the winch moves, the substep is that of the shortest length the
interval reaches, with the transport speed |dL/dt| added to the axial wave speed.
"""

import math

import numpy as np

from tether_sim.errors import UnstableTimeStepError
from tether_sim.physics.boundary import END_NAMES
from tether_sim.solvers.dg import layout as Y
from tether_sim.solvers.dg.timestep import _A, _coef


class WinchMixin:
    """set_pay_out_rate, unstretched_length and the bookkeeping of a moving winch."""

    def _setup_winch(self, config):
        """After the parameters, before the damping set-up (it copies iprm) and the workspace."""
        w = getattr(config, "winch", None)
        self.winch_enabled = bool(getattr(w, "enabled", False))
        self.winch_end = None
        self._hw = np.ascontiguousarray(self.h / self.L)
        self.prm[Y.P_WL] = self.L
        if not self.winch_enabled:
            return
        end = getattr(w, "end", "ship")
        if end not in END_NAMES:
            raise ValueError(f"winch.end: {end!r} is not one of {', '.join(END_NAMES)}")
        e = END_NAMES.index(end)
        if not self.ends[e].kinematic:
            raise ValueError(
                f"winch.end = {end}: {('ship_end', 'vehicle_end')[e]}.kind is {self.kinds[e]!r}, a force end; "
                "the winch needs a kinematic end (prescribed, fixed, clamped or body) whose point is the sheave")
        cab = config.cable
        if config.dg.damping == "implicit" and (cab.damping > 0.0 or cab.bending_damping > 0.0):
            raise ValueError("winch.enabled with dg.damping = implicit: the implicit damping operators are built "
                             "for fixed element sizes; use dg.damping: explicit with a winch")
        self.winch_end = end
        self.iprm[Y.I_WINCH] = e + 1

    @property
    def unstretched_length(self) -> float:
        """L(t): unstretched length of cable in the domain (m)."""
        return float(self.prm[Y.P_WL])

    @property
    def pay_out_rate(self) -> float:
        """dL/dt reached at the current time (m/s)."""
        return float(self.prm[Y.P_WR0])

    def set_pay_out_rate(self, rate: float) -> None:
        """Rate dL/dt (m/s, > 0 pays out) reached by a linear ramp over the next advance_to, then held."""
        if not self.winch_enabled:
            raise ValueError("set_pay_out_rate: this solver has no winch (winch.enabled is false)")
        r = float(rate)
        if not math.isfinite(r):
            raise ValueError(f"set_pay_out_rate: non-finite rate {rate!r}")
        self.prm[Y.P_WR1] = r

    def _winch_moving(self) -> bool:
        return self.winch_enabled and (self.prm[Y.P_WR0] != 0.0 or self.prm[Y.P_WR1] != 0.0)

    def _winch_substep(self, span):
        """Substep for an interval of length span while the winch moves (None when it does not)."""
        limit = self._winch_limit(span)
        if limit is None:
            return None
        if self.fixed_dt > 0.0:
            if self.fixed_dt > limit:
                raise UnstableTimeStepError(
                    f"dg.fixed_time_step = {self.fixed_dt:g} s exceeds the stability limit {limit:g} s of the "
                    f"shortest length this winch interval reaches")
            return self.fixed_dt
        return self.config.dg.cfl * limit

    def _winch_limit(self, span):
        """Stability limit (cfl = 1) over an interval of length span while the winch moves (None when it
        does not): that of the shortest length reached, the transport speed added to the waves."""
        if not self._winch_moving():
            return None
        r0, r1 = float(self.prm[Y.P_WR0]), float(self.prm[Y.P_WR1])
        L0 = float(self.prm[Y.P_WL])
        lmin = min(L0, L0 + 0.5 * (r0 + r1) * span)
        if r0 < 0.0 < r1:  # hauls in, then pays out: the shortest length is where the rate is zero
            lmin = min(lmin, L0 + 0.5 * r0 * (-r0 / (r1 - r0) * span))
        if not lmin > 0.0:
            raise ValueError(f"winch: the rate ramp {r0:g} -> {r1:g} m/s over {span:g} s would haul in all of the "
                             f"{L0:g} m of cable (the length must stay positive)")
        h = self._hw * lmin
        cfl = self.config.dg.cfl
        rate = cfl / self.stable_time_step(h) + _coef(_A, self.P, 2) * max(abs(r0), abs(r1)) / float(np.min(h))
        return 1.0 / rate

    def _winch_sync(self):
        """After a moving interval: length, element edges, sampling plans and time step follow L."""
        self.L = float(self.prm[Y.P_WL])
        self.s_edges = np.concatenate(([0.0], np.cumsum(self.h)))
        self._plans.clear()
        self._dt_rule = self.stable_time_step()

    def _winch_snapshot(self):
        if not self.winch_enabled:
            return {}
        return {"winch": (self.prm[[Y.P_WL, Y.P_WLDOT, Y.P_WR0, Y.P_WR1]].copy(), self.h.copy())}

    def _winch_restore(self, snap):
        if "winch" not in snap:
            return
        vals, h = snap["winch"]
        self.prm[[Y.P_WL, Y.P_WLDOT, Y.P_WR0, Y.P_WR1]] = vals
        self.h[:] = h
        self._winch_sync()
