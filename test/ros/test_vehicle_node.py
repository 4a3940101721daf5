"""The closed loop in-process: the MuJoCo vehicle node owns /clock and publishes vehicle/pose, the
simulation node follows it and publishes tether/vehicle_wrench, the vehicle applies it. Deterministic
(sim time, the vehicle ticked by the test, each tick waited for by the tether's state).

config/light_tether_vehicle.yaml: a light tether (40 m, 0.07 kg/m, slightly heavier than sea water)
from a fixed point at 2 m depth to a BlueROV2 Heavy holding station; node.input_delay 0 (the pose is
extrapolated, no added lag)."""

import math
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("rclpy")
pytest.importorskip("tether_sim_msgs")
pytest.importorskip("mujoco")

from geometry_msgs.msg import PoseStamped, WrenchStamped  # noqa: E402

from tether_sim.ros.closed_loop import ClosedLoop  # noqa: E402
from tether_sim.ros.convert import time_msg  # noqa: E402

pytestmark = pytest.mark.ros

PARAMS = Path(__file__).resolve().parents[2] / "config" / "light_tether_vehicle.yaml"
ANCHOR = (0.0, 0.0, -2.0)  # as in the file
ATTACH = (-0.2, 0.0, 0.0)  # tether attachment in the vehicle frame (the rear of the frame)
L = 40.0


@pytest.fixture
def loop():
    made = []

    def factory(*args, **kwargs):
        made.append(ClosedLoop(*args, params_file=PARAMS, **kwargs))
        return made[-1]

    yield factory
    for x in made:
        x.close()


def test_the_tether_force_reaches_the_vehicle_and_a_taut_tether_pulls_it_back(loop):
    """Station 45 m from the anchor, at its depth, on a 40 m tether: the vehicle is held back where
    the tether is taut, the force it applies is the published wrench (vehicle frame), pointing back along the
    tether toward the anchor, and it holds the station the tether allows with zero input delay."""
    setpoint = (45.0, 0.0, -2.0)
    lp = loop(start=(36.0, 0.0, -2.0), setpoint=setpoint)
    lp.run(20.0)
    t, p, applied, used = lp.trace[-1]
    assert np.all(np.isfinite(p))
    # the vehicle applies the wrench it received: the message it held when it stepped, as it is
    last = next(w for w in reversed(lp.wrenches) if abs(w.header.stamp.sec + 1e-9 * w.header.stamp.nanosec - used) < 1e-9)
    f_msg = np.array([last.wrench.force.x, last.wrench.force.y, last.wrench.force.z])
    assert last.header.frame_id == "rov/base_link"
    assert np.array_equal(applied[:3], f_msg)
    # taut: the vehicle is as far as the tether reaches, and the tether pulls it toward the anchor
    attach_world = p + lp.sim.rotation() @ np.array(ATTACH)
    chord = np.linalg.norm(attach_world - np.array(ANCHOR))
    assert chord == pytest.approx(L, rel=0.02)
    f_world = lp.sim.rotation() @ f_msg
    toward = (np.array(ANCHOR) - attach_world) / chord
    assert np.dot(f_world, toward) > 0.95 * np.linalg.norm(f_world) > 5.0  # N: the thrusters pull against it
    # the loop is stable with no input delay: along the taut tether the vehicle stays within 3 cm over
    # the last 4 s (no ringing of the cable-vehicle spring), and it moves slower than 0.15 m/s overall
    # (the heave and pitch integrals still settle against the tether's pull and the thrusters' limits)
    late = np.array([x[1] for x in lp.trace[-200:]])
    along = (late - np.array(ANCHOR)) @ (-toward)
    assert np.ptp(along) < 0.03
    assert np.abs(np.diff(late, axis=0)).max() / 0.02 < 0.15


@pytest.mark.parametrize("args, says", [(["--rate", "0"], "--rate 0.0"), (["--current", "nan", "0", "0"], "--current"),
                                        (["--dt", "0.5"], "--dt 0.5")])
def test_bad_arguments_are_refused_with_the_reason(args, says, capsys):
    from tether_sim.ros.vehicle_node import main

    assert main(["tether-sim-vehicle", *args]) == 2
    assert says in capsys.readouterr().err


def test_a_wrench_in_the_wrong_frame_or_not_finite_is_rejected_and_an_old_one_stops_acting(loop):
    lp = loop(start=(36.0, 0.0, -2.0), setpoint=(36.0, 0.0, -2.0), tether=False)
    node = lp.vehicle
    msg = WrenchStamped()
    msg.header.stamp, msg.header.frame_id = time_msg(node.sim.time), "map"
    msg.wrench.force.x = 10.0
    node._on_wrench(msg)
    msg.header.frame_id, msg.wrench.force.y = "rov/base_link", math.nan
    node._on_wrench(msg)
    assert node.wrench is None and node.rejected == 2
    msg.wrench.force.y = 0.0
    node._on_wrench(msg)
    assert node._tether_wrench(node.sim.time)[0][0] == 10.0
    assert not np.any(node._tether_wrench(node.sim.time + 0.6)[0]) and node.stale  # older than WRENCH_TIMEOUT


def test_an_unstable_vehicle_simulation_stops_publishing(loop):
    """A tether wrench of 1e12 N makes MuJoCo's state blow up (and MuJoCo would reset it to the start):
    the node says so and publishes no more poses, rather than a vehicle back at its start."""
    lp = loop(start=(36.0, 0.0, -2.0), setpoint=(36.0, 0.0, -2.0), tether=False)
    node = lp.vehicle
    poses = []
    lp.probe.create_subscription(PoseStamped, "/vehicle/pose", poses.append, 100)
    node.wrench = (node.sim.time, np.array([1e12, 0.0, 0.0]), np.array([0.0, 1e12, 0.0]))
    node.tick()
    n = len(poses)
    for _ in range(5):
        node.tick()
        lp.executor.spin_once(timeout_sec=0.01)
    assert node.failed and len(poses) == n


@pytest.mark.parametrize("args, says", [(["--duration", "1"], "--duration 1.0"), (["--current", "5"], "--current 5.0")])
def test_the_demo_refuses_bad_arguments(args, says, capsys):
    from tether_sim.ros.rov_demo import main

    assert main(args) == 2
    assert says in capsys.readouterr().err


def test_the_vehicle_flies_on_the_tms_excursion_tether():
    """config/ropos_tms.yaml (ship, 1730 m tether, cage, 30 m excursion tether to the vehicle) in the loop: the
    network node follows the MuJoCo vehicle's pose, every tick publishes the lines' states, and the vehicle
    applies the excursion tether's wrench as published (vehicle frame); told to move 5 m away from the cage
    it moves that way against the tether, and the mean force on it has a part pulling it back toward the cage."""
    tms = Path(__file__).resolve().parents[2] / "config" / "ropos_tms.yaml"
    start = np.array([20.0, 0.0, -1751.0]) - np.array(ATTACH)  # the file's vehicle point, the attachment behind
    lp = ClosedLoop(tuple(start), tuple(start + [5.0, 0.0, 0.0]), params_file=tms, **{"node.input_delay": 0.0})
    try:
        lp.run(4.0)
        assert not lp.vehicle.failed and len(lp.states) >= 140  # states from ~1 s (the node's start), then
        stamps = np.array([m.header.stamp.sec + 1e-9 * m.header.stamp.nanosec for m in lp.states[-100:]])
        assert np.allclose(np.diff(stamps), 0.02, atol=1e-6)  # one per 50 Hz tick
        t, p, applied, used = lp.trace[-1]
        last = next(w for w in reversed(lp.wrenches)
                    if abs(w.header.stamp.sec + 1e-9 * w.header.stamp.nanosec - used) < 1e-9)
        f_msg = np.array([last.wrench.force.x, last.wrench.force.y, last.wrench.force.z])
        assert np.array_equal(applied[:3], f_msg)
        assert p[0] > start[0] + 0.5  # it flies out, away from the cage
        forces = np.array([x[2][:3] for x in lp.trace[-100:]])
        cage = np.array([0.0, 0.0, -1734.4 - 2.1])  # the cage's lower attachment in the file, near enough
        toward = (cage - p) / np.linalg.norm(cage - p)
        assert np.all(np.isfinite(forces)) and float(np.mean(forces @ toward)) > 0.0
    finally:
        lp.close()
