"""A winch at one end of the tether: the commanded pay-out rate each tick (pure Python, no ROS).

The winch owns the unstretched length paid out, ``L``, and its rate ``v = dL/dt`` (``v > 0`` pays
out, ``v < 0`` hauls in). Each tick of length ``dt`` it takes the drum-side tension ``T`` (the axial
tension at the winch end, measured at the start of the tick) and returns the rate ``v1`` the solver
must reach at the end of the tick; the solver ramps the rate linearly from ``v0`` to ``v1`` over the
tick (``solver.set_pay_out_rate``), so the length advances by the trapezoid ``(v0 + v1) dt / 2``,
the same rule the winch uses for its own length.

Modes (``winch.mode``, a ``WinchCommand`` or a schedule entry), with the setpoint's unit:

- ``speed`` [m/s]: ``v_des = setpoint``.
- ``length`` [m]: ``v_des = sign(e) min(v_max, sqrt(2 (a_max / 2) |e|), k_L |e|)``, ``e = setpoint - L``:
  a braking profile at half the acceleration limit (so the rate limit never binds while braking)
  ending in a linear approach of rate ``k_L`` (``winch.length_gain``). From rest the discrete loop
  (rate from the error at the start of the tick, trapezoid length) has real positive eigenvalues
  while ``k_L dt < 0.34``, so the length approaches the setpoint monotonically: no overshoot.
- ``tension`` [N]: render / recover: pay out when the drum-side tension is above the setpoint, haul
  in when below. PI on ``e = T_f - setpoint`` (``T_f``: ``T`` through a first-order filter of time
  constant ``winch.tension_filter``): ``v_des = k_p e + I``, ``dI/dt = k_i e``. Anti-windup by
  conditional integration: ``I`` is frozen while a limit cuts the rate in the direction the error
  pushes it. Entering the mode resets ``I`` to 0; the acceleration limit keeps the rate continuous.
  On a span whose tension falls as length is paid out (an elastic or catenary span between fixed
  points, ``dT/dL = -k_c < 0``, e.g. a tether-management system behind a station-keeping vehicle)
  the linear loop is ``e'' + k_c k_p e' + k_c k_i e = 0``: stable for any positive gains. On a
  freely hanging load the quasi-static tension grows with length (``dT/dL = +w``, submerged weight
  per length): the loop ``e' = w k_p e`` diverges, i.e. a constant-tension winch cannot hold a
  hanging load; it lowers it (setpoint below its weight) or lifts it (above) until a length limit.

Limits, applied in this order to ``v_des``: ``|v| <= winch.max_speed``; ``|v1 - v0| <= a_max dt``
(``winch.max_acceleration``); then the length limits, which win over the acceleration limit: the
rate towards a limit is capped by the same braking profile as the length mode (distance to the
limit), and finally by the rate that lands exactly on the limit, so ``min_length <= L <=
max_length`` always holds. The flags of :class:`WinchState` say which limit cut the rate.
"""

import math
from dataclasses import dataclass

import numpy as np

from tether_sim.errors import ConfigError
from tether_sim.physics.boundary import END_NAMES
from tether_sim.spec import param

MODES = ("speed", "length", "tension")
UNITS = {"speed": "m/s", "length": "m", "tension": "N"}


@dataclass(frozen=True)
class WinchConfig:
    """Winch at one end of the tether (tether_sim/physics/winch.py; the length at the start is cable.length)."""

    enabled: bool = param(False, doc="the cable length changes during the run under this winch (solver API set_pay_out_rate)")
    end: str = param("ship", doc="end the winch is at: ship (s = 0, the fairlead) or vehicle (s = L, a tether-management system)", choices=END_NAMES)
    mode: str = param("speed", doc="mode at the start: speed (setpoint m/s, > 0 pays out), length (setpoint m) or tension (setpoint N, drum side)", choices=MODES)
    setpoint: float = param(0.0, unit="m/s, m or N", doc="setpoint of winch.mode at the start (unit by mode)", min=-1e9, max=1e9)
    max_speed: float = param(2.0, unit="m/s", doc="largest pay-out or haul-in speed", min=0.0, max=100.0)
    max_acceleration: float = param(0.5, unit="m/s^2", doc="largest change of the pay-out speed per second", min=1e-6, max=100.0)
    min_length: float = param(1.0, unit="m", doc="shortest unstretched length the winch hauls in to", min=1e-3, max=1e6)
    max_length: float = param(10000.0, unit="m", doc="longest unstretched length the winch pays out to", min=1e-3, max=1e6)
    length_gain: float = param(1.0, unit="1/s", doc="length mode: rate of the final linear approach (keep below 0.34 x node.output_rate for no overshoot)", min=1e-6, max=1000.0)
    tension_kp: float = param(1e-5, unit="m/s/N", doc="tension mode: proportional gain (pay-out speed per newton above the setpoint)", min=0.0, max=1.0)
    tension_ki: float = param(1e-6, unit="m/s^2/N", doc="tension mode: integral gain", min=0.0, max=1.0)
    tension_filter: float = param(0.0, unit="s", doc="tension mode: time constant of the first-order filter on the measured tension (0: none)", min=0.0, max=1e3)
    schedule_times: tuple = param((), unit="s", doc="schedule: times (from the start of the run, non-decreasing) at which the entries below take over")
    schedule_modes: tuple[str, ...] = param((), doc="schedule: mode of each entry (speed, length, tension)")
    schedule_setpoints: tuple = param((), unit="m/s, m or N", doc="schedule: setpoint of each entry (unit by mode)")

    def __post_init__(self):
        if self.min_length >= self.max_length:
            raise ConfigError(f"winch.min_length {self.min_length} m must be below winch.max_length {self.max_length} m")
        n = len(self.schedule_times)
        if len(self.schedule_modes) != n or len(self.schedule_setpoints) != n:
            raise ConfigError(f"winch.schedule_times, schedule_modes and schedule_setpoints are parallel arrays: got "
                              f"{n}, {len(self.schedule_modes)} and {len(self.schedule_setpoints)} entries")
        times = list(self.schedule_times)
        if any(t < 0.0 for t in times) or any(b < a for a, b in zip(times, times[1:])):
            raise ConfigError(f"winch.schedule_times must be >= 0 and non-decreasing, got {times}")
        problems = [f"entry {i} ({t} s): {why}" for i, (t, m, s) in
                    enumerate(zip(times, self.schedule_modes, self.schedule_setpoints))
                    if (why := command_problem(self, m, s)) is not None]
        if self.mode in MODES and (why := command_problem(self, self.mode, self.setpoint)) is not None:
            problems.insert(0, f"winch.mode/winch.setpoint: {why}")
        if problems:
            raise ConfigError("winch: " + "; ".join(problems))


def command_problem(cfg: WinchConfig, mode: str, setpoint: float):
    """Why (mode, setpoint) is not a valid winch command under ``cfg``, or None."""
    if mode not in MODES:
        return f"mode {mode!r} is not one of {', '.join(MODES)}"
    try:
        setpoint = float(setpoint)
    except (TypeError, ValueError):
        return f"setpoint {setpoint!r} is not a number"
    if not math.isfinite(setpoint):
        return f"setpoint {setpoint} is not finite"
    if mode == "speed" and abs(setpoint) > cfg.max_speed:
        return f"speed setpoint {setpoint:g} m/s exceeds winch.max_speed {cfg.max_speed:g} m/s"
    if mode == "length" and not cfg.min_length <= setpoint <= cfg.max_length:
        return (f"length setpoint {setpoint:g} m is outside [winch.min_length, winch.max_length] = "
                f"[{cfg.min_length:g}, {cfg.max_length:g}] m")
    if mode == "tension" and setpoint < 0.0:
        return f"tension setpoint {setpoint:g} N is negative (a cable cannot push)"
    return None


@dataclass
class WinchState:
    """What the winch reports (SI units; flags: which limit cut the rate in the last tick)."""

    time: float  # s, run time of this state
    length: float  # unstretched length paid out, m
    speed: float  # pay-out rate dL/dt, m/s (> 0 pays out)
    commanded_speed: float  # v_des of the mode before the limits, m/s
    tension: float  # drum-side tension last measured, N
    mode: str
    setpoint: float
    speed_limited: bool = False
    acceleration_limited: bool = False
    at_min_length: bool = False
    at_max_length: bool = False


class Schedule:
    """The ``winch.schedule_*`` entries: (time, mode, setpoint), taken in order."""

    def __init__(self, cfg: WinchConfig):
        self.entries = list(zip(cfg.schedule_times, cfg.schedule_modes, cfg.schedule_setpoints))
        self.next = 0  # index of the next entry to apply

    def due(self, t: float) -> list:
        """The entries whose time is <= t and not yet applied (in order)."""
        out = []
        while self.next < len(self.entries) and self.entries[self.next][0] <= t + 1e-12:
            out.append(self.entries[self.next])
            self.next += 1
        return out


def static_end_tensions(forces, upper: int, weight_per_length: float, paid_out: float) -> tuple:
    """Static end tensions (ship, vehicle) after ``paid_out`` metres (negative: hauled in) of cable
    were added to a static state whose end forces (by the cable on each end, world frame, N) are
    ``forces`` (2, 3). The added cable's weight in water, w x paid_out, is carried by the ``upper``
    end (0 ship, 1 vehicle) as vertical force; the horizontal forces and the other end are kept:

        T_upper = sqrt(H^2 + (|F_z| + w x paid_out)^2),   T_other unchanged.

    Exact for a cable hanging a load that is free to move (the ROV or cage below the ship, in still
    water: H = 0 and T = W_load + w L at the top); with a fixed far end or a current it is the
    first-order estimate (the added weight changes the shape, hence H, only at second order)."""
    f = np.asarray(forces, float).reshape(2, 3)
    out = [float(np.linalg.norm(f[0])), float(np.linalg.norm(f[1]))]
    h = math.hypot(f[upper, 0], f[upper, 1])
    v = max(abs(f[upper, 2]) + weight_per_length * paid_out, 0.0)
    out[upper] = math.hypot(h, v)
    return out[0], out[1]


def braking_speed(distance: float, max_speed: float, max_acceleration: float, gain: float) -> float:
    """Largest speed towards a point ``distance`` away (>= 0): min(v_max, sqrt(a_max d), k d)
    (braking at a_max / 2, then the linear approach)."""
    d = max(distance, 0.0)
    return min(max_speed, math.sqrt(max_acceleration * d), gain * d)


class Winch:
    """The winch controller and its state (see the module docstring)."""

    def __init__(self, cfg: WinchConfig, length: float, time: float = 0.0):
        if not cfg.min_length <= length <= cfg.max_length:
            raise ConfigError(f"cable.length {length:g} m (the winch's length at the start) is outside "
                              f"[winch.min_length, winch.max_length] = [{cfg.min_length:g}, {cfg.max_length:g}] m")
        self.cfg = cfg
        self.time = float(time)
        self.length = float(length)
        self.speed = 0.0
        self.commanded_speed = 0.0
        self.tension = math.nan  # drum-side tension, N (unknown until the first tick)
        self.filtered = math.nan  # T_f
        self.integral = 0.0  # I of the PI, m/s
        self.flags = dict(speed_limited=False, acceleration_limited=False, at_min_length=False, at_max_length=False)
        self.mode, self.setpoint = "speed", 0.0
        self.command(cfg.mode, cfg.setpoint)

    # ------------------------------------------------------------------ commands
    def command(self, mode: str, setpoint: float):
        """Switch to (mode, setpoint); returns None, or the reason the command was refused."""
        problem = command_problem(self.cfg, mode, setpoint)
        if problem is not None:
            return problem
        if mode == "tension" and self.mode != "tension":
            self.integral = 0.0
        self.mode, self.setpoint = mode, float(setpoint)
        return None

    # ------------------------------------------------------------------ stepping
    def step(self, dt: float, tension: float) -> float:
        """Advance the winch by ``dt`` s given the drum-side ``tension`` [N] at the start of the tick;
        returns the pay-out rate at the end of the tick (the solver ramps to it linearly)."""
        if not dt > 0.0:
            return self.speed
        cfg, v0, length0 = self.cfg, self.speed, self.length
        self._measure(dt, tension)
        v_des = self._desired(dt)
        v = min(max(v_des, -cfg.max_speed), cfg.max_speed)
        speed_limited = v != v_des
        a_dv = cfg.max_acceleration * dt
        v_acc = min(max(v, v0 - a_dv), v0 + a_dv)
        accel_limited = v_acc != v
        v = self._length_limits(v_acc, v0, dt)
        at_max = v < v_acc or (v >= 0.0 and self.length >= cfg.max_length - 1e-9)
        at_min = v > v_acc or (v <= 0.0 and self.length <= cfg.min_length + 1e-9)
        if self.mode == "tension":
            self._integrate(dt, v_des, v)
        self.speed, self.commanded_speed = v, v_des
        self.length = min(max(length0 + 0.5 * (v0 + v) * dt, cfg.min_length), cfg.max_length)
        self.time += dt
        self.flags = dict(speed_limited=speed_limited, acceleration_limited=accel_limited,
                          at_min_length=at_min, at_max_length=at_max)
        return v

    def _measure(self, dt, tension):
        tension = float(tension)
        if math.isfinite(tension):
            self.tension = tension
            tau = self.cfg.tension_filter
            if tau <= 0.0 or not math.isfinite(self.filtered):
                self.filtered = tension
            else:
                self.filtered += (tension - self.filtered) * dt / (tau + dt)  # backward Euler

    def _desired(self, dt):
        cfg = self.cfg
        if self.mode == "speed":
            return self.setpoint
        if self.mode == "length":
            e = self.setpoint - self.length
            return math.copysign(braking_speed(abs(e), cfg.max_speed, cfg.max_acceleration, cfg.length_gain), e)
        if not math.isfinite(self.filtered):
            return self.speed  # no tension measured yet: hold the current rate
        return cfg.tension_kp * (self.filtered - self.setpoint) + self.integral

    def _integrate(self, dt, v_des, v):
        """Conditional integration: frozen while a limit cuts the rate in the direction e pushes it."""
        if not math.isfinite(self.filtered):
            return
        e = self.filtered - self.setpoint
        cut = v_des - v
        if cut == 0.0 or (cut > 0.0) != (e > 0.0):
            self.integral += self.cfg.tension_ki * e * dt

    def _length_limits(self, v, v0, dt):
        """Cap the rate towards a length limit (braking profile, then exact landing on the limit)."""
        cfg, L = self.cfg, self.length
        cap_out = braking_speed(cfg.max_length - L, cfg.max_speed, cfg.max_acceleration, cfg.length_gain)
        cap_in = braking_speed(L - cfg.min_length, cfg.max_speed, cfg.max_acceleration, cfg.length_gain)
        v = min(max(v, -cap_in), cap_out)
        land_out = 2.0 * (cfg.max_length - L) / dt - v0  # the v that ends the tick exactly on a limit
        land_in = 2.0 * (cfg.min_length - L) / dt - v0
        return min(max(v, land_in), land_out)

    def observe_length(self, length: float) -> None:
        """The solver's unstretched length after a tick (the solver is the truth)."""
        self.length = float(length)

    def state(self) -> WinchState:
        return WinchState(self.time, self.length, self.speed, self.commanded_speed, self.tension, self.mode,
                          self.setpoint, **self.flags)

    def snapshot(self) -> dict:
        return dict(self.__dict__, flags=dict(self.flags))

    def restore(self, snap: dict) -> None:
        self.__dict__.update(snap)
        self.flags = dict(snap["flags"])
