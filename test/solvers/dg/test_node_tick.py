"""The one-call node tick (solver.tick, dg/tick.node_tick) against the composition it replaces.

``tick(t, ship=(p, v))`` must give, bit for bit, what set_end_motion + advance_to +
drain_end_tensions + end_forces give (base.compose_tick): the same compiled stepper runs in both,
so any difference would be a bookkeeping error (targets, outputs, drain). Checked on the ROPOS
cable driven by the benchmark's fairlead orbit through its first snap (slack and re-tension), with
and without bending, then the state after the run. Marked ``jit_off``: the same assertions hold
with the kernels interpreted (a shorter run there).
"""

import os

import numpy as np
import pytest

from benchmarks import ropos_case as rc
from tether_sim.errors import SolverDivergedError
from tether_sim.solvers import factory
from tether_sim.solvers.base import LOAD_F, LOAD_M, LOAD_T, compose_tick

pytestmark = pytest.mark.jit_off
JIT_OFF = os.environ.get("NUMBA_DISABLE_JIT") == "1"


def pair(length, alpha, n, order):
    cfg = rc.ropos_config(length, alpha=alpha, n_elements=n, order=order, cfl=0.8)
    a, b = factory.build_solver(cfg), factory.build_solver(cfg)
    a.drain_end_tensions()
    b.drain_end_tensions()
    return a, b


@pytest.mark.parametrize("length,alpha,n,order", [(200.0, 0.0, 2, 4), (200.0, 1.0, 2, 4), (1730.0, 1.0, 6, 2)])
def test_tick_equals_the_composition_bit_for_bit(length, alpha, n, order):
    fast, ref = pair(length, alpha, n, order)
    ticks = 15 if JIT_OFF else 400  # 8 s at 50 Hz: the orbit ramps up and the cage goes slack and snaps
    peak, static = 0.0, None
    for k in range(ticks):
        t1 = (k + 1) / 50.0
        motion = rc.fairlead_motion(t1)
        out = fast.tick(t1, ship=motion)
        want = compose_tick(ref, t1, ship=motion)
        assert out.count == want.count > 0
        static = out.vehicle_tension[0] if static is None else static
        np.testing.assert_array_equal(out.samples[:, :out.count], want.samples)
        np.testing.assert_array_equal(out.loads[:, :7], want.loads)
        peak = max(peak, float(out.ship_tension.max()), float(out.vehicle_tension.max()))
    assert fast.time == ref.time
    np.testing.assert_array_equal(fast.state().position, ref.state().position)
    np.testing.assert_array_equal(fast.state().tension, ref.state().tension)
    if not JIT_OFF:  # the run went through a snap (the first peak is ~2.3x the static cage weight)
        assert peak > 1.5 * static
    # the loads are the end forces of the interface, in the documented columns
    f = fast.end_forces()
    np.testing.assert_array_equal(out.loads[0, LOAD_F:LOAD_F + 3], f.ship_force)
    np.testing.assert_array_equal(out.loads[1, LOAD_M:LOAD_M + 3], f.vehicle_moment)
    assert out.loads[1, LOAD_T] == f.vehicle_tension


def test_tick_without_drain_keeps_the_samples_for_the_next_drain():
    fast, ref = pair(200.0, 0.0, 2, 4)
    for k in range(3):
        t1 = (k + 1) / 50.0
        out = fast.tick(t1, ship=rc.fairlead_motion(t1), drain=False)
        assert out.count == 0
        ref.set_end_motion("ship", *rc.fairlead_motion(t1))
        ref.advance_to(t1)
    t, ship, vehicle = fast.drain_end_tensions()
    t_ref, ship_ref, vehicle_ref = ref.drain_end_tensions()
    np.testing.assert_array_equal(ship, ship_ref)
    np.testing.assert_array_equal(t, t_ref)


def test_each_tick_result_says_its_own_count_and_substeps():
    """tick() gives its previous result again when the count and the substeps repeat (the arrays are the
    workspace's views): with the drain skipped every third tick and intervals of two lengths, each result
    must still carry that tick's count, substeps and samples."""
    fast, ref = pair(1730.0, 0.0, 6, 2)
    t1 = 0.0
    for k in range(9):
        t1 += 0.02 if k < 5 else 0.005
        drain = k % 3 != 1
        out = fast.tick(t1, ship=rc.fairlead_motion(t1), drain=drain)
        ref.set_end_motion("ship", *rc.fairlead_motion(t1))
        n = ref.advance_to(t1)
        assert out.substeps == n > 0
        if drain:
            want = ref.drain_end_tensions()
            assert out.count == want[0].size > 0
            np.testing.assert_array_equal(out.samples[:, :out.count], np.array(want))
        else:
            assert out.count == 0
        np.testing.assert_array_equal(out.loads[0, LOAD_F:LOAD_F + 3], ref.end_forces().ship_force)


def test_tick_rejects_bad_input_and_leaves_the_solver_unchanged():
    fast, _ = pair(200.0, 0.0, 2, 4)
    fast.tick(0.02, ship=rc.fairlead_motion(0.02))
    before = fast.ws.U.copy()
    p, v = rc.fairlead_motion(0.04)
    with pytest.raises(ValueError, match="non-finite position or velocity for the ship end"):
        fast.tick(0.04, ship=(p, np.array([0.0, np.nan, 0.0])))
    with pytest.raises(ValueError, match="3 numbers each"):
        fast.tick(0.04, ship=(p[:2], v))
    with pytest.raises(ValueError, match="vehicle end is 'body', not 'prescribed'"):
        fast.tick(0.04, vehicle=(p, v))
    with pytest.raises(ValueError, match="before the current time"):
        fast.tick(0.01, ship=(p, v))
    assert fast.time == 0.02
    np.testing.assert_array_equal(fast.ws.U, before)
    out = fast.tick(0.04, ship=(p, v))  # and it goes on
    assert out.count > 0 and np.all(np.isfinite(out.loads))


def test_tick_reports_a_divergence_like_advance_to():
    fast, _ = pair(200.0, 0.0, 2, 4)
    p, v = rc.fairlead_motion(0.02)
    with pytest.raises(SolverDivergedError, match="non-finite"):
        fast.tick(0.02, ship=(p + np.array([0.0, 0.0, 1e12]), v))  # a jump of 1e12 m in one tick
