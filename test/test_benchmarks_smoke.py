"""The benchmark case builders produce valid, physically consistent inputs (no timing asserted)."""

import math

import numpy as np
import pytest

from benchmarks import ropos_case as rc
from tether_sim.io.params import from_flat, to_flat


@pytest.mark.parametrize("length,alpha,solver", [(200.0, 0.0, "dg"), (1730.0, 100.0, "dg"), (1730.0, 1.0, "hybrid")])
def test_ropos_config_is_valid(length, alpha, solver):
    """The ROPOS SimConfig survives the validating loader unchanged (every key within bounds)."""
    cfg = rc.ropos_config(length, alpha=alpha, solver=solver)
    assert from_flat(to_flat(cfg)) == cfg
    assert cfg.cable.EI == pytest.approx(alpha * rc.EI_STAR)
    # the cage attachment point hangs L below the fairlead start point
    top = np.array(cfg.ship_end.position)
    attach = np.array(cfg.body.initial_position) + np.array(cfg.body.attachment)
    assert top[2] - attach[2] == pytest.approx(length)


def test_tether_weight_matches_paper():
    """PE2020 Sec. 6.1: the tether weighs 44 kN in water at L = 1730 m (2 significant figures,
    hence the 1.5% tolerance)."""
    assert rc.wet_weight_per_metre() * 1730.0 == pytest.approx(44e3, rel=0.015)


def test_fairlead_motion_velocity_is_derivative_and_orbit_radius():
    """The analytic velocity is the time derivative of the position (central differences, h =
    1e-5 s: truncation ~ a w^3 h^2 ~ 1e-9 m/s); after the ramp the orbit has radius a."""
    h = 1e-5
    for t in (0.0, 1.3, 4.99, 7.7, 33.3):
        p_minus, _ = rc.fairlead_motion(t - h) if t > h else rc.fairlead_motion(t)
        p_plus, _ = rc.fairlead_motion(t + h)
        _, v = rc.fairlead_motion(t)
        fd = (p_plus - p_minus) / (2 * h if t > h else h)
        assert np.allclose(v, fd, atol=1e-4)
    p0, v0 = rc.fairlead_motion(0.0)
    assert np.allclose(v0, 0.0) and p0[2] == pytest.approx(-rc.ORBIT_DEPTH)
    for t in np.linspace(rc.RAMP_TIME, 30.0, 17):
        p, _ = rc.fairlead_motion(t)
        assert math.hypot(p[0], p[2] + rc.ORBIT_DEPTH) == pytest.approx(rc.ORBIT_AMPLITUDE)


def test_moordyn_line_type_gives_same_forces_per_metre():
    """MoorDyn's single diameter is rescaled so that buoyancy, drag and added mass per metre equal
    ours [PE2020 Eq. 13, 14, 17]; BA equals zeta because MoorDyn's damping is BA * deps/dt."""
    lt = rc.moordyn_line_type()
    d_v = lt["diam"]
    assert math.pi / 4 * d_v**2 == pytest.approx(rc.material_area())  # buoyancy volume
    assert lt["Cd"] * d_v == pytest.approx(rc.CDN * rc.DIAMETER)  # normal drag per metre
    assert lt["CdAx"] * math.pi * d_v == pytest.approx(rc.CDT * rc.DIAMETER)  # tangential drag
    assert lt["Ca"] * d_v**2 == pytest.approx(rc.CMN * rc.DIAMETER**2)  # normal added mass
    assert lt["BA"] == rc.ZETA


@pytest.mark.parametrize("cage", ["body", "point"])
def test_moordyn_static_top_tension(tmp_path, cage):
    """MoorDyn's static solve of the generated input carries cable + cage wet weight at the
    fairlead: 48.1 kN at L = 200 m, with the cage as a body or as a point of the same mass and volume.
    Tolerance 0.5%: the lumped end node's half segment and the IC solver's residual (< 1e-3 m/s^2) are
    far smaller."""
    moordyn = pytest.importorskip("moordyn")
    length, n_seg = 200.0, 20
    path = tmp_path / "ropos.txt"
    path.write_text(rc.moordyn_input(length, n_seg, rc.moordyn_time_step(length, n_seg, 0.005), cage=cage))
    system = moordyn.Create(str(path))
    p0, v0 = rc.fairlead_motion(0.0)
    assert moordyn.Init(system, list(p0), list(v0)) == 0
    force = moordyn.Step(system, list(p0), [0.0, 0.0, 0.0], 0.0, 0.005)
    moordyn.Close(system)
    assert np.linalg.norm(force) == pytest.approx(rc.static_ship_tension(length), rel=5e-3)


def test_snap_metrics_on_synthetic_record():
    """Per-period peaks of a known signal: peaks 100 + k at t = 20.5 + 5k (k = 0..7)."""
    t = np.arange(0.0, 60.005, 0.01)
    tension = np.zeros_like(t)
    for k in range(12):
        tension[np.argmin(abs(t - (0.5 + 5 * k)))] = 100.0 + (k - 4)
    m = rc.snap_metrics(t, tension)
    assert m["cycle_peaks"] == pytest.approx([100.0 + k for k in range(8)])
    assert m["mean_peak"] == pytest.approx(103.5)
    assert m["first_peak"] == pytest.approx(97.0)
    assert m["max_peak"] == pytest.approx(107.0)


def _line_type_row(text):
    """{column: value} of the single line type of a MoorDyn input text (header row below the
    LINE TYPES banner, then the units row, then the type row)."""
    lines = text.splitlines()
    i = next(k for k, s in enumerate(lines) if "LINE TYPES" in s)
    header, row = lines[i + 1].split(), lines[i + 3].split()
    assert len(header) == len(row)
    return dict(zip(header, row))


@pytest.mark.parametrize("alpha", [0.0, 1.0])
def test_moordyn_input_carries_bending_stiffness(alpha):
    """The line type's EI column (MoorDyn v2: bending stiffness, N m^2) is alpha * EI_STAR, so
    MoorDyn runs with alpha = 1 bend like the DG cable with EI = EI_STAR."""
    row = _line_type_row(rc.moordyn_input(200.0, 40, 1e-4, alpha=alpha))
    assert row["TypeName"] == "tether"
    assert float(row["EI"]) == pytest.approx(alpha * rc.EI_STAR)
    assert float(row["EA"]) == pytest.approx(rc.EA)


def test_network_moordyn_input_bends_the_excursion_tether_only(monkeypatch):
    """The network cross-check gives MoorDyn the excursion tether's EI in that line type's EI column
    (the same bending stiffness as tether_sim's cable.EI) and leaves the tether's at 0."""
    from benchmarks.studies import network_vs_moordyn as nm

    monkeypatch.setattr(nm, "EXCURSION", nm.EXCURSION)  # restored after the test
    nm.set_excursion_bending(78.125)
    lines = nm.moordyn_input(1e-4).splitlines()
    i = next(k for k, s in enumerate(lines) if "LINE TYPES" in s)
    header = lines[i + 1].split()
    rows = {r.split()[0]: dict(zip(header, r.split())) for r in lines[i + 3:i + 5]}
    assert float(rows["excursion"]["EI"]) == pytest.approx(78.125)
    assert float(rows["tether"]["EI"]) == 0.0
    assert nm.EXCURSION.EI == 78.125 and nm.EXCURSION.bending_damping == 0.0


def test_best_wall_passes_alpha_to_moordyn(monkeypatch, tmp_path):
    """bench_moordyn.best_wall hands its alpha to run_moordyn (default 0: no bending)."""
    from benchmarks import bench_moordyn

    seen = []

    def fake_run(length, n_seg, duration, coupling_step, dt, alpha=0.0, workdir=None, cage="body"):
        seen.append(alpha)
        assert cage == "body"
        return {"step_wall": 1.0, "step_cpu": 0.5}

    monkeypatch.setattr(bench_moordyn, "run_moordyn", fake_run)
    assert bench_moordyn.best_wall(200.0, 40, 1.0, 0.02, 1e-4, tmp_path, 2) == (1.0, 0.5)
    assert bench_moordyn.best_wall(200.0, 40, 1.0, 0.02, 1e-4, tmp_path, 1, alpha=1.0) == (1.0, 0.5)
    assert seen == [0.0, 0.0, 1.0]


def test_moordyn_bending_rungs_table():
    """Errors against the finest N of the same alpha; the bending effect per N."""
    from benchmarks.studies import moordyn_bending_rungs as mbr

    peaks = {(0.0, 20): (102.0, 1e-3), (0.0, 40): (100.0, 2e-3),
             (1.0, 20): (101.0, 1e-3), (1.0, 40): (101.0, 2e-3)}
    lines = mbr.table(200.0, [20, 40], peaks)
    assert "N = 40" in lines[0]
    assert "2.000 %" in lines[2] and "0.000 %" in lines[2]  # EI=0 2 % off, EI* on its reference
    assert "-0.980 %" in lines[2] and "+1.000 %" in lines[3]  # 101/102 - 1, 101/100 - 1
    assert lines[3].count("(ref)") == 2


def test_baseline_copy_follows_the_other_checkout(tmp_path):
    """The same-process comparisons (regression_vs_baseline.py, bench_tick.py, bench_vs_moordyn.py) import another
    checkout through a renamed copy kept between runs for its numba cache: the copy is keyed by the sources'
    content, so a changed checkout is copied again, never compared from a stale copy of an earlier state."""
    from benchmarks.bench_tick import _source_digest
    root = tmp_path / "checkout"
    (root / "tether_sim" / "ros").mkdir(parents=True)
    (root / "benchmarks").mkdir()
    (root / "tether_sim" / "kernels.py").write_text("A = 1\n")
    (root / "tether_sim" / "ros" / "node.py").write_text("B = 1\n")
    (root / "benchmarks" / "ropos_case.py").write_text("C = 1\n")
    d0, d0_ros = _source_digest(root), _source_digest(root, with_ros=True)
    assert d0 != d0_ros
    (root / "tether_sim" / "ros" / "node.py").write_text("B = 2\n")
    assert _source_digest(root) == d0 and _source_digest(root, with_ros=True) != d0_ros
    (root / "tether_sim" / "kernels.py").write_text("A = 2\n")
    assert _source_digest(root) != d0
    (root / "tether_sim" / "kernels.py").write_text("A = 1\n")
    assert _source_digest(root) == d0
    (root / "benchmarks" / "ropos_case.py").write_text("C = 2\n")
    assert _source_digest(root) != d0


def test_bench_tick_trees_take_turns_on_the_same_work():
    """bench_tick.measure_trees times every tree's blocks in turn within each repeat; two solvers of the
    same tree do the same work (same substeps per tick) and each block restores its start state, so a
    block leaves the solver where it found it (no timing asserted)."""
    from benchmarks import bench_tick
    from tether_sim.solvers import factory
    sols = {name: (bench_tick.prepared(factory, rc, 1730.0, 3, 0.0, t_warm=0.1), rc) for name in ("base", "new")}
    t0 = {name: sol.time for name, (sol, _) in sols.items()}
    row = bench_tick.measure_trees(sols, steps=20, repeat=2, ticks=3)
    assert set(row) == {"base", "new"}
    assert row["base"][2] == row["new"][2] > 0  # substeps per tick
    assert all(np.isfinite(v[0]) and np.isfinite(v[1]) for v in row.values())
    assert all(sols[name][0].time == t0[name] for name in sols)


def test_moordyn_step_bisection_finds_the_least_passing_n(monkeypatch):
    """bench_vs_moordyn.bisect_moordyn_step: the least n (largest step 0.02 / n) whose run passes the check;
    a finite run whose peak moved by more than the tolerance fails it, as a run that blew up does."""
    from benchmarks import bench_vs_moordyn as bvm

    def fake_peak(length, n_seg, alpha, cage, dt, workdir, duration, coupling):
        n = round(coupling / dt)
        if n < 5:
            return float("nan"), float("nan"), False  # blew up
        return (100.0 * (1.01 if n < 7 else 1.0)), 200.0, True  # n = 5, 6: finite, peak 1 % off

    monkeypatch.setattr(bvm, "moordyn_first_peak", fake_peak)
    monkeypatch.setattr(bvm.rc, "moordyn_time_step", lambda length, n_seg, coupling: coupling / 12)
    dt, n, n_safe, _ = bvm.bisect_moordyn_step(200.0, 40, 0.0, "point", None, 10.2)
    assert (n, n_safe) == (7, 12) and dt == 0.02 / 7
    assert bvm.bisect_moordyn_step(200.0, 40, 0.0, "point", None, 10.2, tol=float("inf"))[1] == 5
