"""Rigid-body kernels against closed forms (ROPOS cage values, PE2020 Table 3)."""

import math

import numpy as np
import pytest

from tether_sim.physics.bodies import (
    BODY_STATE_SIZE,
    RigidBodyProperties,
    body_acceleration,
    body_attachment_kinematics,
    body_derivatives,
    initial_body_state,
    pack_body_params,
    submerged_weight,
)
from tether_sim.physics.environment import Environment

ENV = Environment()
CAGE = RigidBodyProperties()


def rk4(state, params, force_fn, dt, n, record=None):
    """Classical RK4 on body_derivatives; force_fn(state) gives the cable force at P."""
    k = [np.zeros(BODY_STATE_SIZE) for _ in range(4)]
    u = np.zeros(3)
    out = []
    for _ in range(n):
        body_derivatives(state, params, force_fn(state), u, k[0])
        body_derivatives(state + 0.5 * dt * k[0], params, force_fn(state + 0.5 * dt * k[0]), u, k[1])
        body_derivatives(state + 0.5 * dt * k[1], params, force_fn(state + 0.5 * dt * k[1]), u, k[2])
        body_derivatives(state + dt * k[2], params, force_fn(state + dt * k[2]), u, k[3])
        state = state + dt / 6.0 * (k[0] + 2 * k[1] + 2 * k[2] + k[3])
        if record is not None:
            out.append(record(state))
    return state, out


def quat(axis, angle):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    return np.r_[axis * math.sin(angle / 2), math.cos(angle / 2)]


def test_buoyancy_and_submerged_weight():
    w_sub = submerged_weight(CAGE, ENV)
    # m g (1 - rho_f/rho_b) = 4995 * 9.81 * (1 - 1025/8448) = 43.05 kN
    assert w_sub == pytest.approx(4995 * 9.81 * (1 - 1025 / 8448), rel=1e-12)
    params = pack_body_params(CAGE, ENV)
    state = initial_body_state(CAGE)
    acc = np.zeros(3)
    body_acceleration(state, params, np.zeros(3), np.zeros(3), acc)
    # Heave acceleration from rest: -W_sub / (m + m_a,z) (added mass resists buoyant sinking too).
    assert acc == pytest.approx([0.0, 0.0, -w_sub / (4995 + 9200)], rel=1e-12, abs=1e-15)
    body_acceleration(state, params, np.array([0.0, 0.0, w_sub]), np.zeros(3), acc)
    assert np.allclose(acc, 0.0, atol=1e-12)


def test_free_fall_reaches_terminal_velocity_with_added_mass():
    # (m + m_a) dv/dt = -W_s + D v^2 (falling, v < 0), D = rho Cd A / 2
    # => v(t) = -v_t tanh(t a0 / v_t), v_t = sqrt(W_s/D), a0 = W_s/(m + m_a).
    params = pack_body_params(CAGE, ENV)
    w_sub = submerged_weight(CAGE, ENV)
    drag = 0.5 * 1025.0 * 2.7 * 7.12
    v_t = math.sqrt(w_sub / drag)
    a0 = w_sub / (4995.0 + 9200.0)
    dt, n = 0.01, 2000
    _, vz = rk4(initial_body_state(CAGE), params, lambda s: np.zeros(3), dt, n, record=lambda s: s[9])
    t = dt * np.arange(1, n + 1)
    exact = -v_t * np.tanh(t * a0 / v_t)
    # RK4 at dt = 0.01 s on a 3 s time scale: error ~1e-9 relative; 1e-6 leaves room.
    assert np.max(np.abs(np.array(vz) - exact)) < 1e-6 * v_t
    assert vz[-1] == pytest.approx(-v_t, rel=1e-6)


def test_added_mass_acts_per_body_axis():
    props = RigidBodyProperties(added_mass=(1000.0, 3000.0, 9200.0), drag_coefficients=(0.0, 0.0, 0.0))
    params = pack_body_params(props, Environment(g=0.0))
    state = initial_body_state(props)
    state[3:7] = quat([1.0, 2.0, 0.5], 0.9)
    R = np.empty((3, 3))
    # A force along the rotated body y axis accelerates along it with 1/(m + m_a,y).
    from tether_sim.physics.bodies import rotation_matrix

    rotation_matrix(state, R)
    acc = np.zeros(3)
    body_acceleration(state, params, 500.0 * R[:, 1], np.zeros(3), acc)
    assert acc == pytest.approx(500.0 / (4995.0 + 3000.0) * R[:, 1], rel=1e-12)


def test_attachment_kinematics_consistent_with_derivatives():
    params = pack_body_params(CAGE, ENV)
    state = initial_body_state(CAGE, attachment_world=(1.0, 2.0, -50.0))
    pos, vel = np.zeros(3), np.zeros(3)
    body_attachment_kinematics(state, params, pos, vel)
    assert pos == pytest.approx([1.0, 2.0, -50.0])
    state[3:7] = quat([0.3, 1.0, -0.2], 0.4)
    state[7:10] = [0.5, -0.2, 0.1]
    state[10:13] = [0.2, -0.4, 0.3]
    body_attachment_kinematics(state, params, pos, vel)
    d = np.zeros(BODY_STATE_SIZE)
    body_derivatives(state, params, np.zeros(3), np.zeros(3), d)
    h = 1e-6
    p2, v2 = np.zeros(3), np.zeros(3)
    body_attachment_kinematics(state + h * d, params, p2, v2)
    # Forward difference of P along the state flow equals v_P to O(h).
    assert (p2 - pos) / h == pytest.approx(vel, abs=1e-5)


def test_pitch_pendulum_period_from_attachment_offset():
    # A constant vertical force F = W_sub at P (a taut vertical tether) holds the CoG still;
    # the pitch obeys I theta'' = -F h sin(theta): period 2 pi sqrt(I / (F h)), h = 2.1 m.
    params = pack_body_params(CAGE, ENV)
    w_sub = submerged_weight(CAGE, ENV)
    period = 2 * math.pi * math.sqrt(19.0e3 / (w_sub * 2.1))
    state = initial_body_state(CAGE)
    theta0 = 0.02
    state[3:7] = quat([0.0, 1.0, 0.0], theta0)
    dt = period / 400
    n = 1000  # 2.5 periods
    force = np.array([0.0, 0.0, w_sub])
    _, rec = rk4(state, params, lambda s: force, dt, n, record=lambda s: (2 * math.atan2(s[4], s[6]), s[0], s[2]))
    theta = np.array([r[0] for r in rec])
    t = dt * np.arange(1, n + 1)
    # Upward zero crossings -> period; finite amplitude adds theta0^2/16 = 2.5e-5 relative.
    idx = np.where((theta[:-1] < 0) & (theta[1:] >= 0))[0]
    tz = t[idx] - theta[idx] * dt / (theta[idx + 1] - theta[idx])
    assert len(tz) >= 2
    assert np.diff(tz).mean() == pytest.approx(period, rel=1e-3)
    # CoG stays put: net force is zero and the drag on a body at rest is zero.
    assert max(abs(r[1]) for r in rec) < 1e-9
    assert max(abs(r[2] + 200.0) for r in rec) < 1e-9


def test_bad_parameters_raise_clear_errors():
    with pytest.raises(ValueError, match="added_mass"):
        pack_body_params(RigidBodyProperties(added_mass=(1.0, 2.0)), ENV)
    with pytest.raises(ValueError, match="positive"):
        pack_body_params(RigidBodyProperties(added_mass=(-1e4, 0.0, 0.0)), ENV)
