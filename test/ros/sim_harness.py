"""In-process harness for the simulation node tests: one Context, the node, and a probe node that
publishes /clock and the end poses and records every output topic (sim time, so the runs are
deterministic and independent of the machine's speed)."""

import math

import rclpy
from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import PoseStamped, WrenchStamped
from rclpy.executors import SingleThreadedExecutor
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rosgraph_msgs.msg import Clock
from tether_sim_msgs.msg import SlackWarning, SnapLoadEvent, TetherDescription, TetherState

from tether_sim.ros.convert import time_msg
from tether_sim.ros.sim_node import TetherSimNode

OUTPUTS = {"/tether/state": TetherState, "/tether/ship_wrench": WrenchStamped,
           "/tether/vehicle_wrench": WrenchStamped, "/tether/snap_events": SnapLoadEvent,
           "/tether/slack_warnings": SlackWarning, "/diagnostics": DiagnosticArray,
           "/vehicle/sim_pose": PoseStamped}


def overrides(flat: dict) -> list:
    """rclpy Parameters of a flat {key: value} dict (tuples as lists), plus use_sim_time."""
    out = [Parameter("use_sim_time", Parameter.Type.BOOL, True)]
    for k, v in flat.items():
        out.append(Parameter(k, value=list(v) if isinstance(v, tuple) else v))
    return out


class SimHarness:
    """The node under test plus a probe; ``step(t, ship=..., vehicle=...)`` advances sim time."""

    def __init__(self, flat: dict, **node_kwargs):
        self.context = rclpy.Context()
        rclpy.init(context=self.context)
        self.node = TetherSimNode(context=self.context, parameter_overrides=overrides(flat), **node_kwargs)
        self.probe = rclpy.create_node("probe", context=self.context)
        self.clock = self.probe.create_publisher(Clock, "/clock", QoSProfile(depth=1, reliability=ReliabilityPolicy.BEST_EFFORT))
        self.pose_pubs = {end: self.probe.create_publisher(PoseStamped, f"/{end}/pose", 10) for end in ("ship", "vehicle")}
        self.received = {topic: [] for topic in OUTPUTS}
        self.received["/tether/description"] = []
        for topic, msg_type in OUTPUTS.items():
            depth = 100 if topic in ("/tether/snap_events", "/tether/slack_warnings") else 1000
            self.probe.create_subscription(msg_type, topic, self.received[topic].append, depth)
        latched = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self.probe.create_subscription(TetherDescription, "/tether/description", self.received["/tether/description"].append, latched)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        self.executor.add_node(self.probe)
        self.time = 0.0

    def pose_msg(self, t, position, orientation=(0.0, 0.0, 0.0, 1.0), frame="map"):
        msg = PoseStamped()
        msg.header.stamp = time_msg(t)
        msg.header.frame_id = frame
        msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = (float(x) for x in position)
        q = msg.pose.orientation
        q.x, q.y, q.z, q.w = (float(x) for x in orientation)
        return msg

    def spin(self, n=6):
        for _ in range(n):
            self.executor.spin_once(timeout_sec=0.002)

    def step(self, t, **poses):
        """Publish /clock = t and the given poses (end -> position or PoseStamped), then spin."""
        for end, pose in poses.items():
            msg = pose if isinstance(pose, PoseStamped) else self.pose_msg(t, pose)
            self.pose_pubs[end].publish(msg)
        self.clock.publish(Clock(clock=time_msg(t)))
        states = self.received["/tether/state"]
        n = len(states)
        self.spin(2)
        for _ in range(30):  # a running node publishes once per tick: wait for that state
            if len(states) > n or self.node.driver.solver is None:
                break
            self.spin(1)
        self.time = t

    def run(self, t_end, dt=0.02, **poses):
        """Step the clock to t_end, publishing the same poses every step."""
        n = int(math.ceil((t_end - self.time) / dt - 1e-9))
        for k in range(1, n + 1):
            self.step(self.time + dt, **poses)

    def close(self):
        self.executor.shutdown()
        self.node.destroy_node()
        self.probe.destroy_node()
        rclpy.shutdown(context=self.context)


def status(diag: DiagnosticArray, suffix: str):
    """The DiagnosticStatus whose name ends with ``suffix`` (None if absent)."""
    return next((s for s in diag.status if s.name.endswith(suffix)), None)


def values(st) -> dict:
    return {kv.key: kv.value for kv in st.values}


class HandDriven:
    """The node without executor or clock: ``tick(ship_pose)`` feeds one ship pose 20 ms after the
    last and runs one timer tick; every publish of the tick lands in ``log[-1]`` as (topic, message),
    and every publisher reports one subscriber (so nothing is skipped for want of one)."""

    def __init__(self, context, flat: dict, node_name=None, t0=100.0):
        flat = {k: v for k, v in flat.items() if k != "use_sim_time"}
        kwargs = {} if node_name is None else {"node_name": node_name}
        self._drive(TetherSimNode(context=context, parameter_overrides=overrides(flat), **kwargs), t0)

    @classmethod
    def network(cls, context, files, overrides=None, node_name=None, held=None, t0=100.0):
        """The line-network node of ``files`` (NetworkSimNode; ``overrides``: flat ``node.*`` keys) driven
        the same way; ``held``: {point: position} of the other driven points, fed with every ship pose."""
        from tether_sim.ros.network_node import NetworkSimNode

        self = cls.__new__(cls)
        kwargs = {} if node_name is None else {"node_name": node_name}
        self._drive(NetworkSimNode(files=[str(f) for f in files], overrides=overrides, context=context, **kwargs), t0,
                    held)
        return self

    @classmethod
    def tms(cls, context, overrides=None, node_name=None, t0=100.0):
        """The line-network node of config/ropos_tms.yaml with its vehicle held where the file puts it."""
        from pathlib import Path

        from tether_sim.network.params import load_network_files

        tms = Path(__file__).resolve().parents[2] / "config" / "ropos_tms.yaml"
        spec, config = load_network_files([tms])
        vehicle = tuple(p - a for p, a in zip(spec.points["vehicle"].position, config.node.vehicle_attachment))
        return cls.network(context, [tms], overrides, node_name=node_name, held={"vehicle": vehicle}, t0=t0)

    def _drive(self, node, t0, held=None):
        self.node = node
        self.held = dict(held or {})
        self.node.driver.wall_budget = None
        self.log = []
        for publisher in self.node.publishers:
            def record(msg, topic=publisher.topic_name):
                self.log[-1].append((topic, msg))
            publisher.publish = record
            publisher.get_subscription_count = lambda: 1
        self.clock = t0
        self.node._now = lambda: self.clock

    def tick(self, z: float, quaternion=(0.0, 0.0, 0.0, 1.0)) -> None:
        """The ship at height ``z`` with orientation (x, y, z, w), stamped 20 ms after the last tick."""
        self.feed(z, quaternion)
        self.node._on_tick()

    def feed(self, z: float, quaternion=(0.0, 0.0, 0.0, 1.0)) -> None:
        """The ship pose of :meth:`tick` 20 ms after the last, without the tick (a period the timer skipped:
        its ``log`` entry stays empty)."""
        self.log.append([])
        self.clock += 0.02
        msg = PoseStamped()
        msg.header.stamp, msg.header.frame_id = time_msg(self.clock), self.node.config.node.world_frame
        msg.pose.position.z = z
        o = msg.pose.orientation
        o.x, o.y, o.z, o.w = quaternion
        self.node._on_pose("ship", msg)
        for name, position in self.held.items():
            held = PoseStamped()
            held.header = msg.header
            held.pose.position.x, held.pose.position.y, held.pose.position.z = (float(v) for v in position)
            held.pose.orientation.w = 1.0
            self.node._on_pose(name, held)
