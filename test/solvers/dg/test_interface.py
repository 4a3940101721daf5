"""DGCableSolver honours the TetherSolver contract (solvers/base.py) on small, fast cases."""

import numpy as np
import pytest

from tether_sim.config import SimConfig
from tether_sim.errors import SolverDivergedError, UnstableTimeStepError
from tether_sim.physics.boundary import EndCondition
from tether_sim.physics.cable import CableProperties
from tether_sim.physics.environment import Environment
from tether_sim.solvers.base import TetherSolver
from tether_sim.solvers.config import DGOptions, InitialState
from tether_sim.solvers.dg.solver import DGCableSolver
from tether_sim.solvers.factory import build_solver


def small_config(ship="prescribed", vehicle="fixed", **dg):
    cab = CableProperties(length=50.0, EA=1e5, gamma0=2.0, diameter=0.02, density=4000.0, damping=100.0)
    opts = dict(n_elements=4, order=3)
    opts.update(dg)
    return SimConfig(cable=cab, environment=Environment(),
                     ship_end=EndCondition(kind=ship, position=(0.0, 0.0, 0.0)),
                     vehicle_end=EndCondition(kind=vehicle, position=(30.0, 0.0, -35.0)),
                     dg=DGOptions(**opts), initial=InitialState(kind="static"))


def test_factory_builds_a_protocol_solver():
    s = build_solver(small_config())
    assert isinstance(s, DGCableSolver) and isinstance(s, TetherSolver)
    assert s.name == "dg"


def test_prescribed_end_goes_exactly_where_told_and_other_end_stays():
    s = DGCableSolver(small_config())
    for k in range(1, 11):
        t = 0.05 * k
        p = np.array([0.3 * np.sin(2 * t), 0.1 * t, 0.2 * np.sin(3 * t)])
        v = np.array([0.6 * np.cos(2 * t), 0.1, 0.6 * np.cos(3 * t)])
        s.set_end_motion("ship", p, v)
        n = s.advance_to(t)
        assert n >= 1 and s.time == t
        st = s.state(np.array([0.0, 50.0]))
        # the anchor end is set to the Hermite end point exactly after each substep
        assert np.array_equal(st.position[0], p)
        # the far end follows from int q ds, conserved by the DG fluxes: round-off only
        assert np.allclose(st.position[1], [30.0, 0.0, -35.0], atol=1e-9)


def test_drain_end_tensions_returns_every_substep_once():
    s = DGCableSolver(small_config())
    n1 = s.advance_to(0.02)
    n2 = s.advance_to(0.05)
    t, T0, T1 = s.drain_end_tensions()
    assert t.size == n1 + n2 and np.all(np.diff(t) > 0) and t[0] == 0.0
    # a hanging cable: both end tensions positive, ship end (higher) carries more than the weight share
    assert np.all(T0 > 0) and np.all(T1 > 0)
    assert s.drain_end_tensions()[0].size == 0


def test_end_forces_balance_weight_at_rest():
    cfg = small_config(ship="fixed", n_elements=8, order=4)
    s = DGCableSolver(cfg)
    f = s.end_forces()
    cab, env = cfg.cable, cfg.environment
    w = env.g * (cab.gamma0 - env.fluid_density * cab.area) * cab.length
    total = f.ship_force + f.vehicle_force
    # static state: the ends carry the submerged weight; the catenary parameter H/w = 14 m is
    # comparable to h = 6 m, and N = 8, P = 4 resolves the end forces to ~1e-4 of the weight
    assert np.allclose(total, [0.0, 0.0, -w], rtol=0, atol=1e-3 * w)


def test_snapshot_restore_reproduces_the_run():
    s = DGCableSolver(small_config(ship="fixed"))
    s.advance_to(0.01)
    snap = s.snapshot()
    s.advance_to(0.05)
    a = s.state().position.copy()
    s.restore(snap)
    s.advance_to(0.05)
    assert np.array_equal(a, s.state().position)


def test_fixed_time_step_above_limit_is_refused():
    with pytest.raises(UnstableTimeStepError, match="fixed_time_step"):
        DGCableSolver(small_config(fixed_time_step=1.0))
    s = DGCableSolver(small_config())
    with pytest.raises(UnstableTimeStepError):
        s.step(10.0)


def test_wrong_end_kind_and_bad_input_are_clear_errors():
    s = DGCableSolver(small_config())
    with pytest.raises(ValueError, match="not 'prescribed'"):
        s.set_end_motion("vehicle", (0, 0, 0), (0, 0, 0))
    with pytest.raises(ValueError, match="not 'force'"):
        s.set_end_load("ship", (0, 0, 1))
    with pytest.raises(ValueError, match="non-finite"):
        s.set_end_motion("ship", (np.nan, 0, 0), (0, 0, 0))
    with pytest.raises(ValueError, match="unknown end"):
        s.set_end_motion("cage", (0, 0, 0), (0, 0, 0))


def test_non_finite_state_raises_diverged():
    s = DGCableSolver(small_config())
    s.ws.U[1, 0, 4] = np.nan
    with pytest.raises(SolverDivergedError):
        s.advance_to(0.01)


def test_free_end_hangs_and_force_end_carries_its_load():
    cfg = small_config(ship="fixed", vehicle="force")
    s = DGCableSolver(cfg)
    s.set_end_load("vehicle", (0.0, 0.0, -500.0))
    s.advance_to(0.05)
    f = s.end_forces()
    # T_hat = n F_BC at a force end: the cable pulls the load point up by exactly the load
    assert np.allclose(f.vehicle_force, [0.0, 0.0, 500.0])


def test_outputs_evaluated_inside_the_tick_equal_a_fresh_evaluation():
    """Once outputs are read, the compiled tick evaluates them at its end (tick.dg_tick): a solver
    read every tick and one read only at the end give the same bits, and a ring that wrapped keeps
    the newest entries in time order."""
    a = DGCableSolver(small_config(vehicle="body", tension_buffer=16))
    b = DGCableSolver(small_config(vehicle="body", tension_buffer=16))
    for k in range(1, 6):
        t = 0.03 * k
        p, v = np.array([0.2 * np.sin(4 * t), 0.0, 0.1 * t]), np.array([0.8 * np.cos(4 * t), 0.0, 0.1])
        for s in (a, b):
            s.set_end_motion("ship", p, v)
            s.advance_to(t)
        assert a._outputs_valid == (k > 1)  # from the second tick on the tick itself evaluated them
        assert not b._outputs_valid
        st, ef, bs = a.state(), a.end_forces(), a.body_state("vehicle")
    sb, eb, bb = b.state(), b.end_forces(), b.body_state("vehicle")
    for name in ("position", "velocity", "tension", "strain", "curvature", "bending_moment"):
        assert np.array_equal(getattr(st, name), getattr(sb, name))
    assert np.array_equal(ef.vehicle_force, eb.vehicle_force) and ef.ship_tension == eb.ship_tension
    assert np.array_equal(bs.acceleration, bb.acceleration)
    t_a, ship_a, _ = a.drain_end_tensions()
    assert t_a.size == 16 and np.all(np.diff(t_a) > 0) and t_a[-1] < 0.15  # the newest 16 substep starts
    assert np.array_equal(t_a, b.drain_end_tensions()[0])


def test_body_pose_is_the_body_states_position_and_orientation():
    """body_pose (what the node's outputs read of a body end) gives body_state's two arrays bit for bit, as
    copies, at every tick of a driven run; None for an end that is no body."""
    s = DGCableSolver(small_config(vehicle="body"))
    for k in range(1, 6):
        t = 0.03 * k
        s.set_end_motion("ship", np.array([0.2 * np.sin(4 * t), 0.0, 0.1 * t]), np.array([0.8 * np.cos(4 * t), 0.0, 0.1]))
        s.advance_to(t)
        pose, full = s.body_pose("vehicle"), s.body_state("vehicle")
        assert pose.position.tobytes() == full.position.tobytes()
        assert pose.orientation.tobytes() == full.orientation.tobytes()
        pose.position[:] = 0.0  # a copy: the solver's body state is not touched
        assert s.body_state("vehicle").position.tobytes() == full.position.tobytes()
    assert s.body_pose("ship") is None
