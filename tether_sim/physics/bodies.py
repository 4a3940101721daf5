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
def _rotation_matrix(state, out):
    """R (body -> world) from the (normalised) quaternion x, y, z, w at state[3:7]."""
    qx, qy, qz, qw = state[3], state[4], state[5], state[6]
    n = np.sqrt(qx * qx + qy * qy + qz * qz + qw * qw)
    qx, qy, qz, qw = qx / n, qy / n, qz / n, qw / n
    out[0, 0] = 1.0 - 2.0 * (qy * qy + qz * qz)
    out[0, 1] = 2.0 * (qx * qy - qz * qw)
    out[0, 2] = 2.0 * (qx * qz + qy * qw)
    out[1, 0] = 2.0 * (qx * qy + qz * qw)
    out[1, 1] = 1.0 - 2.0 * (qx * qx + qz * qz)
    out[1, 2] = 2.0 * (qy * qz - qx * qw)
    out[2, 0] = 2.0 * (qx * qz - qy * qw)
    out[2, 1] = 2.0 * (qy * qz + qx * qw)
    out[2, 2] = 1.0 - 2.0 * (qx * qx + qy * qy)


@jit
def _lever_arm(state, params, R, out):
    """Vector from the CoG to P in the world frame, R r_P."""
    for i in range(3):
        out[i] = (R[i, 0] * params[_P_ATTACH] + R[i, 1] * params[_P_ATTACH + 1]
                  + R[i, 2] * params[_P_ATTACH + 2])


@jit
def body_attachment_kinematics(state, params, out_pos, out_vel):
    """World position x + R r_P and velocity v + omega x (R r_P) of the attachment point P."""
    R = np.empty((3, 3))
    r = np.empty(3)
    _rotation_matrix(state, R)
    _lever_arm(state, params, R, r)
    wx, wy, wz = state[10], state[11], state[12]
    out_pos[0] = state[0] + r[0]
    out_pos[1] = state[1] + r[1]
    out_pos[2] = state[2] + r[2]
    out_vel[0] = state[7] + wy * r[2] - wz * r[1]
    out_vel[1] = state[8] + wz * r[0] - wx * r[2]
    out_vel[2] = state[9] + wx * r[1] - wy * r[0]


@jit
def _translational_acceleration(state, params, cable_force, fluid_velocity, R, out_acc):
    """a = R diag(1/(m+m_a)) R^T (F_cable + (m - rho V) g + F_drag); drag per body axis."""
    m = params[_P_MASS]
    g = params[_P_G]
    # Relative velocity in the body frame, v_b = R^T (v - u).
    f_body = np.empty(3)
    for j in range(3):
        vb = 0.0
        for i in range(3):
            vb += R[i, j] * (state[7 + i] - fluid_velocity[i])
        f_body[j] = -params[_P_DRAG + j] * abs(vb) * vb
    force = np.empty(3)
    for i in range(3):
        force[i] = cable_force[i] + R[i, 0] * f_body[0] + R[i, 1] * f_body[1] + R[i, 2] * f_body[2]
    force[2] -= (m - params[_P_RHO] * params[_P_VOLUME]) * g
    # Solve the effective mass matrix R diag(m + m_a) R^T: rotate in, divide, rotate back.
    fb = np.empty(3)
    for j in range(3):
        fb[j] = (R[0, j] * force[0] + R[1, j] * force[1] + R[2, j] * force[2]) / (m + params[_P_ADDED_MASS + j])
    for i in range(3):
        out_acc[i] = R[i, 0] * fb[0] + R[i, 1] * fb[1] + R[i, 2] * fb[2]


@jit
def body_acceleration(state, params, cable_force, fluid_velocity, out_acc):
    """CoG acceleration (3,) (world) under the cable force at P, gravity, buoyancy and drag."""
    R = np.empty((3, 3))
    _rotation_matrix(state, R)
    _translational_acceleration(state, params, cable_force, fluid_velocity, R, out_acc)


@jit
def body_derivatives(state, params, cable_force, fluid_velocity, out):
    """d(state)/dt (13,): Newton-Euler in the world frame with added mass/inertia per body axis.

    I_w dw/dt = r_P x F_cable - w x (I_w w) - C_w w,  I_w = R diag(I + I_a) R^T,
    dq/dt = 0.5 (0, w) (x) q (world angular velocity, quaternion x, y, z, w); a drift term
    -(|q|^2 - 1) q keeps the quaternion on the unit sphere.
    """
    R = np.empty((3, 3))
    _rotation_matrix(state, R)
    acc = np.empty(3)
    _translational_acceleration(state, params, cable_force, fluid_velocity, R, acc)
    out[0] = state[7]
    out[1] = state[8]
    out[2] = state[9]
    out[7] = acc[0]
    out[8] = acc[1]
    out[9] = acc[2]
    qx, qy, qz, qw = state[3], state[4], state[5], state[6]
    wx, wy, wz = state[10], state[11], state[12]
    drift = qx * qx + qy * qy + qz * qz + qw * qw - 1.0
    out[3] = 0.5 * (wx * qw + wy * qz - wz * qy) - drift * qx
    out[4] = 0.5 * (-wx * qz + wy * qw + wz * qx) - drift * qy
    out[5] = 0.5 * (wx * qy - wy * qx + wz * qw) - drift * qz
    out[6] = 0.5 * (-wx * qx - wy * qy - wz * qz) - drift * qw
    # Angular momentum balance, evaluated in the body frame (diagonal inertia there).
    r = np.empty(3)
    _lever_arm(state, params, R, r)
    tau = np.empty(3)
    tau[0] = r[1] * cable_force[2] - r[2] * cable_force[1]
    tau[1] = r[2] * cable_force[0] - r[0] * cable_force[2]
    tau[2] = r[0] * cable_force[1] - r[1] * cable_force[0]
    wb = np.empty(3)
    tb = np.empty(3)
    for j in range(3):
        wb[j] = R[0, j] * wx + R[1, j] * wy + R[2, j] * wz
        tb[j] = R[0, j] * tau[0] + R[1, j] * tau[1] + R[2, j] * tau[2]
    ib = np.empty(3)
    for j in range(3):
        ib[j] = params[_P_INERTIA + j] + params[_P_ADDED_INERTIA + j]
    # Euler's equations in the body frame: I dw_b/dt = tau_b - w_b x (I w_b) - C w_b.
    hx, hy, hz = ib[0] * wb[0], ib[1] * wb[1], ib[2] * wb[2]
    dwb = np.empty(3)
    dwb[0] = (tb[0] - (wb[1] * hz - wb[2] * hy) - params[_P_ROT_DAMP] * wb[0]) / ib[0]
    dwb[1] = (tb[1] - (wb[2] * hx - wb[0] * hz) - params[_P_ROT_DAMP + 1] * wb[1]) / ib[1]
    dwb[2] = (tb[2] - (wb[0] * hy - wb[1] * hx) - params[_P_ROT_DAMP + 2] * wb[2]) / ib[2]
    # d(w_world)/dt = R dw_b/dt (the w x w term of dR/dt vanishes).
    for i in range(3):
        out[10 + i] = R[i, 0] * dwb[0] + R[i, 1] * dwb[1] + R[i, 2] * dwb[2]
