"""The stepping core shared by the ROS node and the offline runner (imports no rclpy).

Clock mapping: a solver time ``t_sim`` corresponds to the clock time ``anchor + t_sim`` (node clock:
wall time, /clock, or the stamps of an input recording). Each :meth:`SimulationDriver.tick` advances
the solver towards ``now - node.input_delay - anchor`` (the small delay lets pose inputs be
interpolated between samples instead of extrapolated). Overload policy (docs/node.md): the
simulation never squeezes motion in time and never invents a snap from a discontinuity.

1. If the clock went backwards (a replay loop), the pose histories are reset and the anchor moves
   so that the simulation continues from its current state (reported as a clock jump).
2. Falling behind: simulated time may lag the clock. The ends are always driven with their pose
   history evaluated at the simulated instant (never at the clock), outputs carry the simulated
   instant as stamp, and ``lag`` / ``degraded`` say how late they are. Only when the lag exceeds
   ``node.max_lag`` does the driver re-synchronise: the anchor moves so that the simulated instant
   is the newest input time, the cable keeps its current state, and every prescribed end keeps its
   commanded motion and catches up with its stream by a decaying offset that ends on its own
   (tether_sim/ros/bridging.py; running blends keep their progress), so that re-synchronisations
   faster than blends finish cannot let an end coast away (reported).
3. Each tick steps in chunks: at most ``node.max_substeps_per_tick`` substeps, and (node only) no
   more than fit in ``wall_budget`` seconds of wall time at the measured cost per substep; while
   that cost is unknown (the first tick) one substep is taken and timed first, so the first ticks
   respect the budget too. The remaining lag carries over (reported as ``capped``).
4. Prescribed ends get the attachment position/velocity at each chunk's target time from their
   source (a validated pose input, an analytic motion, or their fixed configured position). When
   an input falls silent beyond ``max_extrapolation`` (the source then holds the end at rest) or a
   held end gets motion again, after a re-synchronisation, a recovery and a (re)start from rest (pose
   inputs only: an analytic motion of the offline runner is the scenario and starts as given), the
   end is moved by a C2 blend ``p = h + w(u) (p_s - h)``
   from its held trajectory ``h`` (current position, extrapolated with its current velocity) onto
   the stream ``p_s``, with the quintic ``w = 10u^3 - 15u^4 + 6u^5``, over a time chosen so that the blend adds at
   most ``BLEND_ACCELERATION`` and half of ``node.max_end_speed`` (:func:`blend_time`). Only an
   end that never had an input and whose first pose lies farther than ``node.max_end_speed`` allows
   in one tick restarts the solver from a static equilibrium (its held position was a placeholder).
5. A :class:`SolverDivergedError` is caught: the last good snapshot (cable and end states) is
   restored (or, if that fails again from the same snapshot, the solver is rebuilt from a fresh
   static equilibrium at the current end positions); the anchor moves so the lost time is skipped
   and the ends are blended onto the stream; the error is reported. The code and its policy are
   shared with the network driver (tether_sim/ros/recovery.py).
6. The end tensions of every substep go through the streaming snap detector, except across a
   discontinuity of the cable state or its clock (recovery, restart, clock jump, the start-up
   blend): detection is suspended from the discontinuity until the blend ends and then restarts
   with a fresh detector, so no snap can be made of a restart (reported). An input's blend (lost,
   resumed, revised) keeps the cable state and its clock: detection goes on across it and an event
   overlapping it is published as degraded (a dropout during a slack period used to lose its snap).
   A re-synchronisation keeps the cable state and its simulated time: detection
   goes on across it, the detectors' clock skipping the dropped time with the anchor (a slack
   period keeps its simulated duration), and an event whose slack or re-tensioning overlaps the
   skip or the blend after it is published as degraded. (Suspending there lost real snaps: a node
   behind re-synchronises every few seconds and was blind to a snap whose slack began before a
   re-synchronisation, publishing its peak, 4.7 x static, as a degraded state with no event.)
"""

import time as wallclock
from dataclasses import dataclass, field, replace

import numpy as np

from tether_sim.errors import SolverDivergedError
from tether_sim.physics.boundary import END_NAMES
from tether_sim.physics.snap import NumericalSnapWarning, SnapDetector, SnapEvent, SlackStarted, snap_guard
from tether_sim.ros import winch_link
from tether_sim.ros.body_frame import BodyFrame
from tether_sim.ros.bridging import Bridges, CatchUp, shift_detectors
from tether_sim.ros.end_commands import BLEND_ACCELERATION, BLEND_MIN_TIME, Blend, EndCommands, MotionSource, blend_time
from tether_sim.ros.recovery import Recovery
from tether_sim.solvers.base import lazy_relative_end_speed, shortest_element
from tether_sim.solvers.factory import build_solver

@dataclass
class TickReport:
    """What one tick did (for diagnostics and logs)."""

    stamp: float  # clock time of the state after the tick, s (the simulated instant)
    substeps: int = 0
    lag: float = 0.0  # simulated instant behind clock - input_delay after the tick, s
    capped: bool = False  # the substep cap or the wall budget stopped the tick short of its target
    dropped: float = 0.0  # clock time skipped by a re-synchronisation this tick, s
    clock_jump: bool = False
    degraded: bool = False  # outputs of this tick are late, blended or have snap detection suspended
    blending: bool = False  # an end is being blended onto its input (its motion is a bridge, not the input)
    events: list = field(default_factory=list)  # SlackStarted / SnapEvent
    error: str | None = None  # divergence message, if any
    recovery: str | None = None  # "snapshot" or "static"
    restart: str | None = None  # why the solver was restarted at new end positions
    blends: list = field(default_factory=list)  # (end, duration s, reason) of blends started this tick


class SimulationDriver(EndCommands, Recovery, BodyFrame):
    """Owns the solver, the clock mapping, recovery and the snap detector; the end commands and blends
    (input handling) are :class:`~tether_sim.ros.end_commands.EndCommands`, the snapshots and divergence
    recovery :class:`~tether_sim.ros.recovery.Recovery`, the body-frame queries
    :class:`~tether_sim.ros.body_frame.BodyFrame`."""

    def __init__(self, config, sources: dict | None = None, *, solver_factory=build_solver, wall_budget=None,
                 start_blend=True):
        self.config = config
        self.start_blend = start_blend  # blend pose-input ends from rest at a (re)start (the node)
        self.sources = dict(sources or {})  # end -> EndPoseInput | MotionSource (prescribed ends)
        self.solver_factory = winch_link.wrap_factory(config, solver_factory)  # winch.enabled: the winch drives L
        self.solver = None
        self.wall_budget = wall_budget  # s of wall time one tick may spend stepping (None: no limit)
        self.wall_per_substep = 0.0  # measured cost of a substep, s (0: not yet measured)
        self._solver_config = config
        self._end_state = {}  # end -> (position, velocity) commanded at the solver's current time
        self._held = {}  # end -> the last command came from a held (silent) input
        self._had_input = {}  # end -> the end ever followed an input
        self._blends = {}  # end -> Blend
        self._hold_at = {}  # end -> rest point of an end held after a clock jump, until its input resumes
        self._suspended_until = None  # clock time until which snap detection is suspended
        self.catchup = CatchUp()  # per end: the offsets re-synchronisations added (tether_sim/ros/bridging.py)
        self.bridges = Bridges()  # clock spans of the latest re-synchronisations and input blends (bridged)
        self._pending = TickReport(stamp=0.0)  # what a (re)start did, reported by the next tick
        self.anchor = 0.0
        self.last_now = None
        self._init_recovery()  # divergences, last_error, last_recovery, the snapshot (recovery.py)
        self.resyncs = 0
        self.dropped_total = 0.0
        self.capped_ticks = 0
        self.lag = 0.0  # simulated instant behind (clock - input_delay), s, after the last tick
        self.degraded = False  # the last tick's outputs are late, blended or unmonitored for snaps
        self._substep = 0.0  # the solver's stable substep, s (re-read at each snapshot)
        self.real_time_factor = 0.0
        self._last_wall = None
        # a node catching up on skipped output periods (sim_node.py): their ticks' advance is added to the next
        # regular tick's, whose real-time factor then spans them all (a catch-up tick's own would be 20 ms of
        # simulated time over microseconds of wall time); their outputs carry the last regular tick's factor
        self.catching_up = False
        self._rate_advance = 0.0
        self.static_tensions = (0.0, 0.0)
        self._reference = None  # winch_link.LengthReference while a winch changes the length
        self.detector = self.span_detector = None
        self.slack = {"ship": False, "vehicle": False}
        self.static_by_location = {}
        self.span_arc = np.zeros(0)
        self.numerical_snaps = 0  # re-tensionings the snap guard rejected (published as warnings, never as snaps)
        self.last_numerical_snap = ""
        # the node's output points when its next output carries the state there (else None): _detect samples
        # the state there once, reads the relative end speed from its end samples and leaves it in
        # output_state = (solver, solver time, arc lengths' bytes, state) for the outputs (convert.OutputFrame)
        self.output_points = None
        self.output_state = None

    # ------------------------------------------------------------------ set-up
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
        self.last_now = now
        self._last_wall = wallclock.perf_counter()
        self._rebuild(now)
        self._had_input = {end: self._has_data(end) for end in END_NAMES if self._prescribed(end)}

    def _build_detector(self):
        """Ends: every substep (drained end tensions). Span points (``snap.monitor_arc_lengths``):
        sampled once per tick from the state, so their peaks are resolved at the output rate only."""
        L = self.config.cable.length
        guard = snap_guard(self.config, shortest_element(self.solver, self.config))
        self.detector = SnapDetector(self.config.snap, list(END_NAMES), list(self.static_tensions), [0.0, L], guard)
        self.slack = {end: False for end in END_NAMES}
        self.static_by_location = dict(zip(END_NAMES, self.static_tensions))
        self.span_arc = np.array([s for s in self.config.snap.monitor_arc_lengths if 0.0 < s < L], float)
        self.span_detector = None
        self.bridges.clear()
        if self.span_arc.size:
            names = [f"span s={s:g} m" for s in self.span_arc]
            if not hasattr(self, "_span_static") or len(self._span_static) != len(names):
                self._span_static = [float(x) for x in self.solver.state(self.span_arc).tension]
            self.span_detector = SnapDetector(self.config.snap, names, list(self._span_static), list(self.span_arc), guard)
            self.static_by_location.update(zip(names, self._span_static))
            self.slack.update({name: False for name in names})

    def set_snap_config(self, snap_config) -> None:
        """Live change of the snap thresholds (slack state kept)."""
        self.config = replace(self.config, snap=snap_config)
        for detector in (self.detector, self.span_detector):
            if detector is not None:
                detector.set_config(snap_config)

    @property
    def _sim_time(self):
        return self.solver.time

    def _capture_snapshot(self):
        """The cable's state and the ends' commanded states (Recovery._take_snapshot)."""
        # (the substep is re-read here, not every tick: it only sizes the substep cap)
        self._substep = self.solver.stable_time_step()
        return self.solver.snapshot(), {e: (p.copy(), v.copy()) for e, (p, v) in self._end_state.items()}

    def _restore_snapshot(self, snap):
        state, ends = snap
        self.solver.restore(state)
        self.solver.drain_end_tensions()
        self._end_state = {e: (p.copy(), v.copy()) for e, (p, v) in ends.items()}

    def _rebuild_static(self, now, report):
        self._rebuild(now)

    # ------------------------------------------------------------------ stepping
    def tick(self, now: float) -> TickReport:
        """Advance towards clock time ``now`` under the policy of the module docstring."""
        if self.solver is None:
            self.start(now)
        now -= self.config.node.input_delay  # simulate the past, where the inputs are known
        pending = self._pending.blends
        if pending:  # what the last (re)start did; else the empty pending report is kept (one report a tick, not two)
            report = TickReport(stamp=self.stamp, blends=pending)
            self._pending = TickReport(stamp=now)
        else:
            report = TickReport(stamp=self.stamp)
        if self.last_now is not None and now < self.last_now:
            report.clock_jump = True
            self.anchor = now - self.solver.time
            self.catchup.clear()  # (absorbed into the holds below: they start from the commanded state)
            for end, src in self.sources.items():
                if hasattr(src, "reset"):
                    src.reset()
                    self._hold_after_jump(end, now, report)
            self._suspend_detection(now)
        self.last_now = now
        node = self.config.node
        lag = now - self.anchor - self.solver.time
        if lag > node.max_lag:
            self._resync(now, lag, report)
        target = now - self.anchor
        if target > self.solver.time:
            t0, wall0 = self.solver.time, wallclock.perf_counter()
            if not self._step_to(target, now, wall0, report):
                return self._finish(now, report)
            self._update_rate(self.solver.time - t0, wall0)
            self._detect(report)
            if self._snapshot_due(node.snapshot_interval):
                self._take_snapshot()
        return self._finish(now, report)

    def _finish(self, now, report):
        report.stamp = self.stamp
        self.lag = report.lag = max(0.0, now - report.stamp)
        report.blending = bool(self._blends) or bool(self.catchup)
        period = 1.0 / max(self.config.node.output_rate, 1e-9)
        report.degraded = (report.lag > 1.5 * period or report.blending or self._suspended_until is not None
                           or report.dropped > 0.0 or report.error is not None or report.restart is not None
                           or report.clock_jump or bool(self._hold_at))
        self.degraded = report.degraded
        return report

    def _resync(self, now, lag, report):
        """Lag beyond max_lag: jump the simulated instant to ``now`` keeping the cable state; every
        prescribed end keeps its commanded motion and catches up with its input by a decaying offset
        (tether_sim/ros/bridging.py), running blends keep their progress. Snap detection goes on
        across it (module doc, 6): the detectors' clock skips ``lag`` with the anchor, and the skip
        and the catch-up are recorded so that an event overlapping them is published as degraded
        (:meth:`bridged`)."""
        report.dropped = lag
        self.dropped_total += lag
        self.resyncs += 1
        self.anchor += lag
        for blend in self._blends.values():
            blend.t0 += lag
        self.catchup.shift(lag)
        if self._suspended_until is not None:
            self._suspended_until += lag
        duration = 0.0
        for end, (p_before, v_before) in self._end_state.items():
            p_after, v_after = self._commanded(end, now, drop=False)
            T = self.catchup.add(end, now, p_before - p_after, v_before - v_after, self.config.node.max_end_speed)
            if T > 0.0:
                report.blends.append((end, T, "re-synchronised"))
            duration = max(duration, T)
        shift_detectors((self.detector, self.span_detector), lag)
        self.bridges.shift(lag)
        self.bridges.add(now, now + duration)

    def bridged(self, event) -> bool:
        """True when a detector event's slack period or re-tensioning overlaps a re-synchronisation,
        the catch-up after it or an input blend (its tension history ran across skipped clock time,
        its ends were bridged onto their inputs): published with ``degraded``."""
        return self.bridges.covers(event)

    def _chunk_substeps(self, steps_done, wall0):
        """Substeps the next chunk may take (0: stop): the cap, then the wall budget at the measured
        cost; one substep (to measure it) while the cost is unknown."""
        left = self.config.node.max_substeps_per_tick - steps_done
        if self.wall_budget is None or left <= 0:
            return max(left, 0)
        if self.wall_per_substep <= 0.0:
            return 1
        remaining = self.wall_budget - (wallclock.perf_counter() - wall0)
        n = int(remaining / self.wall_per_substep)
        return min(left, n if steps_done else max(n, 1))  # at least one substep a tick: progress

    def _step_to(self, target, now, wall0, report) -> bool:
        """Chunks of substeps towards ``target`` (solver time) within the tick's limits; False when
        the tick ended in a recovery or a restart."""
        while self.solver.time < target - 1e-12:
            n = self._chunk_substeps(report.substeps, wall0)
            if n <= 0:
                break
            chunk = min(target, self.solver.time + n * self._substep)
            t_clock = self.anchor + chunk
            if self._first_pose_far(t_clock, chunk, report):
                self._rebuild(now)
                return False
            commands = {end: self._command(end, t_clock, report) for end in END_NAMES if self._prescribed(end)}
            for end, (position, velocity) in commands.items():
                self.solver.set_end_motion(end, position, velocity)
            chunk_wall = wallclock.perf_counter()
            try:
                k = self.solver.advance_to(chunk)
            except SolverDivergedError as exc:
                self._recover(now, str(exc), report)
                return False
            self._end_state = {end: (np.asarray(p, float), np.asarray(v, float)) for end, (p, v) in commands.items()}
            self._measure(k, wallclock.perf_counter() - chunk_wall)
            report.substeps += k
        report.capped = self.solver.time < target - 1e-12
        self.capped_ticks += report.capped
        return True

    def _measure(self, substeps, seconds):
        """Running cost per substep: a lower measurement is taken at once (the first one may include
        JIT compiling), a higher one is averaged in."""
        if substeps <= 0:
            return
        cost = seconds / substeps
        if self.wall_per_substep == 0.0 or cost < self.wall_per_substep:
            self.wall_per_substep = cost
        else:
            self.wall_per_substep = 0.7 * self.wall_per_substep + 0.3 * cost

    def _detect(self, report):
        """Feed the snap detectors, unless detection is suspended (module doc, 6)."""
        times, t_ship, t_vehicle = self.solver.drain_end_tensions()
        if self._suspended_until is not None:
            if self.stamp < self._suspended_until or any(b.suspends for b in self._blends.values()):
                return  # (a re-synchronisation's blend does not hold it: a node behind would never detect)
            self._suspended_until = None
            self._build_detector()  # fresh: nothing carries across the discontinuity
            keep = np.asarray(times) + self.anchor >= self.stamp - 1e-12
            times, t_ship, t_vehicle = np.asarray(times)[keep], np.asarray(t_ship)[keep], np.asarray(t_vehicle)[keep]
        if self._reference is not None:  # the references follow the winch's length (docs/winch.md)
            refs = self._reference.tensions(self.solver.unstretched_length)
            self.detector.set_static_tensions(refs)
            self.static_by_location.update(zip(END_NAMES, refs))
        state, arc = None, self.output_points
        if arc is not None and hasattr(self.solver, "end_bodies"):  # (the same numbers as end_kinematics': DG)
            arc = np.asarray(arc, float)
            state = self.solver.state(arc)
            self.output_state = (self.solver, self.solver.time, arc.tobytes(), state)
        speed = lazy_relative_end_speed(self.solver, self.config.cable.length, state)  # (read when a detector needs it)
        if len(times):
            tensions = np.empty((len(times), 2))  # (np.column_stack's values, without its wrapper)
            tensions[:, 0] = t_ship
            tensions[:, 1] = t_vehicle
            report.events = self.detector.update(np.asarray(times) + self.anchor, tensions, speed)
        if self.span_detector is not None:
            tension = self.solver.state(self.span_arc).tension
            report.events += self.span_detector.update(np.array([self.stamp]), np.asarray(tension, float).reshape(1, -1),
                                                       speed)
        self.count_numerical(report.events)
        self.slack.update(self.detector.slack_now())  # the state now, not the last event (a slack period can
        if self.span_detector is not None:           # end without a snap: no event clears it)
            self.slack.update(self.span_detector.slack_now())

    def count_numerical(self, events) -> None:
        """Count the snap guard's rejections among ``events`` (diagnostics, report)."""
        for ev in events:
            if isinstance(ev, NumericalSnapWarning):
                self.numerical_snaps += 1
                self.last_numerical_snap = f"{ev.location} t = {ev.time:.3f} s: {ev.reason}"

    def _update_rate(self, sim_advance, wall0):
        if self.catching_up:
            self._rate_advance += sim_advance
            return
        sim_advance, self._rate_advance = sim_advance + self._rate_advance, 0.0
        wall = wallclock.perf_counter()
        elapsed = wall - (self._last_wall if self._last_wall is not None else wall0)
        self._last_wall = wall
        if elapsed > 0:
            self.real_time_factor = sim_advance / elapsed

    def _rebuild(self, now):
        """A fresh solver (static equilibrium) at the current end positions, clock ``now``."""
        self._solver_config = self._start_config(now)
        self.solver = self.solver_factory(self._solver_config)
        self.solver.drain_end_tensions()
        self.anchor = now - self.solver.time
        self._blends.clear()
        self.catchup.clear()
        self._suspended_until = None
        self._end_state = {end: (np.asarray(getattr(self._solver_config, f"{end}_end").position, float), np.zeros(3))
                           for end in END_NAMES if self._prescribed(end)}
        # an end without input yet is held: its first pose starts a blend ("input resumed") from the
        # configured position, never a step onto the stream (a pose arriving between the start and
        # the first tick)
        self._held = {end: not self._has_data(end) for end in self._end_state}
        self._hold_at.clear()
        forces = self.solver.end_forces()
        self.static_tensions = (float(forces.ship_tension), float(forces.vehicle_tension))
        self._reference = winch_link.length_reference(self.solver, self.config)  # None without a winch
        if hasattr(self, "_span_static"):
            del self._span_static
        self._build_detector()
        self._take_snapshot()
        self._pending = TickReport(stamp=now)  # blends started here are reported by the next tick
        for end in list(self._end_state):  # the cable is at rest: start pose-input ends from rest too
            # (an analytic motion, or the offline runner's inputs, are the scenario: applied as given)
            if self.start_blend and hasattr(self.sources.get(end), "is_held"):
                self._start_blend(end, now, "started from rest", self._pending)

    # ------------------------------------------------------------------ queries
    @property
    def stamp(self) -> float:
        """Clock time of the current solver state."""
        return self.anchor + (self.solver.time if self.solver is not None else 0.0)

    @property
    def end_speed_limit(self) -> float:
        """m/s: the fastest an end may be moved (``node.max_end_speed``; sizes the blends)."""
        return self.config.node.max_end_speed


__all__ = ["SimulationDriver", "TickReport", "MotionSource", "SnapEvent", "SlackStarted", "NumericalSnapWarning", "Blend", "blend_time",
           "BLEND_ACCELERATION", "BLEND_MIN_TIME"]
