"""Cost of the node's /tf output per tick (tether_sim/ros/tf.py), against the whole tick.

Runs the real node in this process (wall clock, 50 Hz ticks driven by hand, ship pose published at
50 Hz by a probe that also subscribes to /tf, so the transforms are built and published), and
records the thread CPU time of ``TfPublisher.publish`` and of the whole tick callback. Prints the
median / p99 of both and their ratio, and the machine's load.

Usage: python benchmarks/bench_tf.py [--params config/ropos_L1730.yaml] [--ticks 500] [--tether-frames 0]
"""

import argparse
import os
import time

import numpy as np
import rclpy
from geometry_msgs.msg import PoseStamped
from rclpy.executors import SingleThreadedExecutor
from tf2_msgs.msg import TFMessage

from tether_sim.ros.convert import time_msg
from tether_sim.ros.sim_node import TetherSimNode


def timed(fn, sink):
    def wrapper(*args, **kwargs):
        t0 = time.thread_time_ns()
        try:
            return fn(*args, **kwargs)
        finally:
            sink.append(time.thread_time_ns() - t0)
    return wrapper


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--params", default="config/ropos_L1730.yaml", help="parameter file (default: %(default)s)")
    ap.add_argument("--ticks", type=int, default=500, help="ticks measured (default: %(default)s)")
    ap.add_argument("--tether-frames", type=int, default=0, help="node.tf_tether_frames (default: %(default)s)")
    args = ap.parse_args()
    rclpy.init()
    node = TetherSimNode(cli_args=["--ros-args", "--params-file", args.params,
                                   "-p", f"node.tf_tether_frames:={args.tether_frames}"])
    probe = rclpy.create_node("bench_tf_probe")
    pose = probe.create_publisher(PoseStamped, "/ship/pose", 10)
    received = []
    probe.create_subscription(TFMessage, "/tf", received.append, 100)
    executor = SingleThreadedExecutor()
    for n in (node, probe):
        executor.add_node(n)
    tf_ns, tick_ns = [], []
    node.tf.publish = timed(node.tf.publish, tf_ns)
    node._on_tick = timed(node._on_tick, tick_ns)
    t_end = time.monotonic() + 120.0
    while len(tick_ns) < args.ticks + 20 and time.monotonic() < t_end:
        msg = PoseStamped()
        msg.header.stamp, msg.header.frame_id = time_msg(time.time()), "map"
        msg.pose.orientation.w = 1.0
        pose.publish(msg)
        node._on_tick()
        executor.spin_once(timeout_sec=0.02)
    tf = np.array(tf_ns[20:]) / 1e6
    tick = np.array(tick_ns[20:len(tf_ns)]) / 1e6
    print(f"load average {os.getloadavg()[0]:.1f}; {args.params}, node.tf_tether_frames = {args.tether_frames}; "
          f"{len(tf)} ticks, {len(received)} /tf messages received")
    print(f"/tf per tick (thread CPU): median {np.median(tf):.3f} ms, p99 {np.percentile(tf, 99):.3f} ms")
    print(f"whole tick   (thread CPU): median {np.median(tick):.3f} ms, p99 {np.percentile(tick, 99):.3f} ms")
    print(f"/tf share of the tick: {np.median(tf) / np.median(tick) * 100:.1f} % (medians)")
    executor.shutdown()
    node.destroy_node()
    probe.destroy_node()
    rclpy.shutdown()


if __name__ == "__main__":
    main()
