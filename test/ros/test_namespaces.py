"""Two tethers in one ROS domain, one per namespace (`-r __ns:=/rov1`, `/rov2`): every topic of a
node moves into its namespace (only /diagnostics, /clock, /tf, /tf_static stay global), each node
follows its own ship pose and solves its own cable; with `node.frame_prefix` each publishes its own
TF frames (no frame from two nodes, stamps in order per frame), and their /diagnostics statuses
carry distinct names and hardware ids."""

import pytest

pytest.importorskip("rclpy")
pytest.importorskip("tether_sim_msgs")
import rclpy  # noqa: E402
from geometry_msgs.msg import PoseStamped  # noqa: E402
from rclpy.executors import SingleThreadedExecutor  # noqa: E402
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy  # noqa: E402
from diagnostic_msgs.msg import DiagnosticArray  # noqa: E402
from rosgraph_msgs.msg import Clock  # noqa: E402
from sim_harness import overrides  # noqa: E402
from tether_sim_msgs.msg import TetherDescription, TetherState  # noqa: E402
from test_sim_node import G, RHO_F, W, base_params  # noqa: E402

from tether_sim.ros.convert import time_msg  # noqa: E402
from tether_sim.ros.sim_node import TetherSimNode  # noqa: E402
from tether_sim.ros.tf import TF_QOS, TF_STATIC_QOS, TFMessage  # noqa: E402

pytestmark = pytest.mark.ros
LENGTHS = {"rov1": 100.0, "rov2": 60.0}
CAGE, RHO_BODY = 4995.0, 8448.0


def test_two_namespaced_nodes_in_one_domain_keep_their_topics_apart():
    context = rclpy.Context()
    rclpy.init(context=context)
    nodes, executor = [], SingleThreadedExecutor(context=context)
    try:
        for ns, length in LENGTHS.items():
            flat = base_params(**{"cable.length": length, "vehicle_end.kind": "body",
                                  "vehicle_end.position": (0.0, 0.0, -length),
                                  "body.initial_position": (0.0, 0.0, -length - 2.1),
                                  "node.frame_prefix": f"{ns}/"})
            nodes.append(TetherSimNode(context=context, parameter_overrides=overrides(flat),
                                       cli_args=["--ros-args", "-r", f"__ns:=/{ns}"]))
        probe = rclpy.create_node("probe", context=context)
        clock = probe.create_publisher(Clock, "/clock", QoSProfile(depth=1, reliability=ReliabilityPolicy.BEST_EFFORT))
        poses = {ns: probe.create_publisher(PoseStamped, f"/{ns}/ship/pose", 10) for ns in LENGTHS}
        states = {ns: [] for ns in LENGTHS}
        descriptions = {ns: [] for ns in LENGTHS}
        latched = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL)
        for ns in LENGTHS:
            probe.create_subscription(TetherState, f"/{ns}/tether/state", states[ns].append, 100)
            probe.create_subscription(TetherDescription, f"/{ns}/tether/description", descriptions[ns].append, latched)
        tf, tf_static, diagnostics = [], [], []
        if TFMessage is not None:
            probe.create_subscription(TFMessage, "/tf", tf.append, TF_QOS)
            # as tf2's static listener: deep enough to keep both nodes' latched messages
            static_qos = QoSProfile(depth=100, reliability=TF_STATIC_QOS.reliability, durability=TF_STATIC_QOS.durability)
            probe.create_subscription(TFMessage, "/tf_static", tf_static.append, static_qos)
        probe.create_subscription(DiagnosticArray, "/diagnostics", diagnostics.append, 10)
        for node in nodes + [probe]:
            executor.add_node(node)
        t = 0.0
        while t < 1.2 or not diagnostics:
            t += 0.02
            for ns, pub in poses.items():
                msg = PoseStamped()
                msg.header.stamp, msg.header.frame_id = time_msg(t), "map"
                msg.pose.orientation.w = 1.0
                pub.publish(msg)
            clock.publish(Clock(clock=time_msg(t)))
            for _ in range(6):
                executor.spin_once(timeout_sec=0.002)

        names = {name for name, _ in probe.get_topic_names_and_types()}
        for ns in LENGTHS:
            for topic in ("tether/state", "tether/description", "tether/vehicle_wrench", "tether/snap_events",
                          "ship/pose", "vehicle/sim_pose"):
                assert f"/{ns}/{topic}" in names, (ns, topic, sorted(names))
        assert not {"/tether/state", "/ship/pose", "/tether/description"} & names, sorted(names)
        assert {"/diagnostics", "/tf", "/tf_static"} <= names  # global by convention

        weight = CAGE * G * (1.0 - RHO_F / RHO_BODY)  # submerged weight of the cage
        for ns, length in LENGTHS.items():
            assert states[ns] and descriptions[ns], ns
            assert descriptions[ns][-1].length == pytest.approx(length)
            last = states[ns][-1]
            # each node hangs its own cage on its own cable: ship tension = cage + W L (same 0.5 %
            # as test_sim_node's hanging-cage check); the two lengths differ by 40 m, 2.5 kN of
            # ship tension, far outside the tolerance, so crossed topics cannot pass
            assert last.ship_end_tension == pytest.approx(weight + W * length, rel=0.005), ns
            assert last.arc_length[-1] == pytest.approx(length)
            assert (descriptions[ns][-1].ship_frame, descriptions[ns][-1].vehicle_frame) == \
                (f"{ns}/ship/base_link", f"{ns}/rov/base_link")

        # diagnostics: one simulation status per node, named and identified apart
        statuses = {(st.name, st.hardware_id) for d in diagnostics for st in d.status}
        for ns in LENGTHS:
            assert (f"{ns}/tether_sim: simulation", f"/{ns}/tether_sim") in statuses, statuses
            assert (f"{ns}/tether_sim: ship input", f"/{ns}/tether_sim") in statuses, statuses
        assert len({hw for _, hw in statuses}) == len(LENGTHS)

        if TFMessage is None:
            pytest.skip("tf2_msgs is not importable: no /tf to check (the rest passed)")
        # TF: each node's frames behind its prefix; no child frame published by both; in order
        parents = {}  # child -> set of (parent, publisher namespace by prefix)
        stamps = {}
        for msg in tf:
            for tr in msg.transforms:
                parents.setdefault(tr.child_frame_id, set()).add(tr.header.frame_id)
                stamps.setdefault(tr.child_frame_id, []).append(tr.header.stamp.sec * 10**9 + tr.header.stamp.nanosec)
        statics = {tr.child_frame_id: tr.header.frame_id for msg in tf_static for tr in msg.transforms}
        for ns in LENGTHS:
            assert parents[f"{ns}/ship/base_link"] == {"map"} and parents[f"{ns}/rov/base_link"] == {"map"}
            assert statics[f"{ns}/ship/tether_sheave"] == f"{ns}/ship/base_link"
            assert statics[f"{ns}/rov/tether_attach"] == f"{ns}/rov/base_link"
        assert set(parents) == {f"{ns}/{leaf}" for ns in LENGTHS for leaf in ("ship/base_link", "rov/base_link")}
        for child, seq in stamps.items():  # one publisher per frame: its stamps never go back
            assert all(b > a for a, b in zip(seq, seq[1:])), child
    finally:
        executor.shutdown()
        for node in nodes:
            node.destroy_node()
        rclpy.shutdown(context=context)
