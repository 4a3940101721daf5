"""Rigid body attached to a cable end [PE2020 Table 1 'rigid body connection', Sec. 6, Table 3].

Body frame FLU (x forward, y left, z up) per REP-103; world frame ENU.

State layout (``BODY_STATE_SIZE = 13``)::

    [x, y, z, qx, qy, qz, qw, vx, vy, vz, wx, wy, wz]

CoG position (world), orientation quaternion body -> world, CoG velocity (world) and angular
velocity (world). The body is driven by the cable force at its attachment point P, gravity,
buoyancy (displaced volume = mass / density, centre of buoyancy at the CoG), quadratic Morison
drag per body axis and added mass / added inertia per body axis; the effective mass matrix is
``R diag(m + m_a) R^T`` (Driscoll et al. / PE2020 Sec. 6.1 model the cage as a submerged cylinder
with the lid area as heave drag area).
"""

from dataclasses import dataclass

import numpy as np

from tether_sim.numerics.jit import jit
from tether_sim.numerics.rotations import quaternion_rotation
from tether_sim.spec import param

BODY_STATE_SIZE = 13

# Offsets in the packed parameter vector (see pack_body_params).
_P_MASS, _P_VOLUME, _P_G, _P_RHO = 0, 1, 2, 3
_P_ADDED_MASS, _P_DRAG, _P_INERTIA, _P_ADDED_INERTIA, _P_ROT_DAMP, _P_ATTACH = 4, 7, 10, 13, 16, 19
BODY_PARAMS_SIZE = 22


@dataclass(frozen=True)
class RigidBodyProperties:
    """A 6-DOF body (e.g. the ROPOS cage) with Morison-type hydrodynamics per body axis."""

    mass: float = param(4995.0, unit="kg", doc="dry mass m_cg", min=1e-9, max=1e9)
    density: float = param(8448.0, unit="kg/m^3", doc="mean density; displaced volume = mass/density (buoyancy)", min=1e-3, max=1e6)
    added_mass: tuple = param((9200.0, 9200.0, 9200.0), unit="kg", doc="added mass along body x, y, z")
    drag_coefficients: tuple = param((1.3, 1.3, 2.7), doc="quadratic drag coefficients along body x, y, z")
    drag_areas: tuple = param((12.6, 12.6, 7.12), unit="m^2", doc="reference areas of the drag along body x, y, z")
    inertia: tuple = param((19.0e3, 19.0e3, 19.0e3), unit="kg m^2", doc="moments of inertia about body x, y, z (centre of gravity)")
    added_inertia: tuple = param((0.0, 0.0, 0.0), unit="kg m^2", doc="added moments of inertia about body x, y, z")
    rotational_damping: tuple = param((0.0, 0.0, 0.0), unit="N m s", doc="linear rotational damping about body x, y, z")
    attachment: tuple = param((0.0, 0.0, 2.1), unit="m", doc="cable attachment point P in the body frame, from the centre of gravity")
    initial_position: tuple = param((0.0, 0.0, -200.0), unit="m", doc="initial centre-of-gravity position, world frame (overridden by the static solve if enabled)")


def _vec3(values, name):
    arr = np.asarray(values, dtype=np.float64).reshape(-1)
    if arr.shape != (3,) or not np.all(np.isfinite(arr)):
        raise ValueError(f"body.{name}: expected 3 finite numbers, got {values!r}")
    return arr


def pack_body_params(props: RigidBodyProperties, env) -> np.ndarray:
    """Flat float64 parameter vector for the kernels (layout private to this module).

    Drag entries hold 0.5 * rho_f * C_d * A per body axis [Morison drag]. ``env`` is an
    :class:`tether_sim.physics.environment.Environment`.
    """
    p = np.zeros(BODY_PARAMS_SIZE)
    p[_P_MASS] = props.mass
    p[_P_VOLUME] = props.mass / props.density
    p[_P_G] = env.g
    p[_P_RHO] = env.fluid_density
    p[_P_ADDED_MASS:_P_ADDED_MASS + 3] = _vec3(props.added_mass, "added_mass")
    cd = _vec3(props.drag_coefficients, "drag_coefficients")
    area = _vec3(props.drag_areas, "drag_areas")
    p[_P_DRAG:_P_DRAG + 3] = 0.5 * env.fluid_density * cd * area
    p[_P_INERTIA:_P_INERTIA + 3] = _vec3(props.inertia, "inertia")
    p[_P_ADDED_INERTIA:_P_ADDED_INERTIA + 3] = _vec3(props.added_inertia, "added_inertia")
    p[_P_ROT_DAMP:_P_ROT_DAMP + 3] = _vec3(props.rotational_damping, "rotational_damping")
    p[_P_ATTACH:_P_ATTACH + 3] = _vec3(props.attachment, "attachment")
    if np.any(p[_P_ADDED_MASS:_P_ADDED_MASS + 3] + props.mass <= 0.0):
        raise ValueError("body: mass + added_mass must be positive on every axis")
    if np.any(p[_P_INERTIA:_P_INERTIA + 3] + p[_P_ADDED_INERTIA:_P_ADDED_INERTIA + 3] <= 0.0):
        raise ValueError("body: inertia + added_inertia must be positive about every axis")
    return p


def submerged_weight(props: RigidBodyProperties, env) -> float:
    """Weight minus buoyancy, m g (1 - rho_f / rho_body) (N); positive when the body sinks."""
    return props.mass * env.g * (1.0 - env.fluid_density / props.density)


def initial_body_state(props: RigidBodyProperties, attachment_world=None) -> np.ndarray:
    """Upright body at rest; CoG at ``initial_position`` or placed so that P sits at ``attachment_world``."""
    state = np.zeros(BODY_STATE_SIZE)
    state[6] = 1.0  # identity quaternion (x, y, z, w)
    if attachment_world is None:
        state[0:3] = _vec3(props.initial_position, "initial_position")
    else:
        state[0:3] = _vec3(attachment_world, "attachment_world") - _vec3(props.attachment, "attachment")
    return state


@jit
def _rotation(state):
    """R (body -> world) as 9 scalars (row major) from the normalised quaternion x, y, z, w at
    state[3:7]; scalars instead of an array so the per-stage body kernels allocate nothing."""
    return quaternion_rotation(state[3], state[4], state[5], state[6])


@jit
def rotation_matrix(state, out):
    """out (3, 3) = R (body -> world) of the body state (for callers outside the hot loop)."""
    R = _rotation(state)
    for i in range(3):
        for j in range(3):
            out[i, j] = R[3 * i + j]


@jit
def _rotate(R, x, y, z):
    """R (x, y, z)."""
    return (R[0] * x + R[1] * y + R[2] * z, R[3] * x + R[4] * y + R[5] * z,
            R[6] * x + R[7] * y + R[8] * z)


@jit
def _rotate_back(R, x, y, z):
    """R^T (x, y, z)."""
    return (R[0] * x + R[3] * y + R[6] * z, R[1] * x + R[4] * y + R[7] * z,
            R[2] * x + R[5] * y + R[8] * z)


@jit
def _lever_arm(params, R):
    """Vector from the CoG to P in the world frame, R r_P."""
    return _rotate(R, params[_P_ATTACH], params[_P_ATTACH + 1], params[_P_ATTACH + 2])


@jit
def body_attachment_kinematics(state, params, out_pos, out_vel):
    """World position x + R r_P and velocity v + omega x (R r_P) of the attachment point P."""
    R = _rotation(state)
    r0, r1, r2 = _lever_arm(params, R)
    wx, wy, wz = state[10], state[11], state[12]
    out_pos[0] = state[0] + r0
    out_pos[1] = state[1] + r1
    out_pos[2] = state[2] + r2
    out_vel[0] = state[7] + wy * r2 - wz * r1
    out_vel[1] = state[8] + wz * r0 - wx * r2
    out_vel[2] = state[9] + wx * r1 - wy * r0


@jit
def _translational_acceleration(state, params, cable_force, fluid_velocity, R, out_acc):
    """a = R diag(1/(m+m_a)) R^T (F_cable + (m - rho V) g + F_drag); drag per body axis."""
    m = params[_P_MASS]
    g = params[_P_G]
    # Relative velocity in the body frame, v_b = R^T (v - u); quadratic drag per body axis.
    v0, v1, v2 = _rotate_back(R, state[7] - fluid_velocity[0], state[8] - fluid_velocity[1],
                              state[9] - fluid_velocity[2])
    d0 = -params[_P_DRAG] * abs(v0) * v0
    d1 = -params[_P_DRAG + 1] * abs(v1) * v1
    d2 = -params[_P_DRAG + 2] * abs(v2) * v2
    e0, e1, e2 = _rotate(R, d0, d1, d2)
    f0 = cable_force[0] + e0
    f1 = cable_force[1] + e1
    f2 = cable_force[2] + e2 - (m - params[_P_RHO] * params[_P_VOLUME]) * g
    # Solve the effective mass matrix R diag(m + m_a) R^T: rotate in, divide, rotate back.
    b0, b1, b2 = _rotate_back(R, f0, f1, f2)
    a0, a1, a2 = _rotate(R, b0 / (m + params[_P_ADDED_MASS]), b1 / (m + params[_P_ADDED_MASS + 1]),
                         b2 / (m + params[_P_ADDED_MASS + 2]))
    out_acc[0] = a0
    out_acc[1] = a1
    out_acc[2] = a2


@jit
def body_acceleration(state, params, cable_force, fluid_velocity, out_acc):
    """CoG acceleration (3,) (world) under the cable force at P, gravity, buoyancy and drag."""
    _translational_acceleration(state, params, cable_force, fluid_velocity, _rotation(state), out_acc)


@jit
def body_derivatives(state, params, cable_force, fluid_velocity, out):
    """d(state)/dt (13,): Newton-Euler in the world frame with added mass/inertia per body axis.

    I_w dw/dt = r_P x F_cable - w x (I_w w) - C_w w,  I_w = R diag(I + I_a) R^T,
    dq/dt = 0.5 (0, w) (x) q (world angular velocity, quaternion x, y, z, w); a drift term
    -(|q|^2 - 1) q keeps the quaternion on the unit sphere. Allocates nothing.
    """
    R = _rotation(state)
    out[0] = state[7]
    out[1] = state[8]
    out[2] = state[9]
    _translational_acceleration(state, params, cable_force, fluid_velocity, R, out[7:10])
    qx, qy, qz, qw = state[3], state[4], state[5], state[6]
    wx, wy, wz = state[10], state[11], state[12]
    drift = qx * qx + qy * qy + qz * qz + qw * qw - 1.0
    out[3] = 0.5 * (wx * qw + wy * qz - wz * qy) - drift * qx
    out[4] = 0.5 * (-wx * qz + wy * qw + wz * qx) - drift * qy
    out[5] = 0.5 * (wx * qy - wy * qx + wz * qw) - drift * qz
    out[6] = 0.5 * (-wx * qx - wy * qy - wz * qz) - drift * qw
    # Angular momentum balance, evaluated in the body frame (diagonal inertia there).
    r0, r1, r2 = _lever_arm(params, R)
    t0 = r1 * cable_force[2] - r2 * cable_force[1]
    t1 = r2 * cable_force[0] - r0 * cable_force[2]
    t2 = r0 * cable_force[1] - r1 * cable_force[0]
    w0, w1, w2 = _rotate_back(R, wx, wy, wz)
    tb0, tb1, tb2 = _rotate_back(R, t0, t1, t2)
    i0 = params[_P_INERTIA] + params[_P_ADDED_INERTIA]
    i1 = params[_P_INERTIA + 1] + params[_P_ADDED_INERTIA + 1]
    i2 = params[_P_INERTIA + 2] + params[_P_ADDED_INERTIA + 2]
    # Euler's equations in the body frame: I dw_b/dt = tau_b - w_b x (I w_b) - C w_b.
    hx, hy, hz = i0 * w0, i1 * w1, i2 * w2
    dw0 = (tb0 - (w1 * hz - w2 * hy) - params[_P_ROT_DAMP] * w0) / i0
    dw1 = (tb1 - (w2 * hx - w0 * hz) - params[_P_ROT_DAMP + 1] * w1) / i1
    dw2 = (tb2 - (w0 * hy - w1 * hx) - params[_P_ROT_DAMP + 2] * w2) / i2
    # d(w_world)/dt = R dw_b/dt (the w x w term of dR/dt vanishes).
    a0, a1, a2 = _rotate(R, dw0, dw1, dw2)
    out[10] = a0
    out[11] = a1
    out[12] = a2
