"""A rigid body of a line network: the 6-DOF body of ``physics/bodies.py`` (same state layout, same
hydrodynamics: wet weight at the centre of gravity, quadratic drag per body axis, added mass and
inertia per body axis) under the loads of several line ends, each at its own attachment point.

Time stepping is the kick-drift-kick (velocity Verlet) split of docs/network.md: a half kick with
the loads at the start of the coupling step, a drift of the position and orientation with the
half-step velocities, the lines advanced with the body's new kinematics, a half kick with their
new end loads. Every kick's impulses are kept by kind (line ends, wet weight, drag) so the body's
momentum balance can be checked to round-off (:attr:`NetworkBody.impulse`).
"""

import math

import numpy as np

from tether_sim.numerics.rotations import quaternion_matrix
from tether_sim.physics.bodies import BODY_STATE_SIZE, initial_body_state, submerged_weight


def quat_rotate_world(q, phi):
    """exp(phi) applied on the world side: the quaternion of exp([phi]x) R(q) (phi world rotation vector)."""
    a = float(np.linalg.norm(phi))
    if a == 0.0:
        return np.asarray(q, float).copy()
    s = math.sin(0.5 * a) / a
    px, py, pz, pw = phi[0] * s, phi[1] * s, phi[2] * s, math.cos(0.5 * a)
    x, y, z, w = q
    out = np.array([pw * x + px * w + py * z - pz * y,
                    pw * y - px * z + py * w + pz * x,
                    pw * z + px * y - py * x + pz * w,
                    pw * w - px * x - py * y - pz * z])
    return out / np.linalg.norm(out)


def _cross(a, b):
    """a x b for (..., 3) arrays (numpy's cross is slow on tiny arrays)."""
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    return np.stack([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0], axis=-1)


class NetworkBody:
    """One body: ``state`` (13,) as in physics/bodies.py; ``attachments`` (k, 3) body-frame points."""

    def __init__(self, name, props, env, attachments):
        self.name = name
        self.props = props
        self.attachments = np.asarray(attachments, float).reshape(-1, 3)
        self.mass = float(props.mass)
        self.added_mass = np.asarray(props.added_mass, float)
        self.inertia = np.asarray(props.inertia, float) + np.asarray(props.added_inertia, float)
        self.rot_damping = np.asarray(props.rotational_damping, float)
        self.drag = 0.5 * env.fluid_density * np.asarray(props.drag_coefficients, float) * np.asarray(props.drag_areas, float)
        self.wet_weight = submerged_weight(props, env)
        if np.any(self.mass + self.added_mass <= 0) or np.any(self.inertia <= 0):
            raise ValueError(f"network body {name}: mass + added mass and inertia + added inertia must be positive")
        self.state = initial_body_state(props)
        self.impulse_table = np.zeros((3, 3))  # rows: line ends, wet weight, drag (body_kernels.IMP_*)
        self.impulse = {"lines": self.impulse_table[0], "weight": self.impulse_table[1], "drag": self.impulse_table[2]}

    # ------------------------------------------------------------------ kinematics
    @property
    def rotation(self):
        return quaternion_matrix(self.state[3:7])

    def attachment_points(self, state=None):
        """World positions (k, 3) and velocities (k, 3) of the attachment points."""
        s = self.state if state is None else state
        R = quaternion_matrix(s[3:7])
        lever = self.attachments @ R.T
        return s[0:3] + lever, s[7:10] + _cross(s[10:13], lever)

    def place(self, position, rotation_vector=(0.0, 0.0, 0.0)):
        """Put the body at rest at CoG ``position`` with orientation exp(rotation_vector) (world)."""
        self.state[:] = initial_body_state(self.props)
        self.state[0:3] = position
        self.state[3:7] = quat_rotate_world(self.state[3:7], np.asarray(rotation_vector, float))
        self.state[7:13] = 0.0

    # ------------------------------------------------------------------ loads
    def loads(self, forces, moments, fluid_velocity=(0.0, 0.0, 0.0), state=None):
        """Net force and moment about the CoG (world) and their parts: forces/moments (k, 3) are the
        line ends' loads on the body at the attachments. Returns (F, M, F_lines, F_weight, F_drag)."""
        s = self.state if state is None else state
        R = quaternion_matrix(s[3:7])
        lever = self.attachments @ R.T
        f_lines = np.sum(forces, axis=0)
        m = np.sum(_cross(lever, forces), axis=0) + np.sum(moments, axis=0)
        vb = R.T @ (s[7:10] - np.asarray(fluid_velocity, float))
        f_drag = R @ (-self.drag * np.abs(vb) * vb)
        f_weight = np.array([0.0, 0.0, -self.wet_weight])
        return f_lines + f_weight + f_drag, m, f_lines, f_weight, f_drag

    def accelerations(self, force, moment, state=None):
        """CoG acceleration and angular acceleration (world) [the Newton-Euler equations of
        physics/bodies.body_derivatives, with the moment of several attachments]."""
        s = self.state if state is None else state
        R = quaternion_matrix(s[3:7])
        a = R @ ((R.T @ force) / (self.mass + self.added_mass))
        wb = R.T @ s[10:13]
        tb = R.T @ moment
        dwb = (tb - _cross(wb, self.inertia * wb) - self.rot_damping * wb) / self.inertia
        return a, R @ dwb

    # ------------------------------------------------------------------ kick-drift-kick
    def kick(self, dt, forces, moments, fluid_velocity=(0.0, 0.0, 0.0), closing=False):
        """Velocity update over dt with the line loads given; impulses recorded. The velocity-dependent
        loads (drag, gyroscopic and damping moments) are taken at the current velocities, or with
        ``closing`` (the second half kick, which ends at t_n+1) at the end velocities of a trial kick,
        so that they too are second order in the coupling step."""
        F, M, fl, fw, fd = self.loads(forces, moments, fluid_velocity)
        a, alpha = self.accelerations(F, M)
        if closing:
            trial = self.state.copy()
            trial[7:10] += dt * a
            trial[10:13] += dt * alpha
            F, M, fl, fw, fd = self.loads(forces, moments, fluid_velocity, state=trial)
            a, alpha = self.accelerations(F, M, state=trial)
        self.state[7:10] += dt * a
        self.state[10:13] += dt * alpha
        self.impulse["lines"] += dt * fl
        self.impulse["weight"] += dt * fw
        self.impulse["drag"] += dt * fd

    def drift(self, dt):
        """Position and orientation over dt with the current (half-step) velocities."""
        self.state[0:3] += dt * self.state[7:10]
        self.state[3:7] = quat_rotate_world(self.state[3:7], dt * self.state[10:13])

    def predicted_end_state(self, dt, forces, moments, fluid_velocity=(0.0, 0.0, 0.0)):
        """Body state at the end of the coupling step with the second half kick taken with the
        loads of the start (the target of the lines' end motion; the body itself is kicked with
        the lines' new loads afterwards)."""
        s = self.state.copy()
        F, M, *_ = self.loads(forces, moments, fluid_velocity, state=s)
        a, alpha = self.accelerations(F, M, state=s)
        s[7:10] += dt * a
        s[10:13] += dt * alpha
        return s

    @property
    def momentum(self):
        """(m + m_a) v per body axis, world frame: the momentum of the body and its entrained water."""
        R = self.rotation
        return R @ ((self.mass + self.added_mass) * (R.T @ self.state[7:10]))


assert BODY_STATE_SIZE == 13
