"""The simulation node's real-time margins: per-tick cost split solver / node, start-up (cold / warm
numba cache), memory.

Each measurement runs the real node (``tether_sim.ros.sim_node.TetherSimNode``, rclpy, timer at
``node.output_rate`` = 50 Hz, the SingleThreadedExecutor ``rclpy.spin`` uses) alone in a child
process, next to a helper process that publishes the ship pose on the project's circle (a = 2 m,
f = 0.2 Hz, the parameter file's ``motion``) at 50 Hz and subscribes (raw bytes, no decoding) to
every periodic output, like a recorder or RViz would (the node builds and publishes only the
outputs that have a reader; ``--subscribe state``: the TetherState only):

- cold start: empty numba cache (NUMBA_CACHE_DIR = a fresh temporary directory);
- warm start: the same cache directory again (kernels loaded from disk);
- start-up = process launch (parent, just before ``exec``) -> first TetherState received by the
  helper; also the node process's CPU time until it published it (what the start-up would take
  on an idle core: the wall figure grows with the machine's load), and the split: interpreter +
  imports, node construction (parameters, solver warm-up), first tick (first pose, first timer
  period, start, publish), delivery;
- per tick (after the first ten): wall time of the timer callback, split into the solver's
  ``advance_to`` (the substeps), its ``state()`` sampling of the output points, its other outputs
  (``end_forces``, ``body_state``, ``drain_end_tensions``), and the node's own overhead (the rest:
  clock mapping, pose interpolation, snap detector, wrenches, message encoding, publishing --
  publishing also on its own); median / p99 / max, and the thread CPU time of the same parts;
- the tick's thread CPU with its advance rescaled to one output period of simulated time (a
  tick that starts late covers more simulated time and takes more substeps; this removes that
  effect of the machine's load on the timer from the per-tick cost);
- the interval between tick starts (timer jitter; a skipped period shows as an interval near 2
  periods); kept up: simulated time advanced / wall time over the window (1 = real time, as the
  node runs at its clock), dropped lag, capped ticks; the node process's CPU over the window (all
  its threads: executor, pose callbacks, DDS);
- memory: resident set size (VmRSS) and its peak (VmHWM) at the end, and VmRSS after the imports.

Usage (the project's venv; NUMBA_CACHE_DIR of the cold run is a throw-away directory):
  python benchmarks/bench_node.py [--params config/ropos_L1730.yaml ...] [--seconds 20] [--alpha 1]
        [--starts cold warm] [--subscribe all|state] [--json out/bench_node.json]
"""

import argparse
import importlib
import json
import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EI_STAR = 2.62e3  # N m^2, the ROPOS bending stiffness of alpha = 1 [PE2020 Sec. 6.2]


def instrument(build_solver, timed):
    """A solver factory whose solvers time their calls by part with ``timed(fn, part)``: advance, state, and
    the end outputs (also bench_node_tick.py)."""
    def factory(config):
        solver = build_solver(config)
        solver.advance_to = timed(solver.advance_to, "advance")
        solver.state = timed(solver.state, "state")
        for name in ("end_forces", "body_state", "drain_end_tensions"):
            setattr(solver, name, timed(getattr(solver, name), "outputs"))
        return solver
    return factory


def _rss_mb(key="VmRSS"):
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith(key + ":"):
            return float(line.split()[1]) / 1024.0
    return float("nan")


def _stats(values_s):
    import numpy as np

    a = np.asarray(values_s, float) * 1e3
    if a.size == 0:
        return {"median": float("nan"), "p99": float("nan"), "max": float("nan"), "mean": float("nan")}
    return {"median": float(np.median(a)), "p99": float(np.percentile(a, 99)), "max": float(a.max()),
            "mean": float(a.mean())}


def helper(params, subscribe):
    """Runs in its own process: the ship pose at 50 Hz on the parameter file's motion, and raw
    subscriptions to the node's periodic outputs; prints the time the first TetherState arrived."""
    import rclpy
    from geometry_msgs.msg import PoseStamped
    from rclpy.executors import ExternalShutdownException
    from rclpy.qos import qos_profile_sensor_data

    from tether_sim.io.params import load_config
    from tether_sim.physics.motion import build_motion
    from tether_sim.ros import convert
    from tether_sim.ros.sim_node import RELIABLE

    cfg = load_config(params)
    motion = build_motion(cfg.motion, cfg.ship_end.position)
    rclpy.init()
    node = rclpy.create_node("ship_pose_bench")
    pub = node.create_publisher(PoseStamped, "/ship/pose", qos_profile_sensor_data)
    got = []

    def on_state(_msg):
        if not got:
            got.append(time.time())
            print(f"FIRST_STATE {got[0]!r}", flush=True)

    for topic, (type_name, _) in convert.TOPICS.items():
        end = topic.split("/")[1]
        periodic = topic in convert.SHAPE_TOPICS or topic.endswith("_wrench") or (
            topic.endswith("sim_pose") and getattr(cfg, f"{end}_end").kind == "body")
        if topic == "/tether/state" or (periodic and subscribe == "all"):  # raw bytes: no decoding cost
            package, _, name = type_name.split("/")
            msg_type = getattr(importlib.import_module(f"{package}.msg"), name)
            node.create_subscription(msg_type, topic, on_state if topic == "/tether/state" else (lambda _m: None),
                                     RELIABLE, raw=True)
    t0 = time.time()

    def publish_pose():
        p, _, _ = motion.at(time.time() - t0)
        msg = PoseStamped()
        msg.header.stamp = node.get_clock().now().to_msg()
        msg.header.frame_id = cfg.node.world_frame
        msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = (float(v) for v in p)
        msg.pose.orientation.w = 1.0
        pub.publish(msg)

    node.create_timer(0.02, publish_pose)
    print("HELPER_READY", flush=True)
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass


def child(params, seconds, alpha, t_launch):
    """Runs in the child process: the node alone (the helper is another process), prints one JSON line."""
    t_main = time.time()
    import numpy as np
    import rclpy
    from rclpy.executors import SingleThreadedExecutor

    from tether_sim.io.params import load_config
    from tether_sim.ros.sim_node import TetherSimNode
    from tether_sim.solvers.factory import build_solver

    t_imported = time.time()
    rss_imported = _rss_mb()
    cfg = load_config(params)
    parts = {f"{k}{c}": 0.0 for k in ("advance", "state", "outputs", "publish") for c in ("", "_cpu")}

    def timed(fn, key):
        def wrapper(*a, **k):
            w, c = time.perf_counter(), time.thread_time()
            out = fn(*a, **k)
            parts[key] += time.perf_counter() - w
            parts[key + "_cpu"] += time.thread_time() - c
            return out
        return wrapper

    args = ["tether_sim", "--ros-args", "--params-file", str(params), "-p", f"cable.EI:={alpha * EI_STAR}"]
    rclpy.init(args=args)
    node = TetherSimNode(where=str(params), solver_factory=instrument(build_solver, timed))
    t_node = time.time()
    for publisher in node.pubs.values():
        publisher.publish = timed(publisher.publish, "publish")
    rows = []  # (start, wall, cpu, advance, advance_cpu, state, state_cpu, sim time) per tick
    first = {}
    original = node._on_tick
    skip = 10  # the first ticks may still load lazily used kernels (outputs, snaps)

    def timed_tick():
        for k in parts:
            parts[k] = 0.0
        w, c = time.perf_counter(), time.thread_time()
        original()
        wall, cpu = time.perf_counter() - w, time.thread_time() - c
        if node.driver.solver is None:
            return
        if "first_tick_end" not in first:
            first["first_tick_end"] = time.time()
        first["n"] = first.get("n", 0) + 1
        if first["n"] > skip:
            rows.append((w, wall, cpu, parts["advance"], parts["advance_cpu"], parts["state"], parts["state_cpu"],
                         node.driver.solver.time, parts["publish"], parts["publish_cpu"], parts["outputs"],
                         parts["outputs_cpu"]))

    node._on_tick = timed_tick  # (the node's timer calls its _on_timer, which calls _on_tick)
    on_pose = node._on_pose

    def first_pose(end, msg):
        first.setdefault("first_pose", time.time())
        on_pose(end, msg)

    node._on_pose = first_pose
    state_pub = node.pubs["/tether/state"]
    timed_publish = state_pub.publish

    def first_publish(data):
        if "first_state" not in first:
            first["first_state"] = time.time()
            first["first_state_cpu"] = time.process_time()  # all threads of the process since its start
        timed_publish(data)

    state_pub.publish = first_publish
    ex = SingleThreadedExecutor()  # what rclpy.spin(node) in tether-sim uses
    ex.add_node(node)
    deadline = None
    cpu0 = None
    while True:
        ex.spin_once(timeout_sec=0.1)
        if len(rows) == 1 and deadline is None:
            deadline = time.perf_counter() + seconds
            cpu0 = (time.process_time(), time.perf_counter())
        if deadline is not None and time.perf_counter() >= deadline:
            break
        if deadline is None and time.time() - t_launch > 1200:
            break
    process_cpu = (time.process_time() - cpu0[0]) / (time.perf_counter() - cpu0[1]) if cpu0 else float("nan")
    r = np.array(rows) if rows else np.zeros((0, 12))
    wall, cpu, adv, adv_cpu, st, st_cpu = (r[:, k] for k in range(1, 7))
    outp, outp_cpu = r[:, 10], r[:, 11]
    period = 1.0 / cfg.node.output_rate
    intervals = np.diff(r[:, 0])
    # the substeps of a tick scale with the simulated time it covered (a late tick covers more):
    # the tick's CPU with its advance rescaled to exactly one output period of simulated time
    covered = np.diff(r[:, 7])
    ok = covered > 0
    per_period = adv_cpu[1:][ok] * period / covered[ok] + (cpu - adv_cpu)[1:][ok]
    keep_up = (r[-1, 7] - r[0, 7]) / (r[-1, 0] - r[0, 0]) if len(r) > 1 else 0.0
    out = {
        "params": str(params), "alpha": alpha, "output_rate": cfg.node.output_rate,
        "startup_published_s": first.get("first_state", float("nan")) - t_launch,
        "startup_cpu_s": first.get("first_state_cpu", float("nan")),
        "startup_parts_s": {"interpreter_and_imports": t_imported - t_launch, "of_which_interpreter": t_main - t_launch,
                            "node_construction": t_node - t_imported,
                            "first_tick": first.get("first_state", float("nan")) - t_node,
                            "first_pose_after_construction": first.get("first_pose", float("nan")) - t_node},
        "ticks": int(len(r)),
        "tick_wall": _stats(wall), "tick_cpu": _stats(cpu),
        "solver_advance_wall": _stats(adv), "solver_advance_cpu": _stats(adv_cpu),
        "state_sampling_wall": _stats(st), "state_sampling_cpu": _stats(st_cpu),
        "solver_outputs_wall": _stats(outp), "solver_outputs_cpu": _stats(outp_cpu),
        "node_overhead_wall": _stats(wall - adv - st - outp), "node_overhead_cpu": _stats(cpu - adv_cpu - st_cpu - outp_cpu),
        "publish_wall": _stats(r[:, 8]), "publish_cpu": _stats(r[:, 9]),
        "tick_cpu_one_period": _stats(per_period),
        "tick_interval": _stats(intervals), "skipped_periods": int(np.sum(intervals > 1.5 * period)),
        "sim_per_wall": float(keep_up), "dropped_s": float(node.driver.dropped_total),
        "capped_ticks": int(node.driver.capped_ticks), "process_cpu_fraction": process_cpu,
        "rss_mb": _rss_mb(), "rss_peak_mb": _rss_mb("VmHWM"), "rss_after_imports_mb": rss_imported,
        "load": list(os.getloadavg()),
    }
    print("BENCH_NODE " + json.dumps(out), flush=True)
    ex.shutdown()
    node.destroy_node()
    rclpy.shutdown()


def launch(params, seconds, alpha, cache_dir, subscribe):
    """One node run with NUMBA_CACHE_DIR = cache_dir next to a helper process; returns the dict."""
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache_dir), ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST",
               ROS_DOMAIN_ID=str(100 + os.getpid() % 100))
    helper_proc = subprocess.Popen([sys.executable, __file__, "--helper", str(params), "--subscribe", subscribe],
                                   env=env, cwd=ROOT, stdout=subprocess.PIPE, text=True)
    try:
        if helper_proc.stdout.readline().strip() != "HELPER_READY":
            raise RuntimeError("the pose/subscriber helper did not start")
        t_launch = time.time()
        proc = subprocess.run([sys.executable, __file__, "--child", str(params), "--seconds", str(seconds),
                               "--alpha", str(alpha), "--t-launch", repr(t_launch)],
                              env=env, cwd=ROOT, capture_output=True, text=True, timeout=2400)
    finally:
        helper_proc.send_signal(signal.SIGINT)
        try:
            helper_out = helper_proc.communicate(timeout=20)[0]
        except subprocess.TimeoutExpired:
            helper_proc.kill()
            helper_out = helper_proc.communicate()[0]
    for line in proc.stdout.splitlines():
        if line.startswith("BENCH_NODE "):
            r = json.loads(line[len("BENCH_NODE "):])
            received = [float(x.split()[1]) for x in helper_out.splitlines() if x.startswith("FIRST_STATE ")]
            r["startup_s"] = (received[0] - t_launch) if received else float("nan")
            r["startup_parts_s"]["delivery"] = r["startup_s"] - r["startup_published_s"]
            r["started_without_pose"] = "starting without" in proc.stderr  # input_timeout ran out first
            return r
    raise RuntimeError(f"node run failed ({proc.returncode}):\n{proc.stdout[-2000:]}\n{proc.stderr[-3000:]}")


def _line(name, s):
    return f"{name:<24s} {s['median']:7.3f} {s['p99']:7.3f} {s['max']:7.3f}"


def report(r):
    """Printed figures of one run."""
    p = r["startup_parts_s"]
    print(f"  start-up {r['startup_s']:.2f} s to the first TetherState received ({r['startup_cpu_s']:.2f} s of the node's "
          f"process CPU): interpreter {p['of_which_interpreter']:.2f}, imports "
          f"{p['interpreter_and_imports'] - p['of_which_interpreter']:.2f}, node construction incl. solver warm-up "
          f"{p['node_construction']:.2f}, first tick {p['first_tick']:.2f} (first pose "
          f"{p['first_pose_after_construction']:.2f} s after the construction), delivery {p['delivery'] * 1e3:.1f} ms")
    if r.get("started_without_pose"):
        print("  (no pose had arrived within node.input_timeout: the node started from the configured positions)")
    print(f"  {r['ticks']} ticks at {r['output_rate']:g} Hz (ms)      median     p99     max")
    for key, name in (("tick_wall", "tick, wall"), ("solver_advance_wall", "  solver advance_to"),
                      ("state_sampling_wall", "  solver state()"),
                      ("solver_outputs_wall", "  solver other outputs"), ("node_overhead_wall", "  node overhead"),
                      ("publish_wall", "    of which publishing"), ("tick_cpu", "tick, thread CPU"), ("solver_advance_cpu", "  solver advance_to"),
                      ("state_sampling_cpu", "  solver state()"),
                      ("solver_outputs_cpu", "  solver other outputs"), ("node_overhead_cpu", "  node overhead"),
                      ("publish_cpu", "    of which publishing"),
                      ("tick_cpu_one_period", "tick CPU, 1 period sim."),
                      ("tick_interval", "interval between ticks")):
        print("  " + _line(name, r[key]))
    print(f"  skipped timer periods {r['skipped_periods']}, sim/wall {r['sim_per_wall']:.3f}, dropped {r['dropped_s']:.2f} s, "
          f"capped ticks {r['capped_ticks']}, node process CPU {100 * r['process_cpu_fraction']:.0f} % of a core")
    print(f"  RSS {r['rss_mb']:.0f} MB (peak {r['rss_peak_mb']:.0f}; {r['rss_after_imports_mb']:.0f} after the imports), "
          f"load average {r['load'][0]:.2f} / {r['load'][1]:.2f} / {r['load'][2]:.2f}", flush=True)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--params", nargs="+", default=["config/ropos_L1730.yaml"])
    ap.add_argument("--seconds", type=float, default=20.0)
    ap.add_argument("--alpha", type=float, default=1.0, help="bending factor, EI = alpha * 2.62 kN m^2")
    ap.add_argument("--starts", nargs="+", default=["cold", "warm"], choices=["cold", "warm"],
                    help="cold: empty numba cache; warm: the cache the previous run filled (or the tree's "
                         "__pycache__ when only 'warm' is given)")
    ap.add_argument("--json", default="out/bench_node.json")
    ap.add_argument("--child", default=None)
    ap.add_argument("--helper", default=None)
    ap.add_argument("--t-launch", type=float, default=None)
    ap.add_argument("--subscribe", default="all", choices=["all", "state"],
                    help="which periodic outputs get a reader (the node builds and publishes only those)")
    args = ap.parse_args(argv)
    if args.child:
        return child(args.child, args.seconds, args.alpha, args.t_launch)
    if args.helper:
        return helper(args.helper, args.subscribe)
    print(f"bench_node, {os.cpu_count()} cores, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, "
          f"{args.seconds:g} s of ticks, alpha={args.alpha:g}, load average {os.getloadavg()[0]:.2f}")
    rows = []
    for params in args.params:
        with tempfile.TemporaryDirectory(prefix="numba_cold_") as cold_dir:
            for kind in args.starts:
                cache = cold_dir if "cold" in args.starts else os.environ.get("NUMBA_CACHE_DIR", "")
                r = launch(params, args.seconds, args.alpha, cache, args.subscribe)
                r["start"] = kind
                rows.append(r)
                print(f"{Path(params).name}, {kind} start:")
                report(r)
    Path(args.json).parent.mkdir(parents=True, exist_ok=True)
    Path(args.json).write_text(json.dumps(rows, indent=1))
    print(f"wrote {args.json}")


if __name__ == "__main__":
    main()
