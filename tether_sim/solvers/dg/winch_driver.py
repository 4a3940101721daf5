"""The winch of the DG solver, driver side: functions of the workspace that DGCableSolver calls
(kernels in winch.py; no compiled code here).

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
from tether_sim.solvers.config import SPLIT_DAMPING

# the winch state a snapshot keeps (with the element sizes)
_STATE = [Y.P_WL, Y.P_WLDOT, Y.P_WR0, Y.P_WR1]


def setup(config, ends, kinds, prm, iprm, h, L):
    """The winch end (None without a winch) and h / L (the hw slot), after the parameters and before
    the damping set-up (it copies iprm): sets prm's length and, with a winch, iprm's I_WINCH."""
    w = getattr(config, "winch", None)
    hw = np.ascontiguousarray(h / L)
    prm[Y.P_WL] = L
    if not bool(getattr(w, "enabled", False)):
        return None, hw
    end = getattr(w, "end", "ship")
    if end not in END_NAMES:
        raise ValueError(f"winch.end: {end!r} is not one of {', '.join(END_NAMES)}")
    e = END_NAMES.index(end)
    if not ends[e].kinematic:
        raise ValueError(
            f"winch.end = {end}: {('ship_end', 'vehicle_end')[e]}.kind is {kinds[e]!r}, a force end; "
            "the winch needs a kinematic end (prescribed, fixed, clamped or body) whose point is the sheave")
    cab = config.cable
    if config.dg.damping in SPLIT_DAMPING and (cab.damping > 0.0 or cab.bending_damping > 0.0):
        raise ValueError(f"winch.enabled with dg.damping = {config.dg.damping}: the damping step's operators are built "
                         "for fixed element sizes; use dg.damping: explicit with a winch")
    iprm[Y.I_WINCH] = e + 1
    return end, hw


def set_rate(ws, enabled, rate):
    """Rate dL/dt (m/s, > 0 pays out) reached by a linear ramp over the next interval, then held."""
    if not enabled:
        raise ValueError("set_pay_out_rate: this solver has no winch (winch.enabled is false)")
    r = float(rate)
    if not math.isfinite(r):
        raise ValueError(f"set_pay_out_rate: non-finite rate {rate!r}")
    ws.prm[Y.P_WR1] = r


def moving(ws, enabled) -> bool:
    """The winch turns now or over the next interval (rate reached or ramp target nonzero)."""
    return enabled and (ws.prm[Y.P_WR0] != 0.0 or ws.prm[Y.P_WR1] != 0.0)


def limit(ws, enabled, span, P, cfl, stable_time_step):
    """Stability limit (cfl = 1) over an interval of length span while the winch moves (None when it
    does not): that of the shortest length reached, the transport speed added to the waves
    (stable_time_step(h): the solver's automatic substep on element sizes h)."""
    if not moving(ws, enabled):
        return None
    r0, r1 = float(ws.prm[Y.P_WR0]), float(ws.prm[Y.P_WR1])
    L0 = float(ws.prm[Y.P_WL])
    lmin = min(L0, L0 + 0.5 * (r0 + r1) * span)
    if r0 < 0.0 < r1:  # hauls in, then pays out: the shortest length is where the rate is zero
        lmin = min(lmin, L0 + 0.5 * r0 * (-r0 / (r1 - r0) * span))
    if not lmin > 0.0:
        raise ValueError(f"winch: the rate ramp {r0:g} -> {r1:g} m/s over {span:g} s would haul in all of the "
                         f"{L0:g} m of cable (the length must stay positive)")
    h = ws.hw * lmin
    rate = cfl / stable_time_step(h) + _coef(_A, P, 2) * max(abs(r0), abs(r1)) / float(np.min(h))
    return 1.0 / rate


def substep(ws, enabled, span, P, cfl, fixed_dt, stable_time_step):
    """Substep for an interval of length span while the winch moves (None when it does not)."""
    lim = limit(ws, enabled, span, P, cfl, stable_time_step)
    if lim is None:
        return None
    if fixed_dt > 0.0:
        if fixed_dt > lim:
            raise UnstableTimeStepError(
                f"dg.fixed_time_step = {fixed_dt:g} s exceeds the stability limit {lim:g} s of the "
                f"shortest length this winch interval reaches")
        return fixed_dt
    return cfl * lim


def snapshot(ws, enabled):
    """The winch's part of a snapshot (length, rates, element sizes)."""
    if not enabled:
        return {}
    return {"winch": (ws.prm[_STATE].copy(), ws.h.copy())}


def restore(ws, snap) -> bool:
    """Back to a snapshot's winch state; returns whether it had one (the driver then follows L)."""
    if "winch" not in snap:
        return False
    vals, h = snap["winch"]
    ws.prm[_STATE] = vals
    ws.h[:] = h
    return True
