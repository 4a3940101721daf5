"""tether-sim-record: chosen topics to an MCAP file exactly as rosbag2 writes it.

Each topic is subscribed once a publisher is discovered, with ``raw=True`` so the CDR bytes go to
:class:`tether_sim.io.mcap_log.RosMcapWriter` untouched; the (data, info) callback gives rosbag2's
times: log_time = receive time (the node clock with use_sim_time, as rosbag2 does), publish_time =
source timestamp, sequence = publication sequence number. The subscription QoS follows the offers
(RELIABLE / TRANSIENT_LOCAL only when every publisher offers it), depth >= 100. Chunks are closed
every ``flush_interval_s`` so a crash loses at most that much; Ctrl-C and SIGTERM close the file.

    tether-sim-record -o out/run.mcap /tether/state /tether/snap_events
    tether-sim-record --ros-args --params-file config/recorder.yaml
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import rclpy
from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor
from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor
from rclpy.clock import Clock, ClockType
from rclpy.node import Node
from rclpy.signals import SignalHandlerOptions

from tether_sim.io.mcap_log import McapLogError, RosMcapWriter
from tether_sim.io.mcap_scan import inspect
from tether_sim.ros.bag_common import adapted_subscription_qos, message_class, offer_to_dict, stop_on_signals

NODE_NAME = "tether_sim_recorder"
SKIPPED_BY_DEFAULT = {"/rosout", "/parameter_events"}


def _describe(text, *, float_range=None, int_range=None) -> ParameterDescriptor:
    descriptor = ParameterDescriptor(description=text)
    if float_range:
        descriptor.floating_point_range = [FloatingPointRange(from_value=float_range[0],
                                                              to_value=float_range[1], step=0.0)]
    if int_range:
        descriptor.integer_range = [IntegerRange(from_value=int_range[0], to_value=int_range[1],
                                                 step=0)]
    return descriptor


def keep_unfinished(output: Path, logger=None):
    """If ``output`` is a leftover unfinished MCAP (a recorder killed before closing it), move it
    aside to ``<name>.unfinished-<n>.mcap`` instead of overwriting it, and say so (with how to
    recover it). Returns the new path or None."""
    if not output.is_file():
        return None
    try:
        damage = inspect(output)
    except McapLogError:
        return None  # not an MCAP file: the writer overwrites it as before
    if damage.complete:
        return None
    stem = output.name[:-5] if output.name.endswith(".mcap") else output.name
    n = 1
    while (aside := output.with_name(f"{stem}.unfinished-{n}.mcap")).exists():
        n += 1
    output.rename(aside)
    text = (f"found a leftover unfinished recording at {output} ({damage.describe()}); moved it to {aside}; "
            f"run `tether-sim-recover {aside}` to make it a complete MCAP")
    if logger is not None:
        logger.warning(text)
    return aside


class RecorderNode(Node):
    """Discovers, subscribes (raw) and writes; ``stop()`` is safe from a signal handler."""

    def __init__(self, output=None, topics=None, all_topics=None, **kwargs):
        super().__init__(NODE_NAME, **kwargs)
        p = self.declare_parameter
        p("output", "recording.mcap", _describe("MCAP file to write (directories are created), path"))
        p("topics", [""], _describe("topic names to record (relative: in the recorder's namespace)"))
        p("all_topics", False, _describe("record every topic except /rosout and /parameter_events"))
        p("depth", 1000, _describe("subscription queue depth, messages", int_range=(100, 100000)))
        p("discovery_period_s", 0.2, _describe("how often new publishers are looked for, s",
                                               float_range=(0.01, 10.0)))
        p("flush_interval_s", 1.0, _describe("a chunk is closed at least this often, s",
                                             float_range=(0.05, 60.0)))
        p("chunk_size", 262144, _describe("uncompressed bytes per chunk", int_range=(1024, 1 << 30)))
        p("duration_s", 0.0, _describe("stop after this long (wall clock), s; 0 = until stopped",
                                       float_range=(0.0, 1e7)))
        get = lambda name: self.get_parameter(name).value  # noqa: E731
        self.output = Path(output or get("output"))
        wanted = topics if topics else [t for t in get("topics") if t]
        self.all_topics = bool(all_topics) if all_topics is not None else bool(get("all_topics"))
        # a relative name resolves in the recorder's namespace, as the node's topics do in its own
        ns = self.get_namespace().rstrip("/")
        self.wanted = [t if t.startswith("/") else f"{ns}/{t}" for t in wanted]
        if not self.wanted and not self.all_topics:
            raise ValueError("no topics to record: give topic names, 'topics' or 'all_topics'")
        self.depth = int(get("depth"))
        self.duration_s = float(get("duration_s"))
        self.leftover = keep_unfinished(self.output, self.get_logger())
        self.writer = RosMcapWriter(self.output, chunk_size=int(get("chunk_size")),
                                    flush_interval_s=float(get("flush_interval_s")))
        self._recorded = {}
        # (topic, cdr, receive time, publish time, sequence) received before the first /clock
        self._pending = []
        self.stopped = False
        self.started = time.monotonic()
        steady = Clock(clock_type=ClockType.STEADY_TIME)  # timers must run without /clock too
        self.create_timer(float(get("discovery_period_s")), self.discover, clock=steady)
        self.create_timer(float(get("flush_interval_s")), self.writer.flush, clock=steady)
        self.get_logger().info(f"recording to {self.output}: "
                               f"{'all topics' if self.all_topics else ', '.join(self.wanted)}")
        self.discover()

    @property
    def use_sim_time(self) -> bool:
        return bool(self.get_parameter("use_sim_time").value)

    def _candidates(self):
        if not self.all_topics:
            return self.wanted
        names = [name for name, _ in self.get_topic_names_and_types()]
        return [n for n in names if n not in SKIPPED_BY_DEFAULT and "/_" not in n]

    def discover(self) -> None:
        """Subscribe to every wanted topic that has publishers now (once per topic)."""
        if self.duration_s > 0 and time.monotonic() - self.started >= self.duration_s:
            self.stopped = True
        for topic in self._candidates():
            if topic in self._recorded:
                continue
            infos = [i for i in self.get_publishers_info_by_topic(topic)
                     if i.node_name != NODE_NAME]
            if not infos:
                continue
            types = sorted({i.topic_type for i in infos})
            if len(types) > 1:
                self.get_logger().error(f"{topic}: publishers disagree on the type {types}; skipped")
                self._recorded[topic] = None
                continue
            try:
                msg_type = message_class(types[0])
            except ImportError as exc:
                self.get_logger().error(f"{topic}: {exc}; not recorded")
                self._recorded[topic] = None
                continue
            offers = [offer_to_dict(i.qos_profile) for i in infos]
            type_hash = str(infos[0].topic_type_hash) or None
            self.writer.add_topic(topic, types[0], offered_qos_profiles=offers, type_hash=type_hash)
            qos = adapted_subscription_qos(offers, self.depth)
            self._recorded[topic] = self.create_subscription(
                msg_type, topic, self._callback_for(topic), qos, raw=True)
            self.get_logger().info(f"subscribed {topic} [{types[0]}] "
                                   f"{qos.reliability.name.lower()}/{qos.durability.name.lower()}")

    def _callback_for(self, topic):
        def on_message(data: bytes, info) -> None:
            log_time = info["received_timestamp"]
            sequence = info.get("publication_sequence_number") or None
            if self.use_sim_time:
                now = self.get_clock().now().nanoseconds
                if now <= 0:  # no /clock yet: hold the message, log it at the first sim time
                    self._pending.append((topic, bytes(data), log_time, info["source_timestamp"], sequence))
                    return
                self._write_pending(now)
                log_time = now
            self.writer.write(topic, data, log_time, info["source_timestamp"], sequence=sequence)
        return on_message

    def _write_pending(self, log_time=None) -> None:
        """Write the messages held before the first /clock (at ``log_time``, else their receive times)."""
        for topic, data, received, published, sequence in self._pending:
            self.writer.write(topic, data, received if log_time is None else log_time, published, sequence=sequence)
        self._pending.clear()

    @property
    def recorded_topics(self):
        return sorted(t for t, s in self._recorded.items() if s is not None)

    def close(self) -> None:
        if not self.writer.closed:
            self._write_pending()  # no /clock ever came: keep them, at their receive times
            self.writer.close()
            self.get_logger().info(f"closed {self.output}: {self.writer.message_count} messages "
                                   f"on {len(self.recorded_topics)} topics")


def parse_args(argv):
    parser = argparse.ArgumentParser(prog="tether-sim-record", description=__doc__.split("\n")[0])
    parser.add_argument("topics", nargs="*", help="topics to record (default: the parameter 'topics')")
    parser.add_argument("-o", "--output", help="MCAP file to write (default: parameter 'output', "
                                               "recording.mcap)")
    parser.add_argument("-a", "--all", action="store_true", default=None,
                        help="record all topics except /rosout and /parameter_events (default: off)")
    return parser.parse_args(argv)


def main(argv=None) -> int:
    argv = sys.argv if argv is None else argv
    rclpy.init(args=argv, signal_handler_options=SignalHandlerOptions.NO)
    args = parse_args(rclpy.utilities.remove_ros_args(argv)[1:])
    try:
        node = RecorderNode(args.output, args.topics, args.all)
    except (ValueError, OSError) as exc:
        print(f"tether-sim-record: {exc}", file=sys.stderr)
        rclpy.try_shutdown()
        return 2

    stop_on_signals(node)
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    try:
        while not node.stopped and rclpy.ok():
            executor.spin_once(timeout_sec=0.05)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.close()
        executor.shutdown()
        node.destroy_node()
        rclpy.try_shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
