"""An ROV as data: rigid body, hydrodynamics in Fossen's form and thrusters (body frame FLU, origin at
the centre of gravity).

Equations of motion (Fossen 2011, Ch. 6-7), body frame, nu = (u, v, w, p, q, r), nu_r = nu - nu_c
(nu_c the current in the body frame, constant in the world):

    (M_RB + M_A) d(nu)/dt + C_RB(nu) nu + C_A(nu_r) nu_r + D(nu_r) nu_r + g(eta) = tau_thrust + tau_tether

with M_A = diag(added mass), D(nu_r) = diag(linear) + diag(quadratic) |nu_r|, g(eta) the weight at
the centre of gravity and the buoyancy rho g V at the centre of buoyancy, and C_A(nu_r) the added
mass's Coriolis and centripetal matrix (the Munk moment among them).

BLUEROV2_HEAVY is Table A1 of von Benzon, Sorensen, Uth, Jouffroy, Liniger and Pedersen, "An
Open-Source Benchmark Simulator: Control of a BlueROV2 Underwater Robot", J. Mar. Sci. Eng. 10(12)
1898 (2022), doi:10.3390/jmse10121898 (coefficients identified in a test tank; the table gives them
in NED/FRD, their magnitudes are the same in FLU). Its thrusters are Blue Robotics T200s, four
horizontal at 45 degrees and four vertical (the "Heavy" configuration); the positions below are
read off the frame's published dimensions (0.457 x 0.575 x 0.254 m) to about a centimetre, and the
thrust is limited to 40 N each way (the T200's reverse thrust at 16 V; its forward thrust is ~51 N).
"""

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class VehicleModel:
    name: str
    mass: float  # kg
    volume: float  # m^3 displaced (buoyancy rho g V)
    inertia: tuple  # (Ixx, Iyy, Izz) kg m^2 about the centre of gravity
    cob: tuple  # centre of buoyancy in the body frame (FLU, from the centre of gravity), m
    added_mass: tuple  # (X_udot, Y_vdot, Z_wdot, K_pdot, M_qdot, N_rdot), kg and kg m^2 (positive)
    linear_damping: tuple  # (X_u, Y_v, Z_w, K_p, M_q, N_r), N s/m and N m s (positive)
    quadratic_damping: tuple  # (X_u|u|, ..., N_r|r|), N s^2/m^2 and N m s^2 (positive)
    thruster_positions: tuple  # ((x, y, z), ...) body frame, m
    thruster_directions: tuple  # ((dx, dy, dz), ...) unit vectors, body frame
    thrust_limit: float  # N, each thruster, both ways
    source: str = ""

    def rigid_mass(self) -> np.ndarray:
        """diag(M_RB) (6,): mass three times, then the principal inertias."""
        return np.array([self.mass] * 3 + list(self.inertia), float)

    def total_mass(self) -> np.ndarray:
        """diag(M_RB + M_A) (6,)."""
        return self.rigid_mass() + np.asarray(self.added_mass, float)

    def thrust_matrix(self) -> np.ndarray:
        """(6, n) the body wrench of unit thrust of each thruster: (d, r x d)."""
        r = np.asarray(self.thruster_positions, float)
        d = np.asarray(self.thruster_directions, float)
        return np.vstack([d.T, np.cross(r, d).T])


_H = np.sqrt(0.5)
BLUEROV2_HEAVY = VehicleModel(
    name="BlueROV2 Heavy",
    mass=13.5, volume=0.0134, inertia=(0.26, 0.23, 0.37), cob=(0.0, 0.0, 0.01),
    added_mass=(6.36, 7.12, 18.68, 0.189, 0.135, 0.222),
    linear_damping=(13.7, 0.0, 33.0, 0.0, 0.8, 0.0),
    quadratic_damping=(141.0, 217.0, 190.0, 1.19, 0.47, 1.5),
    thruster_positions=((0.156, -0.111, -0.085), (0.156, 0.111, -0.085), (-0.156, -0.111, -0.085),
                        (-0.156, 0.111, -0.085), (0.120, -0.218, 0.0), (0.120, 0.218, 0.0),
                        (-0.120, -0.218, 0.0), (-0.120, 0.218, 0.0)),
    thruster_directions=((_H, _H, 0.0), (_H, -_H, 0.0), (_H, -_H, 0.0), (_H, _H, 0.0),
                         (0.0, 0.0, 1.0), (0.0, 0.0, 1.0), (0.0, 0.0, 1.0), (0.0, 0.0, 1.0)),
    thrust_limit=40.0,
    source="von Benzon et al. (2022), J. Mar. Sci. Eng. 10(12) 1898, Table A1",
)

MODELS = {"bluerov2_heavy": BLUEROV2_HEAVY}


def hydrodynamic_wrench(model: VehicleModel, nu_r) -> np.ndarray:
    """-(C_A(nu_r) + D(nu_r)) nu_r (6,), body frame: damping and the added mass's Coriolis terms
    (Fossen 2011 Eq. 6.43 with M_A diagonal: C_A = [[0, -S(A1 v)], [-S(A1 v), -S(A2 w)]])."""
    nu_r = np.asarray(nu_r, float)
    A = np.asarray(model.added_mass, float)
    v, w = nu_r[:3], nu_r[3:]
    a1, a2 = A[:3] * v, A[3:] * w
    # C_A nu_r = [-S(a1) w, -S(a1) v - S(a2) w] = [-(a1 x w), -(a1 x v) - (a2 x w)]
    coriolis = np.concatenate([-np.cross(a1, w), -np.cross(a1, v) - np.cross(a2, w)])
    damping = (np.asarray(model.linear_damping, float) + np.asarray(model.quadratic_damping, float)
               * np.abs(nu_r)) * nu_r
    return -coriolis - damping


def restoring_wrench(model: VehicleModel, R, rho: float, g: float) -> np.ndarray:
    """Weight and buoyancy as a body-frame wrench about the centre of gravity (6,); R rotates body to
    world (ENU, z up)."""
    up = R.T @ np.array([0.0, 0.0, 1.0])
    W, B = model.mass * g, rho * g * model.volume
    force = (B - W) * up
    return np.concatenate([force, np.cross(np.asarray(model.cob, float), B * up)])
