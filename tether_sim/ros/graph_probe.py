"""main_job's view of the ROS graph: who publishes and subscribes, and the node's start-up.

A node of its own (own rclpy Context) in the job's private domain. ``prime()`` brings the
simulation node up before the replay like a paused player and measures its speed."""

from __future__ import annotations

import time

from tether_sim.ros.processes import StepFailed


class GraphProbe:
    """A small node in the job's domain that watches the graph (publishers, subscriptions)."""

    def __init__(self):
        import rclpy
        from rclpy.context import Context

        self.rclpy = rclpy
        self.context = Context()
        rclpy.init(context=self.context)
        self.node = rclpy.create_node("tether_sim_main_job", context=self.context)

    def recorder_matched(self, topics) -> list[str]:
        """Topics among ``topics`` that have a publisher but no recorder subscription yet."""
        waiting = []
        for topic in topics:
            pubs = self.node.get_publishers_info_by_topic(topic)
            subs = [s.node_name for s in self.node.get_subscriptions_info_by_topic(topic)]
            if not pubs or "tether_sim_recorder" not in subs:
                waiting.append(topic)
        return waiting

    def prime(self, t_start_ns: int, pose_cdr: bytes, timeout_s: float, check,
              measure_s: float = 0.0) -> tuple[float, float | None, float | None]:
        """Bring the node up before the replay, like a paused player; returns (wall time taken,
        measured real-time factor, measured tick load), each None when not measured.

        1. /clock runs up to ``measure_s + 2`` s before the record's start and holds there, with
           the record's first ship pose offered (stamped with the clock), until the node has built
           its solver (latched /tether/description) and stepped up to the held clock: building
           and the first steps (numba compilation) stay out of the replayed time.
        2. If ``measure_s`` > 0 the clock then runs in real time up to just before the start
           while the node's /diagnostics real_time_factor and tick_load (the fraction of wall
           time the node spends in its ticks) are sampled (the ship is still at rest).
        The replay then continues the clock from the record's start."""
        t0 = time.monotonic()
        watch = _PrimeWatch(self, t_start_ns, pose_cdr, check)
        hold_a = t_start_ns - int((measure_s + 0.05) * 1e9)
        try:
            watch.drive(lambda e: hold_a - int(1e9 * max(0.0, 2.0 - e)),
                        lambda: watch.seen and watch.latest >= hold_a - 500_000_000, timeout_s,
                        "the node did not start its solver")
            if measure_s > 0:
                watch.measuring = True
                t_m = time.monotonic()
                watch.drive(lambda e: hold_a + int(1e9 * min(e, measure_s)),
                            lambda: time.monotonic() - t_m >= measure_s + 0.5, measure_s + 5, "measuring")
                watch.measuring = False
                hold_b = t_start_ns - 50_000_000
                watch.drive(lambda e: hold_b, lambda: watch.latest >= hold_b - 1_000_000_000
                            or time.monotonic() - t_m > 3 * measure_s, 4 * measure_s + 10,
                            "the node did not catch up")
        finally:
            watch.close()
        return time.monotonic() - t0, _median(watch.rtf), _median(watch.load)

    def _spin(self, seconds: float) -> None:
        from rclpy.executors import SingleThreadedExecutor

        if not hasattr(self, "_executor"):
            self._executor = SingleThreadedExecutor(context=self.context)
            self._executor.add_node(self.node)
        self._executor.spin_once(timeout_sec=seconds)

    def close(self):
        if hasattr(self, "_executor"):
            self._executor.shutdown()
        self.node.destroy_node()
        self.rclpy.try_shutdown(context=self.context)


def _median(samples):
    """Median of the samples after the first (which may include the start), None without any."""
    rest = sorted(samples[1:])
    return float(rest[len(rest) // 2]) if rest else None


class _PrimeWatch:
    """What GraphProbe.prime publishes (/clock, the held ship pose) and watches (the latched
    description, the newest TetherState stamp, the node's real_time_factor diagnostics)."""

    def __init__(self, probe: GraphProbe, t_start_ns: int, pose_cdr: bytes, check):
        from diagnostic_msgs.msg import DiagnosticArray
        from geometry_msgs.msg import PoseStamped
        from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
        from rclpy.serialization import deserialize_message
        from rosgraph_msgs.msg import Clock
        from tether_sim_msgs.msg import TetherDescription, TetherState

        from tether_sim.ros.bag_common import clock_qos

        self.probe, self.t_start_ns, self.check = probe, t_start_ns, check
        node = probe.node
        self.clock_pub = node.create_publisher(Clock, "/clock", clock_qos())
        self.pose_pub = node.create_publisher(PoseStamped, "/ship/pose",
                                              QoSProfile(depth=1, reliability=ReliabilityPolicy.BEST_EFFORT))
        self.seen, self.latest, self.rtf, self.load, self.measuring = [], 0, [], [], False
        latched = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                             durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self.subs = [node.create_subscription(TetherDescription, "/tether/description", self.seen.append, latched),
                     node.create_subscription(TetherState, "/tether/state", self._on_state, 10),
                     node.create_subscription(DiagnosticArray, "/diagnostics", self._on_diagnostics, 10)]
        self.pose = deserialize_message(pose_cdr, PoseStamped)
        self.clock = Clock()
        self.last_pose = -1.0
        self.last_pose_ns = -1  # the stamp of the last pose published

    def _on_state(self, msg):
        self.latest = max(self.latest, msg.header.stamp.sec * 10**9 + msg.header.stamp.nanosec)

    def _on_diagnostics(self, msg):
        if not self.measuring:
            return
        for status in msg.status:
            for kv in status.values:
                sink = {"real_time_factor": self.rtf, "tick_load": self.load}.get(kv.key)
                if sink is not None:
                    try:
                        sink.append(float(kv.value))
                    except ValueError:
                        pass

    def drive(self, clock_at, done, limit_s, what):
        """Publish /clock = clock_at(elapsed) and the pose until done() (StepFailed after limit_s)."""
        start = time.monotonic()
        while not done():
            self.check()
            elapsed = time.monotonic() - start
            if elapsed > limit_s:
                raise StepFailed(f"{what} within {limit_s:.0f} s (description seen: "
                                 f"{bool(self.seen)}, last state {(self.latest - self.t_start_ns) / 1e9:+.2f} s "
                                 f"from the record's start)")
            self.clock.clock.sec, self.clock.clock.nanosec = divmod(int(clock_at(elapsed)), 10**9)
            self.clock_pub.publish(self.clock)
            now_ns = self.clock.clock.sec * 10**9 + self.clock.clock.nanosec
            # (a held clock: the pose once per stamp; the node rejects a repeated stamp as not increasing)
            if time.monotonic() - self.last_pose >= 0.2 and now_ns > self.last_pose_ns:
                self.last_pose = time.monotonic()
                self.last_pose_ns = now_ns
                self.pose.header.stamp = self.clock.clock
                self.pose_pub.publish(self.pose)
            self.probe._spin(0.02)

    def close(self):
        node = self.probe.node
        for sub in self.subs:
            node.destroy_subscription(sub)
        node.destroy_publisher(self.pose_pub)
        node.destroy_publisher(self.clock_pub)
