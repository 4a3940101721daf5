"""The network node's clock and detection around a :class:`NetworkSolver` (no rclpy; the
single-line node's counterpart is tether_sim/ros/driver.py).

- Clock: the network's time 0 is the clock time ``anchor``; each tick advances it to the clock
  minus ``node.input_delay`` so that the driven points' pose inputs are interpolated (as the
  single-line node does). A tick further behind than ``node.max_lag`` re-synchronises as the
  single-line node does, with the same code (tether_sim/ros/bridging.py): the skipped span is not
  simulated (the anchor moves), the lines and bodies keep their state, each driven point keeps its
  commanded motion and catches up with its input by a decaying offset (``CatchUp``), and snap
  detection goes on across the skip (the detectors' clock skips with the anchor, a slack period
  open across it keeps its simulated duration); an event whose slack or re-tensioning overlaps the
  skip or the catch-up after it is published as degraded (:meth:`NetworkDriver.bridged`). The
  outputs are marked degraded while a point catches up.
- Clock jumps back (a replayed or restarted simulation clock): as the single-line node, the network
  keeps its state and is re-anchored, the inputs' histories are reset, each driven point is
  brought to rest and held until its input resumes, then blended onto it; snap detection is
  suspended meanwhile and restarts fresh (:meth:`NetworkDriver._clock_jump`). Before 2026-11-28 the
  network waited, frozen and silent, until the clock passed the old time again.
- Start: the network statics at the driven points' current positions; a DG line whose discrete
  equilibrium polish failed settles with the points held before the clock starts, at least
  ``SETTLE_TIME`` and then until two consecutive 1 s chunks are quiet (:func:`settle_quiet`), at
  most ``SETTLE_MAX`` (the snap detectors' static tensions are taken after it). The node builds in
  one tick and starts the clock in a later one, once the poses that came meanwhile are in
  (:meth:`NetworkDriver.inputs_cover`), each point with a pose input blended from rest onto its
  input as the single-line node starts: the build's CPU time (a second on config/ropos_tms.yaml) is
  not clock the first tick must catch up, and no point is blended onto a stale input.
- Inputs: each driven (``prescribed``) point follows its source (an ``EndPoseInput``, or anything
  with ``has_data`` and ``attachment_at(t)``) as the single-line node's ends do, with the same code
  (:class:`~tether_sim.ros.end_commands.EndCommands`): without data it holds its configured
  position; when its input falls silent (held past its extrapolation), resumes, or is revised
  where the point already went (samples that arrive after the tick that extrapolated them, e.g.
  after the process stalled), the point is blended onto the stream (a C2 blend, at most
  ``BLEND_ACCELERATION``), never stepped; the blend is a bridge (an event overlapping it is
  published as degraded) and the outputs are degraded while it runs.
- Snap detection: one :class:`SnapDetector` per line over its two ends, fed with every substep's
  end tensions, guarded by :func:`line_snap_guard` (the snap plausibility bound with the mass of
  the bodies the line ends on). Event locations are ``<line>/ship`` and ``<line>/vehicle`` (the
  line's s = 0 and s = L ends).
- Divergence (a line solver diverging: a hybrid Newton failure, a DG state turning non-finite; or
  a body's state turning non-finite): recovered as the single-line node recovers, with the same
  code and policy (tether_sim/ros/recovery.py). A snapshot of the whole network (every line's
  state with its winch, every body's state, every point's motion, the end loads) is taken when the
  clock starts and then every ``node.snapshot_interval`` s of simulated time; on a divergence it
  is restored, the anchor moves so that the lost clock time is skipped (the restored state carries
  the clock time the failed tick was heading for: stamps stay monotonic), each driven point is
  blended from its snapshot state onto its input, and every line's snap detection is suspended
  until the blends end and restarts with fresh detectors (no snap is made of the recovery); the
  outputs are degraded meanwhile. A second divergence before a newer snapshot rebuilds the network
  from its static equilibrium at the driven points' current positions (each winch keeps its length
  and command; fresh reference tensions). Counted in ``divergences``, ``last_error``,
  ``last_recovery``; the report's ``error`` and ``recovery`` say it (the node logs an error,
  diagnostics ERROR). Any other exception in a tick (not a divergence: a defect) leaves the
  network half-stepped: it stops the simulation, :attr:`failed` holds the reason and nothing more
  is published (never physics that did not happen).
"""

import time
from dataclasses import dataclass, field, replace

import numpy as np

from tether_sim.errors import SolverDivergedError
from tether_sim.network.solver import NetworkSolver
from tether_sim.network.spec import NetworkSpec, PointSpec
from tether_sim.physics.boundary import END_NAMES, EndCondition
from tether_sim.physics.snap import NumericalSnapWarning, SnapDetector, SnapEvent, snap_guard
from tether_sim.ros.bridging import Bridges, CatchUp, shift_detectors
from tether_sim.ros.end_commands import EndCommands
from tether_sim.ros.recovery import Recovery
from tether_sim.solvers.base import lazy_relative_end_speed, shortest_element

SETTLE_TIME = 3.0  # s: the least simulated time a network with an unpolished DG line settles before its clock starts
SETTLE_MAX = 30.0  # s: the most (the clock then starts with the lines as they are)
SETTLE_CHUNK = 1.0  # s: settled once two consecutive chunks are quiet (settle_quiet)


_ARC_LENGTHS = {}


def output_arc_lengths(length, n):
    """np.linspace(0, length, n), kept per (length, n) (the same array while a line's length holds; a
    winch paying out makes new ones, the cache is then cleared now and then). Read-only: not to be changed."""
    key = (length, n)
    a = _ARC_LENGTHS.get(key)
    if a is None:
        if len(_ARC_LENGTHS) > 64:
            _ARC_LENGTHS.clear()
        a = _ARC_LENGTHS[key] = np.linspace(0.0, length, n)
        a.flags.writeable = False
    return a


def settle_quiet(samples) -> bool:
    """True when a line's end tensions over a settling chunk (samples (3, k): time, s = 0 end,
    s = L end) stay within 0.5 N + 5 % of their mean at each end: at rest to the mesh's ringing."""
    if samples.shape[1] == 0:
        return True
    for row in samples[1:3]:
        if float(np.max(row) - np.min(row)) > 0.5 + 0.05 * abs(float(np.mean(row))):
            return False
    return True


def line_snap_guard(spec: NetworkSpec, line: str, solver):
    """The snap guard of one network line: its ends on bodies count as body ends with that body's
    mass and added mass (with two bodies, the lighter one: the smaller moving mass gives the smaller,
    stricter energy bound), ends on points as kinematic."""
    ln = spec.lines[line]
    kinds, body = [], None
    for e in ln.ends:
        if e.kind == "body":
            kinds.append("body")
            props = spec.bodies[e.target].props
            if body is None or props.mass + max(props.added_mass) < body.mass + max(body.added_mass):
                body = props
        elif e.kind == "point":
            kinds.append(spec.points[e.target].kind)
        else:
            kinds.append("free")
    conds = [EndCondition(kind=k, position=(0.0, 0.0, 0.0)) for k in kinds]
    gcfg = replace(ln.config, ship_end=conds[0], vehicle_end=conds[1])
    if body is not None:
        gcfg = replace(gcfg, body=body)
    return snap_guard(gcfg, shortest_element(solver, ln.config))


@dataclass
class NetworkTickReport:
    events: dict = field(default_factory=dict)  # line -> [SnapEvent | SlackStarted | NumericalSnapWarning]
    dropped: float = 0.0  # s skipped by a re-synchronisation
    error: str = ""  # a divergence (recovered: ``recovery``) or a failure that stopped the simulation
    recovery: str = ""  # "snapshot" or "static" after a divergence (tether_sim/ros/recovery.py)
    advanced: bool = False
    blends: list = field(default_factory=list)  # (point, duration, reason) of the blends started
    clock_jump: bool = False  # the clock went backwards: re-anchored, points held until their inputs resume


class NetworkDriver(EndCommands, Recovery):
    """Owns the NetworkSolver, the clock mapping and one snap detector per line (module doc); its
    driven points' commands are :class:`~tether_sim.ros.end_commands.EndCommands`'s, its snapshots and
    divergence recovery :class:`~tether_sim.ros.recovery.Recovery`'s (the single-line driver's)."""

    def __init__(self, spec: NetworkSpec, node_options, sources: dict | None = None, statics: bool = True,
                 settle: float = SETTLE_TIME):
        self.spec0 = spec
        self.settle = float(settle)
        self.settled = []  # lines whose discrete equilibrium was reached by settling (start)
        self.node = node_options
        self.sources = dict(sources or {})
        self.statics = statics
        self.net = None
        self.anchor = 0.0
        self.detectors = {}
        self.static_tensions = {}  # line -> [s = 0 end, s = L end] reference tensions, N
        self.degraded = False
        self.dropped_total = 0.0
        self.resyncs = 0
        self.failed = ""  # a failure that is not a divergence stopped the simulation: its reason
        self._init_recovery()  # divergences, last_error, last_recovery, the snapshot (recovery.py)
        self.snaps = 0
        self.numerical_snaps = 0
        self.last_numerical_snap = ""
        self.slack = {}
        self.real_time_factor = 0.0
        self.lag = 0.0
        # the node's catch-up of skipped output periods (sim_node.py, shared): its ticks share one tick's stepping
        # budget; the real-time factor here is the network's simulated time over its own stepping's wall time,
        # which a catch-up tick does not distort (catching_up is set, and unused)
        self.wall_budget = node_options.tick_budget / node_options.output_rate
        self.catching_up = False
        self.output_layout = None  # what network_outputs.tick_outputs keeps of this network (its _Layout)
        self.catchup = CatchUp()  # point -> the offsets re-synchronisations added
        self.bridges = Bridges()  # clock spans of the latest re-synchronisations and input blends (bridged)
        self._held = {}  # point -> the last command came from a held (silent) input
        self._blends = {}  # point -> Blend
        self._hold_at = {}  # point -> rest point of a point held after a clock jump, until its input resumes
        self._suspended_until = None  # clock time until which snap detection is suspended (a clock jump)
        self._last_target = None  # the clock time (minus the input delay) of the last tick
        self._released = False  # detection resumed in this tick (after a clock jump)
        self._states = {}  # line -> its state at the output points, sampled once per tick (line_state)
        self._share_states = not getattr(node_options, "shape_rate", 0.0) > 0.0  # shapes at every output

    @property
    def stamp(self) -> float:
        """Clock time of the current state."""
        return self.anchor + (self.net.time if self.net is not None else 0.0)

    @property
    def last_now(self):
        """The clock time minus ``node.input_delay`` of the last tick (None before the clock starts)."""
        return self._last_target

    @property
    def end_speed_limit(self) -> float:
        """m/s: the fastest a driven point may be moved (``node.max_end_speed``; sizes the blends)."""
        return self.node.max_end_speed

    @property
    def _end_state(self):
        """point -> (position, velocity) commanded at the network's current time (EndCommands)."""
        if self.net is None:
            return {}
        return {n: (self.net.points[n].pos, self.net.points[n].vel) for n in self.driven_points()}

    def driven_points(self):
        return [n for n, p in self.spec0.points.items() if p.kind == "prescribed"]

    def _start_spec(self, t):
        """The spec with every driven point where its input is at clock time t (if it has data)."""
        points = dict(self.spec0.points)
        for name in self.driven_points():
            src = self.sources.get(name)
            if src is not None and src.has_data:
                pos, _ = src.attachment_at(t)
                points[name] = PointSpec(name, "prescribed", tuple(float(x) for x in pos))
        return replace(self.spec0, points=points)

    def start(self, now: float) -> None:
        """Solve the network statics at the inputs' positions at clock time ``now`` and start the
        clock there (the offline runner, the tests; the node splits the two: :meth:`build`, then
        :meth:`start_clock` once its inputs have caught up with the clock)."""
        self.build(now)
        self.start_clock(now, blend=False)

    def build(self, now: float) -> None:
        """The network statics at the driven points' input positions at clock time ``now`` (their
        configured ones without a pose), and the settling of an unpolished DG line; kept if already
        built at these positions and at rest (the node's build at construction). The clock does not
        start: on config/ropos_tms.yaml this takes about a second of CPU, which the first tick would
        otherwise have to catch up (a re-synchronisation)."""
        spec = self._start_spec(now - self.node.input_delay)
        if self.net is not None and not self.failed and all(
                np.allclose(p.position, self.spec.points[n].position, rtol=0.0, atol=1e-9) for n, p in spec.points.items()):
            return
        self._build(spec)

    def inputs_cover(self, now: float) -> bool:
        """True when every driven point's pose input with data reaches the clock time ``now`` minus
        ``node.input_delay`` (its newest stamp): the poses that came while the network was built are
        in (the node starts the clock then)."""
        t = now - self.node.input_delay
        for name in self.driven_points():
            src = self.sources.get(name)
            if src is not None and getattr(src, "has_data", False) and getattr(src, "last_stamp", t) < t:
                return False
        return True

    def start_clock(self, now: float, blend: bool = True) -> list:
        """Start the clock at ``now`` on the built network, at rest: fresh detectors (their static
        tensions from this state); ``blend``: every driven point with a pose input is blended from
        rest at its static position onto its input, as the single-line node starts (EndCommands'
        "started from rest" blend; snap detection waits for it). Returns the blends started,
        (point, duration, reason)."""
        report = NetworkTickReport()
        self._start_at(now - self.node.input_delay, blend, report)
        return report.blends

    def _start_at(self, t0, blend, report):
        """The clock starts at ``t0`` (clock time minus the input delay) on the network as built
        (start_clock, the static rebuild after a divergence); the first snapshot."""
        self.anchor = t0 - self.net.time
        self._clear_commands()
        self._build_detectors()
        for name in self.driven_points() if blend else ():
            if hasattr(self.sources.get(name), "is_held"):  # a pose input (not an analytic motion)
                self._start_blend(name, t0, "started from rest", report)
        self._take_snapshot()

    def _build(self, spec, winches=None):
        """The network statics of ``spec`` (and the settling of an unpolished DG line); ``winches``:
        the winch links to carry on (NetworkSolver)."""
        self.spec = spec
        self.net = NetworkSolver(self.spec, statics=self.statics, winches=winches)
        # a DG line whose static polish failed (a near-neutral slack line: equilibrium_iterations -1)
        # starts off its discrete equilibrium and rings; let the network settle with the points held
        # before the clock starts, so that start-up ringing is neither published nor detected
        self.settled = [n for n, s in self.net.lines.items() if getattr(s, "equilibrium_iterations", 0) == -1]
        if self.settled and self.settle > 0.0:
            for link in (winches or {}).values():  # a rebuild: the drums stand still while it settles
                link.hold()
            self.net.tick(self.settle)
            quiet = 0  # then in chunks until the unpolished lines' end tensions are steady (a coarse mesh rings longer)
            while quiet < 2 and self.net.time < SETTLE_MAX - 1e-9:
                out = self.net.tick(min(self.net.time + SETTLE_CHUNK, SETTLE_MAX))
                quiet = quiet + 1 if all(settle_quiet(out[n]["samples"]) for n in self.settled) else 0
            for name, link in (winches or {}).items():
                link.release(self.net.lines[name])

    def _build_detectors(self, static=True):
        """Fresh detectors; ``static``: take the reference (static) end tensions from the current
        state (at the start, at rest), else keep the start's."""
        self.detectors = {}
        for name, solver in self.net.lines.items():
            if static or name not in self.static_tensions:
                tension = [abs(self.net.end_load(name, e)[1]) for e in END_NAMES]
                self.static_tensions[name] = [max(t, 1.0) for t in tension]
            L = float(self.spec.lines[name].config.cable.length)
            self.detectors[name] = SnapDetector(self.spec.lines[name].config.snap, [f"{name}/{e}" for e in END_NAMES],
                                                self.static_tensions[name], [0.0, L],
                                                line_snap_guard(self.spec, name, solver))
            for e in END_NAMES:
                self.slack[f"{name}/{e}"] = False
        self.bridges.clear()

    # ------------------------------------------------------------------ recovery (tether_sim/ros/recovery.py)
    @property
    def _sim_time(self):
        return self.net.time

    def _capture_snapshot(self):
        """The whole network: every line (with its winch), body and point, the end loads."""
        return self.net.snapshot()

    def _restore_snapshot(self, snap):
        self.net.restore(snap)
        for solver in self.net.lines.values():  # (samples of the failed tick's partial steps)
            solver.drain_end_tensions()
        self._states.clear()

    def _rebuild_static(self, target, report):
        """The network statics at the driven points' positions at clock time ``target``, each winch
        carried on with its current length; the clock restarts there (fresh reference tensions)."""
        links = dict(self.net.winches)
        spec = self._start_spec(target)
        lines = {n: replace(ln, config=replace(ln.config, cable=replace(ln.config.cable, length=links[n].winch.length)))
                 if n in links else ln for n, ln in spec.lines.items()}
        self._build(replace(spec, lines=lines), links)
        self._states.clear()
        self._start_at(target, True, report)

    def _clear_commands(self):
        """No catch-up offsets, blends or held inputs: the points start on their inputs."""
        self.catchup.clear()
        self._blends.clear()
        self._held.clear()
        self._hold_at.clear()
        self._suspended_until = None
        self._last_target = None

    def _resync(self, target, skip, report):
        """Skip ``skip`` s of clock (module doc): the network keeps its state, each driven point its
        commanded motion (a decaying offset onto its input), the detectors run on with their clock
        shifted; running blends keep their progress; the skip and the catch-up are recorded as a bridge."""
        self.anchor += skip
        report.dropped = skip
        self.dropped_total += skip
        self.resyncs += 1
        for blend in self._blends.values():
            blend.t0 += skip
        self.catchup.shift(skip)
        duration = 0.0
        for name in self.driven_points():
            if self.sources.get(name) is None:
                continue
            after = self._commanded(name, target, drop=False)
            p = self.net.points[name]  # its commanded state at the network's time (the clock before the skip)
            T = self.catchup.add(name, self.stamp, p.pos - after[0], p.vel - after[1], self.end_speed_limit)
            if T > 0.0:
                report.blends.append((name, T, "re-synchronised"))
            duration = max(duration, T)
        shift_detectors(self.detectors.values(), skip)
        self.bridges.shift(skip)
        self.bridges.add(self.stamp, self.stamp + duration)

    def bridged(self, event) -> bool:
        """True when a detector event's slack period or re-tensioning overlaps a re-synchronisation or
        the catch-up after it: published with ``degraded``."""
        return self.bridges.covers(event)

    def line_state(self, name, points=None):
        """The line's state() at ``points`` (default ``node.output_points``) evenly spaced on its
        unstretched length, sampled once per state: the snap guard's end speed and the messages read
        the same samples (kept until the next tick, and only while the length and time hold)."""
        solver = self.net.lines[name]
        n = self.node.output_points if points is None else points
        L = float(getattr(solver, "unstretched_length", self.spec.lines[name].config.cable.length))
        kept = self._states.get(name)
        if kept is not None and kept[0] == L and kept[1] == n and kept[2] == solver.time:
            return kept[3]
        st = solver.state(output_arc_lengths(L, n))
        self._states[name] = (L, n, solver.time, st)
        return st

    def _clock_jump(self, target, report):
        """The clock went backwards (a replayed or restarted simulation clock): the network keeps its
        state and is re-anchored at ``target``; every input's history is reset (its stamps are of
        the old clock) and each driven point is brought to rest where it goes (EndCommands'
        ``_hold_after_jump``) until its input resumes; snap detection is suspended until then and
        the blends back onto the inputs end, and restarts fresh (the tension history's clock broke)."""
        report.clock_jump = True
        self.anchor = target - self.net.time
        self.catchup.clear()
        for name in self.driven_points():
            src = self.sources.get(name)
            if src is not None and hasattr(src, "reset"):
                src.reset()
                self._hold_after_jump(name, target, report)
        self._suspend_detection(target)
        self._released = False

    def _detecting(self) -> bool:
        """False while detection is suspended (a clock jump, module doc); the tick that ends the
        suspension rebuilds the detectors (their static tensions kept) and sets ``_released``."""
        self._released = False
        if self._suspended_until is None:
            return True
        if self.stamp < self._suspended_until or self._hold_at or any(b.suspends for b in self._blends.values()):
            return False
        self._suspended_until = None
        self._build_detectors(static=False)
        self._released = True
        return True

    def tick(self, now: float) -> NetworkTickReport:
        report = NetworkTickReport()
        self._states.clear()
        if self.net is None or self.failed:
            return report
        target = now - self.node.input_delay
        if self._last_target is not None and target < self._last_target:
            self._clock_jump(target, report)
        self._last_target = target
        behind = target - self.stamp
        if behind <= 0.0:
            return report
        if behind > self.node.max_lag:  # re-synchronise: skip to the inputs' present (one output period left to step)
            self._resync(target, behind - 1.0 / self.node.output_rate, report)
        for name in self.driven_points():
            if self.sources.get(name) is not None:  # (a point without a source keeps its configured position)
                self.net.set_point_motion(name, *self._command(name, target, report))
        self.degraded = bool(self.catchup) or bool(self._blends) or self._suspended_until is not None
        wall0 = time.perf_counter()
        sim0 = self.net.time
        try:
            out = self.net.tick(target - self.anchor)
        except SolverDivergedError as exc:  # restored (or rebuilt), reported (module doc)
            self._recover(target, str(exc), report)
            self._last_target = target
            self.degraded = True
            self.lag = max(0.0, target - self.stamp)
            return report
        except Exception as exc:  # noqa: BLE001 - not a divergence: the network is half-stepped, it stops
            self.failed = f"{type(exc).__name__}: {exc}"
            report.error = self.failed
            return report
        wall = time.perf_counter() - wall0
        if wall > 0:
            self.real_time_factor = (self.net.time - sim0) / wall
        self.lag = max(0.0, now - self.node.input_delay - self.stamp)
        report.advanced = True
        if self._snapshot_due(self.node.snapshot_interval):
            self._take_snapshot()
        if not self._detecting():
            return report
        for name, o in out.items():
            s = o["samples"]
            times = s[0] + self.anchor
            if self._released:  # (detection resumed this tick: only what follows the resume)
                keep = times >= self.stamp - 1e-12
                s, times = s[:, keep], times[keep]
            if s.shape[1] == 0:
                continue
            solver = self.net.lines[name]
            # the output points' state serves the speed where its ends are the solver's end samples
            # (end_bodies, DG) and the shapes go out at every output (else two end samples are cheaper);
            # the speed is read only when a detector needs it (as the single-line driver's)
            shared = (lambda n=name: self.line_state(n)) if self._share_states and hasattr(solver, "end_bodies") else None
            speed = lazy_relative_end_speed(solver, self.spec.lines[name].config.cable.length, shared)
            events = self.detectors[name].update(times, s[1:3].T, speed)  # (k, 2): the detector makes it contiguous
            for ev in events:
                if isinstance(ev, NumericalSnapWarning):
                    self.numerical_snaps += 1
                    self.last_numerical_snap = f"{ev.location} t = {ev.time:.3f} s: {ev.reason}"
                elif isinstance(ev, SnapEvent):
                    self.snaps += 1
            self.slack.update(self.detectors[name].slack_now())  # the state now (a slack period can end without a snap)
            if events:
                report.events[name] = events
        return report
