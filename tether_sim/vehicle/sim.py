"""The vehicle in MuJoCo: MuJoCo integrates the rigid body (a free joint: quaternion kinematics and
the gyroscopic terms); the loads of ``model`` are computed here and applied each step.

MuJoCo's own fluid model (an equivalent ellipsoid or inertia box, ``opt.density``/``viscosity``) is
not the vehicle's identified hydrodynamics, so it is off, and so is MuJoCo's gravity: the weight,
buoyancy, damping, added mass Coriolis terms, thrust and tether wrench are summed here as one body
wrench tau. MuJoCo has no added-mass matrix either; with M_A diagonal and the origin at the centre of
gravity the added mass is applied exactly per axis by handing MuJoCo M_RB (M_RB + M_A)^-1 tau, which
gives its rigid body the acceleration (M_RB + M_A)^-1 tau. (The rigid body's own gyroscopic terms,
which MuJoCo adds with M_RB only, are then off by the ratio of added to total inertia: rotation rates
of a station-keeping vehicle make this negligible.) Frames: world ENU (z up, the tether's world),
body FLU, as REP-103.

``StationKeeper`` holds a position and heading with a PID per world axis and yaw (roll and pitch
held level), maps the wanted body wrench to the thrusters by the pseudo-inverse of the thrust
matrix and clips each thruster at its limit.
"""

import logging
import math

import mujoco
import numpy as np

from tether_sim.numerics.rotations import quaternion_matrix
from tether_sim.vehicle.model import hydrodynamic_wrench, restoring_wrench

_XML = """<mujoco>
  <option timestep="{dt}" gravity="0 0 0" density="0" viscosity="0" integrator="RK4"/>
  <worldbody>
    <body name="rov" pos="{x} {y} {z}">
      <freejoint/>
      <inertial pos="0 0 0" mass="{m}" diaginertia="{ix} {iy} {iz}"/>
    </body>
  </worldbody>
</mujoco>"""


# MuJoCo's warnings go to the log, not to a MUJOCO_LOG.TXT in the working directory
mujoco.set_mju_user_warning(lambda text: logging.getLogger("tether_sim.vehicle").warning("MuJoCo: %s", text))
_UNSTABLE = (mujoco.mjtWarning.mjWARN_BADQACC, mujoco.mjtWarning.mjWARN_BADQVEL, mujoco.mjtWarning.mjWARN_BADQPOS)


class VehicleDiverged(RuntimeError):
    """MuJoCo found the vehicle's state non-finite or huge (and would reset it to the start)."""


class VehicleSim:
    """One ROV in MuJoCo (module docstring). ``step(thrust, tether_force, tether_torque)`` advances
    one MuJoCo time step with the thrusters' forces (n,) and the tether's wrench on the vehicle in
    its body frame about its origin (as ``tether/vehicle_wrench`` carries it)."""

    def __init__(self, model, position=(0.0, 0.0, -10.0), yaw=0.0, dt=0.005, rho=1025.0, g=9.81,
                 current=(0.0, 0.0, 0.0)):
        self.model, self.rho, self.g, self.dt = model, float(rho), float(g), float(dt)
        self.current = np.asarray(current, float)
        ix, iy, iz = model.inertia
        x, y, z = (float(c) for c in position)
        self.mj = mujoco.MjModel.from_xml_string(_XML.format(dt=dt, x=x, y=y, z=z, m=model.mass,
                                                              ix=ix, iy=iy, iz=iz))
        self.data = mujoco.MjData(self.mj)
        self.data.qpos[3:7] = [math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)]  # MuJoCo: (w, x, y, z)
        mujoco.mj_forward(self.mj, self.data)
        self.scale = model.rigid_mass() / model.total_mass()
        self.B = model.thrust_matrix()
        self.last_tau = np.zeros(6)  # the body wrench of the last step, before the added-mass scaling

    @property
    def time(self) -> float:
        return float(self.data.time)

    @property
    def position(self) -> np.ndarray:
        return self.data.qpos[0:3].copy()

    @property
    def orientation(self) -> np.ndarray:
        """Unit quaternion (x, y, z, w), body to world."""
        w, x, y, z = self.data.qpos[3:7]
        return np.array([x, y, z, w]) / math.sqrt(w * w + x * x + y * y + z * z)

    def rotation(self) -> np.ndarray:
        return quaternion_matrix(self.orientation)

    def body_velocity(self, R=None) -> np.ndarray:
        """nu = (u, v, w, p, q, r) in the body frame (MuJoCo's free joint: linear in the world,
        angular in the body frame); R: the rotation, if the caller has it."""
        R = self.rotation() if R is None else R
        return np.concatenate([R.T @ self.data.qvel[0:3], self.data.qvel[3:6]])

    def loads(self, thrust, tether_force, tether_torque, R=None) -> np.ndarray:
        """tau (6,), the total body wrench about the centre of gravity (module docstring)."""
        R = self.rotation() if R is None else R
        nu = self.body_velocity(R)
        nu_r = nu - np.concatenate([R.T @ self.current, np.zeros(3)])
        tau = hydrodynamic_wrench(self.model, nu_r) + restoring_wrench(self.model, R, self.rho, self.g)
        tau = tau + self.B @ np.asarray(thrust, float)
        return tau + np.concatenate([np.asarray(tether_force, float), np.asarray(tether_torque, float)])

    def step(self, thrust, tether_force=(0.0, 0.0, 0.0), tether_torque=(0.0, 0.0, 0.0)):
        R = self.rotation()
        tau = self.loads(thrust, tether_force, tether_torque, R)
        self.last_tau = tau
        applied = self.scale * tau  # M_RB (M_RB + M_A)^-1 tau
        self.data.xfrc_applied[1, 0:3] = R @ applied[0:3]  # world frame, at the body's centre of mass
        self.data.xfrc_applied[1, 3:6] = R @ applied[3:6]
        before = [self.data.warning[w].number for w in _UNSTABLE]
        t = self.time
        mujoco.mj_step(self.mj, self.data)
        if [self.data.warning[w].number for w in _UNSTABLE] != before or not np.all(np.isfinite(self.data.qpos)):
            # MuJoCo has reset the state to the start: that is not the vehicle's motion
            raise VehicleDiverged(f"the vehicle simulation went unstable at t = {t:.3f} s (loads {np.round(tau, 1)} "
                                  "N, N m in the body frame)")


def yaw_of(q) -> float:
    x, y, z, w = q
    return math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))


class StationKeeper:
    """PID on the world position and the yaw, and on roll and pitch (level); thrust allocation per
    thruster group (``allocate``), the integral of each axis clamped to what the thrusters can give
    on it (anti-windup). Gains from a
    natural frequency omega (rad/s; attitude_omega for roll and pitch) and damping ratio zeta on the
    total (rigid + added) mass per axis:
    Kp = M omega^2, Kd = 2 zeta omega M, Ki = Kp omega / 4 (the closed loop s^3 + 2 zeta omega s^2 +
    omega^2 s + omega^3 / 4 of a free axis is stable: Routh, 2 zeta > 1 / 4)."""

    def __init__(self, model, omega=0.6, zeta=1.0, attitude_omega=2.4):
        M = model.total_mass()
        w = np.array([omega] * 3 + [attitude_omega] * 2 + [omega])  # roll and pitch stiffer: they carry the thrust
        self.kp, self.kd, self.ki = M * w**2, 2.0 * zeta * w * M, M * w**3 / 4.0
        B = model.thrust_matrix()
        self.limit = model.thrust_limit
        # two groups: thrusters in the horizontal plane (surge, sway, yaw) and the vertical ones (heave, roll,
        # pitch); each group is allocated on its own axes, the vertical group also cancelling the roll and
        # pitch moments the horizontal thrust makes, so a saturated surge cannot take the depth with it
        vertical = np.abs(np.asarray(model.thruster_directions, float)[:, 2]) > 0.5
        self.groups = [(np.flatnonzero(~vertical), [0, 1, 5]), (np.flatnonzero(vertical), [2, 3, 4])]
        self.group_pinv = [np.linalg.pinv(B[np.ix_(axes, idx)]) for idx, axes in self.groups]
        self.B = B
        self.integral = np.zeros(6)
        # anti-windup: the integral term of an axis is clamped to what all thrusters together can give on it
        self.reach = model.thrust_limit * np.abs(model.thrust_matrix()).sum(axis=1)

    def thrust(self, sim, setpoint, yaw, dt) -> np.ndarray:
        q = sim.orientation
        R = quaternion_matrix(q)
        nu = sim.body_velocity(R)
        e_world = np.asarray(setpoint, float) - sim.position
        roll = math.atan2(2 * (q[3] * q[0] + q[1] * q[2]), 1 - 2 * (q[0] ** 2 + q[1] ** 2))
        pitch = math.asin(max(-1.0, min(1.0, 2 * (q[3] * q[1] - q[2] * q[0]))))
        e_yaw = (yaw - yaw_of(q) + math.pi) % (2 * math.pi) - math.pi
        e = np.concatenate([R.T @ e_world, [-roll, -pitch, e_yaw]])  # body-frame errors
        self.integral = np.clip(self.integral + e * dt, -self.reach / self.ki, self.reach / self.ki)
        return self.allocate(self.kp * e + self.ki * self.integral - self.kd * nu)

    def allocate(self, wanted) -> np.ndarray:
        """Thruster forces for a wanted body wrench (6,): group by group (see __init__), a group's
        forces scaled down together when one would pass the limit (the direction of its wrench kept)."""
        u = np.zeros(self.B.shape[1])
        for (idx, axes), pinv in zip(self.groups, self.group_pinv):
            need = np.asarray(wanted, float)[axes] - (self.B @ u)[axes]
            ug = pinv @ need
            peak = np.abs(ug).max()
            u[idx] = ug * (self.limit / peak if peak > self.limit else 1.0)
        return u


class Mission:
    """Where the vehicle is told to be: hold ``station``, and from ``transit_after`` s (after the
    mission starts) move the set point in a straight line to ``target`` at ``speed`` m/s, then hold
    it. Without a target: hold the station."""

    def __init__(self, station, target=None, transit_after=0.0, speed=0.3):
        self.station = np.asarray(station, float)
        self.target = None if target is None else np.asarray(target, float)
        self.transit_after, self.speed = float(transit_after), float(speed)

    def setpoint(self, t: float) -> np.ndarray:
        if self.target is None or t <= self.transit_after:
            return self.station
        leg = self.target - self.station
        length = float(np.linalg.norm(leg))
        done = min(1.0, self.speed * (t - self.transit_after) / length) if length > 0 else 1.0
        return self.station + done * leg
