"""Solver results -> ROS messages. The only place where output messages are built.

Shared by the simulation node (published) and the offline runner (serialized into MCAP), so both
produce identical topics. The periodic outputs (:func:`tick_outputs`) are serialized CDR bytes
built from numpy arrays (:mod:`tether_sim.ros.cdr`); events, the description and diagnostics are
rclpy message objects. Frames: cable states in the world frame (ENU); wrenches in the body frames
(force BY the tether ON the body, torque about the body frame origin).
"""

import math
import threading

import numpy as np
from builtin_interfaces.msg import Time
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from geometry_msgs.msg import Point
from std_msgs.msg import Header
from tether_sim_msgs.msg import SlackWarning, SnapLoadEvent, TetherDescription

from tether_sim.io.params import to_flat
from tether_sim.numerics.colour_map import tension_rgba
from tether_sim.physics.boundary import END_NAMES
from tether_sim.physics.snap import NumericalSnapWarning, SnapEvent
from tether_sim.ros import cdr

# Output topics, their message types and QoS kind (the MCAP writer's names). Remappable in the node.
TOPICS = {
    "/tether/state": ("tether_sim_msgs/msg/TetherState", "reliable"),
    "/tether/marker": ("visualization_msgs/msg/Marker", "reliable"),
    "/tether/path": ("nav_msgs/msg/Path", "reliable"),
    "/tether/ship_wrench": ("geometry_msgs/msg/WrenchStamped", "reliable"),
    "/tether/vehicle_wrench": ("geometry_msgs/msg/WrenchStamped", "reliable"),
    "/tether/snap_events": ("tether_sim_msgs/msg/SnapLoadEvent", "reliable"),
    "/tether/slack_warnings": ("tether_sim_msgs/msg/SlackWarning", "reliable"),
    "/tether/description": ("tether_sim_msgs/msg/TetherDescription", "latched"),
    "/diagnostics": ("diagnostic_msgs/msg/DiagnosticArray", "reliable"),
    "/ship/sim_pose": ("geometry_msgs/msg/PoseStamped", "reliable"),
    "/vehicle/sim_pose": ("geometry_msgs/msg/PoseStamped", "reliable"),
}

# Topics that stay absolute by ROS convention; every other name is created relative (without the
# leading "/") so the node's namespace applies: `-r __ns:=/rov1` gives /rov1/tether/state. The keys
# above (and the MCAP writer's names) are the resolved names in the root namespace.
GLOBAL_TOPICS = ("/diagnostics", "/clock", "/tf", "/tf_static", "/rosout", "/parameter_events")


def ros_name(topic: str) -> str:
    """The name a node creates a publisher/subscription with: relative unless in GLOBAL_TOPICS."""
    return topic if topic in GLOBAL_TOPICS else topic.lstrip("/")


LEVEL_OK, LEVEL_WARN, LEVEL_ERROR, LEVEL_STALE = (DiagnosticStatus.OK, DiagnosticStatus.WARN,
                                                  DiagnosticStatus.ERROR, DiagnosticStatus.STALE)
_SEVERITY = {LEVEL_OK: 0, LEVEL_WARN: 1, LEVEL_STALE: 2, LEVEL_ERROR: 3}


def time_msg(t: float) -> Time:
    """builtin_interfaces/Time of a clock time in seconds (clamped at 0)."""
    sec, nanosec = cdr.stamp_parts(t)
    return Time(sec=sec, nanosec=nanosec)


def to_seconds(stamp) -> float:
    return stamp.sec + stamp.nanosec * 1e-9


def header(t: float, frame_id: str) -> Header:
    return Header(stamp=time_msg(t), frame_id=frame_id)


def _point(p) -> Point:
    return Point(x=float(p[0]), y=float(p[1]), z=float(p[2]))


def _end_label(location: str) -> str:
    return location if location in END_NAMES else "span"


def snap_event(ev, frame_id: str, degraded: bool = False, lag: float = 0.0) -> SnapLoadEvent:
    """SnapLoadEvent from the detector's SnapEvent (times are clock times); ``degraded`` / ``lag``:
    the simulation was running late when the event was detected (its stamps are still honest)."""
    return SnapLoadEvent(header=header(ev.time, frame_id), end=_end_label(ev.location), arc_length=float(ev.arc_length),
                         peak_tension=float(ev.peak_tension), min_tension=float(ev.min_tension),
                         slack_start=time_msg(ev.slack_start), slack_duration=float(ev.slack_duration),
                         rise_time=float(ev.rise_time), static_tension=float(ev.static_tension),
                         amplification=float(ev.amplification) if math.isfinite(ev.amplification) else 0.0,
                         criterion=str(ev.criterion), degraded=bool(degraded), lag=float(lag))


def slack_warning(ev, frame_id: str, static_tension: float) -> SlackWarning:
    """SlackWarning from the detector's SlackStarted."""
    return SlackWarning(header=header(ev.time, frame_id), end=_end_label(ev.location), arc_length=float(ev.arc_length),
                        tension=float(ev.tension), threshold=float(ev.threshold), static_tension=float(static_tension))


def description(config, output_arc_length, t: float) -> TetherDescription:
    """The latched TetherDescription: cable, ends, frames and every configuration key."""
    node, cable = config.node, config.cable
    msg = TetherDescription(header=header(t, node.world_frame), solver=config.solver, length=float(cable.length),
                            axial_stiffness=float(cable.EA), bending_stiffness=float(cable.EI),
                            mass_per_length=float(cable.gamma0), diameter=float(cable.diameter),
                            wave_speed=float(cable.wave_speed), ship_end_kind=config.ship_end.kind,
                            vehicle_end_kind=config.vehicle_end.kind, ship_frame=node.body_frame("ship"),
                            vehicle_frame=node.body_frame("vehicle"), ship_attachment=_point(node.ship_attachment),
                            vehicle_attachment=_point(node.vehicle_attachment))
    msg.output_arc_length = np.asarray(output_arc_length, float).tolist()
    msg.parameters = [KeyValue(key=k, value=str(list(v) if isinstance(v, tuple) else v))
                      for k, v in to_flat(config).items()]
    return msg


def _status(name, level, message, values, hardware_id) -> DiagnosticStatus:
    return DiagnosticStatus(level=level, name=name, message=message, hardware_id=hardware_id,
                            values=[KeyValue(key=k, value=str(v)) for k, v in values.items()])


def diagnostics(t: float, node_name: str, sim: dict, inputs: dict) -> DiagnosticArray:
    """DiagnosticArray: one status for the simulation, one per pose input.

    ``node_name``: the node's fully qualified name (``/rov1/tether_sim``). The statuses are named
    ``rov1/tether_sim: simulation``, ``rov1/tether_sim: ship input``... and carry it as their
    hardware_id, so the statuses of several tethers on the one /diagnostics stay apart.

    ``sim`` has: real_time_factor, time_step, lag, degraded, dropped_total, resyncs(_recent),
    capped_ticks, behind, divergences, error_recent, last_error, tick_errors(_recent),
    last_tick_error, slack (dict end -> bool), snaps(_recent) (snap events published: total, in the
    period), numerical_snaps(_recent) and last_numerical_snap (the snap guard's rejections: total, in
    the period, the last one),
    running (bool).
    ``inputs``: end -> EndPoseInput.health(now) dict plus ``rejected_recent`` (count in the period).
    The simulation status message lists every problem of the period (none hides another, e.g.
    "cannot keep up" stays visible next to snap loads); the level is the worst of them.
    """
    msg = DiagnosticArray(header=header(t, ""))
    problems = []  # (level, text)
    if not sim.get("running", True):
        problems.append((LEVEL_STALE, "waiting for inputs or clock"))
    if sim.get("error_recent"):
        problems.append((LEVEL_ERROR, f"solver diverged and was recovered: {sim.get('last_error')}"))
    if sim.get("tick_errors_recent"):
        problems.append((LEVEL_ERROR, f"{sim['tick_errors_recent']} tick(s) failed: {sim.get('last_tick_error')}"))
    if sim.get("snaps_recent"):
        problems.append((LEVEL_ERROR, f"{sim['snaps_recent']} snap load(s) in the last period"))
    if sim.get("numerical_snaps_recent"):
        problems.append((LEVEL_WARN, f"{sim['numerical_snaps_recent']} re-tensioning peak(s) rejected by the snap guard "
                                     f"as numerical, not published as snaps: {sim.get('last_numerical_snap', '')}"))
    if sim.get("resyncs_recent"):
        problems.append((LEVEL_WARN, "cannot keep up with the clock: re-synchronised (lag beyond node.max_lag)"))
    elif sim.get("behind") or sim.get("degraded"):
        problems.append((LEVEL_WARN, f"cannot keep up with the clock: outputs {float(sim.get('lag', 0.0)):.3g} s late "
                                     "(degraded)" if sim.get("behind") else "degraded (end blend or snap detection suspended)"))
    if any(sim.get("slack", {}).values()):
        problems.append((LEVEL_WARN, "tether slack at " + ", ".join(k for k, v in sim["slack"].items() if v)))
    level = max((lvl for lvl, _ in problems), default=LEVEL_OK, key=lambda lvl: _SEVERITY[lvl])
    text = "; ".join(txt for _, txt in problems) or "running"
    values = {k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in sim.items()
              if k not in ("slack",)}
    values.update({f"slack_{k}": v for k, v in sim.get("slack", {}).items()})
    prefix = node_name.lstrip("/")
    msg.status.append(_status(f"{prefix}: simulation", level, text, values, node_name))
    for end, h in inputs.items():
        if h["stale"] and not h["accepted"]:
            rejected = sum(h["rejected"].values())
            level, text = LEVEL_STALE, (f"no {end} pose accepted yet ({rejected} rejected): holding the "
                                        "configured position")
        elif h["stale"]:
            level, text = LEVEL_STALE, (f"no valid {end} pose for {h.get('since_accepted', h['age']):.3g} s "
                                        f"(newest accepted stamp {h['age']:.3g} s old)")
        elif h.get("rejected_recent"):
            level, text = LEVEL_WARN, f"{h['rejected_recent']} {end} pose(s) rejected in the last period"
        else:
            level, text = LEVEL_OK, "ok"
        values = {"accepted": h["accepted"], "age_s": f"{h['age']:.6g}", "rejected_recent": h.get("rejected_recent", 0)}
        values.update({f"rejected_{reason}": n for reason, n in h["rejected"].items()})
        msg.status.append(_status(f"{prefix}: {end} input", level, text, values, node_name))
    return msg


def tension_scale(driver) -> float:
    """Colour scale of the marker: twice the larger static end tension (red = 2x static)."""
    return 2.0 * max(abs(driver.static_tensions[0]), abs(driver.static_tensions[1]), 1.0)


def tension_colours(tension, scale: float) -> np.ndarray:
    """(n, 4) RGBA per point: blue (slack, T <= 0) through green (T = scale / 2) to red (T >= scale),
    linear in between: with d = 2 T / scale - 1 clipped to [-1, 1], (max(d, 0), 1 - |d|, max(-d, 0), 1)
    (one compiled loop: tether_sim/numerics/colour_map.py)."""
    tension = np.ascontiguousarray(tension, dtype=float).reshape(-1)
    rgba = np.empty((tension.size, 4))
    tension_rgba(tension, float(scale), rgba)
    return rgba


MARKER_WIDTH = 0.2  # m, LINE_STRIP line width
MARKER_COLOUR = (1.0, 1.0, 0.0, 1.0)  # RGBA of the strip (the per-vertex colours are used)


SHAPE_TOPICS = ("/tether/state", "/tether/marker", "/tether/path")  # need the state at the output points
VISUAL_TOPICS = ("/tether/marker", "/tether/path")  # drawn, not read: the node sends them (and /tf) at node.visual_rate


class OutputFrame:
    """The driver's outputs at its current simulated instant, each asked of the solver once however
    many messages of the tick read it (the end forces, each end's body state and body orientation,
    the state at a set of arc lengths). Valid for one output: build a new one after the next tick."""

    __slots__ = ("driver", "solver", "_forces", "_bodies", "_orientations", "_states")

    def __init__(self, driver):
        self.driver, self.solver = driver, driver.solver
        self._forces = None
        self._bodies, self._orientations, self._states = {}, {}, {}

    def forces(self):
        if self._forces is None:
            self._forces = self.solver.end_forces()
        return self._forces

    def body(self, end):
        """Pose of a ``body`` end (``position``, ``orientation``: the solver's ``body_pose`` where it has one,
        else its BodyState; what the outputs read of it), None for the other kinds."""
        if end not in self._bodies:
            is_body = getattr(self.driver.config, f"{end}_end").kind == "body"
            if is_body:
                pose = getattr(self.solver, "body_pose", None)
                self._bodies[end] = pose(end) if pose is not None else self.solver.body_state(end)
            else:
                self._bodies[end] = None
        return self._bodies[end]

    def orientation(self, end) -> np.ndarray:
        """Quaternion (x, y, z, w) of the end's body frame (:meth:`SimulationDriver.end_orientation`)."""
        q = self._orientations.get(end)
        if q is None:
            q = self._orientations[end] = self.driver.end_orientation(end, self.body(end))
        return q

    def state(self, arc_lengths):
        """The solver's state at ``arc_lengths`` (one sampling per distinct set of points; the driver's
        ``output_state`` when its snap detection sampled these points at this instant)."""
        arc = np.asarray(arc_lengths, float)
        key = arc.tobytes()
        found = self._states.get(key)
        if found is None:
            shared = getattr(self.driver, "output_state", None)
            if shared is not None and shared[0] is self.solver and shared[1] == self.solver.time and shared[2] == key:
                found = self._states[key] = (arc, shared[3])
            else:
                found = self._states[key] = (arc, self.solver.state(arc_lengths))
        return found[1]

    def end_positions(self, length: float) -> np.ndarray:
        """(2, 3) positions at s = 0 and s = ``length``: the first and last output point when a state
        was sampled here at points that start and end there (the solvers sample each point on its own,
        so the values are those of a sampling at the two points), else a sampling at the two. (The
        points asked for are compared, not the state's arc lengths: a solver may report the last one
        as the sum of its element lengths, 1729.9999999999998 for 1730.)"""
        for arc, state in self._states.values():
            if arc.ndim == 1 and len(arc) >= 2 and arc[0] == 0.0 and arc[-1] == length:
                return np.asarray(state.position, float)[[0, -1]]
        return np.asarray(self.state(np.array([0.0, length])).position, float)


class ShapeGate:
    """Whether the shape outputs (SHAPE_TOPICS) go out with the output at a stamp: at every output
    (``node.shape_rate`` 0), else at the first output and then once at least 1 / shape_rate of clock
    time has passed since the last one (a clock that jumped back starts over)."""

    TOLERANCE = 1e-6  # s: stamps are sums of floats; output_rate / shape_rate outputs make one period

    def __init__(self, shape_rate: float):
        self.period = 1.0 / shape_rate if shape_rate > 0.0 else 0.0
        self.last = None

    def due(self, stamp: float) -> bool:
        if self.period <= 0.0:
            return True
        if self.last is not None and self.last <= stamp < self.last + self.period - self.TOLERANCE:
            return False
        self.last = stamp
        return True


class _Layout:
    """What the periodic outputs of one driver configuration share tick after tick (built at its first
    output, again when the configuration, the solver or the calling thread changes): topic names,
    frames, end kinds and attachment offsets, the colour scale and the encoders of the fixed-size messages (the shape
    encoders are looked up by point count: a winch changes it)."""

    __slots__ = ("config", "solver", "thread", "world", "solver_name", "scale", "statics", "ends", "offsets")

    def __init__(self, driver):
        cfg = self.config = driver.config
        self.solver, self.thread = driver.solver, threading.get_ident()
        node = cfg.node
        self.world, self.solver_name = node.world_frame, driver.solver.name
        self.statics = driver.static_tensions
        self.scale = tension_scale(driver)
        # (end, kind, attachment offset in the end's body frame)
        self.offsets = [(end, getattr(cfg, f"{end}_end").kind, tuple(driver.offset(end))) for end in END_NAMES]
        self.ends = []  # (end, wrench topic, pose topic, is body, wrench encoder, pose encoder, attachment offset)
        for end, kind, offset in self.offsets:
            self.ends.append((end, f"/tether/{end}_wrench", f"/{end}/sim_pose", kind == "body",
                              cdr.encoder(cdr.StampedDoublesEncoder, node.body_frame(end), 6),
                              cdr.encoder(cdr.StampedDoublesEncoder, self.world, 7), offset))

    def valid(self, driver) -> bool:
        return (driver.config is self.config and driver.solver is self.solver and driver.static_tensions is self.statics
                and threading.get_ident() == self.thread)


def _layout(driver) -> _Layout:
    layout = getattr(driver, "_output_layout", None)
    if layout is None or not layout.valid(driver):
        layout = _Layout(driver)
        try:
            driver._output_layout = layout
        except AttributeError:  # (a driver that takes no attributes: built per call)
            pass
    return layout


def tick_outputs(driver, arc_lengths, wanted=None, frame=None, shapes=True) -> list:
    """(topic, serialized CDR bytes) of every periodic output of the current driver state, stamped
    with the clock time of the state (:mod:`tether_sim.ros.cdr`; no message objects per tick).

    ``wanted``: only these topics (the node passes the ones with a subscriber, so nobody pays for
    a Marker or Path no one displays); None = all. ``frame``: the :class:`OutputFrame` of this state
    when other outputs (/tf) read it too. ``shapes``: False leaves out SHAPE_TOPICS (:class:`ShapeGate`)."""
    layout = _layout(driver)
    frame = OutputFrame(driver) if frame is None else frame
    stamp = cdr.stamp_parts(driver.stamp)
    world = layout.world
    want = _ALL if wanted is None else wanted
    out = []
    forces = frame.forces()
    if shapes and ("/tether/state" in want or "/tether/marker" in want or "/tether/path" in want):
        state = frame.state(arc_lengths)
        points = np.asarray(state.position, float)
        if "/tether/state" in want:
            out.append(("/tether/state", cdr.encoder(cdr.TetherStateEncoder, world, layout.solver_name,
                                                     len(state.arc_length)).encode(
                stamp, state.arc_length, points, state.velocity, state.tension, state.curvature,
                state.bending_moment, float(forces.ship_tension), float(forces.vehicle_tension),
                float(state.time_step), float(driver.real_time_factor), float(driver.lag), bool(driver.degraded))))
        if "/tether/marker" in want:
            out.append(("/tether/marker", cdr.encoder(cdr.MarkerLineStripEncoder, world, "tether", 0, MARKER_WIDTH,
                                                      MARKER_COLOUR, len(points)).encode(
                stamp, points, tension_colours(state.tension, layout.scale))))
        if "/tether/path" in want:
            out.append(("/tether/path", cdr.encoder(cdr.PathEncoder, world, len(points)).encode(stamp, points)))
    for end, wrench_topic, pose_topic, is_body, wrench_enc, pose_enc, offset in layout.ends:
        wrench, pose = wrench_topic in want, is_body and pose_topic in want
        if not (wrench or pose):
            continue
        body = frame.body(end)
        if wrench:
            force, torque = driver.body_wrench_floats(end, forces, body, frame.orientation(end), offset)
            out.append((wrench_topic, wrench_enc.encode(stamp, *force, *torque)))
        if body is not None and pose:
            out.append((pose_topic, pose_enc.encode(stamp, *body.position.tolist(), *body.orientation.tolist())))
    return out


class _Everything:
    """A ``wanted`` that holds every topic."""

    def __contains__(self, topic) -> bool:
        return True


_ALL = _Everything()


def event_outputs(events, driver) -> list:
    """(topic, message) for the detector's SlackStarted / SnapEvent items. The snap guard's
    NumericalSnapWarning items have no topic: they are never published as snaps (the node logs them
    and counts them in /diagnostics)."""
    frame = driver.config.node.world_frame
    out = []
    for ev in events:
        if isinstance(ev, NumericalSnapWarning):
            continue
        if isinstance(ev, SnapEvent):
            degraded = driver.degraded or driver.bridged(ev)
            out.append(("/tether/snap_events", snap_event(ev, frame, degraded, driver.lag)))
        else:
            static = driver.static_by_location.get(ev.location, 0.0)
            out.append(("/tether/slack_warnings", slack_warning(ev, frame, static)))
    return out
