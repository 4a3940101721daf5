"""The MuJoCo vehicle (tether_sim/vehicle) against closed forms: the tether's wrench enters rotated
to the world with the added mass, the hydrostatics, the steady thrust of station keeping in a
current, and the thrust allocation."""

import math

import numpy as np
import pytest

pytest.importorskip("mujoco")

from dataclasses import replace  # noqa: E402

from tether_sim.vehicle.model import BLUEROV2_HEAVY, restoring_wrench  # noqa: E402
from tether_sim.numerics.rotations import quaternion_matrix  # noqa: E402
from tether_sim.vehicle.sim import StationKeeper, VehicleSim  # noqa: E402

RHO, G = 1025.0, 9.81
NEUTRAL = replace(BLUEROV2_HEAVY, volume=BLUEROV2_HEAVY.mass / RHO, cob=(0.0, 0.0, 0.0))


def test_a_body_frame_tether_force_accelerates_the_vehicle_along_its_world_image():
    """Held still in a rolled and turned attitude, a body-frame force f gives the world acceleration
    R (f_i / (m + A_ii))_i from rest (the added mass per body axis): the sign and frame of
    tether/vehicle_wrench as the simulator applies it. dt = 1e-4 s: the damping's share of the
    first step is D_lin dt / M < 2e-4, hence rel 1e-3."""
    sim = VehicleSim(NEUTRAL, position=(0, 0, -20), yaw=math.pi / 2, dt=1e-4, rho=RHO, g=G)
    roll = math.radians(30.0)
    w, z = sim.data.qpos[3], sim.data.qpos[6]  # yaw 90 deg, then roll 30 deg about the body x axis
    qr = np.array([math.cos(roll / 2), math.sin(roll / 2), 0.0, 0.0])
    sim.data.qpos[3:7] = [w * qr[0], w * qr[1], z * qr[1], z * qr[0]]
    R = quaternion_matrix(sim.orientation)
    f = np.array([12.0, -5.0, 8.0])
    sim.step(np.zeros(8), tether_force=f)
    a_world = sim.data.qvel[0:3] / sim.dt
    expected = R @ (f / NEUTRAL.total_mass()[:3])
    assert np.allclose(a_world, expected, rtol=1e-3, atol=1e-3 * np.abs(expected).max())
    # the world force handed to MuJoCo is R times the scaled body force (no sign change)
    assert np.allclose(sim.data.xfrc_applied[1, 0:3], R @ (f * NEUTRAL.mass / NEUTRAL.total_mass()[:3]), rtol=1e-9)
    assert R[:, 0] == pytest.approx([0.0, 1.0, 0.0], abs=1e-12)  # body x points north after the turn


def test_hydrostatics_net_buoyancy_and_the_righting_moment():
    """B - W = rho g V - m g up; a heel phi gives the moment -(B z_b) sin(phi) about x (CoB above CoG)."""
    m = BLUEROV2_HEAVY
    phi = math.radians(20.0)
    R = np.array([[1, 0, 0], [0, math.cos(phi), -math.sin(phi)], [0, math.sin(phi), math.cos(phi)]])
    tau = restoring_wrench(m, R, RHO, G)
    B = RHO * G * m.volume
    assert np.linalg.norm(tau[:3]) == pytest.approx(B - m.mass * G, rel=1e-12)
    assert tau[3] == pytest.approx(-B * m.cob[2] * math.sin(phi), rel=1e-12)


def test_station_keeping_thrust_balances_the_drag_of_the_current():
    """Held in a 0.3 m/s current along x, the steady thrust (in the world) is X_u U + X_u|u| U^2
    against the current (16.8 N for the BlueROV2 Heavy; the vehicle holds level, so its surge axis is
    the current's) and the net buoyancy downward; the PID's integral removes the offset."""
    m, U = BLUEROV2_HEAVY, 0.3
    sim = VehicleSim(m, position=(0, 0, -10), dt=0.01, current=(U, 0, 0), rho=RHO, g=G)
    keeper = StationKeeper(m)
    for _ in range(int(150 / sim.dt)):
        sim.step(keeper.thrust(sim, (0, 0, -10), 0.0, sim.dt))
    thrust_world = sim.rotation() @ (m.thrust_matrix() @ keeper.thrust(sim, (0, 0, -10), 0.0, sim.dt))[:3]
    drag = m.linear_damping[0] * U + m.quadratic_damping[0] * U * U
    assert -thrust_world[0] == pytest.approx(drag, rel=0.01)
    assert -thrust_world[2] == pytest.approx(RHO * G * m.volume - m.mass * G, rel=0.01)
    assert np.linalg.norm(sim.position - [0, 0, -10]) < 0.05


def test_the_allocation_reproduces_a_wanted_wrench_within_the_limits():
    m = BLUEROV2_HEAVY
    keeper = StationKeeper(m)
    wanted = np.array([30.0, -20.0, 15.0, 0.5, -0.3, 1.0])
    u = keeper.allocate(wanted)
    assert np.abs(u).max() < m.thrust_limit
    assert np.allclose(m.thrust_matrix() @ u, wanted, atol=1e-9)
    # a surge beyond the horizontal thrusters' reach: surge saturates, depth and attitude are still held
    u = keeper.allocate(np.array([500.0, 0.0, 15.0, 0.0, 0.0, 0.0]))
    got = m.thrust_matrix() @ u
    assert np.abs(u).max() == pytest.approx(m.thrust_limit) and got[0] == pytest.approx(4 * 40.0 * math.sqrt(0.5))
    assert np.allclose(got[1:], [0.0, 15.0, 0.0, 0.0, 0.0], atol=1e-9)


def test_the_mission_holds_then_moves_its_set_point_at_the_transit_speed():
    from tether_sim.vehicle.sim import Mission

    m = Mission((0.0, 0.0, -10.0), target=(30.0, 40.0, -10.0), transit_after=5.0, speed=0.5)
    assert np.allclose(m.setpoint(5.0), (0, 0, -10))
    assert np.allclose(m.setpoint(15.0), (3.0, 4.0, -10.0))  # 5 m along the 50 m leg after 10 s
    assert np.allclose(m.setpoint(500.0), (30.0, 40.0, -10.0))
