"""The simulation node in-process: static poses -> catenary tensions and wrenches; a snap scenario
-> SnapLoadEvent; the latched description; the console script's parameter-file check."""

import math

import numpy as np
import pytest

pytest.importorskip("rclpy")
pytest.importorskip("tether_sim_msgs")
from scipy.optimize import fsolve  # noqa: E402
from sim_harness import SimHarness, status, values  # noqa: E402

from tether_sim.ros.sim_node import main  # noqa: E402

pytestmark = pytest.mark.ros

# ROPOS tether properties [PE2020 Table 3] with a softer EA and a 100 m length, so the explicit
# substep (~ h / (c P^2)) stays cheap in a unit test; the catenary closed form holds for any EA.
L, EA, GAMMA0, RHO_C, RHO_F, G = 100.0, 2.0e6, 3.01, 7153.0, 1025.0, 9.81
W = GAMMA0 * G * (1.0 - RHO_F / RHO_C)  # submerged weight per unstretched metre, N/m [PE2020 Eq. 14]
SHIP = (0.0, 0.0, 0.0)
VEHICLE = (60.0, 0.0, -75.0)  # attachment point; chord 96.0 m < L: a catenary rising from both ends
ATTACH = (0.0, 0.0, 0.5)  # tether attachment in the vehicle frame


def elastic_catenary(span, height):
    """Irvine's elastic catenary from the lower end A: (H, V_A) with x(L) = span, z(L) = height."""

    def residual(u):
        H, V = u
        a0, a1 = V / H, (V + W * L) / H
        x = H * L / EA + H / W * (math.asinh(a1) - math.asinh(a0))
        z = (V * L + W * L * L / 2) / EA + H / W * (math.hypot(1, a1) - math.hypot(1, a0))
        return [x - span, z - height]

    H, V = fsolve(residual, [W * L / 4, -W * L / 4], xtol=1e-13)
    return H, V


def base_params(**extra):
    flat = {"solver": "dg", "cable.length": L, "cable.EA": EA, "cable.gamma0": GAMMA0, "cable.density": RHO_C,
            "cable.damping": 2000.0, "dg.n_elements": 8, "dg.order": 3, "environment.fluid_density": RHO_F,
            "ship_end.kind": "prescribed", "ship_end.position": SHIP,
            "vehicle_end.kind": "prescribed", "vehicle_end.position": VEHICLE,
            "node.vehicle_attachment": ATTACH, "node.output_points": 21, "node.output_rate": 50.0,
            "initial.kind": "static",
            "node.tick_budget": 1.0e6}  # sim time: never cap a tick on wall time (deterministic runs)
    flat.update(extra)
    return flat


@pytest.fixture
def harness():
    made = []

    def factory(flat):
        made.append(SimHarness(flat))
        return made[-1]

    yield factory
    for h in made:
        h.close()


def test_static_poses_give_the_catenary_tensions_and_wrenches(harness):
    h = harness(base_params())
    vehicle_origin = np.subtract(VEHICLE, ATTACH)
    h.run(1.1, ship=SHIP, vehicle=vehicle_origin)
    states = h.received["/tether/state"]
    assert len(states) >= 40  # 50 Hz over 1.1 s of sim time, less the 0.2 s node.input_delay
    H, V = elastic_catenary(VEHICLE[0] - SHIP[0], SHIP[2] - VEHICLE[2])
    T_vehicle, T_ship = math.hypot(H, V), math.hypot(H, V + W * L)
    last = states[-1]
    # 8 elements of order 3 and 1 s of dynamics after the static solve: measured errors against
    # Irvine's closed form are 0.03 % (ship, 2885 N) and 0.1 % (vehicle, 989 N); 1 % leaves room for
    # the pose interpolation and the solver's settling, and still catches a wrong end or frame.
    assert last.ship_end_tension == pytest.approx(T_ship, rel=0.01)
    assert last.vehicle_end_tension == pytest.approx(T_vehicle, rel=0.01)
    assert last.solver == "dg" and len(last.position) == 21 and last.header.frame_id == "map"
    np.testing.assert_allclose([last.position[0].x, last.position[0].y, last.position[0].z], SHIP, atol=1e-6)
    np.testing.assert_allclose([last.position[-1].x, last.position[-1].y, last.position[-1].z], VEHICLE, atol=1e-6)
    # Force BY the tether ON the vehicle, vehicle frame = world orientation: towards the ship
    # (-x) with H, vertical V_A; torque about the frame origin r x F with r = ATTACH.
    wrench = h.received["/tether/vehicle_wrench"][-1]
    assert wrench.header.frame_id == "rov/base_link"
    f = np.array([wrench.wrench.force.x, wrench.wrench.force.y, wrench.wrench.force.z])
    np.testing.assert_allclose(f, (-H, 0.0, V), atol=0.01 * T_vehicle)
    tq = np.array([wrench.wrench.torque.x, wrench.wrench.torque.y, wrench.wrench.torque.z])
    np.testing.assert_allclose(tq, np.cross(ATTACH, f), atol=1e-6 * T_vehicle)
    ship = h.received["/tether/ship_wrench"][-1]
    f_ship = np.array([ship.wrench.force.x, ship.wrench.force.y, ship.wrench.force.z])
    np.testing.assert_allclose(f_ship, (H, 0.0, -(V + W * L)), atol=0.01 * T_ship)
    # the description is latched and complete; diagnostics report a running simulation
    desc = h.received["/tether/description"][-1]
    assert desc.length == L and desc.vehicle_end_kind == "prescribed" and len(desc.output_arc_length) == 21
    assert any(kv.key == "cable.EA" for kv in desc.parameters)
    diag = h.received["/diagnostics"][-1]
    st = status(diag, "simulation")
    assert st.level == b"\x00" and float(values(st)["time_step"]) > 0
    # the compute load is a fraction of the period's wall time (ticks run inside it); the longest
    # tick has no upper bound worth asserting (the first one builds the solver, a cold numba compile)
    load, tick_max = float(values(st)["tick_load"]), float(values(st)["tick_max_ms"])
    assert 0.0 < load <= 1.0 and tick_max > 0.0


def vehicle_heave(t):
    """Vehicle attachment: still for 1 s, up 3 m at 3 m/s, still, back down 3 m at 3 m/s, still."""
    z = VEHICLE[2] + float(np.interp(t, [0.0, 1.0, 2.0, 2.5, 3.5, 5.0], [0.0, 0.0, 3.0, 3.0, 0.0, 0.0]))
    return (VEHICLE[0], 0.0, z)


def test_snap_scenario_publishes_slack_warning_and_snap_load_event(harness):
    # Starting the lower end upwards at 3 m/s drops the tension there by about gamma0*c*v =
    # 3.01 * 815 * 3 = 7.4 kN (axial wave, c = sqrt(EA/gamma0)) > the 1 kN static tension: slack;
    # lowering it again re-tensions the cable with a snap [PE2020 Sec. 6].
    h = harness(base_params())
    t = 0.0
    while t < 5.0:
        t = round(t + 0.02, 10)
        h.step(t, ship=SHIP, vehicle=np.subtract(vehicle_heave(t), ATTACH))
    def seconds(stamp):
        return stamp.sec + stamp.nanosec * 1e-9

    # events of the heave: slack begins while the end rises (1-2 s), re-tensions while it is lowered
    warnings = [m for m in h.received["/tether/slack_warnings"] if m.end == "vehicle" and 1.0 < seconds(m.header.stamp) < 2.6]
    snaps = [m for m in h.received["/tether/snap_events"] if m.end == "vehicle" and 1.0 < seconds(m.slack_start) < 2.6]
    assert warnings and snaps
    snap = max(snaps, key=lambda m: m.peak_tension)
    assert snap.peak_tension > snap.static_tension > 0 and snap.amplification > 1.0
    assert snap.min_tension < warnings[0].threshold and snap.slack_duration > 0.0


def test_console_script_rejects_a_misspelt_key_naming_key_and_file(tmp_path, capsys):
    bad = tmp_path / "bad.yaml"
    bad.write_text("tether_sim:\n  ros__parameters:\n    cable:\n      EAA: 1.0\n")
    assert main(["tether-sim", "--ros-args", "--params-file", str(bad)]) == 2
    err = capsys.readouterr().err
    assert "cable.EAA" in err and str(bad) in err and "cable.EA" in err


def test_live_snap_thresholds_change_and_solver_keys_are_refused(harness):
    from rclpy.parameter import Parameter

    h = harness(base_params())
    h.run(0.1, ship=SHIP, vehicle=np.subtract(VEHICLE, ATTACH))
    static = h.node.driver.static_tensions
    # slack_fraction 0.3 needs retension_fraction above it (default 0.2): both in one atomic change
    ok = h.node.set_parameters_atomically([Parameter("snap.slack_fraction", Parameter.Type.DOUBLE, 0.3),
                                           Parameter("snap.retension_fraction", Parameter.Type.DOUBLE, 0.4)])
    assert ok.successful
    assert h.node.driver.detector.thresholds == pytest.approx([0.3 * static[0], 0.3 * static[1]])
    refused = h.node.set_parameters([Parameter("dg.order", Parameter.Type.INTEGER, 2)])[0]
    assert not refused.successful and refused.reason
    assert h.node.driver.config.dg.order == 3
    n = len(h.received["/tether/state"])
    h.run(0.3, ship=SHIP, vehicle=np.subtract(VEHICLE, ATTACH))
    assert len(h.received["/tether/state"]) >= n + 5  # still running (50 Hz over 0.2 s)
    assert h.received["/tether/description"][-1].parameters  # re-published on the change


def test_vehicle_body_end_publishes_its_pose_and_the_wrench_of_a_hanging_cage(harness):
    # ROPOS cage [PE2020 Table 3] on the (softened, 100 m) tether, hanging still below the ship:
    # tension at the cage = its submerged weight m g (1 - rho_f / rho_body); at the ship that plus W L.
    m, rho_body = 4995.0, 8448.0
    weight = m * G * (1.0 - RHO_F / rho_body)
    h = harness(base_params(**{"vehicle_end.kind": "body", "vehicle_end.position": (0.0, 0.0, -100.0),
                               "body.initial_position": (0.0, 0.0, -102.1)}))
    h.run(0.5, ship=SHIP)
    last = h.received["/tether/state"][-1]
    # static equilibrium of the discretised cable and body, 0.5 s later: 0.5 %
    assert last.vehicle_end_tension == pytest.approx(weight, rel=0.005)
    assert last.ship_end_tension == pytest.approx(weight + W * L, rel=0.005)
    poses = h.received["/vehicle/sim_pose"]
    assert poses and poses[-1].header.frame_id == "map"
    p = poses[-1].pose.position
    # the cage hangs straight below the ship: CoG = attachment - (0, 0, 2.1), about L (1 + eps) down
    assert abs(p.x) < 1e-6 and abs(p.y) < 1e-6 and -106.0 < p.z < -102.0
    wrench = h.received["/tether/vehicle_wrench"][-1].wrench
    assert (wrench.force.x, wrench.force.y) == pytest.approx((0.0, 0.0), abs=1e-3 * weight)
    assert wrench.force.z == pytest.approx(weight, rel=0.005)  # the tether holds the cage up
    assert (wrench.torque.x, wrench.torque.y, wrench.torque.z) == pytest.approx((0.0, 0.0, 0.0), abs=1e-3 * weight)


def test_arguments_outside_the_ros_arguments_are_refused(capsys):
    """`tether-sim --params FILE` (the offline runner's form) must not start the node on its defaults."""
    assert main(["tether-sim", "--params", "config/ropos_L200.yaml"]) == 2
    err = capsys.readouterr().err
    assert "unknown argument(s) --params config/ropos_L200.yaml" in err and "--ros-args --params-file" in err
