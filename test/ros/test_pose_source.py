"""tether-sim-poses (tether_sim/ros/pose_source.py) drives the node without a line of user code:
its poses are in the node's world frame and follow the file's motion, the node accepts every one
and its ship end follows them; a pose in another frame is rejected with a reason that says what to
do, logged once and then as a count, not once per pose."""

import math
import re

import pytest

pytest.importorskip("rclpy")
pytest.importorskip("tether_sim_msgs")
from geometry_msgs.msg import PoseStamped, TwistStamped  # noqa: E402
from rclpy.parameter import Parameter  # noqa: E402
from rclpy.qos import qos_profile_sensor_data  # noqa: E402
from sim_harness import SimHarness, status, values  # noqa: E402
from test_sim_node import SHIP, base_params  # noqa: E402

from tether_sim.errors import ConfigError  # noqa: E402
from tether_sim.io.params import from_flat  # noqa: E402
from tether_sim.ros import pose_source  # noqa: E402

pytestmark = pytest.mark.ros
A, F = 0.5, 0.5  # heave amplitude (m) and frequency (Hz)


def flat_params():
    return base_params(**{"vehicle_end.kind": "fixed", "motion.kind": "heave", "motion.amplitude": A,
                          "motion.frequency": F})


def test_pose_source_drives_the_node_in_the_world_frame():
    flat = flat_params()
    config = from_flat(flat)
    h = SimHarness(flat)
    src = pose_source.PoseSource(config, pose_source.ship_motion(config), 50.0, context=h.context,
                                 parameter_overrides=[Parameter("use_sim_time", value=True)])
    h.executor.add_node(src)
    poses, twists = [], []
    h.probe.create_subscription(PoseStamped, "/ship/pose", poses.append, qos_profile_sensor_data)
    h.probe.create_subscription(TwistStamped, "/ship/twist", twists.append, qos_profile_sensor_data)
    try:
        h.run(2.5)
        w = 2.0 * math.pi * F
        stamp = lambda m: m.header.stamp.sec + 1e-9 * m.header.stamp.nanosec  # noqa: E731
        assert len(poses) > 80 and {m.header.frame_id for m in poses + twists} == {"map"}
        t0 = src.t0  # the motion's start: HOLD s after the probe and the node matched
        assert t0 == pytest.approx(stamp(poses[0]) + pose_source.HOLD, abs=0.05)
        for m in poses:  # z = A sin(w t) about the ship end, held at the start pose until t0
            t = max(0.0, stamp(m) - t0)
            assert m.pose.position.z - SHIP[2] == pytest.approx(A * math.sin(w * t), abs=1e-12)
        for m in twists:
            t = stamp(m) - t0
            assert m.twist.linear.z == pytest.approx(A * w * math.cos(w * t) if t >= 0 else 0.0, abs=1e-12)  # held: still
        ship = values(status(h.received["/diagnostics"][-1], "ship input"))
        assert int(ship["accepted"]) > 80 and not any(k.startswith("rejected_") and int(v) for k, v in ship.items())
        # the node's ship end follows the heave once its start blend is over (input_delay behind the
        # clock, interpolated between 50 Hz samples: error < A w^2 dt^2 / 8 = 2.5e-4 m)
        late = [m for m in h.received["/tether/state"] if stamp(m) > 1.5]
        assert len(late) > 20 and t0 < 1.5
        for m in late:
            assert m.position[0].z - SHIP[2] == pytest.approx(A * math.sin(w * (stamp(m) - t0)), abs=1e-3)
    finally:
        src.destroy_node()
        h.close()


class Log:
    def __init__(self):
        self.lines = []

    def warning(self, text):
        self.lines.append(text)

    info = error = warning


def test_poses_in_another_frame_are_rejected_once_with_the_remedy_then_counted(monkeypatch):
    from tether_sim.ros import sim_node

    h = SimHarness(flat_params())
    log = Log()
    monkeypatch.setattr(h.node, "get_logger", lambda: log)
    # the count period is wall time: on a loaded machine the 100 steps below can take longer than
    # it, so it is held off while they run and restored for the "10 s later" step
    period = sim_node.REJECT_SUMMARY_PERIOD
    monkeypatch.setattr(sim_node, "REJECT_SUMMARY_PERIOD", 1e9)
    try:
        for k in range(1, 101):  # 2 s of 50 Hz poses in 'world'
            t = 0.02 * k
            h.step(t, ship=h.pose_msg(t, SHIP, frame="world"))
        rejected = [line for line in log.lines if line.startswith("ship pose")]
        assert len(rejected) == 1, log.lines  # 100 wrong poses: one line (the count follows every 10 s)
        monkeypatch.setattr(sim_node, "REJECT_SUMMARY_PERIOD", period)
        assert "'world' is not the world frame 'map'" in rejected[0] and "node.world_frame:=world" in rejected[0]
        stale = [line for line in log.lines if "no ship pose accepted yet" in line]
        assert stale and "rejected so far" in stale[-1], log.lines
        # on a loaded machine poses can still be in flight: take them all before the clock moves on
        rejected_now = lambda: h.node.inputs["ship"].rejected["wrong frame"]  # noqa: E731
        quiet, seen = 0, rejected_now()
        while quiet < 100:
            h.spin(1)
            quiet, seen = (quiet + 1, seen) if rejected_now() == seen else (0, rejected_now())
        h.node._last_log[("rejected", "ship", "pose")] -= 10.0  # 10 s later: one line with the count
        before = len(log.lines)
        h.step(2.02, ship=h.pose_msg(2.02, SHIP, frame="world"))
        counted = lambda: [line for line in log.lines[before:] if line.startswith("ship pose")]  # noqa: E731
        for _ in range(2000):  # the pose delivered (a best-effort topic: sent again until it is)
            if counted():
                break
            h.pose_pubs["ship"].publish(h.pose_msg(2.02, SHIP, frame="world"))
            h.spin(1)
        total = rejected_now()  # all but the first, logged at once
        assert len(counted()) == 1, (total, log.lines[before:])
        assert re.match(rf"ship pose: {seen} rejected in the last \d+ s, the latest: frame 'world'", counted()[0]), \
            (seen, total, log.lines)
        assert int(values(status(h.received["/diagnostics"][-1], "ship input"))["rejected_wrong frame"]) > 0
    finally:
        h.close()


def test_a_missing_pose_publisher_is_logged_once_then_at_doubling_intervals_and_shown_in_diagnostics(monkeypatch):
    """No ship pose publisher at all: the stale warning comes at once, then after 2, 4, 8, 16, 32 s and
    then every 60 s (not every 2 s for ever); /diagnostics says it every period. A pose ends the
    episode; the next silence is logged at once again. The back-off clock is the test's."""
    from tether_sim.ros import sim_node

    h = SimHarness(flat_params())
    log = Log()
    monkeypatch.setattr(h.node, "get_logger", lambda: log)
    wall = [0.0]
    monkeypatch.setattr(sim_node, "_monotonic", lambda: wall[0])
    stale = lambda: [line for line in log.lines if "no ship pose accepted yet" in line]  # noqa: E731
    try:
        h.run(2.0, dt=0.1)  # the node starts without the ship pose after node.input_timeout (1 s)
        assert h.node.driver.solver is not None and len(stale()) == 1, log.lines
        assert "next reminder in 2 s" in stale()[0] and "up to 60 s" in stale()[0]
        logged_at = [0.0]
        due = (2.0, 6.0, 14.0, 30.0, 62.0, 122.0, 182.0)
        for w in sorted({*due, *(d - 0.01 for d in due), 1.0, 100.0, 200.0}):  # a tick just before each and at it
            wall[0] = w
            n = len(stale())
            h.step(h.time + 0.1)
            for _ in range(200):  # the tick of this clock time runs while the wall clock reads w
                if h.node.driver.last_now >= h.time - 1e-9:
                    break
                h.spin(1)
            if len(stale()) > n:
                logged_at.append(wall[0])
        assert logged_at == [0.0, *due], logged_at  # 8 lines in 200 s, not 100
        st = status(h.received["/diagnostics"][-1], "ship input")
        assert st.level == b"\x03" and "no ship pose accepted yet (0 rejected)" in st.message, st.message  # STALE
        h.run(h.time + 0.2, ship=SHIP)  # a publisher appears: the episode ends
        assert not h.node.inputs["ship"].is_stale(h.time) and ("stale", "ship") not in h.node._backoff
        n = len(log.lines)
        h.run(h.time + 1.5, dt=0.1)  # and goes silent again: logged at once
        again = [line for line in log.lines[n:] if "ship pose input stale" in line]
        assert len(again) == 1 and "next reminder in 2 s" in again[0], log.lines[n:]
    finally:
        h.close()


def test_the_console_script_refuses_bad_arguments_clearly(tmp_path, capsys):
    path = tmp_path / "p.yaml"
    path.write_text("/**/tether_sim:\n  ros__parameters:\n    motion:\n      kind: none\n")
    assert pose_source.main(["tether-sim-poses", "--params", str(path), "--duration", "0.1"]) == 2
    assert "motion.kind is 'none'" in capsys.readouterr().err
    assert pose_source.main(["tether-sim-poses", "--params", str(path), "--heave", "1"]) == 2
    assert "--heave and --frequency go together" in capsys.readouterr().err
    with pytest.raises(ConfigError, match="motion"):
        pose_source.ship_motion(from_flat({"motion.kind": "rao"}))  # no RAO table given
