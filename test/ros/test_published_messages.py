"""Every periodic message the simulation node publishes in a short deterministic run, field by field,
against the same message written out here from the solver's own outputs with rclpy message objects
(the plain statement of docs/node.md's outputs: no CDR templates, no cached layouts).

The node is driven by hand as benchmarks/bench_node_tick.py drives it (a hand clock, the ship pose
given to its pose callback, the tick called directly; no wall-clock budget), with every publisher
counted as subscribed and its messages recorded. The ship moves on a heave and is yawed and rolled
with an attachment offset, the cage hangs at the other end, and /tf carries three tether frames, so
each rotation and offset of the outputs enters. After each tick the solver still holds the state the
tick published: the expected messages are built from it. A field that changes (a frame, a stamp, a
point, a colour, a sign of a wrench) fails the test.
"""

import math

import numpy as np
import pytest

pytest.importorskip("rclpy")
pytest.importorskip("tether_sim_msgs")
import rclpy  # noqa: E402
from geometry_msgs.msg import PoseStamped, WrenchStamped  # noqa: E402
from nav_msgs.msg import Path  # noqa: E402
from rclpy.serialization import deserialize_message  # noqa: E402
from sim_harness import HandDriven  # noqa: E402
from tether_sim_msgs.msg import TetherState  # noqa: E402
from visualization_msgs.msg import Marker  # noqa: E402

from tether_sim.io.params import load_config, to_flat  # noqa: E402
from tether_sim.numerics.rotations import quaternion_matrix  # noqa: E402
from tether_sim.ros.tf import TFMessage  # noqa: E402

pytestmark = pytest.mark.ros

ROOT = __import__("pathlib").Path(__file__).resolve().parents[2]
YAW, ROLL = 0.5, 0.1  # rad: the ship's fixed attitude
SHIP_ATTACH = (1.5, -0.5, -2.0)  # m, fairlead in the ship frame
TICKS = 60


def ship_quaternion():
    """(x, y, z, w) of a yaw about z followed by a roll about the body x axis."""
    cy, sy, cr, sr = math.cos(YAW / 2), math.sin(YAW / 2), math.cos(ROLL / 2), math.sin(ROLL / 2)
    return (cy * sr, sy * sr, sy * cr, cy * cr)


@pytest.fixture(scope="module")
def run():
    flat = to_flat(load_config(ROOT / "config/ropos_L200.yaml"))
    flat.update({"node.tick_budget": 1.0e6, "node.tf_tether_frames": 3, "node.ship_attachment": SHIP_ATTACH,
                 "node.visual_rate": 0.0})  # every output carries every message (test_visual_rate.py: the rate)
    context = rclpy.Context()
    rclpy.init(context=context)
    driven = HandDriven(context, flat)
    node, log = driven.node, driven.log
    q = ship_quaternion()
    expected = []
    for k in range(TICKS):
        driven.tick(0.8 * math.sin(2.0 * math.pi * 0.5 * (driven.clock + 0.02 - 100.0)), q)
        expected.append(expected_messages(node) if node.driver.solver is not None else {})
    yield node, log, expected
    node.destroy_node()
    rclpy.shutdown(context=context)


def expected_messages(node):
    """{topic: (message type, expected fields)} of the state the node's solver holds now."""
    d, cfg = node.driver, node.config
    solver, world = d.solver, cfg.node.world_frame
    s = node.arc_lengths
    st = solver.state(s)
    forces = solver.end_forces()
    body = solver.body_state("vehicle")
    out = {"stamp": d.stamp, "world": world}
    out["/tether/state"] = dict(arc_length=s, position=st.position, velocity=st.velocity, tension=st.tension,
                                curvature=st.curvature, bending_moment=st.bending_moment,
                                ship_tension=forces.ship_tension, vehicle_tension=forces.vehicle_tension,
                                time_step=st.time_step, lag=d.lag, degraded=d.degraded, solver=solver.name,
                                real_time_factor=d.real_time_factor)
    scale = 2.0 * max(abs(d.static_tensions[0]), abs(d.static_tensions[1]), 1.0)
    dd = np.clip(np.asarray(st.tension) / scale * 2.0 - 1.0, -1.0, 1.0)
    out["colours"] = np.column_stack([np.maximum(dd, 0.0), 1.0 - np.abs(dd), np.maximum(-dd, 0.0),
                                      np.ones_like(dd)]).astype(np.float32)
    R_ship = quaternion_matrix(ship_quaternion())
    R_body = quaternion_matrix(body.orientation)
    for end, R, r in (("ship", R_ship, np.array(SHIP_ATTACH)), ("vehicle", R_body, np.array(cfg.body.attachment))):
        F, M = getattr(forces, f"{end}_force"), getattr(forces, f"{end}_moment")
        f = R.T @ F
        out[f"/tether/{end}_wrench"] = (cfg.node.body_frame(end), f, np.cross(r, f) + R.T @ M)
    out["body"] = (np.array(body.position), np.array(body.orientation))
    ends = solver.state(np.array([0.0, cfg.cable.length])).position
    out["tf"] = {cfg.node.body_frame("ship"): (ends[0] - R_ship @ np.array(SHIP_ATTACH), np.array(ship_quaternion())),
                 cfg.node.body_frame("vehicle"): (np.array(body.position), np.array(body.orientation))}
    L = cfg.cable.length
    pts = solver.state(np.linspace(0.0, L, 3)).position
    for k in range(3):
        out["tf"][cfg.node.tether_frame(k)] = (pts[k], None)
    return out


def stamp_of(header):
    return header.stamp.sec + header.stamp.nanosec * 1e-9


def test_every_periodic_message_is_the_solver_state_field_by_field(run):
    node, log, expected = run
    close = dict(rtol=1e-12, atol=1e-9)  # recomputed rotations: rounding only
    started = [k for k in range(TICKS) if expected[k]]
    assert len(started) >= TICKS - 2
    for k in started:
        exp, got = expected[k], {}
        for topic, data in log[k]:
            got.setdefault(topic, []).append(data)
        for topic in ("/tether/state", "/tether/marker", "/tether/path", "/tether/ship_wrench", "/tether/vehicle_wrench",
                      "/vehicle/sim_pose", "/tf"):
            assert len(got.get(topic, [])) == 1, (k, topic, sorted(got))
        stamp = exp["stamp"]

        state = deserialize_message(got["/tether/state"][0], TetherState)
        e = exp["/tether/state"]
        assert state.header.frame_id == exp["world"] and abs(stamp_of(state.header) - stamp) < 1e-9
        assert state.solver == e["solver"]
        for name in ("arc_length", "tension", "curvature", "bending_moment"):
            np.testing.assert_array_equal(getattr(state, name), e[name], err_msg=name)
        for name in ("position", "velocity"):
            np.testing.assert_array_equal([[p.x, p.y, p.z] for p in getattr(state, name)], e[name], err_msg=name)
        assert (state.ship_end_tension, state.vehicle_end_tension, state.time_step, state.lag, state.degraded,
                state.real_time_factor) == (e["ship_tension"], e["vehicle_tension"], e["time_step"], e["lag"],
                                            e["degraded"], e["real_time_factor"])

        marker = deserialize_message(got["/tether/marker"][0], Marker)
        assert (marker.header.frame_id, marker.ns, marker.id, marker.type, marker.action) == (
            exp["world"], "tether", 0, Marker.LINE_STRIP, Marker.ADD)
        assert abs(stamp_of(marker.header) - stamp) < 1e-9 and not marker.frame_locked
        assert (marker.scale.x, marker.pose.orientation.w, marker.pose.position.x) == (0.2, 1.0, 0.0)
        assert (marker.color.r, marker.color.g, marker.color.b, marker.color.a) == (1.0, 1.0, 0.0, 1.0)
        np.testing.assert_array_equal([[p.x, p.y, p.z] for p in marker.points], e["position"])
        np.testing.assert_array_equal(np.array([[c.r, c.g, c.b, c.a] for c in marker.colors], np.float32),
                                      exp["colours"])

        path = deserialize_message(got["/tether/path"][0], Path)
        assert path.header.frame_id == exp["world"] and len(path.poses) == len(e["position"])
        for pose, p in zip(path.poses, e["position"]):
            assert pose.header == path.header and pose.pose.orientation.w == 1.0
            assert (pose.pose.position.x, pose.pose.position.y, pose.pose.position.z) == tuple(p)

        for end in ("ship", "vehicle"):
            w = deserialize_message(got[f"/tether/{end}_wrench"][0], WrenchStamped)
            frame, f, m = exp[f"/tether/{end}_wrench"]
            assert w.header.frame_id == frame and abs(stamp_of(w.header) - stamp) < 1e-9
            np.testing.assert_allclose([w.wrench.force.x, w.wrench.force.y, w.wrench.force.z], f, **close)
            np.testing.assert_allclose([w.wrench.torque.x, w.wrench.torque.y, w.wrench.torque.z], m, rtol=1e-12,
                                       atol=1e-9 * np.linalg.norm(f))

        pose = deserialize_message(got["/vehicle/sim_pose"][0], PoseStamped)
        p, q = exp["body"]
        assert pose.header.frame_id == exp["world"]
        assert (pose.pose.position.x, pose.pose.position.y, pose.pose.position.z) == tuple(p)
        o = pose.pose.orientation
        assert (o.x, o.y, o.z, o.w) == tuple(q)

        if TFMessage is not None:
            tf = deserialize_message(got["/tf"][0], TFMessage)
            assert [t.child_frame_id for t in tf.transforms] == list(exp["tf"])
            for t in tf.transforms:
                assert t.header.frame_id == exp["world"] and abs(stamp_of(t.header) - stamp) < 1e-9
                p, q = exp["tf"][t.child_frame_id]
                tr, rq = t.transform.translation, t.transform.rotation
                np.testing.assert_allclose([tr.x, tr.y, tr.z], p, **close)
                if q is not None:
                    np.testing.assert_allclose([rq.x, rq.y, rq.z, rq.w], q, **close)
                assert abs(math.sqrt(rq.x ** 2 + rq.y ** 2 + rq.z ** 2 + rq.w ** 2) - 1.0) < 1e-12


def test_the_ship_wrench_is_in_the_yawed_and_rolled_frame(run):
    """The check above can fail: the ship's wrench differs from the world-frame force by the rotation
    (yaw 0.5 rad, roll 0.1 rad), by more than its tolerance."""
    node, log, expected = run
    k = TICKS - 1
    w = deserialize_message(next(d for t, d in log[k] if t == "/tether/ship_wrench"), WrenchStamped)
    world = node.driver.solver.end_forces().ship_force
    assert np.linalg.norm([w.wrench.force.x - world[0], w.wrench.force.y - world[1], w.wrench.force.z - world[2]]) > \
        1e-3 * np.linalg.norm(world)
