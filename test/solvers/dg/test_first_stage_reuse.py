"""The output evaluation reused as the next tick's first stage (tick.py) is the evaluation it replaces.

Two identical solvers take the same ticks and read state() after each, as a node does; in the twin
the kept evaluation is discarded before every tick (``ws.fresh[0] = 0``), so it evaluates the first
stage in full. The states, end loads and drained end tensions must agree bit for bit, and the
reuse must have happened (its counter, ``ws.fresh[1]``). Then inputs of the internal forces are
changed behind the solver's back -- the state, a parameter, an end load, a driven end's state --
and the check of the kept inputs must refuse the reuse (a stale reuse would change the results,
which the twin comparison would see). Marked ``jit_off``: also run with the kernels as Python.
"""

import numpy as np
import pytest

from tether_sim.config import SimConfig
from tether_sim.physics.boundary import EndCondition
from tether_sim.physics.cable import CableProperties
from tether_sim.physics.environment import Environment
from tether_sim.solvers.config import DGOptions, InitialState
from tether_sim.solvers.dg import layout as Y
from tether_sim.solvers.dg.solver import DGCableSolver

pytestmark = pytest.mark.jit_off

TICKS = 6


def solver(vehicle, EI=0.0, N=3, P=3, damping="explicit"):
    """A 60 m cable hanging in water from a prescribed ship end, vehicle end of kind ``vehicle``."""
    cab = CableProperties(length=60.0, EA=2e5, gamma0=3.0, diameter=0.03, density=7000.0, EI=EI, damping=300.0,
                          Cdn=1.2, Cdt=0.05, Cmn=1.0, Cmt=0.3)
    cfg = SimConfig(cable=cab, environment=Environment(g=9.81, fluid_density=1025.0),
                    ship_end=EndCondition(kind="prescribed", position=(0, 0, 0)),
                    vehicle_end=EndCondition(kind=vehicle, position=(20.0, 0, -50.0)),
                    dg=DGOptions(n_elements=N, order=P, damping=damping), initial=InitialState(kind="straight"))
    s = DGCableSolver(cfg)
    if vehicle == "force":
        s.set_end_load("vehicle", (5.0, 0.0, -40.0))
    return s


def ship(t):
    """A small circle of the ship end (position, velocity)."""
    w = 2.0
    return (np.array([0.3 * np.sin(w * t), 0.0, 0.3 * (np.cos(w * t) - 1.0)]),
            np.array([0.3 * w * np.cos(w * t), 0.0, -0.3 * w * np.sin(w * t)]))


def take_tick(s, t, fresh_off):
    if fresh_off:
        s.ws.fresh[0] = 0
    out = s.tick(t, ship=ship(t))
    s.state()
    return out.samples[:, :out.count].copy()


def assert_twins_equal(a, b):
    assert np.array_equal(a.ws.U, b.ws.U)
    assert np.array_equal(a.ws.ra, b.ws.ra)
    assert np.array_equal(a.ws.endf, b.ws.endf)
    assert np.array_equal(a.ws.bs, b.ws.bs)
    sa, sb = a.state(), b.state()
    for k in ("position", "velocity", "tension", "curvature"):
        assert np.array_equal(getattr(sa, k), getattr(sb, k)), k


def run_twins(a, b, ticks, between=None):
    """ticks ticks of both (b without reuse); between(solver, k) runs on both before tick k."""
    step = 3.0 * a._substep()
    counts = []
    for k in range(ticks):
        if between is not None:
            between(a, k)
            between(b, k)
        t = a.time + step
        before = int(a.ws.fresh[1])
        ra, rb = take_tick(a, t, False), take_tick(b, t, True)
        assert np.array_equal(ra, rb)
        counts.append(int(a.ws.fresh[1]) - before)
        assert_twins_equal(a, b)
    assert int(b.ws.fresh[1]) == 0
    return counts


CASES = [dict(vehicle="free", EI=40.0), dict(vehicle="body"), dict(vehicle="force", P=4),
         dict(vehicle="clamped", EI=40.0, N=2)]


@pytest.mark.parametrize("case", CASES, ids=[c["vehicle"] for c in CASES])
def test_reused_first_stage_is_bit_identical_and_happens(case):
    counts = run_twins(solver(**case), solver(**case), TICKS)
    assert counts[1:] == [1] * (TICKS - 1)  # every tick after outputs were read reused them


def _perturb_state(s, k):
    if k == 3:
        s.ws.U[1, 0, 0] += 1e-7  # (a restored snapshot, a set_shape: the work arrays no longer match)


def _perturb_parameter(s, k):
    if k == 3:
        s.ws.prm[Y.P_GAMMA0] *= 1.001  # (read by the internal forces: v = p / gamma0)


def _perturb_end_load(s, k):
    if k == 3:
        s.ws.bc[1, Y.B_F + 2] -= 3.0  # the force end's load, written without set_end_load


def _perturb_driven_end(s, k):
    if k == 3:
        s.ws.ends[0, 5] += 1e-3  # the driven end's velocity, so its kinematics at t0 (the boundary flux) change


def _evaluate_between(s, k):
    if k == 3:
        s._evaluate()  # a full right-hand side overwrites the work arrays (same state)


@pytest.mark.parametrize("between, vehicle", [(_perturb_state, "free"), (_perturb_parameter, "free"),
                                              (_perturb_end_load, "force"), (_perturb_driven_end, "body"),
                                              (_evaluate_between, "free")])
def test_changed_inputs_refuse_the_reuse(between, vehicle):
    counts = run_twins(solver(vehicle, EI=40.0), solver(vehicle, EI=40.0), TICKS, between)
    assert counts[3] == 0  # refused on the tick after the change...
    assert counts[4:] == [1] * (TICKS - 4)  # ...and resumed on the next


def test_not_reused_with_implicit_damping():
    a, b = solver("free", EI=40.0, damping="implicit"), solver("free", EI=40.0, damping="implicit")
    assert run_twins(a, b, 3) == [0, 0, 0]


def test_advance_to_without_outputs_does_not_keep_them():
    s = solver("free")
    for k in range(3):
        s.set_end_motion("ship", *ship(s.time + 0.01))
        s.advance_to(s.time + 0.01)
    assert int(s.ws.fresh[1]) == 0 and int(s.ws.fresh[0]) == 0
