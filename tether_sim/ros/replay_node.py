"""tether-sim-replay: an MCAP file back onto topics with the recorded timing, and /clock.

The stored CDR bytes are published as they are (``publish(bytes)`` = publish_raw, no decoding).
Message i goes out at wall time w0 + (log_time_i - t_start) / rate with t_start = first log time +
start offset; /clock (rosgraph_msgs/Clock, best effort, depth 1) carries t_start + rate * (w - w0)
at ``clock_hz`` >= 40 Hz, so sim-time nodes follow the recording; the clock never passes the stamp
of a message not yet published (each message goes out, then the clock at its log time). Latched topics (every recorded
offer TRANSIENT_LOCAL) are republished TRANSIENT_LOCAL, depth 1. This node keeps use_sim_time
false. With ``loop`` the file restarts and /clock jumps back to t_start, as rosbag2 does.

    tether-sim-replay data/ropos_ship_heave.mcap --rate 1.0 --clock-hz 100
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings

import rclpy
from rcl_interfaces.msg import FloatingPointRange, ParameterDescriptor
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.signals import SignalHandlerOptions

from tether_sim.io.mcap_log import McapLogError, iter_raw, read_summary
from tether_sim.io.mcap_scan import TruncatedMcapWarning
from tether_sim.ros.bag_common import clock_qos, message_class, replay_qos, stop_on_signals, wait_for

NODE_NAME = "tether_sim_replay"
MIN_CLOCK_HZ = 40.0


def _describe(text, lo=None, hi=None) -> ParameterDescriptor:
    d = ParameterDescriptor(description=text)
    if lo is not None:
        d.floating_point_range = [FloatingPointRange(from_value=lo, to_value=hi, step=0.0)]
    return d


class ReplayNode(Node):
    """Publishers for the recorded topics plus /clock; ``play()`` runs the timed loop."""

    def __init__(self, path=None, overrides=None, **kwargs):
        super().__init__(NODE_NAME, **kwargs)
        self.set_parameters([Parameter("use_sim_time", value=False)])
        p = self.declare_parameter
        p("input", "", _describe("MCAP file to replay, path"))
        p("rate", 1.0, _describe("playback speed factor (2 = twice real time)", 0.01, 100.0))
        p("start_offset_s", 0.0, _describe("skip this much of the recording, s", 0.0, 1e7))
        p("duration_s", 0.0, _describe("replay only this much of the recording after the start "
                                       "offset, s; 0 = to the end", 0.0, 1e7))
        p("loop", False, _describe("restart at the end"))
        p("clock", True, _describe("publish /clock"))
        p("clock_hz", 100.0, _describe("/clock publication rate, Hz", MIN_CLOCK_HZ, 1000.0))
        p("topics", [""], _describe("topics to replay (empty: all recorded topics)"))
        p("depth", 100, _describe("publisher queue depth of non-latched topics, messages"))
        p("wait_for_subscribers_s", 0.0, _describe("before playing, wait up to this long for "
                                                   "min_subscribers on every replayed topic, s", 0.0, 600.0))
        p("min_subscribers", 1, _describe("subscribers every replayed topic (and /clock) must have "
                                          "before playing starts (with wait_for_subscribers_s > 0), >= 1"))
        values = {name: self.get_parameter(name).value for name in
                  ("input", "rate", "start_offset_s", "duration_s", "loop", "clock", "clock_hz", "topics",
                   "depth", "wait_for_subscribers_s", "min_subscribers")}
        values.update({k: v for k, v in (overrides or {}).items() if v is not None})
        if path:
            values["input"] = path
        if not values["input"]:
            raise ValueError("no input MCAP given (argument or parameter 'input')")
        if not values["rate"] > 0:
            raise ValueError(f"rate must be > 0, got {values['rate']}")
        self.path, self.rate = str(values["input"]), float(values["rate"])
        self.start_offset_ns = int(float(values["start_offset_s"]) * 1e9)
        self.duration_ns = int(float(values["duration_s"]) * 1e9)
        self.loop, self.wait_s = bool(values["loop"]), float(values["wait_for_subscribers_s"])
        self.min_subscribers = int(values["min_subscribers"])
        if self.min_subscribers < 1:
            raise ValueError(f"min_subscribers must be >= 1, got {self.min_subscribers}")
        self.clock_period = 1.0 / max(MIN_CLOCK_HZ, float(values["clock_hz"]))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", TruncatedMcapWarning)  # reported below, once
            summary = read_summary(self.path)
        if summary.damage is not None:
            warnings.filterwarnings("ignore", category=TruncatedMcapWarning)  # said once, here
            self.get_logger().warning(f"{summary.damage.describe()}; replaying the {summary.message_count} "
                                      f"message(s) kept (tether-sim-recover {self.path} writes a complete copy)")
        if summary.message_count == 0:
            raise ValueError(f"{self.path}: no complete message to replay"
                             + (f" ({summary.damage.describe()})" if summary.damage is not None else ""))
        if summary.profile != "ros2":
            self.get_logger().warning(f"{self.path}: profile {summary.profile!r}, expected 'ros2'")
        wanted = [t for t in values["topics"] if t] or sorted(summary.topics)
        self.publishers_by_topic = {}
        for topic in wanted:
            info = summary.topics.get(topic)
            if info is None:
                raise ValueError(f"{self.path}: topic {topic} is not in the file "
                                 f"(it has {', '.join(sorted(summary.topics))})")
            if info.message_encoding != "cdr":
                self.get_logger().warning(f"{topic}: encoding {info.message_encoding}, skipped")
                continue
            try:
                msg_type = message_class(info.type_name)
            except ImportError as exc:
                self.get_logger().error(f"{topic}: {exc}; skipped")
                continue
            qos = replay_qos(info.offered_qos_profiles, int(values["depth"]))
            self.publishers_by_topic[topic] = self.create_publisher(msg_type, topic, qos)
        self.clock_pub = None
        if values["clock"]:
            from rosgraph_msgs.msg import Clock
            self._clock_msg = Clock()
            self.clock_pub = self.create_publisher(Clock, "/clock", clock_qos())
        self.t_first = summary.start_ns
        self.stopped = False
        self.published = 0

    def publish_clock(self, t_ns: int) -> None:
        if self.clock_pub is not None:
            self._clock_msg.clock.sec, self._clock_msg.clock.nanosec = divmod(int(t_ns), 10**9)
            self.clock_pub.publish(self._clock_msg)

    def subscriber_counts(self) -> dict[str, int]:
        """Matched subscriptions per replayed topic and /clock."""
        pubs = dict(self.publishers_by_topic)
        if self.clock_pub is not None:
            pubs["/clock"] = self.clock_pub
        return {t: p.get_subscription_count() for t, p in sorted(pubs.items())}

    def wait_for_subscribers(self) -> list[str]:
        """Wait (up to wait_for_subscribers_s) until every replayed topic and /clock has matched
        min_subscribers subscriptions; returns those still short, as "topic (k of n)".

        One subscriber is not enough when several processes listen: a recorder on sim time
        matches /clock and the poses as soon as it sees them, and a clock that starts before the
        simulation node has matched runs away from it (the node then finds itself seconds behind)."""
        n = self.min_subscribers
        wait_for(lambda: all(k >= n for k in self.subscriber_counts().values()), self.wait_s,
                 context=self.context)
        return [f"{t} ({k} of {n})" for t, k in self.subscriber_counts().items() if k < n]

    def play_once(self) -> None:
        """One pass over the file with recorded timing."""
        t_start = self.t_first + self.start_offset_ns
        w0 = time.monotonic()
        next_clock = w0

        def bag_time(wall):
            return t_start + int((wall - w0) * self.rate * 1e9)

        def wait_until(deadline, cap_ns=None):
            """Tick /clock until the wall deadline; the clock never passes cap_ns (the next
            message's log time), so a message that is late (a busy machine) still goes out
            before the clock covers its stamp."""
            nonlocal next_clock
            while not self.stopped:
                now = time.monotonic()
                if now >= next_clock:
                    t = bag_time(now)
                    self.publish_clock(t if cap_ns is None else min(t, cap_ns))
                    next_clock = max(next_clock + self.clock_period, now)
                if now >= deadline:
                    return
                time.sleep(max(0.0, min(deadline, next_clock) - now))

        for raw in iter_raw(self.path, list(self.publishers_by_topic)):
            if self.stopped or not rclpy.ok():
                return
            if raw.log_time_ns < t_start:
                continue
            if self.duration_ns and raw.log_time_ns > t_start + self.duration_ns:
                break
            wait_until(w0 + (raw.log_time_ns - t_start) / (self.rate * 1e9), raw.log_time_ns)
            if self.stopped:
                return
            self.publishers_by_topic[raw.topic].publish(raw.data)
            self.publish_clock(raw.log_time_ns)
            self.published += 1
        wait_until(time.monotonic() + 2 * self.clock_period)  # a last tick past the final message

    def play(self) -> None:
        missing = self.wait_for_subscribers() if self.wait_s > 0 else []
        if missing:
            self.get_logger().warning(f"too few subscribers after {self.wait_s:.1f} s on: {', '.join(missing)}")
        counts = ", ".join(f"{t} {k}" for t, k in self.subscriber_counts().items())
        self.get_logger().info(f"replaying {self.path} ({len(self.publishers_by_topic)} topics) at "
                               f"x{self.rate:g}{', looping' if self.loop else ''}; subscribers: {counts}")
        while not self.stopped and rclpy.ok():
            self.play_once()
            if not self.loop:
                break
        self.get_logger().info(f"replay finished: {self.published} messages published")


def parse_args(argv):
    parser = argparse.ArgumentParser(
        prog="tether-sim-replay", description=__doc__.split("\n")[0],
        epilog="Each option overrides the node parameter of the same name (--ros-args -p / --params-file); "
               "the defaults shown are those parameters' defaults.")
    parser.add_argument("input", nargs="?", help="MCAP file (default: parameter 'input')")
    parser.add_argument("-r", "--rate", type=float, help="speed factor (default 1.0: real time)")
    parser.add_argument("-s", "--start-offset", type=float, dest="start_offset_s",
                        help="skip this many seconds of the recording (default 0)")
    parser.add_argument("-d", "--duration", type=float, dest="duration_s",
                        help="replay only this many seconds after the offset (default 0: to the end)")
    parser.add_argument("-l", "--loop", action="store_true", default=None,
                        help="start again at the end; /clock jumps back, as with rosbag2 (default: off)")
    parser.add_argument("--clock-hz", type=float, help="/clock publication rate, Hz (default 100, at least 40)")
    parser.add_argument("--no-clock", dest="clock", action="store_false", default=None,
                        help="do not publish /clock (default: publish it)")
    parser.add_argument("--topics", nargs="+", help="replay only these topics (default: every topic in the file)")
    parser.add_argument("--wait-for-subscribers", type=float, dest="wait_for_subscribers_s",
                        help="wait up to this many seconds for a subscriber on every replayed topic "
                             "before starting (default 0: start at once)")
    parser.add_argument("--min-subscribers", type=int, dest="min_subscribers",
                        help="with --wait-for-subscribers: the subscribers every replayed topic and /clock "
                             "must have (default 1)")
    return parser.parse_args(argv)


def main(argv=None) -> int:
    argv = sys.argv if argv is None else argv
    rclpy.init(args=argv, signal_handler_options=SignalHandlerOptions.NO)
    args = vars(parse_args(rclpy.utilities.remove_ros_args(argv)[1:]))
    path = args.pop("input")
    if args.get("clock_hz") is not None and args["clock_hz"] < MIN_CLOCK_HZ:
        print(f"tether-sim-replay: --clock-hz must be >= {MIN_CLOCK_HZ:g}", file=sys.stderr)
        return 2
    try:
        node = ReplayNode(path, args)
    except (ValueError, McapLogError) as exc:
        print(f"tether-sim-replay: {exc}", file=sys.stderr)
        rclpy.try_shutdown()
        return 2

    stop_on_signals(node)
    try:
        node.play()
    except McapLogError as exc:
        node.get_logger().error(str(exc))
        return 2
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
