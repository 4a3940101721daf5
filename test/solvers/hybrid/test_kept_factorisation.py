"""Simplified Newton across steps (hybrid.reuse_factorisation, docs/hybrid_solver.md "Solving a step").

A step starts with the factorised, row-equilibrated iteration matrix of the last step while the chain (zones, joints,
ends) and the step's parameters (step size, rho_inf) are the same, and refactorises by the rule used within a step
(the scaled residual must fall by 10x per iteration); a step that fails with a kept factorisation starts again with a
fresh Jacobian. The converged step solves the same residual to the same stopping test (every update below
newton_tolerance x its variable's scale), so the states of both ways agree to the size of the tolerance, not to
the size of any physics. Both Newton paths: the compiled one (analytic Jacobian) and its Python twin.
"""

from dataclasses import replace

import numpy as np
import pytest

import tether_sim.solvers.hybrid.solver as hybrid_solver
from benchmarks.ropos_case import ropos_config
from tether_sim.solvers.hybrid.solver import HybridRodCatenarySolver

STEPS = 20


def _solver(jacobian, reuse):
    """ROPOS L = 200 m with the cage as a body, 20 elements, taut (all catenary)."""
    cfg = ropos_config(200.0, alpha=1.0, solver="hybrid", hybrid_segments=20, hybrid_dt=0.01)
    return HybridRodCatenarySolver(replace(cfg, hybrid=replace(cfg.hybrid, zoning="adaptive", static_relax_time=5.0,
                                                               jacobian=jacobian, reuse_factorisation=reuse)))


def _drive(s, steps, dt=0.01):
    """A moving fairlead (0.5 m circle at 1 rad/s), one step of dt per call."""
    p0 = np.asarray(s.config.ship_end.position, dtype=float)
    for _ in range(steps):
        t = s.time + dt
        s.set_end_motion("ship", p0 + 0.5 * np.array([np.sin(t), 0.0, 1.0 - np.cos(t)]),
                         0.5 * np.array([np.cos(t), 0.0, np.sin(t)]))
        s.advance_to(t)


@pytest.mark.parametrize("jacobian", ["analytic", "finite_difference"])
def test_steps_keep_the_factorisation(jacobian):
    """Fails where every step refactorises: without the option each of 20 steps (after 30 from the start) computes
    at least one Jacobian; with it, most steps converge on the kept one (measured 2026-11-29: 30 Jacobians and 107
    iterations without, 7 and 124 with, both paths)."""
    counts = []
    for reuse in (False, True):
        s = _solver(jacobian, reuse)
        _drive(s, 30)
        j0, n0 = s.stats.get("jacobians", 0), s.stats["steps"]
        _drive(s, STEPS)
        assert s.stats["steps"] - n0 == STEPS and s.stats["halvings"] == 0
        assert s.end_forces().ship_tension > 1e4  # taut
        counts.append(s.stats["jacobians"] - j0)
        assert s.stats.get("kept_factorisation_failures", 0) == 0
    fresh, kept = counts
    assert fresh >= STEPS
    assert kept <= STEPS // 2, counts


@pytest.mark.parametrize("jacobian", ["analytic", "finite_difference"])
def test_same_converged_steps_as_fresh_jacobians(jacobian):
    """Both stop at |dx| <= 1e-9 x scale on the same residual. With a kept factorisation the iterations contract
    by at least 10x (else it is refactorised), so the remaining error is below ~0.1 x the last update: the states
    agree to ~1e-9 relative (asserted 1e-7 relative; a result of different physics, e.g. a missing update of the
    end conditions between steps, differs by 1e-3 and more)."""
    out = []
    for reuse in (False, True):
        s = _solver(jacobian, reuse)
        _drive(s, STEPS)
        out.append((s.end_forces(), s.state()))
    (fa, sa), (fb, sb) = out
    assert abs(fa.ship_tension - fb.ship_tension) <= 1e-7 * fb.ship_tension
    assert abs(fa.vehicle_tension - fb.vehicle_tension) <= 1e-7 * fb.vehicle_tension
    assert np.abs(sa.position - sb.position).max() <= 1e-7 * 200.0
    assert np.abs(sa.velocity - sb.velocity).max() <= 1e-7 * np.abs(sb.velocity).max()
    assert np.abs(sa.tension - sb.tension).max() <= 1e-7 * np.abs(sb.tension).max()


@pytest.mark.parametrize("jacobian", ["analytic", "finite_difference"])
def test_a_new_step_size_or_chain_starts_with_a_fresh_jacobian_a_restore_does_not(monkeypatch, jacobian):
    """The kept factorisation belongs to one chain and one step size: after a step of another size, or on a new chain
    (as a re-zoning builds), the first iteration uses a fresh Jacobian; a snapshot carries it, so that a restored run
    repeats the run it was taken from bit for bit (test_solver_interface). Recorded per step: did it start with a kept
    factorisation."""
    started_kept = []
    if jacobian == "analytic":
        compiled = hybrid_solver.newton_band

        def newton_band(*args):
            started_kept.append(bool(args[-2][0]))
            return compiled(*args)

        monkeypatch.setattr(hybrid_solver, "newton_band", newton_band)
    else:
        twin, iterations = HybridRodCatenarySolver._newton_python, HybridRodCatenarySolver._newton_iterations

        def newton_python(self, *args):
            self.first_attempt = True
            return twin(self, *args)

        def newton_iterations(self, *args):
            if self.first_attempt:
                started_kept.append(args[-1] is not None)
                self.first_attempt = False
            return iterations(self, *args)

        monkeypatch.setattr(HybridRodCatenarySolver, "_newton_python", newton_python)
        monkeypatch.setattr(HybridRodCatenarySolver, "_newton_iterations", newton_iterations)
    s = _solver(jacobian, True)
    _drive(s, 3)
    del started_kept[:]
    _drive(s, 2)
    _drive(s, 2, dt=0.005)
    s.restore(s.snapshot())  # the snapshot carries the factorisation: a restored run takes the run's Newton path
    _drive(s, 1, dt=0.005)
    s._set_chain()  # a new chain, as a re-zoning builds
    _drive(s, 1, dt=0.005)
    assert started_kept == [True, True, False, True, True, False]

