"""A ship for a first live run without writing a publisher (console script ``tether-sim-poses``).

    tether-sim-poses --params config/ropos_L200.yaml [--rate HZ] [--duration S] [--heave A --frequency F]
                     [--ros-args -r __ns:=/rov1 -p use_sim_time:=true]

Publishes ``ship/pose`` (geometry_msgs/PoseStamped) and ``ship/twist`` (TwistStamped, the
analytic velocity) as the node expects them: stamped with this node's clock, in the parameter
file's world frame (``node.world_frame``, default ``map``: poses in any other frame are rejected by
the node), moving the fairlead by the file's ``motion`` section (circle, heave, sines, record or an
RAO response to its sea) about ``ship_end.position``; the motion starts 1 s after a subscriber
(the node) has matched, the start pose is held until then.
``--heave A --frequency F`` replaces that motion with a vertical heave of amplitude A (m) and
frequency F (Hz), ramped in over two periods. The names are relative, so a namespace given with
``--ros-args -r __ns:=...`` applies as it does to the node. Exit: Ctrl-C, SIGTERM or ``--duration``.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from dataclasses import replace

import numpy as np
import rclpy
from geometry_msgs.msg import PoseStamped, TwistStamped
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.qos import qos_profile_sensor_data

from tether_sim.errors import ConfigError
from tether_sim.io.params import load_config
from tether_sim.physics.motion import build_motion
from tether_sim.ros.convert import time_msg
from tether_sim.ros.node_cli import ignore_further_signals, stop_flag


def ship_motion(config):
    """The motion generator of ``config``'s ``motion`` section about the ship end (ConfigError if none)."""
    if config.motion.kind == "none":
        raise ConfigError("motion.kind is 'none' in this file: nothing to publish; give --heave A --frequency F")
    waves = None
    if config.motion.kind == "rao":
        from tether_sim.physics.waves import wave_components

        waves = wave_components(config)
    try:
        return build_motion(config.motion, np.asarray(config.ship_end.position, float), waves)
    except (ValueError, OSError) as exc:
        raise ConfigError(f"motion: {exc}") from exc


def describe(motion_config) -> str:
    m = motion_config
    if m.kind in ("circle", "heave"):
        return f"{m.kind}, amplitude {m.amplitude:g} m, {m.frequency:g} Hz, ramped in over {m.ramp_time:g} s"
    return f"{m.kind} (ramped in over {m.ramp_time:g} s)"


HOLD = 1.0  # s the start pose is held after a subscriber matched, so the node's first pose is it


class PoseSource(Node):
    """Publishes the ship pose and twist of ``motion`` at ``rate`` Hz. Until a subscriber has
    matched and for ``HOLD`` s after, the pose is the motion's start (its time 0), so the node's
    first pose is where the file puts the ship and the motion starts smoothly (its ramp) under
    the node's eyes, not half a period into it."""

    def __init__(self, config, motion, rate: float, **kwargs):
        super().__init__("tether_sim_poses", **kwargs)
        self.frame, self.motion, self.t0 = config.node.world_frame, motion, None
        self.pose_pub = self.create_publisher(PoseStamped, "ship/pose", qos_profile_sensor_data)
        self.twist_pub = self.create_publisher(TwistStamped, "ship/twist", qos_profile_sensor_data)
        self.count = 0
        self.create_timer(1.0 / rate, self._publish)

    def _publish(self):
        now = self.get_clock().now().nanoseconds * 1e-9
        if now <= 0.0:
            return  # sim time before the first /clock
        if self.t0 is None and self.pose_pub.get_subscription_count() > 0:
            self.t0 = now + HOLD  # a subscriber (the node): hold still a little longer, then move
        holding = self.t0 is None or now < self.t0
        position, velocity = (np.asarray(v, float) for v in self.motion.at(0.0 if holding else now - self.t0)[:2])
        if holding:
            velocity = np.zeros(3)  # held still (a motion without a ramp starts with a velocity)
        pose, twist = PoseStamped(), TwistStamped()
        pose.header.stamp = twist.header.stamp = time_msg(now)
        pose.header.frame_id = twist.header.frame_id = self.frame
        pose.pose.position.x, pose.pose.position.y, pose.pose.position.z = (float(c) for c in position)
        pose.pose.orientation.w = 1.0
        twist.twist.linear.x, twist.twist.linear.y, twist.twist.linear.z = (float(c) for c in velocity)
        self.pose_pub.publish(pose)
        self.twist_pub.publish(twist)
        self.count += 1


def main(argv=None) -> int:
    argv = list(sys.argv if argv is None else argv)
    ap = argparse.ArgumentParser(prog="tether-sim-poses", description=__doc__.split("\n\n")[0])
    ap.add_argument("--params", required=True, help="the node's parameter file (motion, ship_end.position, node.world_frame)")
    ap.add_argument("--rate", type=float, default=None, help="poses per second (default: node.output_rate of the file)")
    ap.add_argument("--duration", type=float, default=0.0, help="stop after this many seconds (default 0: never)")
    ap.add_argument("--heave", type=float, default=None, metavar="A", help="vertical heave amplitude, m (with --frequency)")
    ap.add_argument("--frequency", type=float, default=None, metavar="F", help="heave frequency, Hz (with --heave)")
    args = ap.parse_args(rclpy.utilities.remove_ros_args(argv)[1:])
    try:
        config = load_config(args.params)
        if (args.heave is None) != (args.frequency is None):
            raise ConfigError("--heave and --frequency go together")
        if args.heave is not None:
            if not (math.isfinite(args.heave) and math.isfinite(args.frequency) and args.frequency > 0):
                raise ConfigError(f"--heave {args.heave} --frequency {args.frequency}: finite, frequency > 0")
            config = replace(config, motion=replace(config.motion, kind="heave", amplitude=args.heave,
                                                    frequency=args.frequency, ramp_time=2.0 / args.frequency))
        rate = args.rate if args.rate is not None else config.node.output_rate
        if not (math.isfinite(rate) and 0.0 < rate <= 1000.0):
            raise ConfigError(f"--rate {rate}: between 0 and 1000 poses per second")
        motion = ship_motion(config)
    except ConfigError as exc:
        print(f"tether-sim-poses: {exc}", file=sys.stderr)
        return 2
    rclpy.init(args=argv)
    node = PoseSource(config, motion, rate)
    node.get_logger().info(f"publishing {node.resolve_topic_name('ship/pose')} and ship/twist at {rate:g} Hz in "
                           f"frame '{config.node.world_frame}': {describe(config.motion)}, about ship_end.position "
                           f"{list(config.ship_end.position)}")
    stopped = stop_flag()  # a signal ends the loop between callbacks, never inside rclpy
    t_end = time.monotonic() + args.duration if args.duration > 0 else math.inf
    try:
        while not stopped and rclpy.ok() and time.monotonic() < t_end:
            rclpy.spin_once(node, timeout_sec=0.1)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        ignore_further_signals()  # more Ctrl-C / SIGTERM must not cut the clean-up short (exit 0, no traceback)
        node.destroy_node()
        rclpy.try_shutdown()
        ignore_further_signals()  # rclpy's shutdown puts back the handlers it found at init
    return 0


if __name__ == "__main__":
    sys.exit(main())
