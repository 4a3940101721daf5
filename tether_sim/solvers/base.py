"""The one solver interface that both solvers implement (DG/LDG and hybrid rod-catenary).

The ROS node, the offline runner, the scenarios and the benchmarks use only this interface.
Ends are named ``"ship"`` (s = 0) and ``"vehicle"`` (s = L). World frame ENU (z up), SI units.

Contract
--------
- ``set_end_motion(end, position, velocity)`` gives the state a ``prescribed`` end must have at the
  target time of the next ``advance_to``; the solver moves the end from its current state to that
  one by cubic Hermite interpolation over the interval (position and velocity stay consistent).
- ``set_end_load(end, force, moment)`` sets the point load of a ``force`` end (held constant).
- ``advance_to(t)`` takes stable substeps (all inside compiled code) until ``time == t`` and returns
  the number of substeps. It raises ``SolverDivergedError`` when the state becomes non-finite.
- ``drain_end_tensions()`` returns the end tensions at every substep since the last call, so that
  snap detection sees every peak even when the node samples at 50 Hz.
- ``tick(t, ship=None, vehicle=None, drain=True)`` is one node tick: ``set_end_motion`` of the
  ends given as (position, velocity), ``advance_to(t)``, ``drain_end_tensions()`` (unless
  ``drain`` is false) and the end loads, returned as a :class:`TickOutput` of views that stay
  valid until the next call on the solver. The results equal those of the composition; the DG
  solver does it in one compiled call (no Python per substep, one call per tick), any other
  solver by :func:`compose_tick`.
- ``snapshot()`` / ``restore(snap)`` copy the full state (for recovery after divergence).
"""

from dataclasses import dataclass, field
from typing import NamedTuple, Protocol, runtime_checkable

import math

import numpy as np

from tether_sim.physics.boundary import END_NAMES


@dataclass
class SolverState:
    """Cable state sampled at output points (n points)."""

    time: float
    arc_length: np.ndarray  # (n,) unstretched s, m
    position: np.ndarray  # (n, 3) m, world ENU
    velocity: np.ndarray  # (n, 3) m/s
    tension: np.ndarray  # (n,) axial tension T, N
    strain: np.ndarray  # (n,) axial strain eps
    curvature: np.ndarray  # (n,) |kappa|, 1/m (0 where the model has none)
    bending_moment: np.ndarray  # (n,) |M|, N m (0 where the model has none)
    time_step: float = 0.0  # the substep in use, s
    extra: dict = field(default_factory=dict)  # solver-specific fields (e.g. hybrid zone flags)


@dataclass
class EndForces:
    """Force (and moment) exerted BY the cable ON each end attachment, world frame."""

    ship_force: np.ndarray  # (3,) N
    vehicle_force: np.ndarray  # (3,) N
    ship_moment: np.ndarray = field(default_factory=lambda: np.zeros(3))  # N m
    vehicle_moment: np.ndarray = field(default_factory=lambda: np.zeros(3))  # N m
    ship_tension: float = 0.0  # axial tension at s = 0, N
    vehicle_tension: float = 0.0  # axial tension at s = L, N


@dataclass
class BodyState:
    """State of a simulated rigid body at an end (world ENU; quaternion x, y, z, w)."""

    position: np.ndarray  # (3,) centre of gravity, m
    orientation: np.ndarray  # (4,) quaternion x, y, z, w (body FLU -> world)
    velocity: np.ndarray  # (3,) m/s
    angular_velocity: np.ndarray  # (3,) rad/s, world frame
    acceleration: np.ndarray  # (3,) m/s^2


class BodyPose(NamedTuple):
    """Pose of a simulated rigid body at an end: :class:`BodyState`'s first two fields (a solver's ``body_pose``)."""

    position: np.ndarray  # (3,) centre of gravity, m
    orientation: np.ndarray  # (4,) quaternion x, y, z, w (body FLU -> world)


# columns of TickOutput.loads[end]: force by the cable on the end (N), axial end tension (N), moment (N m)
LOAD_F, LOAD_T, LOAD_M = 0, 3, 4
N_LOAD = 7


class TickOutput(NamedTuple):
    """One node tick's results (``tick``): views into the solver's arrays, valid until its next call."""

    count: int  # end-tension samples drained by this tick (one per substep; the newest ring capacity kept)
    samples: np.ndarray  # (3, >= count): rows t (s), T_ship (N), T_vehicle (N); the first count columns
    loads: np.ndarray  # (2, >= N_LOAD): per end (0 ship, 1 vehicle) the columns LOAD_F, LOAD_T, LOAD_M
    substeps: int = 0  # substeps taken (advance_to's return)

    @property
    def times(self):
        return self.samples[0, :self.count]

    @property
    def ship_tension(self):
        return self.samples[1, :self.count]

    @property
    def vehicle_tension(self):
        return self.samples[2, :self.count]

    def end_forces(self) -> "EndForces":
        """The loads as an :class:`EndForces` (copies)."""
        f = self.loads
        return EndForces(ship_force=f[0, LOAD_F:LOAD_F + 3].copy(), vehicle_force=f[1, LOAD_F:LOAD_F + 3].copy(),
                         ship_moment=f[0, LOAD_M:LOAD_M + 3].copy(), vehicle_moment=f[1, LOAD_M:LOAD_M + 3].copy(),
                         ship_tension=float(f[0, LOAD_T]), vehicle_tension=float(f[1, LOAD_T]))


def compose_tick(solver, t, ship=None, vehicle=None, drain=True) -> TickOutput:
    """``tick`` as the composition of the interface's calls (the reference the DG solver's compiled
    tick is tested against; the implementation of solvers without a compiled one)."""
    for end, motion in (("ship", ship), ("vehicle", vehicle)):
        if motion is not None:
            position, velocity = motion
            solver.set_end_motion(end, position, velocity)
    substeps = solver.advance_to(t)
    if drain:
        times, t_ship, t_vehicle = solver.drain_end_tensions()
        samples = np.vstack([np.asarray(times, float), np.asarray(t_ship, float), np.asarray(t_vehicle, float)])
    else:
        samples = np.zeros((3, 0))
    f = solver.end_forces()
    loads = np.zeros((2, N_LOAD))
    for e, (force, tension, moment) in enumerate(((f.ship_force, f.ship_tension, f.ship_moment),
                                                   (f.vehicle_force, f.vehicle_tension, f.vehicle_moment))):
        loads[e, LOAD_F:LOAD_F + 3] = force
        loads[e, LOAD_T] = tension
        loads[e, LOAD_M:LOAD_M + 3] = moment
    return TickOutput(samples.shape[1], samples, loads, substeps)


@runtime_checkable
class TetherSolver(Protocol):
    """What every tether solver provides."""

    name: str  # "dg" or "hybrid"
    time: float  # current simulated time, s

    def set_end_motion(self, end: str, position, velocity) -> None: ...

    def set_end_load(self, end: str, force, moment=(0.0, 0.0, 0.0)) -> None: ...

    def stable_time_step(self) -> float: ...

    def step(self, dt: float) -> None: ...

    def advance_to(self, t: float) -> int: ...

    def state(self, arc_lengths=None) -> SolverState: ...

    def end_forces(self) -> EndForces: ...

    def body_state(self, end: str) -> BodyState | None: ...

    def drain_end_tensions(self) -> tuple: ...  # (t (k,), T_ship (k,), T_vehicle (k,))

    def tick(self, t: float, ship=None, vehicle=None, drain: bool = True) -> TickOutput: ...

    def snapshot(self) -> object: ...

    def restore(self, snap: object) -> None: ...


END_INDEX = {name: k for k, name in enumerate(END_NAMES)}


def end_index(end: str) -> int:
    """0 for the ship end (s = 0), 1 for the vehicle end (s = L); ValueError otherwise."""
    try:
        return END_INDEX[end]
    except KeyError:
        raise ValueError(f"unknown end {end!r}; expected 'ship' or 'vehicle'") from None


def shortest_element(solver, config) -> float:
    """The shortest element (DG: the workspace's element sizes) or segment (hybrid: length / segments) of a running
    solver, m: the snap guard's crossing time is this over the axial wave speed."""
    ws = getattr(solver, "ws", None)
    h = getattr(ws, "h", None) if ws is not None else getattr(solver, "h", None)
    if h is not None and np.size(h):
        return float(np.min(h))
    n = getattr(solver, "n_seg", None) or getattr(config.hybrid, "n_segments", 1)
    return float(config.cable.length) / max(int(n), 1)


def _floats(x) -> list:
    """The components of a small vector as Python floats (``tolist`` for a float array: the values
    ``float()`` gives, a fraction of the calls)."""
    if type(x) is np.ndarray and x.dtype == np.float64:
        return x.tolist()
    return [float(c) for c in x]


def lazy_relative_end_speed(solver, length: float, state=None):
    """:func:`relative_end_speed` as a function of no arguments, computed at its first call and kept: what the
    drivers hand ``SnapDetector.update``, which reads it only while a location is out of its taut state
    (the same events as with the number). ``state``: as there, or a function of no arguments that
    returns it (called then too)."""
    memo = []

    def speed():
        if not memo:
            memo.append(relative_end_speed(solver, length, state() if callable(state) else state))
        return memo[0]
    return speed


def relative_end_speed(solver, length: float, state=None) -> float:
    """|v(0) - v(L)|: the relative speed of the two cable ends now, m/s (the snap guard's speed;
    ``length`` is the unstretched length, a winch's current one where there is a winch).

    A body end moves with its body (v + omega x (P - CoG) at the attachment point P, the cable end),
    not with the cable's end trace, which a collapsed end element can corrupt; other ends with the
    cable's end velocity (at a prescribed or fixed end its boundary motion).

    ``state``: the solver's state() now, sampled from s = 0 to s = L (a node's output points): its
    first and last samples are the ends' (the same numbers: the sampling is point by point), read
    instead of sampling again where the solver gives its end bodies (``end_bodies``, DG)."""
    L = float(getattr(solver, "unstretched_length", length))
    kinematics = getattr(solver, "end_kinematics", None)
    end_bodies = getattr(solver, "end_bodies", None)
    if state is not None and end_bodies is not None and state.arc_length.size > 1 and state.arc_length[0] == 0.0 and state.arc_length[-1] == L:
        position, velocity, bodies = state.position[0::state.position.shape[0] - 1], \
            state.velocity[0::state.velocity.shape[0] - 1], end_bodies()
    elif kinematics is not None:  # the same numbers without the rest of the state (DG)
        position, velocity, bodies = kinematics(np.array([0.0, L]))
    else:
        state = solver.state(np.array([0.0, L]))
        position, velocity = state.position, state.velocity
        bodies = tuple((b.position, b.velocity, b.angular_velocity) if b is not None else None
                       for b in (solver.body_state(end) for end in END_NAMES))
    v = np.array(velocity, float)
    for j, body in enumerate(bodies):
        if body is not None:  # v + omega x arm in plain floats (np.cross costs ~15 us on 3-vectors; same operations)
            (px, py, pz), (bx, by, bz) = _floats(position[j]), _floats(body[0])
            ax, ay, az = px - bx, py - by, pz - bz
            wx, wy, wz = _floats(body[2])
            ux, uy, uz = _floats(body[1])
            v[j] = (ux + (wy * az - wz * ay), uy + (wz * ax - wx * az), uz + (wx * ay - wy * ax))
    d = v[0] - v[1]
    return math.sqrt(float(d.dot(d)))  # = np.linalg.norm(d), which computes sqrt(d.dot(d))
