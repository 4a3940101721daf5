"""Offline runner: same messages as the node, straight to MCAP, from a motion generator or an MCAP
of poses; parameter errors are clear."""

import math

import pytest
import yaml

pytest.importorskip("rclpy")
pytest.importorskip("tether_sim_msgs")
from geometry_msgs.msg import PoseStamped  # noqa: E402
from rclpy.serialization import serialize_message  # noqa: E402

from tether_sim.io.mcap_log import RosMcapWriter, read_messages  # noqa: E402
from tether_sim.ros.convert import TOPICS, time_msg  # noqa: E402
from tether_sim.ros.offline import main  # noqa: E402

pytestmark = pytest.mark.ros

SHIP = [0.0, 0.0, 0.0]
VEHICLE = [30.0, 0.0, -40.0]


def write_params(path, **extra):
    p = {"solver": "dg", "duration": 2.0,
         "cable": {"length": 55.0, "EA": 1.0e6, "damping": 1.0e3},
         "ship_end": {"kind": "prescribed", "position": SHIP},
         "vehicle_end": {"kind": "fixed", "position": VEHICLE},
         "dg": {"n_elements": 6, "order": 3},
         "node": {"output_rate": 20.0, "output_points": 11}}
    for k, v in extra.items():
        p[k] = {**p.get(k, {}), **v} if isinstance(v, dict) else v
    path.write_text(yaml.safe_dump({"tether_sim": {"ros__parameters": p}}))
    return str(path)


def by_topic(path):
    out = {}
    for topic, _type, log_ns, msg in read_messages(str(path)):
        out.setdefault(topic, []).append((log_ns, msg))
    return out


def test_motion_generator_run_writes_every_topic_with_sim_time_log_times(tmp_path, capsys):
    # circular fairlead orbit a = 0.5 m, f = 0.5 Hz [PE2020 Sec. 6.2] about the ship end
    params = write_params(tmp_path / "p.yaml", motion={"kind": "circle", "amplitude": 0.5, "frequency": 0.5})
    out = tmp_path / "out.mcap"
    assert main(["--params", params, "--output", str(out), "--no-progress"]) == 0
    printed = capsys.readouterr()
    assert "static tensions" in printed.out and "s of CPU" in printed.out
    # the time it will take is said before it starts (the progress bar's ETA comes only once it runs)
    assert "2 s simulated, 40 output ticks: expected to take about" in printed.err and "of CPU" in printed.err
    msgs = by_topic(out)
    expected = {t for t in TOPICS if not t.endswith("sim_pose")} | {"/tf", "/tf_static"}
    assert set(msgs) == expected
    states = msgs["/tether/state"]
    assert len(states) == 2.0 * 20 + 1  # the initial state and one per tick
    for log_ns, m in states:  # log time = header stamp = sim time
        assert log_ns == m.header.stamp.sec * 1_000_000_000 + m.header.stamp.nanosec
    assert states[-1][0] == 2_000_000_000
    # the ship end follows the orbit (starting at its top) x = a sin(w t), z = a cos(w t)
    w = 2 * math.pi * 0.5
    for log_ns, m in states[::5]:
        t = log_ns * 1e-9
        p = m.position[0]
        assert (p.x, p.z) == pytest.approx((0.5 * math.sin(w * t), 0.5 * math.cos(w * t)), abs=1e-6)
    marker = msgs["/tether/marker"][-1][1]
    assert marker.type == 4 and len(marker.colors) == len(marker.points) == 11  # LINE_STRIP, per-vertex colours
    path = msgs["/tether/path"][-1][1]
    assert [p.pose.position.z for p in path.poses] == [p.z for p in states[-1][1].position]
    assert msgs["/tether/description"][0][1].length == 55.0
    assert len(msgs["/diagnostics"]) == 2
    # an independent reader decodes every message, custom types from the schema text in the file
    from pathlib import Path

    from rosbags.highlevel import AnyReader
    from rosbags.typesys import Stores, get_typestore

    with AnyReader([Path(out)], default_typestore=get_typestore(Stores.EMPTY)) as reader:
        decoded = [(c.topic, reader.deserialize(raw, c.msgtype)) for c, _, raw in reader.messages()]
    assert len(decoded) == sum(len(v) for v in msgs.values())
    last = [m for topic, m in decoded if topic == "/tether/state"][-1]
    assert last.ship_end_tension == states[-1][1].ship_end_tension and len(last.position) == 11
    # /tf_static once, /tf with every state (same stamps), as the node publishes them: composing
    # map -> body -> attachment gives the cable's end points of the TetherState of that stamp
    tf_static = [m for topic, m in decoded if topic == "/tf_static"]
    tf = [m for topic, m in decoded if topic == "/tf"]
    assert len(tf_static) == 1 and len(tf) == len(states)
    attach = {t.header.frame_id: (t.child_frame_id, t.transform.translation) for t in tf_static[0].transforms}
    assert {k: v[0] for k, v in attach.items()} == {"ship/base_link": "ship/tether_sheave",
                                                   "rov/base_link": "rov/tether_attach"}
    for msg, (_, state) in zip(tf, states):
        assert (msg.transforms[0].header.stamp.sec, msg.transforms[0].header.stamp.nanosec) == \
            (state.header.stamp.sec, state.header.stamp.nanosec)
        bodies = {t.child_frame_id: t for t in msg.transforms}
        assert {t.header.frame_id for t in msg.transforms} == {"map"} and set(bodies) == set(attach)
        for body, point in (("ship/base_link", state.position[0]), ("rov/base_link", state.position[-1])):
            tr, q = bodies[body].transform.translation, bodies[body].transform.rotation
            assert (q.x, q.y, q.z, q.w) == (0.0, 0.0, 0.0, 1.0)  # these ends carry no rotation here
            offset = attach[body][1]
            assert (tr.x + offset.x, tr.y + offset.y, tr.z + offset.z) == \
                pytest.approx((point.x, point.y, point.z), abs=1e-9)


def test_input_mcap_poses_drive_the_ship_and_bad_samples_are_skipped(tmp_path):
    poses = tmp_path / "poses.mcap"
    t0 = 1000.0  # recorded clock: the run starts at the first pose
    with RosMcapWriter(str(poses)) as w:
        w.add_topic("/ship/pose", "geometry_msgs/msg/PoseStamped", "best_effort")
        for k in range(31):
            t = t0 + 0.05 * k
            msg = PoseStamped()
            msg.header.stamp = time_msg(t)
            msg.header.frame_id = "map"
            msg.pose.position.x = 0.4 * (t - t0)  # 0.4 m/s east
            msg.pose.position.y = math.nan if k == 17 else 0.0  # one corrupt sample
            msg.pose.orientation.w = 1.0
            w.write("/ship/pose", serialize_message(msg), int(round(t * 1e9)))
    params = write_params(tmp_path / "p.yaml")
    out = tmp_path / "out.mcap"
    assert main(["--params", params, "--input", str(poses), "--output", str(out), "--no-progress"]) == 0
    states = by_topic(out)["/tether/state"]
    assert states[0][0] == 1_000_000_000_000  # clock of the recording
    assert len(states) == 1.5 * 20 + 1  # duration = span of the poses
    for log_ns, m in states:
        t = log_ns * 1e-9
        # linear motion: Hermite interpolation with finite-difference slopes is exact; the NaN
        # sample (rejected) leaves a longer interval, still on the same line
        assert m.position[0].x == pytest.approx(0.4 * (t - t0), abs=1e-6)
        assert m.position[0].y == pytest.approx(0.0, abs=1e-9)
    diag = by_topic(out)["/diagnostics"][-1][1]
    ship = next(s for s in diag.status if s.name.endswith("ship input"))
    assert {kv.key: kv.value for kv in ship.values}["rejected_non-finite"] == "1"


@pytest.mark.parametrize("extra, needle", [
    ({"cable": {"lenght": 5.0}}, "cable.lenght"),
    ({"dg": {"order": 40}}, "dg.order"),
])
def test_parameter_errors_name_the_key_and_the_file(tmp_path, capsys, extra, needle):
    params = write_params(tmp_path / "bad.yaml", **extra)
    assert main(["--params", params, "--output", str(tmp_path / "o.mcap"), "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert needle in err and params in err


def test_an_output_path_under_a_regular_file_is_a_clear_error(tmp_path, capsys):
    params = write_params(tmp_path / "p.yaml")
    blocker = tmp_path / "file.txt"
    blocker.write_text("a regular file")
    assert main(["--params", params, "--output", str(blocker / "sub" / "out.mcap"), "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert "is a regular file, not a directory" in err and "Traceback" not in err


def test_the_estimate_is_announced_before_the_solver_is_built_and_adds_up(tmp_path):
    """run_offline's announcement comes before any solver exists (a long run says what it will cost
    before it starts), and its total is the start, the solver's load-time work estimate and the
    outputs' share (the constants are measured against real runs: docs/node.md "Offline runs")."""
    from tether_sim.io.params import load_config
    from tether_sim.ros import offline
    from tether_sim.solvers.factory import build_solver
    from tether_sim.solvers import work

    config = load_config(write_params(tmp_path / "p.yaml"))
    said = []

    def factory(cfg):
        assert said, "the solver was built before the estimate was announced"
        return build_solver(cfg)

    summary = offline.run_offline(config, None, duration=0.5, progress=False, solver_factory=factory,
                                  announce=said.append)
    assert len(said) == 1 and said[0].startswith("0.5 s simulated, 10 output ticks: expected to take about")
    total, _ = work.run_estimate(config, 0.5)
    assert total == pytest.approx(work.START_CPU + 0.5 * work.estimate(config).cpu + 10 * work.TICK_CPU["dg"])
    assert summary["expected_cpu"] == total and summary["cpu_time"] > 0.0
