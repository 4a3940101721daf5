"""The snap guard's relative end speed (solvers/base.relative_end_speed): a body end moves with its
body, v + omega x (P - CoG) at the attachment point P, the other end with the cable's end velocity.
Checked against the numpy formula it replaced (np.cross, np.linalg.norm) to the last bit, and
against a hand-computed rigid rotation."""

import numpy as np

from tether_sim.solvers.base import BodyState, SolverState, relative_end_speed


class FakeSolver:
    """state() at [0, L] and a vehicle body with the given motion."""

    def __init__(self, position=None, velocity=None, body=None):
        self.position, self.velocity, self.body = position, velocity, body

    def state(self, arc_lengths):
        return SolverState(time=0.0, arc_length=np.asarray(arc_lengths, float), position=self.position,
                           velocity=self.velocity, tension=np.zeros(2), strain=np.zeros(2), curvature=np.zeros(2),
                           bending_moment=np.zeros(2), time_step=1e-3)

    def body_state(self, end):
        return self.body if end == "vehicle" else None


def _numpy_formula(solver, length):
    state = solver.state(np.array([0.0, length]))
    v = np.array(state.velocity, float)
    body = solver.body_state("vehicle")
    arm = np.asarray(state.position[1], float) - np.asarray(body.position, float)
    v[1] = np.asarray(body.velocity, float) + np.cross(np.asarray(body.angular_velocity, float), arm)
    return float(np.linalg.norm(v[0] - v[1]))


def test_equals_the_numpy_formula_bit_for_bit():
    rng = np.random.default_rng(3)
    for _ in range(200):
        scale = 10.0 ** rng.uniform(-6, 3)
        body = BodyState(position=rng.normal(size=3) * 100, orientation=np.array([0.0, 0.0, 0.0, 1.0]),
                         velocity=rng.normal(size=3) * scale, angular_velocity=rng.normal(size=3) * scale,
                         acceleration=np.zeros(3))
        solver = FakeSolver(position=rng.normal(size=(2, 3)) * 100, velocity=rng.normal(size=(2, 3)) * scale, body=body)
        assert relative_end_speed(solver, 200.0) == _numpy_formula(solver, 200.0)


def test_rigid_rotation_of_the_body():
    """Body at rest at the origin spinning at 0.5 rad/s about z, attachment 2 m along x: the vehicle
    end moves at 1 m/s along y; the ship end moves at 1 m/s along x: |(1, -1, 0)| = sqrt(2)."""
    body = BodyState(position=np.zeros(3), orientation=np.array([0.0, 0.0, 0.0, 1.0]), velocity=np.zeros(3),
                     angular_velocity=np.array([0.0, 0.0, 0.5]), acceleration=np.zeros(3))
    solver = FakeSolver(position=np.array([[0.0, 0.0, 100.0], [2.0, 0.0, 0.0]]),
                        velocity=np.array([[1.0, 0.0, 0.0], [9.0, 9.0, 9.0]]), body=body)  # (the cable's end trace is ignored)
    assert abs(relative_end_speed(solver, 100.0) - np.sqrt(2.0)) < 1e-15


def test_dg_end_kinematics_are_the_state_and_body_state_numbers():
    """The DG solver's lean path (end_kinematics: the cable's ends and the bodies without the rest of
    the state) gives relative_end_speed the numbers of state() and body_state(), bit for bit: the 1730 m
    live file (a body at the vehicle end) after its ship end was moved."""
    from tether_sim.io.params import load_config
    from tether_sim.solvers.factory import build_solver

    solver = build_solver(load_config("config/ropos_L1730.yaml"))
    p0 = np.array(solver.state(np.array([0.0])).position[0], float)
    for k in range(1, 6):
        t = 0.1 * k
        solver.tick(t, ship=(p0 + np.array([0.0, 0.0, 0.5 * np.sin(t)]), np.array([0.0, 0.0, 0.5 * np.cos(t)])))

    class StateOnly:  # the same solver seen through state() and body_state() only
        unstretched_length = solver.unstretched_length
        state, body_state = solver.state, solver.body_state

    L = solver.unstretched_length
    pos, vel, bodies = solver.end_kinematics(np.array([0.0, L]))
    state = solver.state(np.array([0.0, L]))
    assert np.array_equal(pos, state.position) and np.array_equal(vel, state.velocity)
    body = solver.body_state("vehicle")
    assert bodies[0] is None and solver.body_state("ship") is None
    assert all(np.array_equal(a, b) for a, b in zip(bodies[1], (body.position, body.velocity, body.angular_velocity)))
    speed = relative_end_speed(solver, 1730.0)
    assert speed == relative_end_speed(StateOnly(), 1730.0) and speed > 0.0
