"""Offline runner on a line-network file: the network node's topics per line, the cage and the
wrenches straight to MCAP, driven by recorded poses of the driven points; the report reads it."""

import math

import numpy as np
import pytest
import yaml

pytest.importorskip("rclpy")
pytest.importorskip("tether_sim_msgs")
from geometry_msgs.msg import PoseStamped  # noqa: E402
from rclpy.serialization import serialize_message  # noqa: E402

from tether_sim.io.mcap_log import RosMcapWriter  # noqa: E402
from tether_sim.ros.convert import time_msg  # noqa: E402
from tether_sim.ros.offline import main  # noqa: E402
from test_offline import by_topic  # noqa: E402

pytestmark = pytest.mark.ros

UMB = dict(length=200.0, EA=45.5e6, gamma0=3.01, density=7153.0, diameter=0.03, damping=45500.0,
           material="bilinear", Cdn=1.0, Cdt=0.02, Cmn=1.0, Cmt=0.0)
EXC = dict(length=30.0, EA=2.0e6, gamma0=1.0, density=2000.0, diameter=0.025, damping=2000.0,
           material="bilinear", Cdn=1.2, Cdt=0.02, Cmn=1.0, Cmt=0.0)
VEHICLE = [20.0, 0.0, -225.0]


def write_network(path, **node):
    tree = dict(
        environment=dict(g=9.81, fluid_density=1025.0), coupling_step=0.02,
        points=dict(ship=dict(kind="prescribed", position=[0.0, 0.0, 0.0]),
                    vehicle=dict(kind="prescribed", position=VEHICLE)),
        bodies=dict(cage=dict(mass=4995.0, density=8448.0, added_mass=[9200.0] * 3,
                              drag_coefficients=[1.3, 1.3, 2.7], drag_areas=[12.642, 12.642, 7.1158],
                              inertia=[19000.0] * 3, initial_position=[0.0, 0.0, -202.1])),
        lines={"umbilical": {"from": "ship", "to": "cage", "to_attachment": [0.0, 0.0, 2.1], "cable": UMB,
                             "dg": dict(n_elements=4, order=2)},
               "excursion": {"from": "cage", "to": "vehicle", "from_attachment": [0.0, 0.0, -2.1], "cable": EXC,
                             "dg": dict(n_elements=4, order=3)}})
    params = {"network": tree, "node": {"output_rate": 20.0, "output_points": 11, **node}}
    path.write_text(yaml.safe_dump({"tether_sim": {"ros__parameters": params}}))
    return str(path)


def ship_z(t, t0):
    return 0.5 * math.sin(2.0 * (t - t0))  # heave a = 0.5 m, 2 rad/s


def write_poses(path, t0, span=1.0):
    with RosMcapWriter(str(path)) as w:
        for point in ("ship", "vehicle"):
            w.add_topic(f"/{point}/pose", "geometry_msgs/msg/PoseStamped", "best_effort")
        for k in range(int(round(span / 0.05)) + 1):
            t = t0 + 0.05 * k
            for point, p in (("ship", (0.0, 0.0, ship_z(t, t0))), ("vehicle", VEHICLE)):
                msg = PoseStamped()
                msg.header.stamp = time_msg(t)
                msg.header.frame_id = "map"
                msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = (float(x) for x in p)
                msg.pose.orientation.w = 1.0
                w.write(f"/{point}/pose", serialize_message(msg), int(round(t * 1e9)))
    return str(path)


def test_network_file_runs_offline_per_line_topics_cage_wrenches_and_report(tmp_path, capsys):
    t0 = 500.0
    poses = write_poses(tmp_path / "poses.mcap", t0)
    out = tmp_path / "net.mcap"
    assert main(["--params", write_network(tmp_path / "net.yaml"), "--input", poses, "--output", str(out),
                 "--no-progress"]) == 0
    printed = capsys.readouterr().out
    assert "network" in printed and "umbilical" in printed and "excursion" in printed
    msgs = by_topic(out)
    for line in ("umbilical", "excursion"):
        for kind in ("state", "path", "marker", "description"):
            assert f"/tether/{line}/{kind}" in msgs
    for topic in ("/tether/ship_wrench", "/tether/vehicle_wrench", "/tether/cage_wrench", "/cage/sim_pose", "/tf",
                  "/diagnostics"):
        assert topic in msgs
    states = msgs["/tether/umbilical/state"]
    assert len(states) == 20 + 1  # the initial state and one per tick over the 1 s span of the poses
    for log_ns, m in states:  # log time = stamp = the recording's clock; the ship end follows the heave
        assert log_ns == m.header.stamp.sec * 1_000_000_000 + m.header.stamp.nanosec
        assert m.position[0].z == pytest.approx(ship_z(log_ns * 1e-9, t0), abs=1e-6)
    assert states[-1][0] == int(round((t0 + 1.0) * 1e9))
    # the vehicle wrench is the excursion tether's pull at its s = L end (world-aligned vehicle frame)
    exc = {ns: m for ns, m in msgs["/tether/excursion/state"]}
    for ns, w in msgs["/tether/vehicle_wrench"][::5]:
        f = np.array([w.wrench.force.x, w.wrench.force.y, w.wrench.force.z])
        # (the end force is the upwind flux at the end, the state its axial tension: within 1 % on this slack line)
        assert np.linalg.norm(f) == pytest.approx(exc[ns].vehicle_end_tension, rel=1e-2)
        end, prev = exc[ns].position[-1], exc[ns].position[-2]
        assert np.dot(f, [prev.x - end.x, prev.y - end.y, prev.z - end.z]) > 0.0  # pulls toward the cage
    # the cage on /tf is the cage on cage/sim_pose, and it hangs below the tether's end
    pose = msgs["/cage/sim_pose"][-1][1].pose.position
    tf = msgs["/tf"][-1][1].transforms[0]
    assert tf.child_frame_id == "cage/base_link"
    assert (tf.transform.translation.x, tf.transform.translation.z) == pytest.approx((pose.x, pose.z), abs=1e-12)
    assert states[-1][1].position[-1].z - pose.z == pytest.approx(2.1, abs=0.05)
    # the report reads it, one report per line
    from tether_sim.report import make_network_report

    make_network_report(out, tmp_path / "report")
    for line in ("umbilical", "excursion"):
        assert (tmp_path / "report" / line / "end_tensions.png").is_file()


def test_without_input_the_points_hold_and_the_system_rests(tmp_path, capsys):
    out = tmp_path / "rest.mcap"
    assert main(["--params", write_network(tmp_path / "net.yaml"), "--duration", "0.5", "--output", str(out),
                 "--no-progress"]) == 0
    assert "held at their configured positions: ship, vehicle" in capsys.readouterr().out
    states = [m for _, m in by_topic(out)["/tether/umbilical/state"]]
    assert len(states) == 11
    # at rest the ship-end tension stays at its static value (the umbilical's and the cage's wet weight
    # plus the excursion tether's pull): the network started at its equilibrium
    t = np.array([m.ship_end_tension for m in states])
    assert np.ptp(t) < 1e-3 * t[0]


def test_a_bad_network_file_names_the_key(tmp_path, capsys):
    path = tmp_path / "bad.yaml"
    write_network(path)
    path.write_text(path.read_text().replace("to: vehicle", "to: vehicel"))
    assert main(["--params", str(path), "--output", str(tmp_path / "x.mcap"), "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert "network.lines.excursion.to" in err and "vehicle" in err
    assert not (tmp_path / "x.mcap").exists()


def test_point_and_body_wrenches_are_the_line_loads_in_the_body_frame(tmp_path):
    """network_outputs.point_wrench / body_wrench (written on floats) against the numpy statement of
    what they are: the summed end loads of the lines on the point or body, rotated into its frame, the
    moment about the frame origin (point: its attachment lever) or the CoG (body), to round-off; with a
    tilted body and a turned vehicle frame."""
    from types import SimpleNamespace

    from tether_sim.network.params import load_network_files
    from tether_sim.network.solver import NetworkSolver
    from tether_sim.numerics.rotations import quaternion_matrix
    from tether_sim.ros import network_outputs as outputs

    spec, cfg = load_network_files([write_network(tmp_path / "net.yaml")])
    net = NetworkSolver(spec)
    rng = np.random.default_rng(5)
    for loads in net._loads.values():
        loads[:] = rng.normal(size=loads.shape) * 1e3
    body = net.bodies["cage"]
    body.state[3:7] = rng.normal(size=4)
    body.state[3:7] /= np.linalg.norm(body.state[3:7])
    driver = SimpleNamespace(net=net, spec=spec)
    q = rng.normal(size=4)
    q /= np.linalg.norm(q)
    node = SimpleNamespace(vehicle_attachment=(0.3, -0.2, 0.5), ship_attachment=(0.0, 0.0, 0.0))
    f, t = outputs.point_wrench(driver, node, "vehicle", q)
    R = quaternion_matrix(q)
    F, _, M = net.end_load("excursion", "vehicle")
    np.testing.assert_allclose(f, R.T @ F, rtol=1e-13, atol=1e-13 * np.abs(F).max())
    np.testing.assert_allclose(t, np.cross(node.vehicle_attachment, R.T @ F) + R.T @ M, rtol=1e-13,
                               atol=1e-12 * np.abs(F).max())
    Fb, Mb = net._body_loads("cage")
    Rb = quaternion_matrix(body.state[3:7])
    lever = body.attachments @ Rb.T
    fb, mb = outputs.body_wrench(net, "cage")
    np.testing.assert_allclose(fb, Rb.T @ Fb.sum(axis=0), rtol=1e-13, atol=1e-13 * np.abs(Fb).max())
    np.testing.assert_allclose(mb, Rb.T @ (np.cross(lever, Fb).sum(axis=0) + Mb.sum(axis=0)), rtol=1e-13,
                               atol=1e-12 * np.abs(Fb).max())
