"""The simulation node on the TMS network file (config/ropos_tms.yaml): ship and vehicle poses in,
per-line states, the wrenches on the vehicle and the cage, the cage on /tf, the winches' topics.
In-process with sim time (/clock from the probe), like sim_harness.py."""

from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("rclpy")
pytest.importorskip("tether_sim_msgs")
import rclpy  # noqa: E402
from geometry_msgs.msg import AccelStamped, PoseStamped, TwistStamped, WrenchStamped  # noqa: E402
from rclpy.executors import SingleThreadedExecutor  # noqa: E402
from rclpy.parameter import Parameter  # noqa: E402
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy  # noqa: E402
from rosgraph_msgs.msg import Clock  # noqa: E402
from tether_sim_msgs.msg import SlackWarning, SnapLoadEvent, TetherDescription, TetherState, WinchCommand, WinchState  # noqa: E402

from tether_sim.network.faults import throw_end_once  # noqa: E402
from tether_sim.numerics.rotations import quaternion_matrix  # noqa: E402
from tether_sim.ros.convert import LEVEL_ERROR, time_msg  # noqa: E402
from tether_sim.ros.network_node import NetworkSimNode  # noqa: E402
from tether_sim.ros.sim_node import main  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
TMS = ROOT / "config" / "ropos_tms.yaml"
VEHICLE = (20.0, 0.0, -1751.0)
G = 9.81


class NetHarness:
    def __init__(self):
        self.context = rclpy.Context()
        rclpy.init(context=self.context)
        self.node = NetworkSimNode(files=[str(TMS)], context=self.context,
                                   parameter_overrides=[Parameter("use_sim_time", Parameter.Type.BOOL, True)])
        self.probe = rclpy.create_node("probe", context=self.context)
        self.clock = self.probe.create_publisher(Clock, "/clock", QoSProfile(depth=1, reliability=ReliabilityPolicy.BEST_EFFORT))
        self.poses = {e: self.probe.create_publisher(PoseStamped, f"/{e}/pose", 10) for e in ("ship", "vehicle")}
        self.winch_cmd = self.probe.create_publisher(WinchCommand, "/winch/excursion/command", 10)
        types = {"/tether/tether/state": TetherState, "/tether/excursion/state": TetherState,
                 "/tether/vehicle_wrench": WrenchStamped, "/tether/ship_wrench": WrenchStamped,
                 "/tether/cage_wrench": WrenchStamped, "/cage/sim_pose": PoseStamped,
                 "/winch/excursion/state": WinchState, "/winch/tether/state": WinchState,
                 "/tether/excursion/slack_warnings": SlackWarning, "/tether/tether/snap_events": SnapLoadEvent,
                 "/tether/excursion/snap_events": SnapLoadEvent, "/cage/sim_twist": TwistStamped,
                 "/cage/sim_accel": AccelStamped, "/cage/hydro_wrench": WrenchStamped}
        self.received = {t: [] for t in types}
        for t, ty in types.items():
            self.probe.create_subscription(ty, t, self.received[t].append, 1000)
        latched = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self.received["/tether/excursion/description"] = []
        self.received["/cage/wet_weight"] = []
        self.probe.create_subscription(WrenchStamped, "/cage/wet_weight", self.received["/cage/wet_weight"].append,
                                       latched)
        self.probe.create_subscription(TetherDescription, "/tether/excursion/description",
                                       self.received["/tether/excursion/description"].append, latched)
        try:
            from tf2_msgs.msg import TFMessage
            self.received["/tf"] = []
            self.probe.create_subscription(TFMessage, "/tf", self.received["/tf"].append, 1000)
        except ImportError:
            pass
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        self.executor.add_node(self.probe)

    def pose(self, t, p):
        msg = PoseStamped()
        msg.header.stamp = time_msg(t)
        msg.header.frame_id = "map"
        msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = (float(x) for x in p)
        msg.pose.orientation.w = 1.0
        return msg

    def run(self, t0, t1, vehicle=lambda t: VEHICLE):
        t = t0
        while t < t1 - 1e-9:
            t = round(t + 0.02, 6)
            self.poses["ship"].publish(self.pose(t, (0.0, 0.0, 0.0)))
            self.poses["vehicle"].publish(self.pose(t, vehicle(t)))
            self.clock.publish(Clock(clock=time_msg(t)))
            for _ in range(8):  # the node's tick and the probe's callbacks of this step (15 topics)
                self.executor.spin_once(timeout_sec=0.002)
        self.drain()
        return t

    def drain(self, quiet=10, most=5000):
        """Spin until ``quiet`` spins in a row bring the probe nothing: every message published is taken (a
        tick the executor's timer called late publishes the skipped periods' states too, node.missed_outputs;
        one spin takes one message)."""
        count, still = -1, 0
        for _ in range(most):
            self.executor.spin_once(timeout_sec=0.002)
            n = sum(len(v) for v in self.received.values())
            still = still + 1 if n == count else 0
            count = n
            if still >= quiet:
                return

    def close(self):
        self.executor.shutdown()
        self.node.destroy_node()
        self.probe.destroy_node()
        rclpy.shutdown(context=self.context)


@pytest.fixture(scope="module")
def tms():
    h = NetHarness()
    yield h
    h.close()


def test_tms_node_publishes_both_lines_the_vehicle_wrench_and_the_cage(tms):
    h = tms
    t = h.run(10.0, 11.5)
    r = h.received
    for line in ("tether", "excursion"):
        assert len(r[f"/tether/{line}/state"]) >= 20, f"{line}: {len(r[f'/tether/{line}/state'])} states"
    tether = r["/tether/tether/state"][-1]
    exc = r["/tether/excursion/state"][-1]
    assert tether.header.frame_id == "map" and len(tether.position) == 41
    # the main tether holds the cage and its own weight: ship tension = cage wet weight + tether wet
    # weight (vertical line, end tensions from the static solve), to the DG mesh's accuracy
    cage_wet = 4995.0 * G * (1.0 - 1025.0 / 8448.0)
    tether_wet = 1730.0 * 3.01 * G * (1.0 - 1025.0 / 7153.0)
    assert tether.ship_end_tension == pytest.approx(cage_wet + tether_wet + exc.ship_end_tension, rel=2e-3)
    assert tether.vehicle_end_tension == pytest.approx(cage_wet + exc.ship_end_tension, rel=2e-3)
    # the cage hangs below the fairlead at the end of the stretched tether; its pose on sim_pose and /tf
    pose = r["/cage/sim_pose"][-1].pose.position
    assert abs(pose.x) < 0.2 and pose.z == pytest.approx(-1730.0 - 2.1, abs=5.0)
    if "/tf" in r:
        frames = {tr.child_frame_id for m in r["/tf"] for tr in m.transforms}
        assert "cage/base_link" in frames
    # the excursion tether's force on the vehicle: its end tension along the line, back toward the cage
    # (at -x; the buoyant line, -40 kg/km in water, arches above the vehicle, so it also pulls up there),
    # none sideways
    wrenches = {(m.header.stamp.sec, m.header.stamp.nanosec): m for m in r["/tether/vehicle_wrench"]}
    exc = [m for m in r["/tether/excursion/state"] if (m.header.stamp.sec, m.header.stamp.nanosec) in wrenches][-1]
    w = wrenches[(exc.header.stamp.sec, exc.header.stamp.nanosec)]  # the same instant
    assert w.header.frame_id == "rov/base_link"
    f = np.array([w.wrench.force.x, w.wrench.force.y, w.wrench.force.z])
    # |F| against the axial T: strain-scale, plus the end flux's transverse part on the slack line (its
    # penalty on the end's transverse velocity mismatch: 10 mN is Z = 1.4 kN s/m times 7 um/s of ringing)
    assert np.linalg.norm(f) == pytest.approx(exc.vehicle_end_tension, rel=1e-4, abs=0.01)
    assert f[0] < 0.0 and f[2] > 0.0 and abs(f[1]) < 1e-6 * np.linalg.norm(f)
    # the cage's wrench: both lines on it balance its wet weight (at rest, within 1 %)
    cw = r["/tether/cage_wrench"][-1].wrench.force
    assert cw.z == pytest.approx(cage_wet, rel=1e-2)
    # the cage's motion and loads, world frame: at rest, its wet weight latched (closed form), its
    # acceleration Newton's on the lines' force, the weight and the drag ((m + m_a) = 14195 kg, isotropic)
    weight = r["/cage/wet_weight"][-1]
    assert weight.header.frame_id == "map" and weight.wrench.force.z == pytest.approx(-cage_wet, rel=1e-12)
    stamps = {(m.header.stamp.sec, m.header.stamp.nanosec) for m in r["/cage/sim_accel"]}
    assert len(stamps) >= 20 and stamps == {(m.header.stamp.sec, m.header.stamp.nanosec) for m in r["/cage/sim_twist"]}
    assert abs(r["/cage/sim_twist"][-1].twist.linear.z) < 0.05
    same = {(m.header.stamp.sec, m.header.stamp.nanosec): m for m in r["/tether/cage_wrench"]}
    drag = {(m.header.stamp.sec, m.header.stamp.nanosec): m for m in r["/cage/hydro_wrench"]}
    a = r["/cage/sim_accel"][-1]
    key = (a.header.stamp.sec, a.header.stamp.nanosec)
    o = {(m.header.stamp.sec, m.header.stamp.nanosec): m for m in r["/cage/sim_pose"]}[key].pose.orientation
    lines = quaternion_matrix([o.x, o.y, o.z, o.w]) @ [same[key].wrench.force.x, same[key].wrench.force.y,
                                                      same[key].wrench.force.z]
    net = lines[2] - cage_wet + drag[key].wrench.force.z
    assert (4995.0 + 9200.0) * a.accel.linear.z == pytest.approx(net, rel=1e-9, abs=1e-6 * cage_wet)
    # winches: the ship winch and the TMS drum report their lengths
    assert r["/winch/excursion/state"][-1].length == pytest.approx(30.0)
    assert r["/winch/tether/state"][-1].length == pytest.approx(1730.0)
    assert r["/tether/excursion/description"] and r["/tether/excursion/description"][-1].length == 30.0
    assert not r["/tether/tether/snap_events"] and not r["/tether/excursion/snap_events"]
    assert t > 11.0


def test_tms_drum_pays_out_the_excursion_tether_on_command(tms):
    h = tms
    h.winch_cmd.publish(WinchCommand(mode="speed", setpoint=0.5))
    h.run(11.5, 13.0)
    states = h.received["/winch/excursion/state"]
    assert states[-1].speed > 0.2
    assert states[-1].length > 30.1
    # the line's arc length and the drum's length at the same instant (the last messages of the two topics
    # can be a tick apart under load: 0.01 m at 0.5 m/s and 50 Hz)
    lengths = {(m.header.stamp.sec, m.header.stamp.nanosec): m.length for m in states}
    exc = [m for m in h.received["/tether/excursion/state"]
           if (m.header.stamp.sec, m.header.stamp.nanosec) in lengths][-1]
    assert exc.arc_length[-1] == pytest.approx(lengths[(exc.header.stamp.sec, exc.header.stamp.nanosec)], abs=0.05)


def test_a_line_divergence_is_recovered_and_the_node_publishes_only_finite_states(tms):
    """The excursion tether's DG state blows up (its cage end thrown 1e30 m away through the solver
    interface): the node logs it, turns /diagnostics ERROR with the divergence counted, restores the
    network's snapshot and runs on: finite states of both lines with strictly increasing stamps, no
    snap event, the states degraded while the points blend back. (Before, the node stopped publishing.)"""
    from diagnostic_msgs.msg import DiagnosticArray

    h = tms
    diags = []
    h.probe.create_subscription(DiagnosticArray, "/diagnostics", diags.append, 100)
    h.run(13.0, 13.5)
    throw_end_once(h.node.driver.net.lines["excursion"], "ship")  # once: the cage end 1e30 m away
    n = {t: len(h.received[t]) for t in h.received}
    h.run(13.5, 16.0)
    d = h.node.driver
    assert d.divergences == 1 and d.last_recovery == "snapshot" and not d.failed and "excursion" in d.last_error
    for line in ("tether", "excursion"):
        states = h.received[f"/tether/{line}/state"][n[f"/tether/{line}/state"]:]
        assert len(states) > 25  # still publishing (2.5 s at 50 Hz; the harness under load takes fewer)
        stamps = [m.header.stamp.sec + 1e-9 * m.header.stamp.nanosec for m in states]
        assert np.all(np.diff(stamps) > 0.0)
        for m in states:
            assert np.all(np.isfinite([(q.x, q.y, q.z) for q in m.position])) and np.all(np.isfinite(m.tension))
            assert np.isfinite(m.ship_end_tension) and np.isfinite(m.vehicle_end_tension)
        assert any(m.degraded for m in states) and not states[-1].degraded  # blended back
    assert len(h.received["/tether/tether/snap_events"]) == n["/tether/tether/snap_events"]
    assert len(h.received["/tether/excursion/snap_events"]) == n["/tether/excursion/snap_events"]
    status = [s for m in diags for s in m.status if s.name.endswith("simulation") and "diverged" in s.message]
    assert status and status[0].level == LEVEL_ERROR
    assert {v.key: v.value for v in status[0].values}["divergences"] == "1"


def test_console_script_names_the_key_of_a_bad_network(tmp_path, capsys):
    bad = tmp_path / "bad.yaml"
    bad.write_text(TMS.read_text().replace("to: vehicle", "to: vehicel"))
    assert main(["tether-sim", "--ros-args", "--params-file", str(bad)]) == 2
    err = capsys.readouterr().err
    assert "network.lines.excursion.to" in err and "vehicle" in err
