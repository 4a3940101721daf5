"""The floor of a tick's publishing: a bare rclpy node that publishes the live node's periodic messages.

The simulation node publishes per 50 Hz tick seven periodic messages (at 1730 m: /tether/state,
/tether/marker, /tether/path, the two wrenches, /vehicle/sim_pose and /tf), each as serialized CDR
bytes. This script takes those exact payloads from the real node (built from ``--params``, ticked
``--capture`` times on the file's motion as ``bench_node_tick.py`` does), then drops it and runs a bare
node with nothing but publishers of the same names, types and QoS and a 50 Hz timer that publishes
the payloads. Per tick it takes the thread CPU of the publish calls, the thread CPU of the spinning
thread from one timer callback to the next (the executor's wait and dispatch included), and over the
whole run the process CPU (every thread: the middleware's own) per tick. That is what a tick costs
before the node computes anything: whatever the node does on top comes on top of it.

Variants (``--variants``, each its own process, in turn with and without a subscriber process):
  bytes    the node's way: 7 publish calls of serialized bytes
  objects  7 publish calls of message objects (rclpy serializes them)
  one      1 publish call of the 7 payloads concatenated (what fewer calls could save at most)
  state    the state message alone (1 call, the largest payload)
``--executor events``: rclpy.experimental's EventsExecutor (C++) instead of the SingleThreadedExecutor
that ``rclpy.spin`` uses. Middleware settings are the process environment: ``--env RMW_FASTRTPS_PUBLICATION_MODE=ASYNCHRONOUS``,
``--env FASTDDS_BUILTIN_TRANSPORTS=SHM`` ... (each ``--env`` set applies to every variant of its run).

Usage: nice -n 19 .venv/bin/python benchmarks/bench_publish_floor.py [--params config/ropos_L1730.yaml]
           [--ticks 1000] [--variants bytes objects one state] [--no-sink-too] [--env KEY=VALUE ...]
"""

import argparse
import json
import os
import resource
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from benchmarks.bench_node_tick import bench_env, run_child  # noqa: E402


def capture(params, ticks):
    """[(topic, type name, qos, payload bytes)] of every periodic output of the real node after
    ``ticks`` ticks (the node then destroyed)."""
    from benchmarks.bench_node_tick import _Bench
    from tether_sim.ros import convert
    from tether_sim.ros.tf import dynamic_transforms, tf_message_cdr

    bench = _Bench("tether_sim", params, 0.0, False)
    for k in range(ticks):
        bench.tick(k, False)
    node, driver = bench.node, bench.node.driver
    frame = convert.OutputFrame(driver)
    payloads = []
    for topic, data in convert.tick_outputs(driver, node.arc_lengths, None, frame, True):
        pub = node.pubs[topic]
        payloads.append((topic, pub.msg_type, pub.qos_profile, bytes(data)))
    if node.tf.enabled:
        data = tf_message_cdr(driver.stamp, driver.config.node.world_frame, dynamic_transforms(driver, frame))
        payloads.append(("/tf", node.tf.pub.msg_type, node.tf.pub.qos_profile, bytes(data)))
    node.destroy_node()
    return payloads


def child(params, ticks, variant, capture_ticks, wait_sink, executor_kind):
    import numpy as np
    import rclpy
    import rclpy.executors
    from rclpy.serialization import deserialize_message

    from tether_sim.ros.convert import ros_name

    rclpy.init(args=["tether_sim", "--ros-args", "--params-file", str(params)])
    payloads = capture(params, capture_ticks)
    node = rclpy.create_node("publish_floor")
    if variant == "state":
        payloads = payloads[:1]
    pubs = [(node.create_publisher(t, ros_name(topic), qos), data) for topic, t, qos, data in payloads]
    if variant == "objects":
        pubs = [(p, deserialize_message(data, p.msg_type)) for p, data in pubs]
    elif variant == "one":
        pubs = [(pubs[0][0], b"".join(data for _, data in pubs))]
    if wait_sink:
        deadline = time.monotonic() + 30.0
        while any(p.get_subscription_count() == 0 for p, _ in pubs) and time.monotonic() < deadline:
            time.sleep(0.05)
    warm = 100
    rows = []  # (publish calls' CPU, spinning thread's CPU since the previous callback)
    state = {"k": 0, "last": None, "ru0": None, "wall0": None}

    def on_tick():
        c0 = time.thread_time()
        for pub, data in pubs:
            pub.publish(data)
        c1 = time.thread_time()
        k = state["k"]
        if k == warm:
            state["ru0"], state["wall0"] = resource.getrusage(resource.RUSAGE_SELF), time.monotonic()
        if warm < k <= warm + ticks:
            rows.append((c1 - c0, c0 - state["last"]))
        state["last"] = c0
        state["k"] = k + 1

    node.create_timer(1.0 / 50.0, on_tick)
    if executor_kind == "events":  # rclpy's C++ events executor (rclpy.experimental)
        from rclpy.experimental import EventsExecutor

        executor = EventsExecutor()
    else:
        executor = rclpy.executors.SingleThreadedExecutor()  # as rclpy.spin(node) of the real node
    executor.add_node(node)
    while state["k"] <= warm + ticks:
        executor.spin_once(timeout_sec=1.0)
    ru1, wall1 = resource.getrusage(resource.RUSAGE_SELF), time.monotonic()
    ru0 = state["ru0"]
    proc_cpu = (ru1.ru_utime + ru1.ru_stime - ru0.ru_utime - ru0.ru_stime) / ticks
    r = np.array(rows) * 1e3
    out = {"variant": variant, "executor": executor_kind, "calls": len(pubs), "bytes": sum(len(d) for _, _, _, d in payloads),
           "sizes": {topic: len(d) for topic, _, _, d in payloads},
           "subscribed": f"{sum(p.get_subscription_count() > 0 for p, _ in pubs)}/{len(pubs)}",
           "publish_ms": [float(np.median(r[:, 0])), float(np.percentile(r[:, 0], 99))],
           "spin_thread_ms": [float(np.median(r[:, 1])), float(np.percentile(r[:, 1], 99))],
           "process_cpu_ms_per_tick": proc_cpu * 1e3, "rate_hz": ticks / (wall1 - state["wall0"]),
           "rmw": os.environ.get("RMW_IMPLEMENTATION", "rmw_fastrtps_cpp (default)"),
           "env": {k: v for k, v in os.environ.items() if k.startswith(("RMW_FASTRTPS", "FASTDDS", "FASTRTPS"))},
           "load": list(os.getloadavg())}
    print("PUBLISH_FLOOR " + json.dumps(out), flush=True)
    node.destroy_node()
    rclpy.shutdown()


def launch(params, ticks, variant, capture_ticks, with_sink, env_extra, executor_kind):
    cmd = [sys.executable, __file__, "--child", str(params), "--ticks", str(ticks), "--variant", variant,
           "--capture", str(capture_ticks), "--executor", executor_kind] + (["--wait-sink"] if with_sink else [])
    return run_child(cmd, bench_env(env_extra), "PUBLISH_FLOOR", with_sink=with_sink, timeout=1800)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--params", default="config/ropos_L1730.yaml")
    ap.add_argument("--ticks", type=int, default=1000)
    ap.add_argument("--capture", type=int, default=150, help="ticks of the real node before its payloads are taken")
    ap.add_argument("--variants", nargs="+", default=["bytes", "objects", "one", "state"])
    ap.add_argument("--no-sink-too", action="store_true", help="each variant also without a subscriber")
    ap.add_argument("--executor", default="single", choices=["single", "events"],
                    help="single: rclpy's SingleThreadedExecutor (rclpy.spin, the node's); events: rclpy.experimental's")
    ap.add_argument("--env", action="append", default=[], metavar="KEY=VALUE")
    ap.add_argument("--json", default="out/bench_publish_floor.json")
    ap.add_argument("--child", default=None)
    ap.add_argument("--variant", default="bytes")
    ap.add_argument("--wait-sink", action="store_true")
    args = ap.parse_args(argv)
    if args.child:
        return child(args.child, args.ticks, args.variant, args.capture, args.wait_sink, args.executor)
    env_extra = dict(item.split("=", 1) for item in args.env)
    print(f"bench_publish_floor, {os.cpu_count()} cores, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, "
          f"{args.params}, {args.ticks} ticks at 50 Hz, executor {args.executor}, env {env_extra or 'default'}, load average "
          f"{os.getloadavg()[0]:.2f}", flush=True)
    rows = []
    for variant in args.variants:
        for with_sink in ([True, False] if args.no_sink_too else [True]):
            r = launch(args.params, args.ticks, variant, args.capture, with_sink, env_extra, args.executor)
            r["sink"] = with_sink
            rows.append(r)
            print(f"{variant:8s} {'subscriber' if with_sink else 'none      '} {r['calls']} call(s), {r['bytes']} B: "
                  f"publish CPU median {r['publish_ms'][0]:.3f} ms (p99 {r['publish_ms'][1]:.3f}); spinning thread "
                  f"per tick {r['spin_thread_ms'][0]:.3f} (p99 {r['spin_thread_ms'][1]:.3f}); process CPU per tick "
                  f"{r['process_cpu_ms_per_tick']:.3f}; rate {r['rate_hz']:.2f} Hz; subscribed {r['subscribed']}; "
                  f"load {r['load'][0]:.2f}", flush=True)
    print("payload sizes (B): " + ", ".join(f"{t} {n}" for t, n in rows[0]["sizes"].items()))
    Path(args.json).parent.mkdir(parents=True, exist_ok=True)
    Path(args.json).write_text(json.dumps(rows, indent=1))
    print(f"wrote {args.json}")


if __name__ == "__main__":
    main()
