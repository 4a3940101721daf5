"""Offline runner (console script ``tether-sim-offline``): the node's solver and messages, straight to MCAP.

    tether-sim-offline --params FILE [--duration S] [--input POSES.mcap] --output OUT.mcap

No DDS: the same :class:`SimulationDriver` and :mod:`tether_sim.ros.convert` messages as the node,
serialized with ``rclpy.serialization`` and written by :class:`tether_sim.io.mcap_log.RosMcapWriter`
with log time = publish time = the state's clock time, as fast as the machine allows.

Clock: with ``--input`` the clock is the pose stamps (the run starts at the first pose); otherwise
the clock starts at 0 and the ship end (if ``prescribed``) follows ``motion`` of the parameter file.
Unlike the node, the offline run never drops lag: every tick is simulated to its target time.
The file also holds /tf_static (once, at the first output) and /tf (every output) as the node
publishes them (``node.publish_tf``; :mod:`tether_sim.ros.tf`).

A line-network file (a ``network`` section, config/ropos_tms.yaml) runs the network node's driver
and messages instead: per-line topics, the cage, the winches (:mod:`tether_sim.ros.network_offline`).
"""

import argparse
import math
import sys
import time as wallclock
from dataclasses import replace
from pathlib import Path

import numpy as np
from rclpy.serialization import serialize_message
from tqdm import tqdm

from tether_sim.errors import ConfigError, TetherSimError
from tether_sim.io.inputs import EndPoseInput, knot_spacing
from tether_sim.io.params import load_config
from tether_sim.ros import cdr, convert, forecast_io, winch_io
from tether_sim.ros import tf as tf_out
from tether_sim.ros.driver import END_NAMES, MotionSource, SimulationDriver
from tether_sim.solvers.factory import build_solver
from tether_sim.solvers.work import run_estimate
from tether_sim.stopping import SignalStop, interrupted_code

class RecordedPoses:
    """Pose (and twist) samples of one end from an MCAP, fed to an EndPoseInput ahead of the clock."""

    def __init__(self, inp: EndPoseInput, poses: list, twists: list):
        self.input = inp
        self.poses = sorted(poses, key=lambda x: x[0])  # (stamp, position, orientation)
        self.twists = sorted(twists, key=lambda x: x[0])  # (stamp, linear, angular, body_frame)
        self._i = self._j = 0

    def feed_until(self, t: float) -> None:
        """Offer every sample up to and including the first one after ``t`` (so t is interpolated)."""
        while self._j < len(self.twists) and self.twists[self._j][0] <= t:
            s, lin, ang, body = self.twists[self._j]
            self.input.add_twist(s, lin, ang, body_frame=body)
            self._j += 1
        while self._i < len(self.poses):
            stamp, p, q = self.poses[self._i]
            self.input.add_pose(stamp, p, q)
            self._i += 1
            if stamp > t:
                break


def read_pose_inputs(path, config, topics) -> dict:
    """end -> RecordedPoses for the prescribed ends, from an MCAP of PoseStamped/TwistStamped."""
    node = config.node
    wanted = {end: (topics[end], getattr(node, f"{end}_attachment")) for end in END_NAMES
              if getattr(config, f"{end}_end").kind == "prescribed"}
    return read_poses(path, wanted, node)


def read_poses(path, wanted: dict, node, required: bool = True) -> dict:
    """name -> RecordedPoses from an MCAP of PoseStamped (and optional TwistStamped on the sibling
    ``.../twist`` topic); ``wanted``: {name: (pose topic, attachment)}. ``required``: a name without
    poses is a ConfigError (else it is left out)."""
    from tether_sim.io.mcap_log import read_messages

    by_topic = {}
    for name, (topic, _) in wanted.items():
        by_topic[topic] = (name, "pose")
        by_topic[topic.rsplit("/", 1)[0] + "/twist"] = (name, "twist")
    poses = {name: [] for name in wanted}
    twists = {name: [] for name in wanted}
    for topic, _type, log_ns, msg in read_messages(str(path), topics=list(by_topic)):
        name, kind = by_topic[topic]
        stamp = msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9 or log_ns * 1e-9
        if kind == "pose":
            p, q = msg.pose.position, msg.pose.orientation
            poses[name].append((stamp, (p.x, p.y, p.z), (q.x, q.y, q.z, q.w)))
        else:
            lin, ang = msg.twist.linear, msg.twist.angular
            body = bool(msg.header.frame_id) and msg.header.frame_id.lstrip("/") != node.world_frame.lstrip("/")
            twists[name].append((stamp, (lin.x, lin.y, lin.z), (ang.x, ang.y, ang.z), body))
    out = {}
    for name, (topic, attachment) in wanted.items():
        if not poses[name]:
            if required:
                raise ConfigError(f"{path}: no PoseStamped messages on {topic} for the prescribed {name} end")
            continue
        inp = EndPoseInput(name, attachment, max_end_speed=node.max_end_speed, input_timeout=node.input_timeout,
                           max_extrapolation=node.max_extrapolation, min_spacing=knot_spacing(node.output_rate))
        out[name] = RecordedPoses(inp, poses[name], twists[name])
    return out


class _NoMcap:
    """Stands in for the MCAP writer when no file is wanted (a study case that keeps only its table)."""

    def __enter__(self):
        return self

    def __exit__(self, *exc_info):
        return None

    def add_topic(self, *args, **kwargs):
        return 0

    def write(self, *args, **kwargs):
        return None

    def write_many(self, *args, **kwargs):
        return None


def run_offline(config, output, *, duration=None, input_path=None, topics=None, progress=True,
                solver_factory=build_solver, stop=None, announce=None) -> dict:
    """Simulate and write every output topic to ``output`` (MCAP; ``None``: serialize, write no file).

    ``stop``: a :class:`tether_sim.stopping.SignalStop`; it is made graceful once the solver has
    started (the file opens then), and a stop request ends the run after the current tick with the
    file closed as at a normal end (``interrupted`` in the summary: the signal's name).
    ``announce``: called with one line (:func:`run_estimate`) before the run starts.
    Returns a summary dict; ``events`` holds the detector's SlackStarted / SnapEvent objects."""
    from tether_sim.io.mcap_log import RosMcapWriter

    topics = topics or {"ship": "/ship/pose", "vehicle": "/vehicle/pose"}
    # offline: never drop lag, never cap a tick (the loop below repeats a tick until it is done);
    # no input delay: the recorded poses are fed one sample ahead of the clock
    config = replace(config, node=replace(config.node, max_lag=math.inf, input_delay=0.0))
    sources, recorded, t0, duration = _inputs(config, input_path, topics, duration)
    # (the recorded poses are the scenario: applied from the first instant, no start-up blend)
    driver = SimulationDriver(config, sources, solver_factory=solver_factory, start_blend=False)
    forecaster = None
    if config.forecast.enabled:  # the node's forecasts, run inline on the runner's tick grid (docs/forecast.md)
        from tether_sim.forecast.service import ForecastService

        forecaster = ForecastService(config, solver_factory=solver_factory)
    rate = config.node.output_rate
    n_ticks = max(1, int(round(duration * rate)))
    expected = math.nan
    if announce is not None:
        expected, line = run_estimate(config, duration)
        announce(line)
    wall0, cpu0 = wallclock.perf_counter(), wallclock.process_time()
    driver.start(t0)  # (the numba compile and the static solve: before the file exists, so a signal stops at once)
    if getattr(driver.solver, "start_warning", ""):
        print(f"tether-sim-offline: warning: {driver.solver.start_warning}", file=sys.stderr)
    if stop is not None:
        stop.graceful = True  # from here on a signal only asks the loop below to end and close the file
    done = 0
    with RosMcapWriter(str(output)) if output is not None else _NoMcap() as writer:
        run = _OfflineOutputs(writer, driver, config)
        run.write([("/tether/description", convert.description(config, run.arc, t0))])
        run.write_tick()
        next_diag = t0 + 1.0
        for k, now in tick_clock(t0, rate, n_ticks, recorded, stop, progress):
            while True:
                report = driver.tick(now)
                run.events.extend(report.events)
                run.write(convert.event_outputs(report.events, driver))
                run.counts["divergences"] += report.error is not None
                if not report.capped:
                    break
            run.write_tick()
            if forecaster is not None:
                forecaster.observe(driver, clock_origin=t0, tick_index=k)
                run.write_forecasts(forecaster.poll())
            if now >= next_diag:
                next_diag += 1.0
                run.write_diagnostics(now, report, sources, forecaster)
            done = k
        run.flush()
    wall, cpu = wallclock.perf_counter() - wall0, wallclock.process_time() - cpu0
    interrupted = stop.name if stop is not None and stop.requested and done < n_ticks else ""
    simulated = done / rate if interrupted else duration
    return {"output": str(output) if output is not None else None, "duration": simulated, "ticks": done,
            "planned_duration": duration, "interrupted": interrupted, "wall_time": wall, "cpu_time": cpu,
            "expected_cpu": expected,
            "speed": simulated / wall if wall > 0 else math.inf,
            "messages": getattr(writer, "message_count", None), "static_tensions": driver.static_tensions,
            "snap_peaks": run.peaks, "events": run.events, "forecasts": run.forecasts, **run.counts,
            "numerical_snaps": driver.numerical_snaps}


def tick_clock(t0, rate, n_ticks, recorded, stop=None, progress=True):
    """(k, clock time) of the ticks k = 1 ... n_ticks of an offline run at ``rate``, with the
    recorded poses fed up to each tick's time; ends early when ``stop`` is requested; a progress bar."""
    bar = tqdm(total=n_ticks, unit="tick", disable=not progress, desc="tether-sim-offline")
    try:
        for k in range(1, n_ticks + 1):
            if stop is not None and stop.requested:
                return
            now = t0 + k / rate
            for r in recorded.values():
                r.feed_until(now)
            yield k, now
            bar.update(1)
    finally:
        bar.close()


def _inputs(config, input_path, topics, duration):
    """(sources, recorded inputs, t0, duration): the recorded poses of ``input_path`` (clock from the
    first pose, default duration their span) or the analytic ``motion`` of the file (clock from 0)."""
    recorded = read_pose_inputs(input_path, config, topics) if input_path else {}
    if recorded:
        sources = {end: r.input for end, r in recorded.items()}
        t0 = min(r.poses[0][0] for r in recorded.values())
        t_last = max(r.poses[-1][0] for r in recorded.values())
        duration = min(config.duration, t_last - t0) if duration is None else duration
    else:
        sources = {}
        if config.ship_end.kind == "prescribed" and config.motion.kind != "none":
            from tether_sim.physics.motion import build_motion
            from tether_sim.physics.waves import wave_components

            sources["ship"] = MotionSource(build_motion(config.motion, np.asarray(config.ship_end.position, float),
                                                        wave_components(config)))
        t0 = 0.0
        duration = config.duration if duration is None else duration
    for r in recorded.values():
        r.feed_until(t0)
    return sources, recorded, t0, duration


class _OfflineOutputs:
    """What run_offline writes: the node's topics into ``writer`` (log time = publish time = stamp),
    with the counts, snap peaks and events of the run."""

    def __init__(self, writer, driver, config):
        self.writer, self.driver = writer, driver
        self.arc = np.linspace(0.0, config.cable.length, config.node.output_points)
        self.counts = {"snap_events": 0, "slack_warnings": 0, "divergences": 0, "numerical_snaps": 0}
        self._numerical_written = self._snaps_written = 0
        self.peaks, self.events, self.forecasts = [], [], []
        self.frame = config.node.world_frame
        self.static_written = False
        self.shape_gate = convert.ShapeGate(config.node.shape_rate)
        for topic, (type_name, qos) in convert.TOPICS.items():
            if topic.endswith("sim_pose") and getattr(config, f"{topic.split('/')[1]}_end").kind != "body":
                continue
            writer.add_topic(topic, type_name, qos)
        for topic, (type_name, qos) in (winch_io.TOPICS.items() if config.winch.enabled else ()):
            writer.add_topic(topic, type_name, qos)
        for topic, (type_name, qos) in (forecast_io.TOPICS.items() if config.forecast.enabled else ()):
            writer.add_topic(topic, type_name, qos)
        # /tf and /tf_static as the node publishes them (tf.py), so that RViz and Foxglove place the
        # body-frame wrenches and the frames of a file written here as in a recording of the node
        self.tf = config.node.publish_tf and tf_out.TFMessage is not None
        if self.tf:
            writer.add_topic("/tf", "tf2_msgs/msg/TFMessage", "reliable")
            writer.add_topic("/tf_static", "tf2_msgs/msg/TFMessage", "latched")

    def write(self, items):
        for topic, msg in items:
            t = convert.to_seconds(msg.header.stamp)
            ns = int(round(t * 1e9))
            self.writer.write(topic, serialize_message(msg), ns, ns)
            if topic == "/tether/snap_events":
                self.counts["snap_events"] += 1
                self.peaks.append((msg.end, msg.peak_tension, msg.amplification, t))
            elif topic == "/tether/slack_warnings":
                self.counts["slack_warnings"] += 1

    def write_tick(self):
        """The periodic outputs (already serialized), log time = their stamp."""
        driver = self.driver
        self.arc, winch_items = winch_io.offline_outputs(driver, self.arc)  # winch: points on [0, L(t)], its topics
        self.write(winch_items)
        sec, nanosec = cdr.stamp_parts(driver.stamp)
        ns = sec * 1_000_000_000 + nanosec
        frame = convert.OutputFrame(driver)  # what the outputs and /tf share
        shapes = self.shape_gate.due(driver.stamp)  # node.shape_rate, as the node
        for topic, data in convert.tick_outputs(driver, self.arc, None, frame, shapes):
            self.writer.write(topic, data, ns, ns)
        if self.tf:
            if not self.static_written:  # once, at the first output, as the node's latched /tf_static
                static = tf_out.TFMessage(transforms=tf_out.static_transforms(driver, driver.stamp))
                self.writer.write("/tf_static", serialize_message(static), ns, ns)
                self.static_written = True
            self.writer.write("/tf", tf_out.tf_message_cdr(driver.stamp, driver.config.node.world_frame,
                                                           tf_out.dynamic_transforms(driver, frame)), ns, ns)

    def write_forecasts(self, forecasts):
        """SnapForecast messages of finished forecasts (log time = their stamp, the state they start from)."""
        self.forecasts.extend(forecasts)
        self.write([("/tether/snap_forecast", forecast_io.forecast_message(f, self.frame)) for f in forecasts])

    def write_diagnostics(self, now, report, sources, forecaster=None):
        driver = self.driver
        sim = {"running": True, "real_time_factor": driver.real_time_factor,
               "time_step": driver.solver.stable_time_step(), "lag": 0.0, "degraded": driver.degraded,
               "divergences": driver.divergences,
               "error_recent": report.error is not None, "last_error": driver.last_error or "",
               "snaps": self.counts["snap_events"], "snaps_recent": self.counts["snap_events"] - self._snaps_written,
               "slack": dict(driver.slack), "numerical_snaps": driver.numerical_snaps,
               "numerical_snaps_recent": driver.numerical_snaps - self._numerical_written,
               "last_numerical_snap": driver.last_numerical_snap}
        self._numerical_written, self._snaps_written = driver.numerical_snaps, self.counts["snap_events"]
        health = {end: dict(src.health(now), rejected_recent=0) for end, src in sources.items()
                  if isinstance(src, EndPoseInput)}
        array = convert.diagnostics(now, "tether_sim_offline", sim, health)
        if forecaster is not None:
            array.status.append(forecast_io.status(forecaster, "tether_sim_offline"))
        self.write([("/diagnostics", array)])

    def flush(self):
        """Close the detectors' open re-tensioning windows (end of the run) and write those events."""
        for detector in (self.driver.detector, self.driver.span_detector):
            if detector is not None:
                flushed = detector.flush()
                self.driver.count_numerical(flushed)
                self.events.extend(flushed)
                self.write(convert.event_outputs(flushed, self.driver))



def check_output_path(output) -> None:
    """ConfigError when ``output`` cannot be a file: a directory, or a folder on its path is a
    regular file (checked before the run, so no time is spent simulating into nowhere)."""
    path = Path(output)
    if path.is_dir():
        raise ConfigError(f"--output {output} is a directory; give a file name such as {path / 'run.mcap'}")
    for parent in path.parents:
        if parent.exists():
            if not parent.is_dir():
                raise ConfigError(f"--output {output}: {parent} is a regular file, not a directory")
            break


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="tether-sim-offline", description=__doc__.split("\n\n")[0])
    ap.add_argument("--params", required=True, help="parameter file (ROS layout, tether_sim: ros__parameters:)")
    ap.add_argument("--duration", type=float, default=None, help="simulated seconds (default: 'duration' of the file, "
                    "or the span of the input poses)")
    ap.add_argument("--input", default=None, help="MCAP with geometry_msgs/PoseStamped of the prescribed ends "
                    "(of a network file: of its driven points, /<point>/pose)")
    ap.add_argument("--output", required=True, help="output MCAP file")
    ap.add_argument("--ship-topic", default="/ship/pose",
                    help="PoseStamped topic of --input that drives the ship end (default: %(default)s)")
    ap.add_argument("--vehicle-topic", default="/vehicle/pose",
                    help="PoseStamped topic of --input that drives the vehicle end (default: %(default)s)")
    ap.add_argument("--no-progress", action="store_true", help="no progress bar")
    args = ap.parse_args(argv)
    stop = SignalStop("tether-sim-offline")
    try:
        with stop:
            summary = _run_main(args, stop)
    except KeyboardInterrupt as exc:  # a signal before the output file was opened: nothing written
        name, code = interrupted_code(exc)
        print(f"tether-sim-offline: stopped by {name} while starting (before the solver ran); "
              f"{args.output} not written", file=sys.stderr)
        return code
    except ConfigError as exc:
        print(f"tether-sim-offline: {exc}", file=sys.stderr)
        return 2
    except (ValueError, TetherSimError) as exc:  # a configuration the solver cannot build or start
        print(f"tether-sim-offline: cannot run this configuration: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:  # the output cannot be written (disk full, permissions, ...)
        print(f"tether-sim-offline: cannot write --output {args.output}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    s = summary
    if s.get("network"):
        from tether_sim.ros.network_offline import print_summary

        print_summary(s, sys.stderr)
        return stop.exit_code if s["interrupted"] else (1 if s["failed"] else 0)
    if s["interrupted"]:
        print(f"tether-sim-offline: stopped by {s['interrupted']} at {s['duration']:.6g} s of "
              f"{s['planned_duration']:.6g} s simulated ({s['ticks']} ticks); the file is complete up to there "
              "and closed", file=sys.stderr)
    took = f"{s['cpu_time']:.3g} s of CPU" + (f", {s['expected_cpu']:.2g} s expected" if math.isfinite(
        s.get("expected_cpu", math.nan)) else "")
    print(f"wrote {s['output']}: {s['duration']:.3g} s simulated in {s['wall_time']:.3g} s "
          f"({s['speed']:.3g} x real time; {took}); static tensions ship {s['static_tensions'][0]:.1f} N, "
          f"vehicle {s['static_tensions'][1]:.1f} N; {s['slack_warnings']} slack warnings, "
          f"{s['snap_events']} snap events, {s['divergences']} solver divergences (recovered)"
          + (f", {s['numerical_snaps']} re-tensioning peak(s) rejected by the snap guard as numerical (not snaps)"
             if s['numerical_snaps'] else ""))
    for end, peak, amp, t in s["snap_peaks"]:
        print(f"  snap at {end}: t = {t:.3f} s, peak {peak:.1f} N ({amp:.2f} x static)")
    if s["forecasts"]:
        warned = sum(f.probability >= 0.5 for f in s["forecasts"])
        print(f"  {len(s['forecasts'])} snap forecasts on /tether/snap_forecast ({warned} with probability >= 0.5, "
              f"{sum(f.degraded for f in s['forecasts'])} degraded)")
    return stop.exit_code if s["interrupted"] else 0


def _run_main(args, stop) -> dict:
    from tether_sim.network.params import file_is_network, load_network_files

    network = file_is_network(args.params)
    if network:
        spec, config = load_network_files([args.params])
    else:
        config = load_config(args.params)
    if args.duration is not None and not (math.isfinite(args.duration) and args.duration > 0):
        raise ConfigError(f"--duration must be a positive number of seconds, got {args.duration}")
    if args.input and not Path(args.input).is_file():
        raise ConfigError(f"--input {args.input}: no such file")
    check_output_path(args.output)
    if network:
        from tether_sim.ros.network_offline import run_network_offline

        summary = run_network_offline(spec, config, args.output, duration=args.duration, input_path=args.input,
                                      topics={"ship": args.ship_topic, "vehicle": args.vehicle_topic},
                                      progress=not args.no_progress, stop=stop)
        return dict(summary, network=True)
    return run_offline(config, args.output, duration=args.duration, input_path=args.input,
                       topics={"ship": args.ship_topic, "vehicle": args.vehicle_topic},
                       progress=not args.no_progress, stop=stop,
                       announce=lambda line: print(f"tether-sim-offline: {line}", file=sys.stderr, flush=True))


if __name__ == "__main__":
    sys.exit(main())
