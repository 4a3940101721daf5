"""The hybrid solver implements tether_sim.solvers.base.TetherSolver (contract in its docstring)."""

from dataclasses import replace

import numpy as np
import pytest

from tether_sim.errors import ConfigError, SolverDivergedError
from tether_sim.scenarios.goyal_perkins import goyal_perkins_config
from tether_sim.solvers.base import TetherSolver
from tether_sim.solvers.factory import build_solver
from tether_sim.solvers.hybrid.solver import HybridRodCatenarySolver


def small_config(**hybrid):
    cfg = goyal_perkins_config(zoning="fixed", n_segments=20)
    return replace(cfg, hybrid=replace(cfg.hybrid, time_step=0.25, **hybrid))


def test_factory_builds_a_tether_solver():
    solver = build_solver(small_config())
    assert isinstance(solver, HybridRodCatenarySolver) and isinstance(solver, TetherSolver)
    assert solver.name == "hybrid" and solver.stable_time_step() == 0.25


def test_advance_to_substeps_state_and_drained_tensions():
    solver = HybridRodCatenarySolver(small_config())
    n = solver.advance_to(1.1)  # 4 full steps + one short one lands exactly on the target
    assert n == 5 and solver.time == pytest.approx(1.1, abs=1e-12)
    t, T0, T1 = solver.drain_end_tensions()
    # one record per implicit step, including steps halved after a failed Newton solve
    assert t.shape == T0.shape == T1.shape == (solver.stats["steps"],) and t.size >= n and t[-1] == pytest.approx(1.1)
    assert solver.drain_end_tensions()[0].size == 0
    st = solver.state()
    n_out = solver.config.node.output_points
    assert st.position.shape == (n_out, 3) and st.tension.shape == (n_out,)
    assert set(np.unique(st.extra["zone"])) == {0, 1}
    assert np.all(st.extra["zone"][st.arc_length < 1.5 - 1e-9] == 0)
    assert np.all(st.bending_moment[st.extra["zone"] == 0] == 0.0)
    ef = solver.end_forces()
    assert np.allclose(ef.vehicle_force, -np.asarray(solver.config.vehicle_end.force), atol=1e-12)
    assert ef.ship_tension == pytest.approx(st.tension[0])
    assert solver.body_state("vehicle") is None



def test_state_fields_are_np_interp_of_the_profile():
    """state() at any points: each field the np.interp of its node_profile column (the compiled many-column pass is
    held to numpy's numbers bit for bit), on a chain with rod and catenary zones (joint nodes share an arc length),
    at grid values, between them and outside the cable; a second call on the same state gives the same numbers."""
    solver = HybridRodCatenarySolver(small_config())
    solver.advance_to(1.0)
    prof = solver._profile()
    xp = prof["s"]
    assert np.any(np.diff(xp) == 0.0)  # a joint: a repeated arc length
    pts = np.concatenate([np.linspace(-1.0, solver.length + 1.0, 97), xp, [solver.length * 0.3371]])
    for s in (pts, np.array([0.0, solver.length])):
        for st in (solver.state(s), solver.state(s)):
            fields = {"position": st.position, "velocity": st.velocity, "shear": st.extra["shear"],
                      "torsion": st.extra["torsion_moment"], "tension": st.tension, "strain": st.strain,
                      "curvature": st.curvature, "moment": st.bending_moment}
            for name, got in fields.items():
                col = prof[name]
                want = np.stack([np.interp(s, xp, col[:, k]) for k in range(3)], axis=1) if col.ndim == 2 else \
                    np.interp(s, xp, col)
                assert got.shape == want.shape and np.ascontiguousarray(got).tobytes() == want.tobytes(), name

def test_snapshot_restore_reproduces_the_run():
    solver = HybridRodCatenarySolver(small_config())
    solver.advance_to(0.5)
    snap = solver.snapshot()
    solver.advance_to(1.5)
    first = solver.state().position.copy()
    solver.restore(snap)
    assert solver.time == 0.5
    solver.advance_to(1.5)
    assert np.array_equal(solver.state().position, first)


def test_prescribed_end_follows_hermite_motion():
    cfg = small_config()
    cfg = replace(cfg, ship_end=replace(cfg.ship_end, kind="prescribed"))
    solver = HybridRodCatenarySolver(cfg)
    solver.set_end_motion("ship", (0.01, 0.0, 0.0), (0.02, 0.0, 0.0))
    solver.advance_to(1.0)
    st = solver.state()
    assert np.allclose(st.position[0], [0.01, 0.0, 0.0], atol=1e-5)  # trapezoid of the Hermite velocity
    assert np.allclose(st.velocity[0], [0.02, 0.0, 0.0], atol=1e-12)


def test_non_finite_state_raises_diverged():
    solver = HybridRodCatenarySolver(small_config())
    solver.Y[3, 3] = np.nan
    with pytest.raises(SolverDivergedError):
        solver.advance_to(0.25)


def test_rod_zoning_without_bending_stiffness_is_a_config_error():
    cfg = small_config()
    with pytest.raises(ConfigError, match="EI"):
        HybridRodCatenarySolver(replace(cfg, cable=replace(cfg.cable, EI=0.0)))
    with pytest.raises(ValueError):
        HybridRodCatenarySolver(cfg).set_end_load("cage", (0, 0, 0))
