"""The real-time tether simulation node (console script ``tether-sim``). See docs/node.md.

Inputs: ``/ship/pose``, ``/vehicle/pose`` (PoseStamped, best effort) and optionally
``/ship/twist``, ``/vehicle/twist`` (TwistStamped) for every end of kind ``prescribed``.
A timer at ``node.output_rate`` drives :class:`SimulationDriver` to the node clock and publishes
the outputs built by :mod:`tether_sim.ros.convert`; diagnostics go out at 1 Hz.
"""

import difflib
import math
import sys
import time

import numpy as np
import rclpy
from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import PoseStamped, TwistStamped, WrenchStamped
from nav_msgs.msg import Path
from rcl_interfaces.msg import SetParametersResult
from rclpy.exceptions import ParameterNotDeclaredException
from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy, qos_profile_sensor_data
from tether_sim_msgs.msg import SlackWarning, SnapLoadEvent, TetherDescription, TetherState
from visualization_msgs.msg import Marker

from tether_sim.errors import ConfigError, TetherSimError
from tether_sim.io.inputs import EndPoseInput
from tether_sim.physics.snap import NumericalSnapWarning
from tether_sim.ros import convert, node_params
from tether_sim.ros.driver import END_NAMES, SimulationDriver
from tether_sim.ros.end_commands import SolverTimeMotion
from tether_sim.ros.forecast_io import NodeForecast
from tether_sim.ros.namespacing import retarget
from tether_sim.ros.node_cli import (USAGE, check_params_files, cli_param_keys, cli_param_values, ignore_further_signals,
                                     params_files, say_stopped, spin_until_signal, wants_help)
from tether_sim.ros.node_startup import warm_up
from tether_sim.ros.snap_markers import SnapMarkerPublisher
from tether_sim.ros.tf import TfPublisher
from tether_sim.ros.winch_io import NodeWinch
from tether_sim.warm import Interrupted, exit_if_compiling, run_interruptibly
from tether_sim.solvers.factory import build_solver
from tether_sim.solvers.resolution import bending_mesh_warning, mesh_summary

RELIABLE = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
EVENTS = QoSProfile(depth=50, reliability=ReliabilityPolicy.RELIABLE)
LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL)
_TYPES = {"TetherState": TetherState, "Marker": Marker, "Path": Path, "WrenchStamped": WrenchStamped,
          "SnapLoadEvent": SnapLoadEvent, "SlackWarning": SlackWarning, "TetherDescription": TetherDescription,
          "DiagnosticArray": DiagnosticArray, "PoseStamped": PoseStamped}
WARN_PERIOD = 2.0  # s between repeated warnings of one kind
REJECT_SUMMARY_PERIOD = 10.0  # s between the counts of repeatedly rejected inputs of one kind
STALE_LOG_MAX = 60.0  # s: a stale input is logged at once, then after 2, 4, 8 ... s, at most this far apart
_monotonic = time.monotonic  # the clock of the stale-input back-off (a test sets its own)


class TetherSimNode(Node):
    """Simulation node: validated inputs -> solver -> outputs (docs/node.md)."""

    def __init__(self, *, node_name="tether_sim", where="parameters", solver_factory=build_solver, cli_keys=(),
                 **kwargs):
        super().__init__(node_name, **kwargs)
        self.config = node_params.declare_all(self, where, cli_keys)
        node = self.config.node
        if self.config.solver == "dg":
            dg = self.config.dg
            self.get_logger().info("DG mesh: " + mesh_summary(dg.n_elements, dg.order, dg.cfl, dg.resolution, dg.snap_tolerance))
            caution = bending_mesh_warning(self.config.cable.length, dg.n_elements, dg.order, self.config.cable.EI,
                                           dg.element_lengths, damping=dg.damping)
            if caution:
                self.get_logger().warning("DG mesh: " + caution)
        self.inputs = {}
        self._last_log = {}  # key -> time.monotonic() of the last throttled log line
        self._rejected_unlogged = {}  # ("rejected", end, what) -> rejections since its last log line
        self._backoff = {}  # key -> (monotonic time of its last log line, gap to the next one)
        for end in END_NAMES:
            if getattr(self.config, f"{end}_end").kind == "prescribed" and not self._ship_from_sea(end):
                self._add_pose_input(end, getattr(node, f"{end}_attachment"))
        # numba compile / cache load in a worker thread: logged when slow, stoppable by SIGINT/SIGTERM
        run_interruptibly(lambda: warm_up(self, solver_factory), log=self.get_logger().info,
                          should_stop=lambda: not self.context.ok(), what=f"{self.config.solver} solver warm-up")
        self.driver = None
        self.driver = SimulationDriver(self.config, self._sources(), solver_factory=solver_factory,
                                       wall_budget=node.tick_budget / node.output_rate)
        self.arc_lengths = np.linspace(0.0, self.config.cable.length, node.output_points)
        self.pubs = {}
        for topic, (type_name, qos) in convert.TOPICS.items():
            end = topic.split("/")[1]
            if topic.endswith("sim_pose") and getattr(self.config, f"{end}_end").kind != "body":
                continue
            profile = LATCHED if qos == "latched" else EVENTS if "events" in topic or "warnings" in topic else RELIABLE
            self.pubs[topic] = self.create_publisher(_TYPES[type_name.rsplit("/", 1)[1]], convert.ros_name(topic), profile)
        self.tf = TfPublisher(self)  # /tf, /tf_static (tether_sim/ros/tf.py)
        self.snap_markers = SnapMarkerPublisher(self)  # tether/snap_markers, for RViz
        self.winch_io = NodeWinch(self)  # winch/command in, winch/state out (winch.enabled; ros/winch_io.py)
        self.forecast_io = NodeForecast(self, solver_factory)  # tether/snap_forecast (forecast.enabled; ros/forecast_io.py)
        # periodic outputs: built (and published) only while someone subscribes to them; the visual ones
        # (marker, path, /tf) only at node.visual_rate, and nothing of them is asked for in between
        self._tick_topics = [t for t in self.pubs if t in convert.SHAPE_TOPICS or t.endswith(("_wrench", "sim_pose"))]
        self._tick_pubs = [(t, self.pubs[t]) for t in self._tick_topics if t not in convert.VISUAL_TOPICS]
        self._visual_pubs = [(t, self.pubs[t]) for t in self._tick_topics if t in convert.VISUAL_TOPICS]
        self._shape_gate = convert.ShapeGate(node.shape_rate)
        # marker and path: at visual_rate among the outputs that carry the shape; /tf: among all outputs
        # (with shape_rate 0 the two gates see the same stamps and pick the same outputs)
        self._visual_gate, self._tf_gate = convert.ShapeGate(node.visual_rate), convert.ShapeGate(node.visual_rate)
        self._first_tick = None
        self._state_every_output = False  # /tether/state had a subscriber at the last output, at every output
        self.tick_errors, self.last_tick_error = 0, ""
        self.snaps_published = 0
        self._last_output = -float("inf")
        # the output timer's grid (clock time of one of its periods' starts) and the period index of the last tick:
        # a tick late by whole periods also publishes the instants of the periods the timer skipped
        self._grid, self._last_slot = None, None
        self._period = _new_period(self.inputs)
        self.add_on_set_parameters_callback(self._on_set_parameters)
        self._output_timer = self.create_timer(1.0 / node.output_rate, self._on_timer)
        self.create_timer(1.0, self._publish_diagnostics)

    def destroy_node(self):
        if getattr(self, "forecast_io", None) is not None:
            self.forecast_io.close()  # stops the look-ahead worker thread
        return super().destroy_node()

    def _ship_from_sea(self, end) -> bool:
        """The ship end follows the RAO response to the configured sea (motion.kind rao), not a pose topic."""
        return end == "ship" and self.config.motion.kind == "rao"

    def _sources(self) -> dict:
        """The driver's end sources: the pose inputs, and the RAO ship motion (in solver time) if configured."""
        sources = dict(self.inputs)
        if getattr(self.config, "ship_end").kind == "prescribed" and self._ship_from_sea("ship"):
            from tether_sim.physics.motion import build_motion
            from tether_sim.physics.waves import wave_components

            try:
                motion = build_motion(self.config.motion, self.config.ship_end.position, wave_components(self.config))
            except (ValueError, OSError) as exc:
                raise ConfigError(f"motion.kind rao: {exc}") from exc
            sources["ship"] = SolverTimeMotion(motion, lambda: self.driver)
            self.get_logger().info(f"ship end: RAO response to the {self.config.waves.kind} sea "
                                   f"({self.config.motion.rao_path}); ship/pose is not subscribed")
        return sources

    def _add_pose_input(self, name, attachment):
        """An EndPoseInput for the driven end or point ``name`` (``self.inputs[name]``) and its
        ``<name>/pose`` and ``<name>/twist`` subscriptions (best effort, sensor data QoS)."""
        self.inputs[name] = EndPoseInput.for_node(name, self.config.node, attachment)
        self.create_subscription(PoseStamped, f"{name}/pose", lambda m, e=name: self._on_pose(e, m),
                                 qos_profile_sensor_data)
        self.create_subscription(TwistStamped, f"{name}/twist", lambda m, e=name: self._on_twist(e, m),
                                 qos_profile_sensor_data)

    # ------------------------------------------------------------------ inputs
    def _now(self) -> float:
        return self.get_clock().now().nanoseconds * 1e-9

    def _log_throttled(self, key, level, text):
        """Log ``text`` at most once per WARN_PERIOD s per ``key``. (rclpy's own throttle filter
        inspects the caller's source frame on every call, ~1-2 ms even when it drops the message:
        that made every capped tick ~1 ms dearer.)"""
        t = time.monotonic()
        if t - self._last_log.get(key, -math.inf) < WARN_PERIOD:
            return
        self._last_log[key] = t
        # one call line per severity: rclpy refuses two severities from the same call site
        # ("Logger severity cannot be changed between calls"), which made a failing tick raise here
        if level == "error":
            self.get_logger().error(text)
        else:
            self.get_logger().warning(text)

    def _log_backoff(self, key, text):
        """Log ``text`` (a warning) at once, then again after WARN_PERIOD, 2 WARN_PERIOD, 4 WARN_PERIOD ...
        s, at most STALE_LOG_MAX s apart, while the condition lasts (its caller drops ``key`` from
        ``_backoff`` when it ends: the next episode is logged at once). /diagnostics reports the
        condition every period meanwhile."""
        t = _monotonic()
        last, gap = self._backoff.get(key, (None, 0.0))
        if last is not None and t - last < gap:
            return
        gap = WARN_PERIOD if last is None else min(2.0 * gap, STALE_LOG_MAX)
        self._backoff[key] = (t, gap)
        self.get_logger().warning(f"{text} (next reminder in {gap:g} s, then at doubling intervals up to "
                                  f"{STALE_LOG_MAX:g} s; /diagnostics reports the input every second)")

    def _reject(self, end, what, reason):
        """Count a rejected input; the first of a kind is logged at once with its reason, repeats
        once per REJECT_SUMMARY_PERIOD as a count (a stream of wrong poses is one line, not 50 a second)."""
        self._period["rejected"][end] += 1
        key = ("rejected", end, what)
        self._rejected_unlogged[key] = self._rejected_unlogged.get(key, 0) + 1
        t, last = time.monotonic(), self._last_log.get(key)
        if last is not None and t - last < REJECT_SUMMARY_PERIOD:
            return
        count = self._rejected_unlogged.pop(key)
        self._last_log[key] = t
        if last is None:
            self.get_logger().warning(f"{end} {what} rejected: {reason}")
        else:
            self.get_logger().warning(f"{end} {what}: {count} rejected in the last {t - last:.0f} s, the latest: {reason}")

    def _on_pose(self, end, msg: PoseStamped):
        frame = msg.header.frame_id
        if frame and frame.lstrip("/") != self.config.node.world_frame.lstrip("/"):
            self.inputs[end].rejected["wrong frame"] += 1
            world = self.config.node.world_frame
            return self._reject(end, "pose", f"frame {frame!r} is not the world frame {world!r}: poses must be expressed in "
                                f"node.world_frame (publish them in {world!r}, or start the node with "
                                f"-p node.world_frame:={frame.lstrip('/')})")
        now = self._now()
        stamp = convert.to_seconds(msg.header.stamp) or now
        p, q = msg.pose.position, msg.pose.orientation
        reason = self.inputs[end].add_pose(stamp, (p.x, p.y, p.z), (q.x, q.y, q.z, q.w), now=now if now > 0.0 else None)
        if reason is not None:
            self._reject(end, "pose", reason)

    def _on_twist(self, end, msg: TwistStamped):
        now = self._now()
        stamp = convert.to_seconds(msg.header.stamp) or now
        frame = msg.header.frame_id.lstrip("/")
        body = bool(frame) and frame != self.config.node.world_frame.lstrip("/")
        lin, ang = msg.twist.linear, msg.twist.angular
        reason = self.inputs[end].add_twist(stamp, (lin.x, lin.y, lin.z), (ang.x, ang.y, ang.z), body_frame=body,
                                            now=now if now > 0.0 else None)
        if reason is not None:
            self._reject(end, "twist", reason)

    # ------------------------------------------------------------------ stepping
    def _ready(self, now) -> bool:
        if self._first_tick is None:
            self._first_tick = now
        if all(inp.has_data for inp in self.inputs.values()):
            return True
        return now - self._first_tick >= self.config.node.input_timeout

    def _on_timer(self):
        """The output timer's callback: its grid read once (rcl keeps the timer on the grid of its first
        period: a call late by more than a period skips the periods it missed), then :meth:`_on_tick`."""
        if self._grid is None:
            now = self._now()
            until = self._output_timer.time_until_next_call()  # ns to the timer's next period start
            if until is not None and now > 0.0:
                self._grid = now + until * 1e-9
        self._on_tick()

    def _on_tick(self):
        wall0 = time.perf_counter()
        try:
            self._tick()
        finally:  # wall time inside the tick: the node's compute load (diagnostics tick_load)
            busy = time.perf_counter() - wall0
            self._period["busy"] += busy
            self._period["tick_max"] = max(self._period["tick_max"], busy)

    def _tick(self):
        now = self._now()
        if now <= 0.0:
            return  # use_sim_time and no /clock yet
        if self.driver.solver is None:
            if not self._ready(now):
                return
            missing = [e for e, inp in self.inputs.items() if not inp.has_data]
            if missing:
                self.get_logger().warning(f"starting without {', '.join(missing)} pose(s): holding the configured positions")
            self.driver.start(now)
            self._publish_description()
            self.get_logger().info(f"{self.config.solver} solver started; static end tensions "
                                   f"{self.driver.static_tensions[0]:.1f} N (ship), {self.driver.static_tensions[1]:.1f} N (vehicle)")
            if getattr(self.driver.solver, "start_warning", ""):
                self.get_logger().warning(self.driver.solver.start_warning)
        self._outputs_catching_up(now)

    def _outputs_catching_up(self, now):
        """The outputs of the output periods the timer skipped (:meth:`_missed_instants`), each stepped to
        and published by ``_output_at`` as a tick of its own, then those of ``now`` (the network node's too)."""
        start, budget = time.perf_counter(), self.driver.wall_budget
        missed = self._missed_instants(now)
        self.driver.catching_up = bool(missed)  # (the real-time factor then spans the whole tick)
        try:
            for t in missed:  # (they share the tick's stepping budget)
                if not self._output_at(t) or (budget is not None and time.perf_counter() - start > budget):
                    break
        finally:
            self.driver.catching_up = False
        self._output_at(now)

    def _missed_instants(self, now) -> list:
        """Clock times of the output periods the timer skipped before this tick (a starved process: the
        timer's call came more than a period late), the latest ``node.missed_outputs`` of them, spaced one output
        period apart before ``now``; none while the simulation runs late (its outputs are late anyway), after
        a gap beyond ``node.max_lag`` (a re-synchronisation) or a clock jump. Each is stepped to and published
        as a tick of its own: a subscriber gets one state per output period through scheduler stalls."""
        rate, most = self.config.node.output_rate, self.config.node.missed_outputs
        if self._grid is None:  # (driven by hand, without the timer: the first tick is on the grid)
            self._grid = now
        slot = math.floor((now - self._grid) * rate + 1e-6)
        last, self._last_slot = self._last_slot, slot
        d = self.driver
        if last is None or d.last_now is None:  # (the driver's last clock time minus the input delay: none before its start)
            return []
        missed = min(slot - last - 1, most)
        if (missed <= 0 or d.lag > 1.5 / rate
                or now - self.config.node.input_delay - d.last_now > self.config.node.max_lag):
            return []
        return [now - j / rate for j in range(missed, 0, -1)]

    def _output_at(self, now) -> bool:
        """Step the driver to clock time ``now`` and publish the outputs of the state it reaches; False
        when the tick failed or fell short of ``now`` (the stepping budget)."""
        try:
            # the state at the output points, sampled once for snap detection and /tether/state (node.shape_rate 0)
            self.driver.output_points = self.arc_lengths if self._state_every_output else None
            report = self.driver.tick(now)
            self._handle_report(now, report)
            if self.driver.stamp > max(self._last_output, 0.0):  # one output per simulated instant
                self._last_output = self.driver.stamp
                self.arc_lengths = self.winch_io.tick(self.arc_lengths)  # outputs follow L(t) (winch)
                stamp = self.driver.stamp
                wanted = {topic for topic, pub in self._tick_pubs if pub.get_subscription_count() > 0}
                self._state_every_output = self.config.node.shape_rate <= 0.0 and "/tether/state" in wanted
                shapes = self._shape_gate.due(stamp)  # node.shape_rate
                if shapes and self._visual_gate.due(stamp):  # node.visual_rate: marker and path
                    wanted.update(topic for topic, pub in self._visual_pubs if pub.get_subscription_count() > 0)
                frame = convert.OutputFrame(self.driver)  # what the outputs and /tf share
                for topic, data in convert.tick_outputs(self.driver, self.arc_lengths, wanted, frame, shapes):
                    self.pubs[topic].publish(data)
                self.tf.publish(self.driver, frame, self._tf_gate.due(stamp))  # /tf at node.visual_rate
                self.forecast_io.tick(now)  # hands a due forecast to its worker thread; publishes finished ones
            return not report.capped
        except Exception as exc:  # noqa: BLE001 - the node must stay up; the error is reported
            if not self.context.ok():
                return False  # shutting down (Ctrl-C): publishers are gone
            self._period["tick_errors"] += 1
            self.tick_errors += 1
            self.last_tick_error = f"{type(exc).__name__}: {exc}"
            self._log_throttled("tick failed", "error", f"tick failed (not a solver divergence): {self.last_tick_error}")
            return False

    def _handle_report(self, now, report):
        log = self.get_logger()
        if report.error:
            self._period["errors"] += 1
            log.error(f"solver diverged ({report.error}); recovered from {'the last snapshot' if report.recovery == 'snapshot' else 'a fresh static equilibrium'}")
            self._publish_diagnostics()
        if report.restart:
            log.warning(f"{report.restart}: solver restarted from a static equilibrium at the new end positions")
            self._publish_description()
        if report.clock_jump:
            self._last_output = -float("inf")
            self._grid = self._last_slot = None  # (the timer starts a new grid after a jump)
            log.warning("clock jumped backwards: pose histories reset, simulation continues")
        if report.dropped > 0:
            self._period["resyncs"] += 1
            log.warning(f"{report.dropped:.3f} s behind the clock (beyond node.max_lag): re-synchronised to the newest "
                        "inputs, cable state kept, ends blended; snap events across the gap are marked degraded")
        for end, duration, reason in report.blends:
            self._log_throttled(("blend", end), "warning", f"{end} end blended onto its pose input over {duration:.2f} s ({reason})")
        if report.degraded and report.lag > 0.0:  # (a capped tick within 1.5 periods is on time: not degraded, not logged)
            self._period["behind"] = True
            self._log_throttled("behind", "warning", f"cannot keep up with the clock: outputs {report.lag:.3f} s late "
                                "(stamped with the simulated instant, marked degraded)")
        for end, inp in self.inputs.items():
            if inp.is_stale(now):
                age, rejected = inp.age(now), sum(inp.rejected.values())
                text = f"{end} pose input stale (newest accepted pose {age:.3g} s old)" if math.isfinite(age) \
                    else f"no {end} pose accepted yet"
                if rejected:
                    text += f"; {rejected} rejected so far (see the rejection warnings)"
                self._log_backoff(("stale", end), f"{text}: holding/extrapolating")
            else:
                self._backoff.pop(("stale", end), None)
        for ev in report.events:
            if isinstance(ev, NumericalSnapWarning):
                self._period["numerical"] += 1
                log.warning(f"re-tensioning at {ev.location} rejected by the snap guard (numerical, not a snap): "
                            f"{ev.reason}")
        for topic, msg in convert.event_outputs(report.events, self.driver) if report.events else ():
            if topic == "/tether/snap_events":
                self._period["snaps"] += 1
                self.snaps_published += 1
                log.warning(f"snap load at {msg.end}: peak {msg.peak_tension:.1f} N ({msg.amplification:.2f} x static)")
            self.pubs[topic].publish(msg)
            if topic == "/tether/snap_events":
                self.snap_markers.publish(msg, self.driver)

    # ------------------------------------------------------------------ parameters, description, diagnostics
    def _on_set_parameters(self, parameters):
        for p in parameters:  # (runs before rclpy's own time-source callback, which never sees a refused change)
            if p.name == "use_sim_time" and bool(p.value) != bool(self.get_parameter("use_sim_time").value):
                return SetParametersResult(successful=False, reason=(
                    "use_sim_time cannot change while the node runs (the solver's clock would switch between "
                    "wall time and /clock mid-run); restart the node with -p use_sim_time:="
                    f"{'true' if p.value else 'false'}"))
        result, config = node_params.check_live_change(parameters, self.config)
        if config is not None:
            self.config = config
            self.driver.set_snap_config(config.snap)
            if self.driver.solver is not None:
                self._publish_description()
        return result

    def _check_undeclared_parameters(self, parameter_list):
        """rclpy's own check consumes its generator in ``any()`` and so answers "undeclared
        parameter(s): []"; name the parameters (and the closest known key) instead."""
        unknown = [p.name for p in parameter_list if isinstance(p, Parameter) and p.name not in self._parameters]
        if unknown:
            hints = [difflib.get_close_matches(name, list(self._parameters), n=1, cutoff=0.7) for name in unknown]
            text = ", ".join(f"{n!r}" + (f" (did you mean {h[0]!r}?)" if h else "") for n, h in zip(unknown, hints))
            raise ParameterNotDeclaredException(f"{text}; tether_sim declares every key of docs/parameters.md")
        super()._check_undeclared_parameters(parameter_list)

    def account(self) -> str:
        """One line on what the node did, for its exit: clock time simulated, re-synchronisations,
        snap events published, failed ticks."""
        d = self.driver
        if d is None or d.solver is None:
            return "the solver had not started"
        ran = d.last_now - (self._first_tick or d.last_now)
        return (f"ran {ran:.1f} s of clock time, outputs up to stamp {d.stamp:.3f} s; "
                f"{d.resyncs} re-synchronisation(s), {self.snaps_published} snap event(s) published, "
                f"{self.tick_errors} failed tick(s)")

    def _publish_description(self):
        self.pubs["/tether/description"].publish(convert.description(self.config, self.arc_lengths, self._now()))

    def _publish_diagnostics(self):
        now, d, p = self._now(), self.driver, self._period
        running = d.solver is not None
        sim = {"running": running, "real_time_factor": float(d.real_time_factor),
               "time_step": float(d.solver.stable_time_step()) if running else 0.0,
               "lag": float(d.lag) if running else 0.0, "input_delay": float(self.config.node.input_delay),
               "degraded": bool(d.degraded), "dropped_total": float(d.dropped_total), "resyncs": d.resyncs,
               "resyncs_recent": p["resyncs"], "capped_ticks": d.capped_ticks, "behind": p["behind"],
               "divergences": d.divergences, "error_recent": p["errors"] > 0, "last_error": d.last_error or "",
               "tick_errors": self.tick_errors, "tick_errors_recent": p["tick_errors"],
               "last_tick_error": self.last_tick_error, "snaps": self.snaps_published, "snaps_recent": p["snaps"], "slack": dict(d.slack),
               "numerical_snaps": d.numerical_snaps, "numerical_snaps_recent": p["numerical"],
               "last_numerical_snap": d.last_numerical_snap,
               "tick_load": p["busy"] / max(time.perf_counter() - p["wall0"], 1e-9), "tick_max_ms": 1e3 * p["tick_max"]}
        inputs = {}
        for end, inp in self.inputs.items():
            inputs[end] = inp.health(now)
            inputs[end]["rejected_recent"] = p["rejected"][end]
        self.pubs["/diagnostics"].publish(
            self.forecast_io.add_status(convert.diagnostics(now, self.get_fully_qualified_name(), sim, inputs)))
        self._period = _new_period(self.inputs)


def _new_period(inputs) -> dict:
    """Counters of one diagnostics period."""
    return {"snaps": 0, "numerical": 0, "errors": 0, "tick_errors": 0, "resyncs": 0, "rejected": {e: 0 for e in inputs},
            "behind": False, "busy": 0.0, "tick_max": 0.0, "wall0": time.perf_counter()}


def main(args=None):
    argv = list(sys.argv if args is None else args)
    if wants_help(argv):
        print(USAGE)
        return 0
    stray = rclpy.utilities.remove_ros_args(argv)[1:]
    if stray:  # e.g. `--params FILE` (tether-sim-offline's form): rclpy would ignore it and run the defaults
        print(f"tether-sim: unknown argument(s) {' '.join(stray)}: the node takes its parameters as ROS arguments, "
              "e.g. tether-sim --ros-args --params-file FILE.yaml -p key:=value (tether-sim --help)", file=sys.stderr)
        return 2
    files = params_files(argv)
    from tether_sim.network.params import file_is_network, load_network_files

    network = any(file_is_network(f) for f in files)  # a line network (docs/network.md): its own node
    try:
        if network:
            load_network_files(files, cli_param_values(argv))
        else:
            check_params_files(files, cli_param_values(argv))
    except ConfigError as exc:
        print(f"tether-sim: parameter error: {exc}", file=sys.stderr)
        return 2
    # a namespaced / renamed node still gets the files' `tether_sim:` sections (namespacing.py)
    argv = retarget(argv, log=lambda text: print(f"tether-sim: {text}", file=sys.stderr))
    rclpy.init(args=argv)
    node = None
    stopping = False  # by a signal: further ones are ignored
    try:
        if network:
            from tether_sim.ros.network_node import NetworkSimNode

            node = NetworkSimNode(files=files, overrides=cli_param_values(argv))
        else:
            node = TetherSimNode(where=", ".join(files) or "command-line parameters", cli_keys=cli_param_keys(argv))
        if not network and node.config.node.executor == "events":  # rclpy's C++ EventsExecutor (node.executor)
            from rclpy.experimental import EventsExecutor

            executor = EventsExecutor()
        else:
            executor = SingleThreadedExecutor()
        got = spin_until_signal(node, executor)
        stopping = True  # by a signal, or the context was shut down by someone else
        ignore_further_signals()
        say_stopped(node, got or "SIGINT/SIGTERM (an rclpy shutdown)")
    except (KeyboardInterrupt, ExternalShutdownException) as exc:
        stopping = True
        ignore_further_signals()
        exit_if_compiling(0)  # SIGINT during the start-up compile: leave without waiting for it
        # rclpy's own handlers turn SIGINT as well as SIGTERM into a shutdown (ExternalShutdownException),
        # whichever reaches spin first: only a KeyboardInterrupt names its signal for sure
        say_stopped(node, "SIGINT" if isinstance(exc, KeyboardInterrupt) else "SIGINT/SIGTERM (an rclpy shutdown)")
    except Interrupted as exc:  # SIGTERM during the start-up compile
        print(f"tether-sim: {exc}", file=sys.stderr)
        exit_if_compiling(0)
    except Exception as exc:
        if not rclpy.ok():  # SIGINT/SIGTERM arrived while a callback was publishing: a normal shutdown
            stopping = True
            ignore_further_signals()
            say_stopped(node, "SIGINT/SIGTERM (an rclpy shutdown)")
        elif isinstance(exc, ConfigError):
            print(f"tether-sim: parameter error: {exc}", file=sys.stderr)
            return 2
        elif isinstance(exc, (ValueError, TetherSimError)):  # the solver could not be built at start-up
            print(f"tether-sim: cannot start the solver for this configuration: {exc}", file=sys.stderr)
            return 2
        else:
            raise
    finally:
        if node is not None:
            node.destroy_node()
        if rclpy.ok():
            rclpy.shutdown()
        if stopping:  # rclpy's shutdown puts back the handlers it found at init
            ignore_further_signals()
    return 0


if __name__ == "__main__":
    sys.exit(main())
