"""Input handling of :class:`tether_sim.ros.driver.SimulationDriver`: what each prescribed end is told.

The driver's policy (module doc of ``driver.py``, point 4): a prescribed end follows its source (a
validated pose input, an analytic motion or its fixed configured position); when the source falls
silent, resumes, or the simulation jumps (re-synchronisation, recovery, start from rest), the end is
moved by a C2 blend from its held trajectory onto the stream (:class:`Blend`, :func:`blend_time`),
and snap detection is suspended until the blend ends. An end that never had an input and whose
first pose lies beyond what ``node.max_end_speed`` allows restarts the solver there
(:meth:`EndCommands._first_pose_far`).

:class:`EndCommands` is a mixin of the drivers (the single-line driver's ends, the network driver's
driven points): it reads and writes the driver's end state (``sources``, ``_end_state``, ``_held``,
``_blends``, ``_hold_at``, ``_suspended_until``, ``catchup``, ``bridges``, ``stamp``,
``end_speed_limit``; the single-line driver's first-pose check also ``_had_input``, ``solver``,
``config``, ``_solver_config``) and holds none of its own. No rclpy here.
"""

import math
from dataclasses import dataclass

import numpy as np

BLEND_ACCELERATION = 0.5  # m/s^2 a blend onto a pose stream may add to the end's own motion
BLEND_MIN_TIME = 0.5  # s, shortest blend
# m: a pose stream revised by more than this where the end already is (extrapolation overtaken by
# samples) is blended onto. Stepping onto it within one 20 ms chunk adds about 1.5 d / 20 ms of end
# speed: 0.075 m/s for 1 mm, a 0.9 kN front on the ROPOS tether (Z = 11.7 kN s/m), 2 % of its static tension.
REVISION_TOLERANCE = 1e-3


@dataclass
class Blend:
    """A C1 blend of one end from its held trajectory onto the pose stream (module doc, 4)."""

    t0: float  # clock time of the start
    duration: float  # s
    p0: np.ndarray
    v0: np.ndarray
    reason: str
    suspends: bool = True  # snap detection is suspended while it runs (not after a re-synchronisation)

    def command(self, t, p_s, v_s):
        """(position, velocity, finished) at clock time ``t`` given the stream's (p_s, v_s)."""
        tau = t - self.t0
        h, dh = self.p0 + self.v0 * tau, self.v0
        w, dw, finished = quintic(tau, self.duration)
        return h + w * (p_s - h), dh + w * (v_s - dh) + dw * (p_s - h), finished


def quintic(tau, duration):
    """(w, dw/dt, finished) of the blend weight ``w = 10u^3 - 15u^4 + 6u^5``, ``u = tau / duration``
    clipped to [0, 1]."""
    u = min(max(tau / duration, 0.0), 1.0)
    return u ** 3 * (10.0 + u * (6.0 * u - 15.0)), 30.0 * (u * (1.0 - u)) ** 2 / duration, u >= 1.0


def blend_time(distance, speed_change, max_end_speed):
    """Blend duration (s) for an offset ``distance`` (m) and velocity change (m/s). The weight is
    the quintic ``w = 10u^3 - 15u^4 + 6u^5`` (zero slope and curvature at both ends, so the blend
    adds no acceleration step: C2 where the stream is); the blend term of the acceleration,
    ``w'' d / T^2 + 2 w' dv / T`` (max |w''| = 10/sqrt(3), max |w'| = 15/8), is kept under
    ``BLEND_ACCELERATION`` (half each) and its speed ``15/8 d / T`` under half of
    ``max_end_speed``; at least ``BLEND_MIN_TIME``."""
    d, dv = float(distance), float(speed_change)
    return max(BLEND_MIN_TIME, math.sqrt(20.0 / math.sqrt(3.0) * d / BLEND_ACCELERATION),
               7.5 * dv / BLEND_ACCELERATION, 3.75 * d / max(max_end_speed, 1e-9))


class MotionSource:
    """A prescribed end driven by an analytic motion ``motion.at(t) -> (position, velocity, ...)``."""

    time_base = "clock"  # the motion is a function of the clock (solver time + the driver's anchor)
    has_data = True  # always (the network driver asks; the single-line code takes a missing one as True)

    def __init__(self, motion):
        self.motion = motion

    def attachment_at(self, t):
        # (a generator's position_velocity: at()'s first two, the same numbers, without the acceleration)
        pv = getattr(self.motion, "position_velocity", None)
        result = pv(t) if pv is not None else self.motion.at(t)
        return np.asarray(result[0], float), np.asarray(result[1], float)

    def orientation_at(self, t):
        return np.array([0.0, 0.0, 0.0, 1.0])


class SolverTimeMotion(MotionSource):
    """An analytic motion evaluated at solver time (clock time minus the driver's anchor; 0 before the
    solver starts): the node's RAO ship (motion.kind rao), so the ship and the waves on the cable, which
    the solver evaluates at its own time, follow the same sea across re-synchronisations."""

    time_base = "solver"

    def __init__(self, motion, driver):
        super().__init__(motion)
        self._driver = driver  # callable returning the SimulationDriver (None while it is being built)

    def attachment_at(self, t):
        d = self._driver()
        tau = t - d.anchor if d is not None and d.solver is not None else 0.0
        return super().attachment_at(tau)


class EndCommands:
    """End commands and blends of :class:`~tether_sim.ros.driver.SimulationDriver` (module doc)."""

    def _prescribed(self, end):
        return getattr(self.config, f"{end}_end").kind == "prescribed"

    def _has_data(self, end):
        src = self.sources.get(end)
        return src is not None and getattr(src, "has_data", True)

    def end_target(self, end, clock_time):
        """(position, velocity) of a prescribed end's source at a clock time (no blend); held at
        rest at its last commanded (else configured) position without input."""
        src = self.sources.get(end)
        if src is None or not getattr(src, "has_data", True):
            held = self._hold_at.get(end, self._end_state.get(end, (None,))[0])
            if held is None:
                held = np.asarray(getattr(self._solver_config, f"{end}_end").position, float)
            return np.asarray(held, float), np.zeros(3)
        p, v = src.attachment_at(clock_time)
        return np.asarray(p, float), np.asarray(v, float)

    def _start_blend(self, end, t, reason, report, probe=None, suspend=True):
        """Blend ``end`` from its current commanded state at clock time ``t`` onto its source
        (sized by the offset to the source at ``probe``, default ``t``; it replaces the end's blend and
        catch-up offsets, which its start includes); ``suspend``: snap detection is suspended until
        the blend ends, else it goes on and the blend is recorded as a bridge (an event overlapping it
        is published as degraded). Returns the blend's duration (0: none needed)."""
        if end not in self._end_state or self.sources.get(end) is None:
            return 0.0
        p0, v0 = self._end_state[end]  # the end's state at t: where the blend starts
        p_s, v_s = self.end_target(end, t if probe is None else probe)
        ahead = p0 + v0 * (0.0 if probe is None else probe - t)  # the held trajectory at the probe (sizing only)
        distance, speed_change = np.linalg.norm(p_s - ahead), np.linalg.norm(v_s - v0)
        if distance < 1e-9 and speed_change < 1e-9:
            return 0.0  # already on the stream
        duration = blend_time(distance, speed_change, self.end_speed_limit)
        self._blends[end] = Blend(t, duration, p0.copy(), v0.copy(), reason, suspend)
        self.catchup.clear(end)
        report.blends.append((end, duration, reason))
        if suspend:
            self._suspend_detection(t + duration)
        else:
            self.bridges.add(t, t + duration)
        return duration

    def _command(self, end, t, report):
        """(position, velocity) commanded for ``end`` at clock time ``t`` (blends applied); starts a
        blend when a held input gets motion again."""
        src = self.sources.get(end)
        held = src is None or not getattr(src, "has_data", True) or \
            (hasattr(src, "is_held") and src.is_held(t))
        was_held = self._held.get(end, False)
        if was_held != held and (not held or self._has_data(end)):  # (replaces a running blend)
            after_jump = not held and self._hold_at.pop(end, None) is not None
            if after_jump and not self._hold_at:
                self._suspended_until = None  # resumed after a clock jump: suspended until this blend ends
            # resumed: blend onto the stream; lost: blend from the motion to rest at the held point. The
            # cable state and its clock run on through both: snap detection goes on (a slack period is
            # not dropped), the blend is a bridge; only the resume after a clock jump (the detector's
            # clock broke there) keeps detection suspended until its blend ends
            self._start_blend(end, self.stamp, "input lost" if held else "input resumed", report, t,
                              suspend=after_jump)
        self._held[end] = held
        if (not held and end not in self._blends and not self.catchup.active(end) and end in self._end_state
                and hasattr(src, "is_held")):
            self._blend_if_revised(end, t, report)
        return self._commanded(end, t)

    def _commanded(self, end, t, drop=True):
        """(position, velocity) of ``end`` at clock time ``t``: its source, its blend, the catch-up
        offsets of re-synchronisations (tether_sim/ros/bridging.py); ``drop``: finished ones are removed."""
        p, v = self.end_target(end, t)
        blend = self._blends.get(end)
        if blend is not None:
            p, v, finished = blend.command(t, p, v)
            if finished and drop:
                del self._blends[end]
        return self.catchup.apply(end, t, p, v, drop)

    def _blend_if_revised(self, end, t, report):
        """A pose input's stream can change where it was already followed: the end was extrapolated
        past the newest sample (or a newest knot was replaced) and the samples that came since say
        otherwise. Where the stream at the chunk's start lies more than ``REVISION_TOLERANCE`` from the
        end's commanded position there, the end is blended onto it, not stepped within one chunk."""
        t0 = self.stamp
        covers = getattr(self.sources.get(end), "covers", None)
        if covers is not None and not covers(t0):
            return  # (a flood shortened the history: the stream before its oldest sample is a placeholder)
        d = self.end_target(end, t0)[0] - self._end_state[end][0]
        if math.sqrt(float(d.dot(d))) > REVISION_TOLERANCE:  # (np.linalg.norm's own sum, without its wrapper)
            self._start_blend(end, t0, "input revised", report, t, suspend=False)

    def _hold_after_jump(self, end, now, report):
        """The clock jumped back and the end's pose history is gone (its stamps are of the old
        clock): bring the end to rest smoothly (a blend from its current motion onto a fixed point
        ahead of it, at most BLEND_ACCELERATION) instead of stopping it dead, and suspend snap
        detection until the input resumes and its blend back onto the stream ends (driver.py's module doc, 1)."""
        if end not in self._end_state:
            return
        p0, v0 = self._end_state[end]
        speed, limit = float(np.linalg.norm(v0)), self.end_speed_limit
        duration = blend_time(0.5 * speed * blend_time(0.0, speed, limit), speed, limit)
        self._hold_at[end] = p0 + 0.5 * duration * v0  # where the decelerating end comes to rest
        reason = "clock jumped back: held until the input resumes"
        self._blends[end] = Blend(now, duration, p0.copy(), v0.copy(), reason)
        report.blends.append((end, duration, reason))
        self._suspend_detection(np.inf)  # released when the input resumes (EndCommands._command)

    def _suspend_detection(self, until):
        self._suspended_until = until if self._suspended_until is None else max(self._suspended_until, until)

    def _first_pose_far(self, t_clock, chunk, report) -> bool:
        """An end that never had an input whose first pose lies beyond what ``max_end_speed``
        allows in this step: its held position was a placeholder, restart there (module doc, 4)."""
        for end in list(self._end_state):
            if self._had_input.get(end, True) or not self._has_data(end):
                continue
            self._had_input[end] = True
            position = self.end_target(end, t_clock)[0]
            held = self._end_state.get(end, (None,))[0]
            reach = self.config.node.max_end_speed * max(chunk - self.solver.time, 1.0 / self.config.node.output_rate)
            if held is not None and np.linalg.norm(position - held) > reach + 1e-6:
                report.restart = f"{end} end's first pose is {np.linalg.norm(position - held):.3g} m from its placeholder"
                self._blends.pop(end, None)
                self.catchup.clear(end)
                return True
        return False
