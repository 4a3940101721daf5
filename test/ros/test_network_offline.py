"""Offline runner on a line-network file: the network node's topics per line, the cage and the
wrenches straight to MCAP, driven by recorded poses of the driven points; the report reads it."""

import math
import signal
import time

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


def test_the_report_of_the_cage_is_the_recorded_cage(tmp_path):
    """The cage's figures (report_body.py) carry the recorded values, and those are the cage's
    motion: the pose, velocity and acceleration of /cage/sim_*, each line's end tension at the cage
    from its state, the lines' force (/tether/cage_wrench turned into the world frame), drag and wet
    weight; the recorded acceleration is Newton's law on the recorded forces (isotropic added mass) to
    round-off, the velocity the integral of it and the position the integral of the velocity (to
    the 20 Hz output step), the wet weight the closed form (m - rho V) g."""
    from tether_sim.numerics.rotations import quaternion_matrix
    from tether_sim.report import make_network_report

    t0 = 500.0
    poses = write_poses(tmp_path / "poses.mcap", t0, span=2.0)
    out = tmp_path / "net.mcap"
    assert main(["--params", write_network(tmp_path / "net.yaml"), "--input", poses, "--output", str(out),
                 "--no-progress"]) == 0
    msgs = by_topic(out)
    result = make_network_report(out, tmp_path / "report")
    cage = result["bodies"]["cage"]
    b = cage["series"]
    pose = [m for _, m in msgs["/cage/sim_pose"]]
    assert len(b.t) == len(pose) == 41
    np.testing.assert_allclose(b.t + result["lines"]["umbilical"]["run"].t0,
                               [m.header.stamp.sec + 1e-9 * m.header.stamp.nanosec for m in pose], rtol=0, atol=1e-9)
    np.testing.assert_array_equal(b.position, [[m.pose.position.x, m.pose.position.y, m.pose.position.z] for m in pose])

    def vectors(topic, get):
        return np.array([[getattr(get(m), c) for c in "xyz"] for _, m in msgs[topic]])

    np.testing.assert_array_equal(b.velocity, vectors("/cage/sim_twist", lambda m: m.twist.linear))
    np.testing.assert_array_equal(b.acceleration, vectors("/cage/sim_accel", lambda m: m.accel.linear))
    np.testing.assert_array_equal(b.drag, vectors("/cage/hydro_wrench", lambda m: m.wrench.force))
    body_frame = vectors("/tether/cage_wrench", lambda m: m.wrench.force)
    q = [[m.pose.orientation.x, m.pose.orientation.y, m.pose.orientation.z, m.pose.orientation.w] for m in pose]
    world = np.array([quaternion_matrix(np.array(x)) @ f for x, f in zip(q, body_frame)])
    np.testing.assert_allclose(b.line_force, world, rtol=0, atol=1e-9 * np.abs(world).max())
    # each line's end tension at the cage: the umbilical's s = L end, the excursion tether's s = 0 end
    umb = [m.vehicle_end_tension for _, m in msgs["/tether/umbilical/state"]]
    exc = [m.ship_end_tension for _, m in msgs["/tether/excursion/state"]]
    np.testing.assert_array_equal(b.end_tension["umbilical (s = L end)"][1], umb)
    np.testing.assert_array_equal(b.end_tension["excursion (s = 0 end)"][1], exc)
    vehicle = vectors("/tether/vehicle_wrench", lambda m: m.wrench.force)
    np.testing.assert_array_equal(b.vehicle_force[1], np.linalg.norm(vehicle, axis=1))
    # the wet weight: the cage of write_network, (m - rho m / rho_c) g
    assert b.wet_weight == pytest.approx(4995.0 * 9.81 * (1.0 - 1025.0 / 8448.0), rel=1e-12)
    # Newton: (m + m_a) a = lines + wet weight + drag, every component (added mass 9200 kg on every axis)
    net = b.line_force + b.drag + np.array([0.0, 0.0, -b.wet_weight])
    np.testing.assert_allclose((4995.0 + 9200.0) * b.acceleration, net, rtol=0, atol=1e-9 * np.abs(net).max())
    np.testing.assert_allclose(b.vertical_forces()["net"], net[:, 2], rtol=0, atol=1e-9 * np.abs(net).max())
    # the motion is one: the velocity is the integral of the acceleration and the position that of the
    # velocity (cumulative trapezoid over the 20 Hz outputs: the acceleration carries the umbilical's
    # axial ringing, 2 L / c = 0.1 s, which 20 Hz samples cannot integrate better than a few per cent)
    from scipy.integrate import cumulative_trapezoid

    v, z = b.velocity[:, 2], b.position[:, 2]
    assert np.ptp(z) > 0.5  # the heave moves the cage
    assert np.abs(cumulative_trapezoid(v, b.t, initial=0.0) - (z - z[0])).max() < 5e-3 * np.ptp(z)
    assert np.abs(cumulative_trapezoid(b.acceleration[:, 2], b.t, initial=0.0) - (v - v[0])).max() < 0.03 * np.abs(v).max()
    # the summary and the figures
    summary = cage["summary"]
    assert summary["z_m"] == {"min": b.position[:, 2].min(), "max": b.position[:, 2].max()}
    assert summary["vertical_acceleration_m_s2"]["max"] == b.acceleration[:, 2].max()
    assert summary["end_tension_N"]["umbilical (s = L end)"]["max"] == max(umb)
    for name in ("motion", "forces"):
        assert cage["figures"][name] == tmp_path / "report" / "cage" / f"{name}.png"
        assert cage["figures"][name].stat().st_size > 10_000
    assert "## Body `cage`" in result["markdown"] and "cage/forces.png" in result["markdown"]


def test_a_study_on_a_network_file_tabulates_every_line(tmp_path):
    """tether-sim-study with a network base file: the cage's mass varied, the ship heaved (the study's
    motion.* keys drive the network's ship point). Every line gets its per-end columns; the static
    tension at the ship grows by the added wet weight of the cage (closed form, to the excursion
    tether's change of pull); the vehicle force column is the largest |force| the run wrote on
    /tether/vehicle_wrench; each line's T_min / T_max bound its recorded end tensions; the report
    tabulates each line."""
    from tether_sim.studies.report import write_report
    from tether_sim.studies.results import read_results
    from tether_sim.studies.runner import run_study

    write_network(tmp_path / "net.yaml")
    study = tmp_path / "study.yaml"
    study.write_text(yaml.safe_dump({
        "name": "cage_mass", "base": "net.yaml",
        "vary": {"grid": {"network.bodies.cage.mass": [4995.0, 9990.0]}},
        "set": {"motion.kind": "heave", "motion.amplitude": 0.5, "motion.frequency": 0.3, "duration": 1.0},
        "keep": {"mcap": True, "events": True}}))
    summary = run_study(study, tmp_path / "out", workers=1)
    assert (summary["ran"], summary["ok"], summary["failed"]) == (2, 2, 0)
    rows = sorted(read_results(tmp_path / "out"), key=lambda r: r["index"])
    for r in rows:
        assert r["network"] and r["status"] == "ok" and r["sim_s"] == 1.0
        assert (r["umbilical.length_m"], r["excursion.length_m"], r["fairlead_amplitude_m"]) == (200.0, 30.0, 0.5)
        msgs = by_topic(r["mcap"])
        ship = [m.position[0].z for _, m in msgs["/tether/umbilical/state"]]
        assert max(ship) == pytest.approx(0.5, abs=0.05)  # the heave drove the ship point
        forces = [np.linalg.norm([m.wrench.force.x, m.wrench.force.y, m.wrench.force.z])
                  for _, m in msgs["/tether/vehicle_wrench"][1:]]  # (the first: the state before the first tick)
        assert r["vehicle_force_max_N"] == pytest.approx(max(forces), rel=1e-12)
        for line in ("umbilical", "excursion"):
            for end in ("ship", "vehicle"):
                recorded = [getattr(m, f"{end}_end_tension") for _, m in msgs[f"/tether/{line}/state"][1:]]
                # the substeps include the output instants (the detector's samples and the state's end
                # tension agree to 1 % of the largest: end flux against axial tension on a slack line)
                slack = 0.01 * max(recorded)
                assert r[f"{line}.{end}_T_min_N"] - slack <= min(recorded) <= max(recorded) <= r[f"{line}.{end}_T_max_N"] + slack
            snaps = msgs.get(f"/tether/{line}/snap_events", [])
            assert r[f"{line}.ship_n_snap"] + r[f"{line}.vehicle_n_snap"] <= len(snaps)  # (one per slack episode)
    added = (9990.0 - 4995.0) * 9.81 * (1.0 - 1025.0 / 8448.0)  # the cage's density kept: its volume doubles
    grew = rows[1]["umbilical.ship_static_N"] - rows[0]["umbilical.ship_static_N"]
    assert grew == pytest.approx(added, rel=2e-3)
    md = write_report(tmp_path / "out").read_text()
    assert "## Line `umbilical`" in md and "## Line `excursion`" in md and "vehicle kN" in md


def test_a_network_recording_replays_to_a_recorder_byte_for_byte(tmp_path, isolated_ros_env):
    """A network recording (per-line custom messages, the cage's latched wet weight) goes through
    tether-sim-replay into tether-sim-record unchanged: every payload of the replayed topics arrives, in
    order, with the bytes it was written with (and the transport's alignment padding), and the latched
    topic is latched again."""
    from tether_sim.io.mcap_log import iter_raw, read_summary
    from test_recorder_replay import ros_env, start, stop

    t0 = 500.0
    src, rec = tmp_path / "net.mcap", tmp_path / "rec.mcap"
    assert main(["--params", write_network(tmp_path / "net.yaml"), "--input", write_poses(tmp_path / "poses.mcap", t0),
                 "--output", str(src), "--no-progress"]) == 0
    topics = ["/tether/umbilical/state", "/tether/excursion/state", "/tether/vehicle_wrench", "/cage/sim_pose",
              "/cage/wet_weight"]
    written = {t: [m.data for m in iter_raw(src, t)] for t in topics}
    assert all(written.values()), {t: len(v) for t, v in written.items()}
    assert read_summary(src).topics["/cage/wet_weight"].latched
    env = ros_env(isolated_ros_env)
    recorder = start("tether_sim.ros.recorder_node", "-o", rec, *topics, "/clock", env=env)
    replay = start("tether_sim.ros.replay_node", src, "--topics", *topics, "--wait-for-subscribers", 30, env=env)
    try:
        replay_out, _ = replay.communicate(timeout=90)
    finally:
        time.sleep(0.5)  # let the last samples arrive
        recorder_out = stop(recorder, signal.SIGTERM)
    assert replay.returncode == 0, replay_out
    assert recorder.returncode == 0, recorder_out
    for t in topics:  # DDS pads a payload to a multiple of 4 bytes on the wire (the RTPS serialized payload);
        got = [m.data for m in iter_raw(rec, t)]  # a CDR reader ignores the padding after the last field
        assert len(got) == len(written[t]), (t, len(got), len(written[t]))
        for g, w in zip(got, written[t]):
            assert g[:len(w)] == w and set(g[len(w):]) <= {0} and len(g) - len(w) < 4 and len(g) % 4 == 0, t
    assert read_summary(rec).topics["/cage/wet_weight"].latched
