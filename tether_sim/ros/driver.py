"""The stepping core shared by the ROS node and the offline runner (imports no rclpy).

Clock mapping: a solver time ``t_sim`` corresponds to the clock time ``anchor + t_sim`` (node clock:
wall time, /clock, or the stamps of an input recording). Each :meth:`SimulationDriver.tick` advances
the solver towards ``now - node.input_delay - anchor`` (the small delay lets pose inputs be
interpolated between samples instead of extrapolated):

1. If the clock went backwards (a replay loop), the pose histories are reset and the anchor moves
   so that the simulation continues from its current state (reported as a clock jump).
2. If the lag ``now - anchor - t_sim`` exceeds ``node.max_lag``, the excess is dropped by moving the
   anchor (the simulation skips that stretch of clock time; reported).
3. At most ``node.max_substeps_per_tick`` stable substeps are taken, and (node only) no more than
   fit in ``wall_budget`` seconds at the measured cost per substep, so one tick never blocks the
   caller for long; the remaining lag carries over to the next tick (reported).
4. Prescribed ends get the attachment position/velocity at the target time from their source
   (a validated pose input, an analytic motion, or their fixed configured position).
   If an end would move faster than ``node.max_end_speed`` (a held end whose input appears far
   away), the solver restarts from a static equilibrium at the new positions (reported).
5. A :class:`SolverDivergedError` is caught: the last good snapshot is restored (or, if that fails
   again from the same snapshot, the solver is rebuilt from a fresh static equilibrium at the
   current end positions); the anchor moves so the lost time is skipped; the error is reported.
6. The end tensions of every substep go through the streaming snap detector.
"""

import time as wallclock
from dataclasses import dataclass, field, replace

import numpy as np

from tether_sim.errors import SolverDivergedError
from tether_sim.physics.snap import SnapDetector, SnapEvent, SlackStarted
from tether_sim.solvers.factory import build_solver

END_NAMES = ("ship", "vehicle")


@dataclass
class TickReport:
    """What one tick did (for diagnostics and logs)."""

    stamp: float  # clock time of the state after the tick, s
    substeps: int = 0
    lag: float = 0.0  # clock time still to simulate after the tick, s
    capped: bool = False  # the substep cap stopped the tick short of its target
    dropped: float = 0.0  # clock time skipped by re-anchoring this tick, s
    clock_jump: bool = False
    events: list = field(default_factory=list)  # SlackStarted / SnapEvent
    error: str | None = None  # divergence message, if any
    recovery: str | None = None  # "snapshot" or "static"
    restart: str | None = None  # why the solver was restarted at new end positions


class MotionSource:
    """A prescribed end driven by an analytic motion ``motion.at(t) -> (position, velocity, ...)``."""

    def __init__(self, motion):
        self.motion = motion

    def attachment_at(self, t):
        result = self.motion.at(t)
        return np.asarray(result[0], float), np.asarray(result[1], float)

    def orientation_at(self, t):
        return np.array([0.0, 0.0, 0.0, 1.0])


class SimulationDriver:
    """Owns the solver, the clock mapping, recovery and the snap detector."""

    def __init__(self, config, sources: dict | None = None, *, solver_factory=build_solver, wall_budget=None):
        self.config = config
        self.sources = dict(sources or {})  # end -> EndPoseInput | MotionSource (prescribed ends)
        self.solver_factory = solver_factory
        self.solver = None
        self.wall_budget = wall_budget  # s of wall time one tick may spend stepping (None: no limit)
        self.wall_per_substep = 0.0
        self._ticks_advanced = 0
        self._solver_config = config
        self._commanded = {}
        self._last_position = {}
        self.anchor = 0.0
        self.last_now = None
        self.divergences = 0
        self.dropped_total = 0.0
        self.capped_ticks = 0
        self.last_error = None
        self.last_recovery = None  # "snapshot" or "static" after a divergence
        self._snapshot = None
        self._snapshot_time = -np.inf
        self._snapshot_failed = False
        self._substep = 0.0  # the solver's stable substep, s (re-read at each snapshot)
        self.real_time_factor = 0.0
        self._last_wall = None
        self.static_tensions = (0.0, 0.0)
        self.detector = self.span_detector = None
        self.slack = {"ship": False, "vehicle": False}
        self.static_by_location = {}
        self.span_arc = np.zeros(0)

    # ------------------------------------------------------------------ set-up
    def _prescribed(self, end):
        return getattr(self.config, f"{end}_end").kind == "prescribed"

    def _start_config(self, now):
        """The configuration with prescribed end positions taken from their sources at ``now``."""
        cfg = self.config
        for end in END_NAMES:
            src = self.sources.get(end)
            if self._prescribed(end) and src is not None and getattr(src, "has_data", True):
                p, _ = src.attachment_at(now)
                cond = getattr(cfg, f"{end}_end")
                cfg = replace(cfg, **{f"{end}_end": replace(cond, position=tuple(float(x) for x in p))})
        return cfg

    def start(self, now: float) -> None:
        """Build the solver (static equilibrium at the current end positions) at clock time ``now``
        (minus ``node.input_delay``)."""
        now -= self.config.node.input_delay
        self._solver_config = self._start_config(now)
        self._commanded = {}
        self._last_position = {}
        self.solver = self.solver_factory(self._solver_config)
        self.anchor = now - self.solver.time
        self.last_now = now
        self._last_wall = wallclock.perf_counter()
        forces = self.solver.end_forces()
        self.static_tensions = (float(forces.ship_tension), float(forces.vehicle_tension))
        self.solver.drain_end_tensions()
        self._build_detector()
        self._take_snapshot()

    def _build_detector(self):
        """Ends: every substep (drained end tensions). Span points (``snap.monitor_arc_lengths``):
        sampled once per tick from the state, so their peaks are resolved at the output rate only."""
        L = self.config.cable.length
        self.detector = SnapDetector(self.config.snap, list(END_NAMES), list(self.static_tensions), [0.0, L])
        self.slack = {end: False for end in END_NAMES}
        self.static_by_location = dict(zip(END_NAMES, self.static_tensions))
        self.span_arc = np.array([s for s in self.config.snap.monitor_arc_lengths if 0.0 < s < L], float)
        self.span_detector = None
        if self.span_arc.size:
            names = [f"span s={s:g} m" for s in self.span_arc]
            static = self.solver.state(self.span_arc).tension
            self.span_detector = SnapDetector(self.config.snap, names, list(static), list(self.span_arc))
            self.static_by_location.update(zip(names, (float(x) for x in static)))
            self.slack.update({name: False for name in names})

    def set_snap_config(self, snap_config) -> None:
        """Live change of the snap thresholds (slack state kept)."""
        self.config = replace(self.config, snap=snap_config)
        for detector in (self.detector, self.span_detector):
            if detector is not None:
                detector.set_config(snap_config)

    def _take_snapshot(self):
        # (the substep is re-read here, not every tick: it only sizes the substep cap)
        self._substep = self.solver.stable_time_step()
        self._snapshot = self.solver.snapshot()
        self._snapshot_time = self.solver.time
        self._snapshot_failed = False

    # ------------------------------------------------------------------ stepping
    def end_target(self, end, clock_time):
        """(position, velocity) of a prescribed end at a clock time; held at rest without input."""
        src = self.sources.get(end)
        if src is None or not getattr(src, "has_data", True):
            held = self._commanded.get(end)
            if held is None:
                held = np.asarray(getattr(self._solver_config, f"{end}_end").position, float)
            return held, np.zeros(3)
        p, v = src.attachment_at(clock_time)
        self._commanded[end] = p
        return p, v

    def tick(self, now: float) -> TickReport:
        """Advance towards clock time ``now`` under the policy of the module docstring."""
        if self.solver is None:
            self.start(now)
        now -= self.config.node.input_delay  # simulate the past, where the inputs are known
        report = TickReport(stamp=self.stamp)
        if self.last_now is not None and now < self.last_now:
            report.clock_jump = True
            for src in self.sources.values():
                if hasattr(src, "reset"):
                    src.reset()
            self.anchor = now - self.solver.time
        self.last_now = now
        node = self.config.node
        lag = now - self.anchor - self.solver.time
        if lag > node.max_lag:
            report.dropped = lag - node.max_lag
            self.anchor += report.dropped
            self.dropped_total += report.dropped
        target = now - self.anchor
        if target <= self.solver.time:
            report.lag = max(0.0, target - self.solver.time)
            return report
        max_steps = node.max_substeps_per_tick
        if self.wall_budget is not None and self.wall_per_substep > 0.0:
            max_steps = min(max_steps, max(1, int(self.wall_budget / self.wall_per_substep)))
        cap = self.solver.time + max_steps * self._substep
        if target > cap:
            target, report.capped = cap, True
            self.capped_ticks += 1
        t0, wall0 = self.solver.time, wallclock.perf_counter()
        targets = {end: self.end_target(end, self.anchor + target) for end in END_NAMES if self._prescribed(end)}
        held = {end: self._last_position.get(end) for end in targets}
        self._last_position = {end: p for end, (p, _) in targets.items()}
        for end, (position, _) in targets.items():
            # (time dropped by re-anchoring counts: the end really moved during the skipped time)
            reach = node.max_end_speed * (target - t0 + report.dropped) + 1e-6
            if held[end] is not None and np.linalg.norm(position - held[end]) > reach:
                # an end that was held (no input) got its first pose far away: restart there
                report.restart = f"{end} end moved {np.linalg.norm(position - held[end]):.3g} m in one tick"
                self._rebuild(now)
                report.stamp = self.stamp
                return report
        for end, (position, velocity) in targets.items():
            self.solver.set_end_motion(end, position, velocity)
        try:
            report.substeps = self.solver.advance_to(target)
        except SolverDivergedError as exc:
            self._recover(now, str(exc), report)
            return report
        self._update_rate(self.solver.time - t0, wall0)
        if report.substeps > 0 and self._ticks_advanced > 0:  # the first advance includes JIT compiling
            cost = (wallclock.perf_counter() - wall0) / report.substeps
            self.wall_per_substep = cost if self.wall_per_substep == 0.0 else 0.7 * self.wall_per_substep + 0.3 * cost
        self._ticks_advanced += 1
        times, t_ship, t_vehicle = self.solver.drain_end_tensions()
        if len(times):
            report.events = self.detector.update(np.asarray(times) + self.anchor,
                                                 np.column_stack([t_ship, t_vehicle]))
        if self.span_detector is not None:
            tension = self.solver.state(self.span_arc).tension
            report.events += self.span_detector.update(np.array([self.stamp]), np.asarray(tension, float).reshape(1, -1))
        for ev in report.events:
            self.slack[ev.location] = isinstance(ev, SlackStarted)
        if self.solver.time - self._snapshot_time >= node.snapshot_interval:
            self._take_snapshot()
        report.stamp = self.stamp
        report.lag = now - report.stamp
        return report

    def _update_rate(self, sim_advance, wall0):
        wall = wallclock.perf_counter()
        elapsed = wall - (self._last_wall if self._last_wall is not None else wall0)
        self._last_wall = wall
        if elapsed > 0:
            self.real_time_factor = sim_advance / elapsed

    def _recover(self, now, message, report):
        """Restore the last good snapshot, or rebuild from a static equilibrium (see module doc)."""
        self.divergences += 1
        self.last_error = message
        self.last_recovery = None
        report.error = message
        if self._snapshot is not None and not self._snapshot_failed:
            self.solver.restore(self._snapshot)
            self._snapshot_failed = True  # a second divergence before a new snapshot -> rebuild
            report.recovery = self.last_recovery = "snapshot"
            self.solver.drain_end_tensions()
            self.anchor = now - self.solver.time
        else:
            self._rebuild(now)
            report.recovery = self.last_recovery = "static"
        self._build_detector()
        report.stamp = self.stamp

    def _rebuild(self, now):
        """A fresh solver (static equilibrium) at the current end positions, clock ``now``."""
        self._solver_config = self._start_config(now)
        self.solver = self.solver_factory(self._solver_config)
        self.solver.drain_end_tensions()
        self.anchor = now - self.solver.time
        self._last_position = {}
        forces = self.solver.end_forces()
        self.static_tensions = (float(forces.ship_tension), float(forces.vehicle_tension))
        self._build_detector()
        self._take_snapshot()

    # ------------------------------------------------------------------ queries
    @property
    def stamp(self) -> float:
        """Clock time of the current solver state."""
        return self.anchor + (self.solver.time if self.solver is not None else 0.0)

    def offset(self, end):
        """Attachment offset in the body frame of an end: ``body.attachment`` (from the centre of
        gravity) for a simulated body, else ``node.ship_attachment`` / ``node.vehicle_attachment``."""
        if getattr(self.config, f"{end}_end").kind == "body":
            return self.config.body.attachment
        return getattr(self.config.node, f"{end}_attachment")

    def end_orientation(self, end, body=None):
        """Quaternion (x, y, z, w) of the body frame of an end at the current state: a simulated
        body's own (``body``: its BodyState if the caller already has it), a pose input's
        interpolated one, otherwise aligned with the world."""
        if getattr(self.config, f"{end}_end").kind == "body":
            body = body if body is not None else self.solver.body_state(end)
            if body is not None:
                return np.asarray(body.orientation, float)
        src = self.sources.get(end)
        if src is not None and getattr(src, "has_data", True):
            return np.asarray(src.orientation_at(self.stamp), float)
        return np.array([0.0, 0.0, 0.0, 1.0])

    def body_wrench(self, end, forces, body=None):
        """Force and torque BY the tether ON the body of ``end``, in its body frame, about its origin
        (``body``: the BodyState of a simulated body end, if the caller already has it):
        ``f = R^T F``, ``torque = r x f + R^T M`` (world force F and moment M, offset r)."""
        q = self.end_orientation(end, body).tolist()
        f = _to_body(q, getattr(forces, f"{end}_force"))
        m = _to_body(q, getattr(forces, f"{end}_moment"))
        (rx, ry, rz), (fx, fy, fz) = self.offset(end), f
        return np.array(f), np.array([ry * fz - rz * fy + m[0], rz * fx - rx * fz + m[1], rx * fy - ry * fx + m[2]])


def _to_body(q, v):
    """``R(q)^T v`` for a unit quaternion (x, y, z, w) and a 3-vector, in plain floats (a few
    microseconds instead of tens for the numpy version with its small-array overheads)."""
    x, y, z, w = q
    a, b, c = (float(e) for e in v)
    return ((1 - 2 * (y * y + z * z)) * a + 2 * (x * y + z * w) * b + 2 * (x * z - y * w) * c,
            2 * (x * y - z * w) * a + (1 - 2 * (x * x + z * z)) * b + 2 * (y * z + x * w) * c,
            2 * (x * z + y * w) * a + 2 * (y * z - x * w) * b + (1 - 2 * (x * x + y * y)) * c)


__all__ = ["SimulationDriver", "TickReport", "MotionSource", "SnapEvent", "SlackStarted"]
