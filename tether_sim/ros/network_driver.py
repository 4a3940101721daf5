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
- Start: the network statics at the driven points' current positions; a DG line whose discrete
  equilibrium polish failed settles with the points held before the clock starts, at least
  ``SETTLE_TIME`` and then until two consecutive 1 s chunks are quiet (:func:`settle_quiet`), at
  most ``SETTLE_MAX`` (the snap detectors' static tensions are taken after it).
- Inputs: each driven (``prescribed``) point follows its source (an ``EndPoseInput``, or anything
  with ``has_data`` and ``attachment_at(t)``); without data it holds its configured position.
- Snap detection: one :class:`SnapDetector` per line over its two ends, fed with every substep's
  end tensions, guarded by :func:`line_snap_guard` (the snap plausibility bound with the mass of
  the bodies the line ends on). Event locations are ``<line>/ship`` and ``<line>/vehicle`` (the
  line's s = 0 and s = L ends).
- A failing tick (a line solver diverging, e.g. a hybrid Newton failure) stops the simulation:
  :attr:`failed` holds the reason and nothing more is published (never physics that did not
  happen); there is no silent recovery of a network yet.
"""

import time
from dataclasses import dataclass, field, replace

import numpy as np

from tether_sim.network.solver import NetworkSolver
from tether_sim.network.spec import NetworkSpec, PointSpec
from tether_sim.physics.boundary import END_NAMES, EndCondition
from tether_sim.physics.snap import NumericalSnapWarning, SnapDetector, SnapEvent, snap_guard
from tether_sim.ros.bridging import Bridges, CatchUp, shift_detectors
from tether_sim.solvers.base import relative_end_speed, shortest_element

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
    error: str = ""  # the tick failed: the simulation stopped
    advanced: bool = False


class NetworkDriver:
    """Owns the NetworkSolver, the clock mapping and one snap detector per line (module doc)."""

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
        self.failed = ""
        self.snaps = 0
        self.numerical_snaps = 0
        self.last_numerical_snap = ""
        self.slack = {}
        self.real_time_factor = 0.0
        self.lag = 0.0
        self.catchup = CatchUp()  # point -> the offsets re-synchronisations added
        self.bridges = Bridges()  # clock spans of the latest re-synchronisations (bridged)
        self._states = {}  # line -> its state at the output points, sampled once per tick (line_state)
        self._share_states = not getattr(node_options, "shape_rate", 0.0) > 0.0  # shapes at every output

    @property
    def stamp(self) -> float:
        """Clock time of the current state."""
        return self.anchor + (self.net.time if self.net is not None else 0.0)

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
        """Solve the network statics at the inputs' current positions and start the clock at ``now``."""
        t0 = now - self.node.input_delay
        spec = self._start_spec(t0)
        if self.net is not None and not self.failed and all(
                np.allclose(p.position, self.spec.points[n].position, rtol=0.0, atol=1e-9) for n, p in spec.points.items()):
            self.anchor = t0 - self.net.time  # built at these positions and at rest (warm-up): keep it
            self.catchup.clear()
            self._build_detectors()
            return
        self.spec = spec
        self.net = NetworkSolver(self.spec, statics=self.statics)
        # a DG line whose static polish failed (a near-neutral slack line: equilibrium_iterations -1)
        # starts off its discrete equilibrium and rings; let the network settle with the points held
        # before the clock starts, so that start-up ringing is neither published nor detected
        self.settled = [n for n, s in self.net.lines.items() if getattr(s, "equilibrium_iterations", 0) == -1]
        if self.settled and self.settle > 0.0:
            self.net.tick(self.settle)
            quiet = 0  # then in chunks until the unpolished lines' end tensions are steady (a coarse mesh rings longer)
            while quiet < 2 and self.net.time < SETTLE_MAX - 1e-9:
                out = self.net.tick(min(self.net.time + SETTLE_CHUNK, SETTLE_MAX))
                quiet = quiet + 1 if all(settle_quiet(out[n]["samples"]) for n in self.settled) else 0
        self.anchor = t0 - self.net.time
        self.catchup.clear()
        self._build_detectors()

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

    def _target(self, name, t, drop=True):
        """(position, velocity) commanded for driven point ``name`` at clock time ``t`` (its input
        with the catch-up offsets; None without input data)."""
        src = self.sources.get(name)
        if src is None or not src.has_data:
            return None
        pos, vel = src.attachment_at(t)
        return self.catchup.apply(name, t, np.asarray(pos, float), np.asarray(vel, float), drop)

    def _resync(self, target, skip, report):
        """Skip ``skip`` s of clock (module doc): the network keeps its state, each driven point its
        commanded motion (a decaying offset onto its input), the detectors run on with their clock
        shifted; the skip and the catch-up are recorded as a bridge."""
        self.anchor += skip
        report.dropped = skip
        self.dropped_total += skip
        self.resyncs += 1
        self.catchup.shift(skip)
        duration = 0.0
        for name in self.driven_points():
            after = self._target(name, target, drop=False)
            if after is None:
                continue
            p = self.net.points[name]  # its commanded state at the network's time (the clock before the skip)
            duration = max(duration, self.catchup.add(name, self.stamp, p.pos - after[0], p.vel - after[1],
                                                      self.node.max_end_speed))
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

    def tick(self, now: float) -> NetworkTickReport:
        report = NetworkTickReport()
        self._states.clear()
        if self.net is None or self.failed:
            return report
        target = now - self.node.input_delay
        behind = target - self.stamp
        if behind <= 0.0:
            return report
        if behind > self.node.max_lag:  # re-synchronise: skip to the inputs' present (one output period left to step)
            self._resync(target, behind - 1.0 / self.node.output_rate, report)
        for name in self.driven_points():
            command = self._target(name, target)
            if command is not None:
                self.net.set_point_motion(name, *command)
        self.degraded = bool(self.catchup)
        wall0 = time.perf_counter()
        sim0 = self.net.time
        try:
            out = self.net.tick(target - self.anchor)
        except Exception as exc:  # noqa: BLE001 - a line solver failing stops the network, reported
            self.failed = f"{type(exc).__name__}: {exc}"
            report.error = self.failed
            return report
        wall = time.perf_counter() - wall0
        if wall > 0:
            self.real_time_factor = (self.net.time - sim0) / wall
        self.lag = max(0.0, now - self.node.input_delay - self.stamp)
        report.advanced = True
        for name, o in out.items():
            s = o["samples"]
            if s.shape[1] == 0:
                continue
            times = s[0] + self.anchor
            solver = self.net.lines[name]
            # the output points' state serves the speed where its ends are the solver's end samples
            # (end_bodies, DG) and the shapes go out at every output (else two end samples are cheaper)
            shared = self.line_state(name) if self._share_states and hasattr(solver, "end_bodies") else None
            speed = relative_end_speed(solver, self.spec.lines[name].config.cable.length, shared)
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
