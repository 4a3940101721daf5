"""GP benchmark [GP Sec. 4, Table 1, Fig. 5-8] at ds = 20 mm (the 5 mm run is benchmarks/bench_hybrid.py).

Hybrid (catenary below s_j = 1.5 m, rod above) vs pure rod of the same solver, both relaxed to
rest with dt = 1 s. Acceptance: tension continuous across the joint, zero at the right end; rod-
zone shear and moment within a few percent of the pure rod (measured 4.4 %, largest next to the
joint where the hybrid's moment-free joint forces M = 0 [GP Eq. 12]; tolerance 6 %).
"""

import numpy as np
import pytest

from tether_sim.scenarios.goyal_perkins import END_FORCE, JOINT, goyal_perkins_config, run_to_rest
from tether_sim.solvers.hybrid.solver import HybridRodCatenarySolver
from tether_sim.solvers.hybrid.state_io import node_profile


@pytest.fixture(scope="module")
def profiles():
    out = {}
    for zoning in ("fixed", "all_rod"):
        solver = HybridRodCatenarySolver(goyal_perkins_config(zoning=zoning, n_segments=100))
        run_to_rest(solver, t_max=120.0)
        assert np.abs(solver.state().velocity).max() < 1e-7
        out[zoning] = node_profile(solver)
    return out


def test_tension_continuous_at_joint_and_zero_at_free_end(profiles):
    hyb = profiles["fixed"]
    j = np.nonzero(np.diff(hyb["s"]) == 0.0)[0]
    assert j.size == 1 and hyb["s"][j[0]] == pytest.approx(JOINT)
    # force vector continuous [GP Eq. 14]; the tension differs only through the tangent kink (< 0.5 %)
    # (to the frame re-derivation from kappa after the step, ~1e-4 relative)
    assert np.allclose(hyb["force"][j[0]], hyb["force"][j[0] + 1], rtol=0, atol=1e-3 * END_FORCE)
    assert abs(hyb["tension"][j[0]] - hyb["tension"][j[0] + 1]) < 5e-3 * hyb["tension"][j[0]]
    assert abs(hyb["tension"][-1]) < 1e-12
    assert hyb["shear"][-1] == pytest.approx(END_FORCE, rel=1e-9)  # tension-free end carries the normal force


def test_rod_zone_shear_and_moment_match_pure_rod(profiles):
    hyb, rod = profiles["fixed"], profiles["all_rod"]
    s = np.linspace(JOINT + 1e-9, 2.0, 101)
    for key in ("shear", "moment", "tension"):
        a = np.interp(s, hyb["s"], hyb[key])
        b = np.interp(s, rod["s"], rod[key])
        assert np.abs(a - b).max() < 0.06 * np.abs(b).max(), key
    # catenary zone carries no moment; the pure rod's moment there stays small (GP Fig. 8)
    assert np.all(hyb["moment"][hyb["zone"] == 0] == 0.0)
    assert rod["moment"][rod["s"] < JOINT].max() < 0.2 * rod["moment"].max()


def test_static_equilibrium_of_the_whole_cable(profiles):
    # at rest the pin carries weight minus the end force: f(0) = F_end + (net weight) [GP Eq. 3, 10]
    cfg = goyal_perkins_config()
    w = (cfg.cable.gamma0 - cfg.environment.fluid_density * cfg.cable.area) * cfg.environment.g
    expected = np.asarray(cfg.vehicle_end.force) + np.array([0.0, 0.0, -w * cfg.cable.length])
    for prof in profiles.values():
        assert np.allclose(prof["force"][0], expected, atol=2e-2 * END_FORCE)


def test_parameter_file_matches_the_scenario():
    from pathlib import Path

    from tether_sim.io.params import load_config

    path = Path(__file__).resolve().parents[3] / "config" / "goyal_perkins.yaml"
    cfg = load_config(path)
    ref = goyal_perkins_config()
    for section in ("cable", "environment", "ship_end", "vehicle_end", "hybrid", "initial"):
        assert getattr(cfg, section) == getattr(ref, section), section  # exact float reprs in the file


def test_rod_zone_starts_at_the_joint(profiles):
    # positions are continuous across the joint (the rod shape is integrated from the joint)
    hyb = profiles["fixed"]
    j = np.nonzero(np.diff(hyb["s"]) == 0.0)[0][0]
    assert np.allclose(hyb["position"][j], hyb["position"][j + 1], atol=1e-12)
    step = np.linalg.norm(np.diff(hyb["position"], axis=0), axis=1)
    assert step.max() < 1.01 * (2.0 / 100)  # no gaps: every element is one ds long (inextensible)
