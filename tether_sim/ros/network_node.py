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
``<body>/sim_pose`` and the transform world -> body frame on /tf, ``<body>/sim_twist`` and
``<body>/sim_accel`` (world frame), ``<body>/hydro_wrench`` (drag and rotational damping, world
frame), ``<body>/wet_weight`` (latched). ``/diagnostics`` at 1 Hz.

The network's keys are read from the parameter files (tether_sim/network/params.py); ``-p``
overrides the ``node.*`` keys. A line solver diverging (e.g. a hybrid Newton failure) is recovered
as on the single-line node (tether_sim/ros/network_driver.py, tether_sim/ros/recovery.py): the last
snapshot of the whole network restored, or the network rebuilt from its statics after a second
divergence, the driven points blended onto their inputs, snap detection suspended meanwhile, the
outputs degraded; an error in the log and /diagnostics ERROR (``divergences``, ``last_error``). Any
other failure of a tick stops the simulation with an error in the log and /diagnostics; nothing
more is published.
"""

import math
import time

from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import AccelStamped, PoseStamped, TwistStamped, WrenchStamped
from nav_msgs.msg import Path
from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy
from tether_sim_msgs.msg import SlackWarning, SnapLoadEvent, TetherDescription, TetherState, WinchCommand, WinchState
from visualization_msgs.msg import Marker

from tether_sim.ros.network_driver import NetworkDriver
from tether_sim.network.params import load_network, load_network_files
from tether_sim.physics.snap import NumericalSnapWarning
from tether_sim.ros import convert
from tether_sim.ros import network_outputs as outputs
from tether_sim.ros.sim_node import EVENTS, LATCHED, RELIABLE, TetherSimNode, _new_period
from tether_sim.ros.tf import TF_QOS, TFMessage, tf_message_cdr

_TYPES = {"TetherState": TetherState, "Path": Path, "Marker": Marker, "SnapLoadEvent": SnapLoadEvent,
          "SlackWarning": SlackWarning, "TetherDescription": TetherDescription, "WrenchStamped": WrenchStamped,
          "PoseStamped": PoseStamped, "DiagnosticArray": DiagnosticArray, "WinchState": WinchState,
          "TwistStamped": TwistStamped, "AccelStamped": AccelStamped}


class NetworkSimNode(Node):
    """Simulation node on a line network (module doc)."""

    # the pose / twist input handling of the single-line node (same rejections, same logging)
    _add_pose_input = TetherSimNode._add_pose_input
    _on_pose = TetherSimNode._on_pose
    _on_twist = TetherSimNode._on_twist
    _reject = TetherSimNode._reject
    _log_throttled = TetherSimNode._log_throttled
    _now = TetherSimNode._now
    # the catch-up of output periods the timer skipped (a starved process), as the single-line node's
    _on_timer = TetherSimNode._on_timer
    _missed_instants = TetherSimNode._missed_instants
    _outputs_catching_up = TetherSimNode._outputs_catching_up

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
            self._add_pose_input(name, self._attachment(name))
        # build once now: compiles the kernels, solves the statics, and a network the solvers cannot
        # build fails at start-up (ConfigError naming network.lines.<line>)
        t0 = time.perf_counter()
        self.driver = NetworkDriver(self.spec, node, self.inputs)
        self.driver.start(0.0)
        self.driver.tick(self.driver.stamp + node.input_delay + 2.0 / node.output_rate)
        outputs.tick_outputs(self.driver, node)  # the outputs' first call (cdr, marker colours) before the clock
        self.get_logger().info(f"network: {len(self.spec.lines)} line(s) ({', '.join(self.spec.lines)}), "
                               f"{len(self.spec.bodies)} body(ies), built in {time.perf_counter() - t0:.1f} s; "
                               f"coupling step {min(self.spec.coupling_step, self.driver.net.coupling_limit):.4g} s")
        self.pubs = {}
        self._tick_pubs = []  # the periodic outputs, built only while someone subscribes (the winch states regardless)
        for topic, (type_name, kind) in outputs.output_topics(self.spec, self.driver.net.winches).items():
            profile = LATCHED if kind == "latched" else EVENTS if kind == "events" else RELIABLE
            self.pubs[topic] = self.create_publisher(_TYPES[type_name.rsplit("/", 1)[1]], convert.ros_name(topic),
                                                     profile)
            if kind == "reliable" and topic != "/diagnostics" and not topic.startswith("/winch/"):
                self._tick_pubs.append((topic, self.pubs[topic]))
        self.tf_pub = None
        self._shape_gate = convert.ShapeGate(self.config.node.shape_rate)
        # the lines' marker and path at node.visual_rate among the outputs that carry the shapes, /tf among all
        # outputs, as the single-line node
        self._visual_gate, self._tf_gate = convert.ShapeGate(node.visual_rate), convert.ShapeGate(node.visual_rate)
        if TFMessage is not None and node.publish_tf:
            self.tf_pub = self.create_publisher(TFMessage, "/tf", TF_QOS)
        reliable = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
        for line in self.driver.net.winches:
            self.create_subscription(WinchCommand, f"winch/{line}/command",
                                     lambda m, ln=line: self._on_winch_command(ln, m), reliable)
        self.started = False
        self._first_tick = None
        self._built_at = None  # clock time the network was built at the inputs' positions (_tick)
        self._last_output = -math.inf
        self.tick_errors, self.last_tick_error = 0, ""
        self.snaps_published = 0  # snap events published since the start (diagnostics "snaps")
        self._failure_logged = False
        self._period = _new_period(self.inputs)
        # the output timer's grid and the period index of the last tick (the catch-up: _missed_instants)
        self._grid, self._last_slot = None, None
        self._output_timer = self.create_timer(1.0 / node.output_rate, self._on_timer)
        self.create_timer(1.0, self._publish_diagnostics)

    # ------------------------------------------------------------------ frames
    def _attachment(self, point):
        return outputs.attachment(self.config.node, point)

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
        for point, duration, reason in d.start_clock(now):  # (built in an earlier tick: _tick)
            self.get_logger().info(f"{point} blended onto its pose input over {duration:.2f} s ({reason})")
        missing = [e for e, inp in self.inputs.items() if not inp.has_data]
        if missing:
            self.get_logger().warning(f"starting without {', '.join(missing)} pose(s): holding the configured positions")
        self.started = True
        for line in self.spec.lines:
            self._publish_description(line)
        for name in self.spec.bodies:
            self.pubs[f"/{name}/wet_weight"].publish(outputs.wet_weight(d, self.config.node, name))
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
            if self._built_at is None:  # the statics at the inputs' positions; the clock starts at a later
                d.build(now)  # tick, once the poses that came meanwhile are taken (not counted as lag)
                self._built_at = self._now()
                return
            if not d.inputs_cover(now) and now - self._built_at < self.config.node.input_timeout:
                return
            self._start(now)
        if d.failed:
            return
        self._outputs_catching_up(now)

    def _output_at(self, now) -> bool:
        """Step the network to clock time ``now`` and publish its events and the outputs of the state it
        reaches; False when the simulation stopped (a line solver failed)."""
        d = self.driver
        report = d.tick(now)
        if report.recovery:
            self._period["errors"] += 1
            how = "the last snapshot" if report.recovery == "snapshot" else "a fresh static equilibrium of the network"
            self.get_logger().error(f"network: line solver diverged ({report.error}); recovered from {how}, "
                                    "snap detection suspended until the points are back on their inputs")
            self._publish_diagnostics()
        elif report.error:
            self.get_logger().error(f"network simulation stopped: {report.error} (no further outputs; restart the node)")
            self._publish_diagnostics()
            return False
        if report.clock_jump:
            self._last_output = -math.inf
            self._grid = self._last_slot = None  # (the timer starts a new grid after a jump)
            self.get_logger().warning("clock jumped backwards: pose histories reset, points held until their inputs "
                                      "resume, snap detection suspended until then; simulation continues")
        for point, duration, reason in report.blends:
            self._log_throttled(("blend", point), "warning", f"{point} blended onto its pose input over {duration:.2f} s ({reason})")
        if report.dropped > 0:
            self._period["resyncs"] += 1
            self.get_logger().warning(f"{report.dropped:.3f} s behind the clock (beyond node.max_lag): skipped, "
                                      "lines kept, points caught up with their inputs; snap events across the gap are marked degraded")
        for line, events in report.events.items():
            self._publish_events(line, events)
        if report.advanced and d.stamp > self._last_output:
            self._last_output = d.stamp
            self._publish_outputs()
        return True

    # ------------------------------------------------------------------ outputs
    def _publish_events(self, line, events):
        for ev in events:
            if isinstance(ev, NumericalSnapWarning):
                self._period["numerical"] += 1
                self._log_throttled(("numerical", line), "warning",
                                    f"{line}: re-tensioning at its {ev.location.rsplit('/', 1)[-1]} end rejected by "
                                    f"the snap guard (numerical, not a snap): {ev.reason}")
        for topic, msg in outputs.event_outputs(self.driver, self.config.node, line, events):
            if topic.endswith("/snap_events"):
                self._period["snaps"] += 1
                self.snaps_published += 1
                self.get_logger().warning(f"snap load on {line} at its {msg.end} end: peak {msg.peak_tension:.1f} N")
            self.pubs[topic].publish(msg)

    def _orientation(self, name):
        inp = self.inputs.get(name)
        return inp.orientation_at(self.driver.stamp) if inp is not None and inp.has_data else None

    def _publish_outputs(self):
        stamp = self.driver.stamp
        wanted = {topic for topic, pub in self._tick_pubs if pub.get_subscription_count() > 0}
        shapes = self._shape_gate.due(stamp)  # node.shape_rate
        visuals = shapes and self._visual_gate.due(stamp)  # node.visual_rate: the lines' marker and path
        tf = self._tf_gate.due(stamp)  # /tf at node.visual_rate
        for topic, payload in outputs.tick_outputs(self.driver, self.config.node, self._orientation, wanted, shapes,
                                                   visuals):
            if topic == "/tf":
                if self.tf_pub is not None and payload and tf:
                    self.tf_pub.publish(tf_message_cdr(self.driver.stamp, self.config.node.world_frame, payload))
            else:
                self.pubs[topic].publish(payload)

    def point_wrench(self, name):
        """Force and torque by the lines on point ``name`` in its body frame (network_outputs.point_wrench)."""
        return outputs.point_wrench(self.driver, self.config.node, name, self._orientation(name))

    def body_wrench(self, name):
        """Force and moment about the CoG by the lines on body ``name``, in its body frame."""
        return outputs.body_wrench(self.driver.net, name)

    def _publish_description(self, line):
        self.pubs[f"/tether/{line}/description"].publish(
            outputs.description(self.spec, self.config.node, line, self._now()))

    def _publish_diagnostics(self):
        now, d, p = self._now(), self.driver, self._period
        sim = {"running": self.started and not d.failed, "real_time_factor": float(d.real_time_factor),
               "time_step": float(min(self.spec.coupling_step, d.net.coupling_limit)), "lag": float(d.lag),
               "degraded": bool(d.degraded), "dropped_total": float(d.dropped_total), "resyncs": d.resyncs,
               "resyncs_recent": p["resyncs"], "divergences": d.divergences, "error_recent": p["errors"] > 0,
               "last_error": d.last_error or "", "tick_errors": self.tick_errors,
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
