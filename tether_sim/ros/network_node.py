"""The simulation node on a line network (docs/network.md, "In the node"): started by ``tether-sim``
when its parameter file holds a ``network`` section (config/ropos_tms.yaml).

Inputs: ``<point>/pose`` (PoseStamped, best effort) and optionally ``<point>/twist`` for every
driven (``prescribed``) point, e.g. ``ship/pose`` and ``vehicle/pose``; ``winch/<line>/command``
(WinchCommand) for every line with a winch.

Outputs, per line ``<line>``: ``tether/<line>/state`` (TetherState; ship = the line's s = 0 end,
vehicle = its s = L end), ``tether/<line>/path``, ``tether/<line>/marker``,
``tether/<line>/snap_events`` (SnapLoadEvent; ``end`` ship / vehicle = the line's s = 0 / s = L
end), ``tether/<line>/slack_warnings``, ``tether/<line>/description`` (latched),
``winch/<line>/state``. Per point ``<point>``: ``tether/<point>_wrench`` (WrenchStamped: the
summed force of every line ending there, on the point, in its body frame, torque about the frame
origin; ``ship`` / ``vehicle`` use node.ship_frame / node.vehicle_frame and their attachments, as
the single-line node). Per body ``<body>``: ``tether/<body>_wrench`` (the lines' force and moment
about its centre of gravity, in its body frame ``<frame_prefix><body>/base_link``),
``<body>/sim_pose`` and the transform world -> body frame on /tf. ``/diagnostics`` at 1 Hz.

The network's keys are read from the parameter files (tether_sim/network/params.py); ``-p``
overrides the ``node.*`` keys. A line solver failing (e.g. a hybrid Newton failure) stops the
simulation with an error in the log and /diagnostics; nothing more is published.
"""

import math
import time
from dataclasses import replace

import numpy as np
from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import PoseStamped, TwistStamped, WrenchStamped
from nav_msgs.msg import Path
from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy, qos_profile_sensor_data
from tether_sim_msgs.msg import SlackWarning, SnapLoadEvent, TetherDescription, TetherState, WinchCommand, WinchState
from visualization_msgs.msg import Marker

from tether_sim.io.inputs import EndPoseInput, knot_spacing
from tether_sim.numerics.rotations import quaternion_matrix
from tether_sim.ros.network_driver import ENDS, NetworkDriver
from tether_sim.network.params import load_network, load_network_files
from tether_sim.physics.snap import NumericalSnapWarning, SnapEvent
from tether_sim.ros import cdr, convert
from tether_sim.ros.sim_node import EVENTS, LATCHED, RELIABLE, TetherSimNode, _new_period, history_span
from tether_sim.ros.tf import TF_QOS, TFMessage, tf_message_cdr


def line_topics(line: str) -> dict:
    """Output topics of one line: {resolved name: (type, qos kind)}."""
    return {f"/tether/{line}/state": (TetherState, "reliable"), f"/tether/{line}/path": (Path, "reliable"),
            f"/tether/{line}/marker": (Marker, "reliable"), f"/tether/{line}/snap_events": (SnapLoadEvent, "events"),
            f"/tether/{line}/slack_warnings": (SlackWarning, "events"),
            f"/tether/{line}/description": (TetherDescription, "latched")}


def _to_body(R, v):
    return R.T @ np.asarray(v, float)


class NetworkSimNode(Node):
    """Simulation node on a line network (module doc)."""

    # the pose / twist input handling of the single-line node (same rejections, same logging)
    _on_pose = TetherSimNode._on_pose
    _on_twist = TetherSimNode._on_twist
    _reject = TetherSimNode._reject
    _log_throttled = TetherSimNode._log_throttled
    _now = TetherSimNode._now

    def __init__(self, *, files=(), overrides=None, flat=None, node_name="tether_sim", **kwargs):
        super().__init__(node_name, **kwargs)
        if flat is not None:
            self.spec, self.config = load_network(flat, where="parameters")
        else:
            self.spec, self.config = load_network_files(files, overrides)
        node = self.config.node
        self._last_log, self._rejected_unlogged = {}, {}
        self.inputs = {}
        for name, p in self.spec.points.items():
            if p.kind != "prescribed":
                continue
            inp = EndPoseInput(name, self._attachment(name), max_end_speed=node.max_end_speed,
                               input_timeout=node.input_timeout, max_extrapolation=node.max_extrapolation,
                               history_span=history_span(node), future_tolerance=node.future_stamp_tolerance,
                               max_age=node.max_input_age, min_spacing=knot_spacing(node.output_rate))
            self.inputs[name] = inp
            self.create_subscription(PoseStamped, f"{name}/pose", lambda m, e=name: self._on_pose(e, m),
                                     qos_profile_sensor_data)
            self.create_subscription(TwistStamped, f"{name}/twist", lambda m, e=name: self._on_twist(e, m),
                                     qos_profile_sensor_data)
        # build once now: compiles the kernels, solves the statics, and a network the solvers cannot
        # build fails at start-up (ConfigError naming network.lines.<line>)
        t0 = time.perf_counter()
        self.driver = NetworkDriver(self.spec, node, self.inputs)
        self.driver.start(0.0)
        self.driver.tick(self.driver.stamp + node.input_delay + 2.0 / node.output_rate)
        self.get_logger().info(f"network: {len(self.spec.lines)} line(s) ({', '.join(self.spec.lines)}), "
                               f"{len(self.spec.bodies)} body(ies), built in {time.perf_counter() - t0:.1f} s; "
                               f"coupling step {min(self.spec.coupling_step, self.driver.net.coupling_limit):.4g} s")
        self.pubs = {}
        for line in self.spec.lines:
            for topic, (msg_type, kind) in line_topics(line).items():
                profile = LATCHED if kind == "latched" else EVENTS if kind == "events" else RELIABLE
                self.pubs[topic] = self.create_publisher(msg_type, convert.ros_name(topic), profile)
        for name in [*self.spec.points, *self.spec.bodies]:
            topic = f"/tether/{name}_wrench"
            self.pubs[topic] = self.create_publisher(WrenchStamped, convert.ros_name(topic), RELIABLE)
        for name in self.spec.bodies:
            topic = f"/{name}/sim_pose"
            self.pubs[topic] = self.create_publisher(PoseStamped, convert.ros_name(topic), RELIABLE)
        self.pubs["/diagnostics"] = self.create_publisher(DiagnosticArray, "/diagnostics", RELIABLE)
        self.tf_pub = None
        if TFMessage is not None and node.publish_tf:
            self.tf_pub = self.create_publisher(TFMessage, "/tf", TF_QOS)
        self.winch_pubs = {}
        reliable = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
        for line in self.driver.net.winches:
            self.winch_pubs[line] = self.create_publisher(WinchState, f"winch/{line}/state", reliable)
            self.create_subscription(WinchCommand, f"winch/{line}/command",
                                     lambda m, ln=line: self._on_winch_command(ln, m), reliable)
        self.started = False
        self._first_tick = None
        self._last_output = -math.inf
        self.tick_errors, self.last_tick_error = 0, ""
        self.snaps_published = 0  # snap events published since the start (diagnostics "snaps")
        self._failure_logged = False
        self._period = _new_period(self.inputs)
        self.create_timer(1.0 / node.output_rate, self._on_tick)
        self.create_timer(1.0, self._publish_diagnostics)

    # ------------------------------------------------------------------ frames
    def _attachment(self, point):
        node = self.config.node
        return getattr(node, f"{point}_attachment") if point in ENDS else (0.0, 0.0, 0.0)

    def _frame(self, name):
        node = self.config.node
        if name in ENDS:
            return node.body_frame(name)
        return f"{node.frame_prefix}{name}/base_link"

    # ------------------------------------------------------------------ winch
    def _on_winch_command(self, line, msg):
        problem = self.driver.net.command_winch(line, msg.mode, msg.setpoint, "topic")
        if problem is not None:
            self.get_logger().warning(f"winch/{line}/command rejected: {problem}")
        else:
            self.get_logger().info(f"winch/{line}/command accepted: {msg.mode} {msg.setpoint:g}")

    # ------------------------------------------------------------------ stepping
    def _on_tick(self):
        wall0 = time.perf_counter()
        try:
            self._tick()
        except Exception as exc:  # noqa: BLE001 - the node stays up; the error is reported
            if not self.context.ok():
                return
            self._period["tick_errors"] += 1
            self.tick_errors += 1
            self.last_tick_error = f"{type(exc).__name__}: {exc}"
            self._log_throttled("tick failed", "error", f"tick failed: {self.last_tick_error}")
        finally:
            busy = time.perf_counter() - wall0
            self._period["busy"] += busy
            self._period["tick_max"] = max(self._period["tick_max"], busy)

    def _start(self, now):
        d = self.driver
        d.start(now)  # the network statics at the inputs' positions (configured ones without a pose)
        missing = [e for e, inp in self.inputs.items() if not inp.has_data]
        if missing:
            self.get_logger().warning(f"starting without {', '.join(missing)} pose(s): holding the configured positions")
        self.started = True
        for line in self.spec.lines:
            self._publish_description(line)
        tens = ", ".join(f"{ln} {d.static_tensions[ln][0]:.1f} / {d.static_tensions[ln][1]:.1f} N" for ln in self.spec.lines)
        self.get_logger().info(f"network started; static end tensions (from / to end): {tens}")

    def _tick(self):
        now = self._now()
        if now <= 0.0:
            return
        d = self.driver
        if not self.started:
            if self._first_tick is None:
                self._first_tick = now
            if not (all(i.has_data for i in self.inputs.values()) or now - self._first_tick >= self.config.node.input_timeout):
                return
            self._start(now)
        if d.failed:
            return
        report = d.tick(now)
        if report.error:
            self.get_logger().error(f"network simulation stopped: {report.error} (no further outputs; restart the node)")
            self._publish_diagnostics()
            return
        if report.dropped > 0:
            self._period["resyncs"] += 1
            self.get_logger().warning(f"{report.dropped:.3f} s behind the clock (beyond node.max_lag): skipped, "
                                      "snap detection restarted past the gap")
        for line, events in report.events.items():
            self._publish_events(line, events)
        if report.advanced and d.stamp > self._last_output:
            self._last_output = d.stamp
            self._publish_outputs()

    # ------------------------------------------------------------------ outputs
    def _publish_events(self, line, events):
        frame = self.config.node.world_frame
        for ev in events:
            end = ev.location.rsplit("/", 1)[-1]
            if isinstance(ev, NumericalSnapWarning):
                self._period["numerical"] += 1
                self._log_throttled(("numerical", line), "warning",
                                    f"{line}: re-tensioning at its {end} end rejected by the snap guard (numerical, "
                                    f"not a snap): {ev.reason}")
                continue
            ev = replace(ev, location=end)
            if isinstance(ev, SnapEvent):
                self._period["snaps"] += 1
                self.snaps_published += 1
                msg = convert.snap_event(ev, frame, self.driver.degraded, self.driver.lag)
                self.get_logger().warning(f"snap load on {line} at its {end} end: peak {msg.peak_tension:.1f} N")
                self.pubs[f"/tether/{line}/snap_events"].publish(msg)
            else:
                static = self.driver.static_tensions[line][ENDS.index(end)]
                self.pubs[f"/tether/{line}/slack_warnings"].publish(convert.slack_warning(ev, frame, static))

    def _wanted(self, topic):
        return self.pubs[topic].get_subscription_count() > 0

    def _publish_outputs(self):
        d, net, node = self.driver, self.driver.net, self.config.node
        stamp = cdr.stamp_parts(d.stamp)
        world = node.world_frame
        for line, solver in net.lines.items():
            names = [f"/tether/{line}/{k}" for k in ("state", "path", "marker")]
            if any(self._wanted(t) for t in names):
                L = float(getattr(solver, "unstretched_length", self.spec.lines[line].config.cable.length))
                st = solver.state(np.linspace(0.0, L, node.output_points))
                pts = np.asarray(st.position, float)
                t0, t1 = net.end_load(line, "ship")[1], net.end_load(line, "vehicle")[1]
                if self._wanted(names[0]):
                    self.pubs[names[0]].publish(cdr.tether_state(
                        stamp, world, solver.name, st.arc_length, pts, st.velocity, st.tension, st.curvature,
                        st.bending_moment, t0, t1, float(st.time_step), float(d.real_time_factor), float(d.lag),
                        bool(d.degraded)))
                if self._wanted(names[1]):
                    self.pubs[names[1]].publish(cdr.path(stamp, world, pts))
                if self._wanted(names[2]):
                    scale = 2.0 * max(max(d.static_tensions[line]), 1.0)
                    self.pubs[names[2]].publish(cdr.marker_line_strip(
                        stamp, world, f"tether/{line}", 0, convert.MARKER_WIDTH, convert.MARKER_COLOUR, pts,
                        convert.tension_colours(st.tension, scale)))
        for name in self.spec.points:
            topic = f"/tether/{name}_wrench"
            if self._wanted(topic):
                force, torque = self.point_wrench(name)
                self.pubs[topic].publish(cdr.wrench_stamped(stamp, self._frame(name), force, torque))
        transforms = []
        for name, b in net.bodies.items():
            force, moment = self.body_wrench(name)
            if self._wanted(f"/tether/{name}_wrench"):
                self.pubs[f"/tether/{name}_wrench"].publish(cdr.wrench_stamped(stamp, self._frame(name), force, moment))
            if self._wanted(f"/{name}/sim_pose"):
                self.pubs[f"/{name}/sim_pose"].publish(cdr.pose_stamped(stamp, world, b.state[0:3], b.state[3:7]))
            transforms.append((self._frame(name), b.state[0:3], b.state[3:7]))
        if self.tf_pub is not None and transforms:
            self.tf_pub.publish(tf_message_cdr(d.stamp, world, transforms))
        for line, pub in self.winch_pubs.items():
            w = net.winches[line].winch
            end = net.winches[line].config.winch.end
            pub.publish(WinchState(header=convert.header(d.stamp, world), end=end, mode=w.mode,
                                   setpoint=float(w.setpoint), length=float(w.length), speed=float(w.speed),
                                   commanded_speed=float(w.commanded_speed),
                                   tension=float(net.end_load(line, end)[1]), **w.flags))

    def point_wrench(self, name):
        """Force and torque by the lines on point ``name`` in its body frame (pose input orientation;
        world-aligned for a fixed point or before the first pose), torque about the frame origin."""
        net = self.driver.net
        F, M = np.zeros(3), np.zeros(3)
        for e in self.spec.ends_on(name):
            f, _, m = net.end_load(e.line, e.end)
            F += f
            M += m
        inp = self.inputs.get(name)
        q = inp.orientation_at(self.driver.stamp) if inp is not None and inp.has_data else np.array([0.0, 0.0, 0.0, 1.0])
        R = quaternion_matrix(np.asarray(q, float))
        f, m = _to_body(R, F), _to_body(R, M)
        r = np.asarray(self._attachment(name), float)
        return f, np.cross(r, f) + m

    def body_wrench(self, name):
        """Force and moment about the CoG by the lines on body ``name``, in its body frame."""
        b = self.driver.net.bodies[name]
        F, M = self.driver.net._body_loads(name)
        R = quaternion_matrix(b.state[3:7])
        lever = b.attachments @ R.T
        force = F.sum(axis=0)
        moment = np.cross(lever, F).sum(axis=0) + M.sum(axis=0)
        return _to_body(R, force), _to_body(R, moment)

    def _publish_description(self, line):
        cfg = replace(self.spec.lines[line].config, node=self.config.node)
        L = float(cfg.cable.length)
        self.pubs[f"/tether/{line}/description"].publish(
            convert.description(cfg, np.linspace(0.0, L, self.config.node.output_points), self._now()))

    def _publish_diagnostics(self):
        now, d, p = self._now(), self.driver, self._period
        sim = {"running": self.started and not d.failed, "real_time_factor": float(d.real_time_factor),
               "time_step": float(min(self.spec.coupling_step, d.net.coupling_limit)), "lag": float(d.lag),
               "degraded": bool(d.degraded), "dropped_total": float(d.dropped_total), "resyncs": d.resyncs,
               "resyncs_recent": p["resyncs"], "tick_errors": self.tick_errors,
               "tick_errors_recent": p["tick_errors"] + (1 if d.failed else 0),
               "last_tick_error": f"network simulation stopped: {d.failed}" if d.failed else self.last_tick_error, "snaps": self.snaps_published, "snaps_recent": p["snaps"], "slack": dict(d.slack),
               "numerical_snaps": d.numerical_snaps, "numerical_snaps_recent": p["numerical"],
               "last_numerical_snap": d.last_numerical_snap, "lines": ", ".join(self.spec.lines),
               "tick_load": p["busy"] / max(time.perf_counter() - p["wall0"], 1e-9), "tick_max_ms": 1e3 * p["tick_max"]}
        if d.failed:
            sim["running"] = True  # the failure (an error), not "waiting for inputs", is the status
        inputs = {}
        for end, inp in self.inputs.items():
            inputs[end] = inp.health(now)
            inputs[end]["rejected_recent"] = p["rejected"][end]
        self.pubs["/diagnostics"].publish(convert.diagnostics(now, self.get_fully_qualified_name(), sim, inputs))
        self._period = _new_period(self.inputs)
