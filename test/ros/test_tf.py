"""/tf and /tf_static of the simulation node, received through rclpy: the frames compose to the
cable's own end points, the cage frame is its simulated pose, and the frames along the cable point
along it. Also: the TFMessage built from msg_defs/tf2_msgs is the upstream type (same RIHS01 hash)."""

import json
import math
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("rclpy")
pytest.importorskip("tether_sim_msgs")
tf2_msgs = pytest.importorskip("tf2_msgs.msg")
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy  # noqa: E402
from sim_harness import SimHarness  # noqa: E402
from test_sim_node import base_params  # noqa: E402

from tether_sim.ros import tf as tf_out  # noqa: E402

pytestmark = pytest.mark.ros
SHEAVE = (2.0, 0.0, 1.0)  # node.ship_attachment, ship body frame
YAW90 = (0.0, 0.0, math.sin(math.pi / 4), math.cos(math.pi / 4))  # ship heading: x axis to north
CAGE_ATTACH = (0.0, 0.0, 2.1)  # body.attachment (default of the cage), from its centre of gravity


def rotate(q, v):
    return tf_out.rotate(q, v)


def test_tf_message_is_the_upstream_type():
    # rosbags' built-in Jazzy store computes the hash of the real tf2_msgs/msg/TFMessage; ours must
    # equal it or RViz / ros2 tools would refuse the topics
    from rosbags.typesys import Stores, get_typestore

    import ament_index_python

    share = Path(ament_index_python.get_package_share_directory("tf2_msgs"))
    ours = json.loads((share / "msg" / "TFMessage.json").read_text())["type_hashes"][0]["hash_string"]
    assert ours == get_typestore(Stores.ROS2_JAZZY).hash_rihs01("tf2_msgs/msg/TFMessage")


def test_helpers():
    assert tf_out.attachment_frame("rov/base_link", "vehicle") == "rov/tether_attach"
    assert tf_out.attachment_frame("ship/base_link", "ship") == "ship/tether_sheave"
    assert tf_out.attachment_frame("boat", "ship") == "boat_tether_sheave"
    for t in ((0, 0, -1), (1, 0, 0), (-1, 0, 0), (0.3, -0.4, 0.5)):
        q = tf_out.tangent_quaternion(t)
        assert np.linalg.norm(q) == pytest.approx(1.0, abs=1e-12)
        assert rotate(q, (1, 0, 0)) == pytest.approx(np.asarray(t) / np.linalg.norm(t), abs=1e-12)


def _compose(parent, child):
    """parent o child of two geometry_msgs/Transform: (translation, quaternion)."""
    tp, qp = parent
    tc, qc = child
    x1, y1, z1, w1 = qp
    x2, y2, z2, w2 = qc
    q = (w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2, w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
         w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2, w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2)
    return np.asarray(tp) + rotate(qp, tc), q


def _tq(msg):
    t, r = msg.transform.translation, msg.transform.rotation
    return np.array([t.x, t.y, t.z]), (r.x, r.y, r.z, r.w)


def test_tf_frames_compose_to_the_cable_ends():
    flat = base_params(**{"vehicle_end.kind": "body", "vehicle_end.position": (0.0, 0.0, -100.0),
                          "body.initial_position": (0.0, 0.0, -102.1), "node.ship_attachment": SHEAVE,
                          "node.tf_tether_frames": 5})
    h = SimHarness(flat)
    try:
        tf, static = [], []
        latched = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL)
        h.probe.create_subscription(tf2_msgs.TFMessage, "/tf", tf.append, 100)
        h.probe.create_subscription(tf2_msgs.TFMessage, "/tf_static", static.append, latched)
        ship_origin = -rotate(YAW90, SHEAVE)  # so that the sheave is at the world origin
        t, dt = 0.0, 0.02
        while t < 1.2:  # (/tf at node.visual_rate, 10 Hz: enough of them to check five)
            t += dt
            h.step(t, ship=h.pose_msg(t, ship_origin, YAW90))
        assert static and tf, "no /tf_static or /tf received"
        st = {m.child_frame_id: m for m in static[-1].transforms}
        assert st["ship/tether_sheave"].header.frame_id == "ship/base_link"
        assert st["rov/tether_attach"].header.frame_id == "rov/base_link"
        assert _tq(st["ship/tether_sheave"])[0] == pytest.approx(SHEAVE)
        assert _tq(st["rov/tether_attach"])[0] == pytest.approx(CAGE_ATTACH)

        states = {(s.header.stamp.sec, s.header.stamp.nanosec): s for s in h.received["/tether/state"]}
        poses = {(p.header.stamp.sec, p.header.stamp.nanosec): p for p in h.received["/vehicle/sim_pose"]}
        checked = 0
        for msg in tf[-10:]:
            frames = {m.child_frame_id: m for m in msg.transforms}
            assert all(m.header.frame_id == "map" for m in msg.transforms)
            stamp = (msg.transforms[0].header.stamp.sec, msg.transforms[0].header.stamp.nanosec)
            state = states[stamp]
            first = np.array([state.position[0].x, state.position[0].y, state.position[0].z])
            last = np.array([state.position[-1].x, state.position[-1].y, state.position[-1].z])
            # ship: the input pose (interpolated at the stamp; the pose is constant) composed with
            # the sheave offset is the cable's first point, which the solver drives there exactly
            ship = _tq(frames["ship/base_link"])
            assert ship[0] == pytest.approx(ship_origin, abs=1e-9)
            assert np.abs(ship[1]) == pytest.approx(np.abs(YAW90), abs=1e-9)
            assert _compose(ship, _tq(st["ship/tether_sheave"]))[0] == pytest.approx(first, abs=1e-6)
            # vehicle: the cage's simulated pose (same numbers as /vehicle/sim_pose) composed with
            # its attachment is the cable's last point: the body-cable coupling holds the cable end
            # at the attachment point; 1 mm allows for the coupling's substep interpolation
            cage = _tq(frames["rov/base_link"])
            p = poses[stamp].pose
            assert cage[0] == pytest.approx((p.position.x, p.position.y, p.position.z), abs=1e-12)
            assert _compose(cage, _tq(st["rov/tether_attach"]))[0] == pytest.approx(last, abs=1e-3)
            # frames along the cable: first and last at the ends, x along the tangent (here the
            # cable hangs straight down: x -> -z)
            along = [_tq(frames[f"tether/{k}"]) for k in range(5)]
            assert along[0][0] == pytest.approx(first, abs=1e-6) and along[-1][0] == pytest.approx(last, abs=1e-6)
            for pos, q in along:
                assert rotate(q, (1, 0, 0)) == pytest.approx((0.0, 0.0, -1.0), abs=1e-3)
            checked += 1
        assert checked >= 5
    finally:
        h.close()


def test_snap_marker_stands_at_the_snapping_point():
    from types import SimpleNamespace

    from tether_sim_msgs.msg import SnapLoadEvent
    from visualization_msgs.msg import Marker

    from tether_sim.ros import snap_markers
    from tether_sim.ros.convert import time_msg

    event = SnapLoadEvent(end="vehicle", arc_length=250.0, peak_tension=41234.0, amplification=2.59)
    event.header.stamp = time_msg(12.5)
    asked = []

    def state(s):  # a straight vertical cable: the point at arc length s is s metres down
        asked.append(list(s))
        return SimpleNamespace(position=np.array([[0.0, 0.0, -float(x)] for x in s]))

    driver = SimpleNamespace(config=SimpleNamespace(cable=SimpleNamespace(length=200.0),
                                                    node=SimpleNamespace(world_frame="map")),
                             solver=SimpleNamespace(state=state))
    sent = []
    pub = snap_markers.SnapMarkerPublisher.__new__(snap_markers.SnapMarkerPublisher)
    pub.pub, pub.count = SimpleNamespace(publish=sent.append), 0
    pub.publish(event, driver)
    m = sent[0]
    assert asked == [[200.0]]  # an arc length past the end is clamped to the cable
    assert (m.pose.position.x, m.pose.position.y, m.pose.position.z) == (0.0, 0.0, -200.0)
    assert m.type == Marker.TEXT_VIEW_FACING and m.header.frame_id == "map" and m.lifetime.sec == 30
    assert m.text == "snap vehicle: 41.2 kN (x2.59)" and m.header.stamp.sec == 12
