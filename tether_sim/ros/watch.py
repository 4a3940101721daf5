"""Watch a running tether-sim from a terminal (no ros2 CLI needed): one line per second with the
end tensions and the node's real-time factor, and every slack warning and snap event as it comes.

    ROS_DOMAIN_ID=<id> .venv/bin/python -m tether_sim.ros.watch [--duration S] [--ros-args -r __ns:=/rov1]

Topics are relative (``tether/state``...), so a namespace given with ``--ros-args -r __ns:=...``
applies as it does to the node. Exit: Ctrl-C, SIGTERM or after ``--duration`` seconds (0: never).
"""

from __future__ import annotations

import argparse
import sys
import time

import rclpy
from diagnostic_msgs.msg import DiagnosticArray
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy
from tether_sim_msgs.msg import SlackWarning, SnapLoadEvent, TetherState

from tether_sim.ros.convert import to_seconds


class Watcher(Node):
    def __init__(self, out=print, **kwargs):
        super().__init__("tether_sim_watch", **kwargs)
        self.out, self.state, self.rtf, self.lines = out, None, None, 0
        events = QoSProfile(depth=50, reliability=ReliabilityPolicy.RELIABLE)
        self.create_subscription(TetherState, "tether/state", self._on_state, 10)
        self.create_subscription(SnapLoadEvent, "tether/snap_events", self._on_snap, events)
        self.create_subscription(SlackWarning, "tether/slack_warnings", self._on_slack, events)
        self.create_subscription(DiagnosticArray, "/diagnostics", self._on_diagnostics, 10)
        self.create_timer(1.0, self._print)
        self.out(f"watching {self.get_namespace().rstrip('/')}/tether/* (Ctrl-C stops) ...")

    def _on_state(self, msg):
        self.state = msg

    def _on_diagnostics(self, msg):
        mine = f"{self.get_namespace().rstrip('/')}/tether_sim".lstrip("/") + ": simulation"
        for status in msg.status:  # /diagnostics is global: only the tether of this namespace
            if status.name == mine:
                self.rtf = next((kv.value for kv in status.values if kv.key == "real_time_factor"), self.rtf)

    def _on_snap(self, msg):
        self.out(f"SNAP  t={to_seconds(msg.header.stamp):.2f} s  {msg.end} s={msg.arc_length:.1f} m  peak "
                 f"{msg.peak_tension / 1e3:.2f} kN (x{msg.amplification:.2f} static, slack {msg.slack_duration:.2f} s)")

    def _on_slack(self, msg):
        self.out(f"slack t={to_seconds(msg.header.stamp):.2f} s  {msg.end} s={msg.arc_length:.1f} m  "
                 f"tension {msg.tension / 1e3:.2f} kN (threshold {msg.threshold / 1e3:.2f} kN)")

    def _print(self):
        if self.state is None:
            self.out("no tether/state yet")
            return
        s = self.state
        self.out(f"t={to_seconds(s.header.stamp):10.2f} s  ship end {s.ship_end_tension / 1e3:8.2f} kN  "
                 f"vehicle end {s.vehicle_end_tension / 1e3:8.2f} kN  max {max(s.tension, default=0) / 1e3:8.2f} kN"
                 + (f"  real-time factor {self.rtf}" if self.rtf is not None else ""))
        self.lines += 1


def main(argv=None) -> int:
    argv = list(sys.argv if argv is None else argv)
    ap = argparse.ArgumentParser(prog="python -m tether_sim.ros.watch", description=__doc__.split("\n")[0])
    ap.add_argument("--duration", type=float, default=0.0, help="stop after this many seconds (default 0: never)")
    args = ap.parse_args(rclpy.utilities.remove_ros_args(argv)[1:])
    rclpy.init(args=argv)
    node = Watcher()
    t_end = time.monotonic() + args.duration if args.duration > 0 else float("inf")
    try:
        while rclpy.ok() and time.monotonic() < t_end:
            rclpy.spin_once(node, timeout_sec=0.2)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    except Exception:
        if rclpy.ok():
            raise
        # Ctrl-C between rclpy.ok() and spin_once's wait: rclpy's handler has shut the context down and the
        # wait cannot be set up (rclpy raises RCLError "context is not valid"): a stop, not an error
    finally:
        node.destroy_node()
        if rclpy.ok():
            rclpy.shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
