"""Soak test of the simulation node (not in CI): one hour of a gentle heave with faults injected.

    .venv/bin/python benchmarks/soak_node.py [--minutes 60] [--params config/ropos_L200.yaml]
                                             [--out out/soak]

The node (``tether-sim``, wall clock, its own process) drives a taut tether whose ship end follows
/ship/pose: a heave of 0.5 m at 0.1 Hz (peak acceleration 0.2 m/s^2; the tether never goes slack,
so every snap event would be false). Every 30 s one fault from a fixed cycle is injected: NaN and
infinite poses, a bad quaternion, a pose stamped 1 h ahead, one 10 s in the past, a backwards
stamp, a wrong frame, a 3 s dropout, a 1 s flood at 1 kHz. This process publishes the poses
(loopback only, private ROS_DOMAIN_ID), subscribes to /tether/state, /tether/snap_events and
/diagnostics (on a line-network file, config/ropos_tms.yaml: to /tether/<line>/state and
/tether/<line>/snap_events of every line, and it holds the other driven points, the vehicle, at their
configured positions on /<point>/pose; the faults go to the ship's pose), samples the node's resident memory every 10 s, and prints / writes
(``summary.txt``, ``soak.png``, ``soak.npz``: every line's end tensions, degraded flag and lag per state): memory at start and end (and its slope), interval between states
(median, p99, max), lag and degraded share, non-finite values received (must be 0), snap events
(must be 0), rejected inputs by reason. Exit code 1 when a non-finite value or a snap event came,
or the node died.
"""

from __future__ import annotations

import argparse
import math
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
FAULTS = ("nan", "inf", "bad quaternion", "future", "past", "backwards", "wrong frame", "dropout", "flood")


def rss_mb(pid: int) -> float:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024.0
    return math.nan


def cpu_s(pid: int) -> float:
    """User + system CPU seconds of a process, all its threads."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def heave(t: float) -> float:
    return 0.5 * math.sin(2 * math.pi * 0.1 * t)


def network_of(params: str):
    """(lines, {driven point other than the ship: position}) of a line-network file, None for a
    single-line file."""
    from tether_sim.network.params import file_is_network, load_network_files

    if not file_is_network(params):
        return None
    spec, _ = load_network_files([params])
    held = {n: p.position for n, p in spec.points.items() if p.kind == "prescribed" and n != "ship"}
    return list(spec.lines), held


class Soak:
    """The probe: publishes the poses, listens to the states, snap events and /diagnostics. On a
    line network (``network``: (lines, held points)) it listens to every ``/tether/<line>/state``
    and ``/tether/<line>/snap_events`` and holds the other driven points (the vehicle) at their
    configured positions; the intervals, lag and degraded share are those of the first line."""

    def __init__(self, node, network=None):
        from diagnostic_msgs.msg import DiagnosticArray
        from geometry_msgs.msg import PoseStamped
        from rclpy.qos import qos_profile_sensor_data
        from tether_sim_msgs.msg import SnapLoadEvent, TetherState

        self.node, self.PoseStamped = node, PoseStamped
        self.pub = node.create_publisher(PoseStamped, "/ship/pose", qos_profile_sensor_data)
        self.states, self.snaps, self.nonfinite, self.diag, self.health = [], [], 0, None, []
        self.ends = {}  # line -> [(stamp, s = 0 end tension, s = L end tension, degraded, lag)] (soak.npz)
        lines, self.held = network if network is not None else ([None], {})
        self.held_pubs = {n: node.create_publisher(PoseStamped, f"/{n}/pose", qos_profile_sensor_data)
                          for n in self.held}
        self.state_counts = {line or "tether": 0 for line in lines}
        for i, line in enumerate(lines):
            prefix = "/tether" if line is None else f"/tether/{line}"
            node.create_subscription(TetherState, f"{prefix}/state",
                                     lambda m, ln=line or "tether", first=(i == 0): self.on_state(m, ln, first), 100)
            node.create_subscription(SnapLoadEvent, f"{prefix}/snap_events",
                                     lambda m, ln=line or "tether": self.snaps.append((ln, m)), 100)
        node.create_subscription(DiagnosticArray, "/diagnostics", self.on_diag, 10)

    def on_state(self, msg, line="tether", first=True):
        values = [msg.ship_end_tension, msg.vehicle_end_tension, *msg.tension,
                  *(c for p in msg.position for c in (p.x, p.y, p.z))]
        if not all(map(math.isfinite, values)):
            self.nonfinite += 1
        self.state_counts[line] += 1
        stamp = msg.header.stamp.sec + 1e-9 * msg.header.stamp.nanosec
        self.ends.setdefault(line, []).append((stamp, msg.ship_end_tension, msg.vehicle_end_tension, msg.degraded, msg.lag))
        if first:
            self.states.append((time.monotonic(), msg.header.stamp.sec + 1e-9 * msg.header.stamp.nanosec,
                                msg.lag, msg.degraded, msg.ship_end_tension))

    def on_diag(self, msg):
        self.diag = {s.name: {kv.key: kv.value for kv in s.values} for s in msg.status}
        sim = next((v for k, v in self.diag.items() if k.endswith(": simulation")), {})
        try:  # one row per diagnostics period: real-time factor, tick load, longest tick (ms)
            self.health.append(tuple(float(sim[k]) for k in ("real_time_factor", "tick_load", "tick_max_ms")))
        except (KeyError, ValueError):
            pass

    def pose(self, t, z, q=(0.0, 0.0, 0.0, 1.0), frame="map"):
        from tether_sim.ros.convert import time_msg

        msg = self.PoseStamped()
        msg.header.stamp, msg.header.frame_id = time_msg(t), frame
        msg.pose.position.z = float(z)
        msg.pose.orientation.x, msg.pose.orientation.y, msg.pose.orientation.z, msg.pose.orientation.w = q
        self.pub.publish(msg)
        for name, pub in self.held_pubs.items():  # a network's other driven points (the vehicle), held
            held = self.PoseStamped()
            held.header.stamp, held.header.frame_id = msg.header.stamp, "map"
            held.pose.position.x, held.pose.position.y, held.pose.position.z = (float(v) for v in self.held[name])
            held.pose.orientation.w = 1.0
            pub.publish(held)


def rate_line(arr) -> str:
    """States per second of wall time from the first to the last one received (its own count over
    that span), and of their stamps (outputs per simulated second: a state the node never published
    shows here)."""
    if len(arr) < 2:
        return "n/a"
    wall, stamps = arr[-1, 0] - arr[0, 0], arr[-1, 1] - arr[0, 1]
    return (f"{(len(arr) - 1) / max(wall, 1e-9):.2f} Hz over {wall:.1f} s of wall time, "
            f"{(len(arr) - 1) / max(stamps, 1e-9):.2f} per second of stamps")


def run(args) -> int:
    import rclpy

    from tether_sim.ros.processes import claim_domain_id, isolated_env

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    env = isolated_env(claim_domain_id())
    import os

    os.environ.update(env)
    log = open(out / "node.log", "w")  # noqa: SIM115
    extra = [a for item in args.extra for a in ("-p", item)]
    node_proc = subprocess.Popen([str(REPO / ".venv/bin/tether-sim"), "--ros-args", "--params-file", args.params, *extra],
                                 env=env, stdout=log, stderr=subprocess.STDOUT)
    rclpy.init()
    probe = rclpy.create_node("soak_probe")
    soak = Soak(probe, network_of(args.params))
    memory, fault_log, cpu = [], [], []
    t_start = time.monotonic()
    end = t_start + 60.0 * args.minutes
    next_pose, next_mem, next_fault, fault_i, dropout_until = t_start, t_start, t_start + 30.0, 0, 0.0
    try:
        while time.monotonic() < end and node_proc.poll() is None:
            rclpy.spin_once(probe, timeout_sec=0.005)
            now_wall = time.monotonic()
            t = probe.get_clock().now().nanoseconds * 1e-9
            if now_wall >= next_pose:
                next_pose += 0.05
                if now_wall >= dropout_until:
                    soak.pose(t, heave(now_wall - t_start))
            if now_wall >= next_mem:
                next_mem += 10.0
                memory.append((now_wall - t_start, rss_mb(node_proc.pid)))
                if soak.states:  # the node's CPU (every thread) while it publishes states
                    cpu.append((now_wall, cpu_s(node_proc.pid)))
            if now_wall >= next_fault:
                next_fault += 30.0
                kind = FAULTS[fault_i % len(FAULTS)]
                fault_i += 1
                fault_log.append((now_wall - t_start, kind))
                z = heave(now_wall - t_start)
                if kind == "nan":
                    soak.pose(t + 0.01, math.nan)
                elif kind == "inf":
                    soak.pose(t + 0.01, math.inf)
                elif kind == "bad quaternion":
                    soak.pose(t + 0.01, z, (0.0, 0.0, 0.0, 0.0))
                elif kind == "future":
                    soak.pose(t + 3600.0, z)
                elif kind == "past":
                    soak.pose(t - 10.0, z)
                elif kind == "backwards":
                    soak.pose(t - 0.5, z)
                elif kind == "wrong frame":
                    soak.pose(t + 0.01, z, frame="odom")
                elif kind == "dropout":
                    dropout_until = now_wall + 3.0
                elif kind == "flood":
                    for k in range(1000):
                        soak.pose(t + k * 1e-3, heave(now_wall - t_start + k * 1e-3))
    finally:
        died = node_proc.poll() is not None
        node_proc.terminate()
        try:
            node_proc.wait(timeout=30)
        except subprocess.TimeoutExpired:
            node_proc.kill()
        memory.append((time.monotonic() - t_start, math.nan))
        probe.destroy_node()
        rclpy.shutdown()
    return report(args, out, soak, memory, fault_log, died, cpu)


def report(args, out, soak, memory, fault_log, died, cpu=()) -> int:
    arr = np.array([s[:4] for s in soak.states], float) if soak.states else np.zeros((0, 4))
    gaps = np.diff(arr[:, 0]) * 1e3 if len(arr) > 1 else np.zeros(1)
    mem = np.array([m for m in memory if math.isfinite(m[1])])
    steady = mem[mem[:, 0] >= 60.0] if len(mem) else mem  # after start-up (imports, JIT, first solve)
    slope = np.polyfit(steady[:, 0] / 3600.0, steady[:, 1], 1)[0] if len(steady) > 2 else math.nan
    load = Path("/proc/loadavg").read_text().split()[:3]
    lines = [f"soak of {args.minutes:g} min, params {args.params}, load average at the end {' '.join(load)}",
             f"node alive to the end: {not died}",
             f"TetherState received: {len(arr)}"
             + (f" (per line: {', '.join(f'{k} {v}' for k, v in soak.state_counts.items())})"
                if len(soak.state_counts) > 1 else "")
             + f"; non-finite: {soak.nonfinite}; snap events: {len(soak.snaps)}"
             + (f" ({', '.join(sorted({ln for ln, _ in soak.snaps}))})" if soak.snaps else ""),
             f"interval between states (wall, ms): median {np.median(gaps):.1f}, p99 {np.percentile(gaps, 99):.1f}, "
             f"max {gaps.max():.1f}",
             f"state rate at the subscriber: {rate_line(arr)}",
             "node CPU while publishing (all threads): " + (f"{100.0 * (cpu[-1][1] - cpu[0][1]) / (cpu[-1][0] - cpu[0][0]):.1f} % "
                                                            f"of a core over {cpu[-1][0] - cpu[0][0]:.0f} s"
                                                            if len(cpu) > 1 else "n/a"),
             f"lag (s): median {np.median(arr[:, 2]) if len(arr) else math.nan:.3f}, max "
             f"{arr[:, 2].max() if len(arr) else math.nan:.3f}; degraded states: "
             f"{100.0 * arr[:, 3].mean() if len(arr) else math.nan:.1f} %",
             f"node RSS (MB): at 1 min {steady[0, 1] if len(steady) else math.nan:.0f}, end "
             f"{mem[-1, 1] if len(mem) else math.nan:.0f}, slope after 1 min {slope:.2f} MB/h",
             health_line(soak.health),
             *[f"snap event on {ln} at its {m.end} end: peak {m.peak_tension:.1f} N ({m.amplification:.2f} x static "
               f"{m.static_tension:.1f} N), stamp {m.header.stamp.sec + 1e-9 * m.header.stamp.nanosec:.3f} s, slack "
               f"{m.slack_duration:.3f} s (min {m.min_tension:.1f} N), rise {1e3 * m.rise_time:.1f} ms, degraded {m.degraded}"
               for ln, m in soak.snaps],
             f"faults injected: {len(fault_log)} ({', '.join(sorted(set(k for _, k in fault_log)))})",
             "last diagnostics: " + repr(soak.diag)]
    text = "\n".join(lines)
    np.savez(out / "soak.npz", **{f"ends_{ln}": np.array(rows, float) for ln, rows in soak.ends.items()})
    print(text)
    (out / "summary.txt").write_text(text + "\n")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(3, 1, figsize=(9, 7), sharex=True, constrained_layout=True)
    t0 = arr[0, 0] if len(arr) else 0.0
    if len(mem):
        axes[0].plot(mem[:, 0] / 60.0, mem[:, 1], "o-", ms=3)
    axes[0].set_ylabel("node RSS [MB]")
    if len(arr) > 1:
        axes[1].plot((arr[1:, 0] - t0) / 60.0, gaps, lw=0.5)
        axes[2].plot((arr[:, 0] - t0) / 60.0, arr[:, 2], lw=0.7, label="lag")
        axes[2].fill_between((arr[:, 0] - t0) / 60.0, 0, arr[:, 3] * max(arr[:, 2].max(), 0.1), color="0.8",
                             label="degraded")
    axes[1].set_ylabel("state interval [ms]")
    axes[2].set_ylabel("lag [s]")
    axes[2].set_xlabel("wall time [min]")
    axes[2].legend(loc="upper right", fontsize=8)
    for tf, kind in fault_log:
        axes[1].axvline(tf / 60.0, color="tab:red", lw=0.4, alpha=0.5)
    axes[0].set_title(f"node soak ({args.minutes:g} min, {Path(args.params).name}; red lines: injected faults)")
    fig.savefig(out / "soak.png", dpi=100)
    return 1 if (died or soak.nonfinite or soak.snaps) else 0


def health_line(rows) -> str:
    """The node's own figures, one row per /diagnostics period (1 s): real-time factor of the
    period, tick load (busy share of the wall clock) and the longest tick of the period."""
    if not rows:
        return "node diagnostics: none received"
    h = np.array(rows, float)
    q = lambda col, p: np.percentile(h[:, col], p)  # noqa: E731
    return (f"node diagnostics ({len(h)} periods): real-time factor median {q(0, 50):.3f}, p1 {q(0, 1):.3f}; "
            f"tick load median {q(1, 50):.3f}, p99 {q(1, 99):.3f}; longest tick per period (ms) median "
            f"{q(2, 50):.1f}, p99 {q(2, 99):.1f}, max {h[:, 2].max():.1f}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--minutes", type=float, default=60.0)
    ap.add_argument("--params", default=str(REPO / "config" / "ropos_L200.yaml"))
    ap.add_argument("--out", default=str(REPO / "out" / "soak"))
    ap.add_argument("-p", dest="extra", action="append", default=[], metavar="KEY:=VALUE",
                    help="a parameter of the node, e.g. node.executor:=events")
    return run(ap.parse_args(argv))


if __name__ == "__main__":
    sys.exit(main())
