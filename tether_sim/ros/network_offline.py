"""Offline runner on a line-network parameter file (``tether-sim-offline --params config/ropos_tms.yaml``):
the network node's driver and messages, straight to MCAP (docs/network.md, "Offline").

The same :class:`NetworkDriver` and :mod:`tether_sim.ros.network_outputs` messages as the network
node, written with log time = publish time = the state's clock time, as fast as the machine allows;
every tick is simulated to its target time (no lag is ever dropped, no input delay).

Inputs: with ``--input`` each driven (``prescribed``) point follows the PoseStamped (and optional
TwistStamped) of ``/<point>/pose`` in that file (``--ship-topic`` / ``--vehicle-topic`` rename the
ship's and the vehicle's); the clock is the pose stamps (the run starts at the first pose). A
driven point without poses in the file holds its configured position, as in the node. Without
``--input`` every point holds its configured position from clock time 0 (a network file has no
``motion`` section).

A line solver failing stops the run as it stops the node: the file is closed with everything up
to the failing tick and the reason is in the summary and on /diagnostics (an ERROR).
"""

import math
import time as wallclock
from dataclasses import replace

from rclpy.serialization import serialize_message

from tether_sim.errors import ConfigError
from tether_sim.physics.snap import NumericalSnapWarning, SnapEvent
from tether_sim.ros import cdr, convert
from tether_sim.ros import network_outputs as outputs
from tether_sim.ros import tf as tf_out
from tether_sim.ros.network_driver import NetworkDriver
from tether_sim.ros.offline import _NoMcap, read_poses, tick_clock

NODE_NAME = "tether_sim_offline"


def _inputs(spec, node, input_path, topics):
    """{point: RecordedPoses} of the driven points that have poses in ``input_path``."""
    driven = [n for n, p in spec.points.items() if p.kind == "prescribed"]
    if not input_path:
        return {}
    wanted = {n: ((topics or {}).get(n, f"/{n}/pose"), outputs.attachment(node, n)) for n in driven}
    recorded = read_poses(input_path, wanted, node, required=False)
    if driven and not recorded:
        names = ", ".join(t for t, _ in wanted.values())
        raise ConfigError(f"{input_path}: no PoseStamped messages on {names} for the driven point(s) "
                          f"{', '.join(driven)}")
    return recorded


class _Writer:
    """What the network runner writes (log time = publish time = stamp) and counts."""

    def __init__(self, writer, driver, spec, node):
        self.writer, self.driver, self.spec, self.node = writer, driver, spec, node
        self.shape_gate = convert.ShapeGate(node.shape_rate)
        self.counts = {"snap_events": 0, "slack_warnings": 0, "numerical_snaps": 0, "divergences": 0}
        self._snaps_written = 0  # snap events up to the last diagnostics (its "snaps_recent")
        self.peaks, self.events = [], []
        for topic, (type_name, qos) in outputs.output_topics(spec, driver.net.winches).items():
            writer.add_topic(topic, type_name, "reliable" if qos == "events" else qos)  # (events: deeper reliable)
        self.tf = node.publish_tf and tf_out.TFMessage is not None and bool(spec.bodies)
        if self.tf:
            writer.add_topic("/tf", "tf2_msgs/msg/TFMessage", "reliable")

    def _put(self, topic, payload, t):
        ns = int(round(t * 1e9))
        data = payload if isinstance(payload, (bytes, bytearray)) else serialize_message(payload)
        self.writer.write(topic, data, ns, ns)

    def descriptions(self):
        for line in self.spec.lines:
            self._put(f"/tether/{line}/description", outputs.description(self.spec, self.node, line, self.driver.stamp),
                      self.driver.stamp)
        for name in self.spec.bodies:
            self._put(f"/{name}/wet_weight", outputs.wet_weight(self.driver, self.node, name), self.driver.stamp)

    def line_events(self, line, events):
        self.events.extend((line, ev) for ev in events)
        for ev in events:
            if isinstance(ev, NumericalSnapWarning):
                self.counts["numerical_snaps"] += 1
            elif isinstance(ev, SnapEvent):
                self.counts["snap_events"] += 1
                self.peaks.append((line, ev.location.rsplit("/", 1)[-1], ev.peak_tension, ev.amplification, ev.time))
            else:
                self.counts["slack_warnings"] += 1
        for topic, msg in outputs.event_outputs(self.driver, self.node, line, events):
            self._put(topic, msg, convert.to_seconds(msg.header.stamp))

    def tick(self, orientation_of):
        d = self.driver
        sec, nanosec = cdr.stamp_parts(d.stamp)
        t = sec + 1e-9 * nanosec
        batch = []
        for topic, payload in outputs.tick_outputs(d, self.node, orientation_of, None, self.shape_gate.due(d.stamp)):
            if topic == "/tf":
                if self.tf and payload:
                    batch.append(("/tf", tf_out.tf_message_cdr(d.stamp, self.node.world_frame, payload)))
            else:
                batch.append((topic, payload if isinstance(payload, (bytes, bytearray)) else serialize_message(payload)))
        self.writer.write_many(batch, int(round(t * 1e9)))  # as _put, one message after the other

    def diagnostics(self, now, sources, report=None):
        d = self.driver
        sim = {"running": True, "real_time_factor": float(d.real_time_factor), "divergences": d.divergences,
               "error_recent": bool(report is not None and report.recovery), "last_error": d.last_error or "",
               "time_step": float(min(self.spec.coupling_step, d.net.coupling_limit)), "lag": 0.0,
               "degraded": bool(d.degraded), "tick_errors_recent": 1 if d.failed else 0,
               "last_tick_error": f"network simulation stopped: {d.failed}" if d.failed else "",
               "snaps": self.counts["snap_events"], "snaps_recent": self.counts["snap_events"] - self._snaps_written,
               "slack": dict(d.slack), "numerical_snaps": d.numerical_snaps,
               "numerical_snaps_recent": 0, "last_numerical_snap": d.last_numerical_snap,
               "lines": ", ".join(self.spec.lines)}
        health = {name: dict(src.health(now), rejected_recent=0) for name, src in sources.items()
                  if hasattr(src, "health")}  # (recorded pose inputs; an analytic motion has no input health)
        self._snaps_written = self.counts["snap_events"]
        self._put("/diagnostics", convert.diagnostics(now, NODE_NAME, sim, health), now)


def run_network_offline(spec, config, output, *, duration=None, input_path=None, topics=None, progress=True,
                        stop=None, sources=None, tap=None) -> dict:
    """Simulate the network ``spec`` and write every output topic to ``output`` (MCAP; None: no file).

    ``config``: the file's node options (``config.node``; ``config.duration`` is the default
    duration without ``--input``). ``topics``: {point: PoseStamped topic} of ``input_path``.
    ``sources``: {point: analytic source} (``has_data``, ``attachment_at(t)``, ``orientation_at(t)``,
    e.g. end_commands.MotionSource; a study's ship motion) for driven points without recorded poses;
    the clock then starts at 0. ``tap(net, out)``: called after every tick of the network (after
    the start and its settling) with the network and the tick's {line: {"samples", "loads"}} (the
    network built at the start: after a static rebuild, recovery.py, it is no longer called).
    Returns a summary dict (``events``: (line, SnapEvent | SlackStarted | NumericalSnapWarning))."""
    from tether_sim.io.mcap_log import RosMcapWriter

    node = replace(config.node, max_lag=math.inf, input_delay=0.0)
    recorded = _inputs(spec, node, input_path, topics)
    if recorded:
        t0 = min(r.poses[0][0] for r in recorded.values())
        span = max(r.poses[-1][0] for r in recorded.values()) - t0
        duration = span if duration is None else duration
    else:
        t0 = 0.0
        duration = config.duration if duration is None else duration
    for r in recorded.values():
        r.feed_until(t0)
    sources = {**(sources or {}), **{name: r.input for name, r in recorded.items()}}
    driver = NetworkDriver(spec, node, sources)
    rate = node.output_rate
    n_ticks = max(1, int(round(duration * rate)))
    wall0 = wallclock.perf_counter()
    driver.start(t0)  # statics of every line (and the settling of an unpolished DG line) before the file opens
    start_wall = wallclock.perf_counter() - wall0
    if tap is not None:  # every tick from here on (not the statics' settling)
        net, advance = driver.net, driver.net.tick

        def tapped(t, drain=True):
            out = advance(t, drain)
            tap(net, out)
            return out

        net.tick = tapped
    if stop is not None:
        stop.graceful = True
    done, cpu0, wall1 = 0, wallclock.process_time(), wallclock.perf_counter()

    def orientation_of(name):
        src = sources.get(name)
        return src.orientation_at(driver.stamp) if src is not None and src.has_data else None

    with RosMcapWriter(str(output)) if output is not None else _NoMcap() as writer:
        run = _Writer(writer, driver, spec, node)
        run.descriptions()
        run.tick(orientation_of)
        next_diag = t0 + 1.0
        for k, now in tick_clock(t0, rate, n_ticks, recorded, stop, progress):
            report = driver.tick(now)
            for line, events in report.events.items():
                run.line_events(line, events)
            if report.error:
                run.counts["divergences"] += bool(report.recovery)
                run.diagnostics(now, sources, report)
                if driver.failed:
                    break
                done = k
                continue  # recovered (tether_sim/ros/recovery.py): nothing advanced, nothing to write
            run.tick(orientation_of)
            if now >= next_diag:
                next_diag += 1.0
                run.diagnostics(now, sources)
            done = k
        for line, det in driver.detectors.items():  # close open re-tensioning windows (end of the run)
            if not driver.failed:
                run.line_events(line, det.flush())
    cpu, wall = wallclock.process_time() - cpu0, wallclock.perf_counter() - wall1
    interrupted = stop.name if stop is not None and stop.requested and done < n_ticks else ""
    simulated = done / rate
    return {"output": str(output) if output is not None else None, "duration": simulated, "ticks": done,
            "planned_duration": duration, "interrupted": interrupted, "failed": driver.failed,
            "start_wall": start_wall, "wall_time": wall, "cpu_time": cpu,
            "speed": simulated / wall if wall > 0 else math.inf,
            "speed_cpu": simulated / cpu if cpu > 0 else math.inf,
            "messages": getattr(writer, "message_count", None), "static_tensions": dict(driver.static_tensions),
            "held_points": [n for n, p in spec.points.items() if p.kind == "prescribed" and n not in recorded],
            "snap_peaks": run.peaks, "events": run.events, **run.counts}


def print_summary(s, stderr) -> None:
    """The console lines of a network run (tether-sim-offline)."""
    if s["interrupted"]:
        print(f"tether-sim-offline: stopped by {s['interrupted']} at {s['duration']:.6g} s of "
              f"{s['planned_duration']:.6g} s simulated ({s['ticks']} ticks); the file is complete up to there "
              "and closed", file=stderr)
    if s["failed"]:
        print(f"tether-sim-offline: the network simulation stopped at {s['duration']:.6g} s: {s['failed']} "
              "(the file holds everything up to there)", file=stderr)
    tens = "; ".join(f"{ln} {a:.1f} / {b:.1f} N" for ln, (a, b) in s["static_tensions"].items())
    print(f"wrote {s['output']}: network, {s['duration']:.3g} s simulated in {s['wall_time']:.3g} s "
          f"({s['speed']:.3g} x real time, {s['speed_cpu']:.3g} x per CPU s; start-up {s['start_wall']:.3g} s); "
          f"static end tensions (from / to end) {tens}; {s['slack_warnings']} slack warnings, "
          f"{s['snap_events']} snap events"
          + (f", {s['divergences']} solver divergence(s) (recovered)" if s["divergences"] else "")
          + (f", {s['numerical_snaps']} re-tensioning peak(s) rejected by the snap guard as numerical (not snaps)"
             if s["numerical_snaps"] else ""))
    if s["held_points"]:
        print(f"  held at their configured positions: {', '.join(s['held_points'])}")
    for line, end, peak, amp, t in s["snap_peaks"]:
        print(f"  snap on {line} at its {end} end: t = {t:.3f} s, peak {peak:.1f} N ({amp:.2f} x static)")
