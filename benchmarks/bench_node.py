"""The simulation node's real-time margins: per-tick cost, start-up (cold / warm cache), memory.

Each measurement runs the real node (``tether_sim.ros.sim_node.TetherSimNode``, rclpy, 50 Hz timer,
all outputs published) in a child process, next to a ship-pose publisher driving the fairlead
along the project's circle (a = 2 m, f = 0.2 Hz, the parameter file's ``motion``) at 50 Hz:

- cold start: empty numba cache (NUMBA_CACHE_DIR set to a fresh temporary directory);
- warm start: the same cache directory again (kernels loaded from disk);
- start-up time = process launch -> end of the node's first stepping tick (imports, parameter
  validation, solver construction incl. static solve, JIT or cache load);
- tick cost = wall time of each timer callback (stepping + snap detection + message building and
  publishing), median / p99 / max over ``--seconds`` of ticks after the first ten; the thread CPU time
  of the same ticks; whether the node kept up (simulated time advanced / wall time);
- memory = resident set size (VmRSS) and its peak (VmHWM) at the end.

Needs rclpy (the project's .venv: ``make setup``). Usage:
  .venv/bin/python benchmarks/bench_node.py [--params config/ropos_L1730.yaml config/ropos_L200.yaml]
        [--seconds 20] [--alpha 1] [--json out/bench_node.json]
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EI_STAR = 2.62e3


def child(params, seconds, alpha, t_launch):
    """Runs in the child process: node + pose publisher, prints one JSON line."""
    import numpy as np
    import rclpy
    from geometry_msgs.msg import PoseStamped
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.qos import qos_profile_sensor_data

    from tether_sim.io.params import load_config
    from tether_sim.physics.motion import build_motion
    from tether_sim.ros.sim_node import TetherSimNode

    cfg = load_config(params)
    motion = build_motion(cfg.motion, cfg.ship_end.position)
    args = ["tether_sim", "--ros-args", "--params-file", str(params), "-p", f"cable.EI:={alpha * EI_STAR}"]
    rclpy.init(args=args)
    node = TetherSimNode(where=str(params))
    ticks, cpus, sims = [], [], []
    first = {}
    original = node._on_tick
    skip = 10  # ticks right after the start may still compile lazily-used kernels (outputs, snaps)

    def timed_tick():
        w, c = time.perf_counter(), time.thread_time()
        original()
        wall, cpu = time.perf_counter() - w, time.thread_time() - c
        if node.driver.solver is None:
            return
        if "startup" not in first:
            first["startup"] = time.time() - t_launch
        first["n"] = first.get("n", 0) + 1
        if first["n"] > skip:
            ticks.append(wall)
            cpus.append(cpu)
            sims.append((time.perf_counter(), node.driver.solver.time))

    # the node created its timer with the bound method; swap the callback the timer calls
    for timer in node.timers:
        if timer.callback == original:
            timer.callback = timed_tick
    pub_node = rclpy.create_node("ship_pose_bench")
    pub = pub_node.create_publisher(PoseStamped, "/ship/pose", qos_profile_sensor_data)
    t0 = time.time()

    def publish_pose():
        p, _, _ = motion.at(time.time() - t0)
        msg = PoseStamped()
        msg.header.stamp = node.get_clock().now().to_msg()
        msg.header.frame_id = cfg.node.world_frame
        msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = (float(v) for v in p)
        msg.pose.orientation.w = 1.0
        pub.publish(msg)

    pub_node.create_timer(0.02, publish_pose)
    ex = SingleThreadedExecutor()
    ex.add_node(node)
    ex.add_node(pub_node)
    deadline = None
    while True:
        ex.spin_once(timeout_sec=0.1)
        if "startup" in first and deadline is None:
            deadline = time.perf_counter() + seconds
        if deadline is not None and time.perf_counter() >= deadline:
            break
        if deadline is None and time.time() - t_launch > 600:
            break
    status = {k: v for k, v in (line.split(":", 1) for line in Path("/proc/self/status").read_text().splitlines())}
    kb = lambda key: float(status[key].split()[0]) / 1024.0  # noqa: E731
    run = np.array(ticks) * 1e3
    cpu = np.array(cpus) * 1e3
    keep_up = (sims[-1][1] - sims[0][1]) / (sims[-1][0] - sims[0][0]) if len(sims) > 1 else 0.0
    out = {
        "params": str(params), "alpha": alpha, "startup_s": first.get("startup"),
        "ticks": int(run.size), "tick_median_ms": float(np.median(run)), "tick_p99_ms": float(np.percentile(run, 99)),
        "tick_max_ms": float(run.max()), "tick_cpu_median_ms": float(np.median(cpu)),
        "tick_cpu_p99_ms": float(np.percentile(cpu, 99)), "sim_per_wall": keep_up,
        "dropped_s": float(node.driver.dropped_total), "capped_ticks": int(node.driver.capped_ticks),
        "rss_mb": kb("VmRSS"), "rss_peak_mb": kb("VmHWM"), "load": os.getloadavg()[0],
    }
    print("BENCH_NODE " + json.dumps(out), flush=True)
    node.destroy_node()
    pub_node.destroy_node()
    rclpy.shutdown()


def launch(params, seconds, alpha, cache_dir):
    """One child run with NUMBA_CACHE_DIR = cache_dir; returns its JSON dict."""
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache_dir), ROS_LOCALHOST_ONLY="1",
               ROS_DOMAIN_ID=str(100 + os.getpid() % 100))
    t_launch = time.time()
    proc = subprocess.run([sys.executable, __file__, "--child", str(params), "--seconds", str(seconds),
                           "--alpha", str(alpha), "--t-launch", repr(t_launch)],
                          env=env, cwd=ROOT, capture_output=True, text=True, timeout=1200)
    for line in proc.stdout.splitlines():
        if line.startswith("BENCH_NODE "):
            return json.loads(line[len("BENCH_NODE "):])
    raise RuntimeError(f"node run failed ({proc.returncode}):\n{proc.stdout[-2000:]}\n{proc.stderr[-3000:]}")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--params", nargs="+", default=["config/ropos_L1730.yaml", "config/ropos_L200.yaml"])
    ap.add_argument("--seconds", type=float, default=20.0)
    ap.add_argument("--alpha", type=float, default=1.0, help="bending factor, EI = alpha * 2.62 kN m^2")
    ap.add_argument("--json", default="out/bench_node.json")
    ap.add_argument("--child", default=None)
    ap.add_argument("--t-launch", type=float, default=None)
    args = ap.parse_args(argv)
    if args.child:
        return child(args.child, args.seconds, args.alpha, args.t_launch)
    print(f"bench_node, {os.cpu_count()} cores, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, "
          f"{args.seconds} s of ticks at the node's output rate, alpha={args.alpha:g}")
    rows = []
    for params in args.params:
        with tempfile.TemporaryDirectory(prefix="numba_cold_") as cache:
            for kind in ("cold", "warm"):
                r = launch(params, args.seconds, args.alpha, cache)
                r["start"] = kind
                rows.append(r)
                print(f"  {Path(params).name:<20s} {kind}: start-up {r['startup_s']:6.2f} s  tick median/p99/max "
                      f"{r['tick_median_ms']:6.2f}/{r['tick_p99_ms']:6.2f}/{r['tick_max_ms']:6.2f} ms (cpu median/p99 "
                      f"{r['tick_cpu_median_ms']:6.2f}/{r['tick_cpu_p99_ms']:6.2f})  sim/wall {r['sim_per_wall']:.2f}  "
                      f"dropped {r['dropped_s']:.1f} s  RSS {r['rss_mb']:.0f} MB (peak {r['rss_peak_mb']:.0f})  "
                      f"load {r['load']:.1f}", flush=True)
    Path(args.json).parent.mkdir(parents=True, exist_ok=True)
    Path(args.json).write_text(json.dumps(rows, indent=1))
    print(f"wrote {args.json}")


if __name__ == "__main__":
    main()
