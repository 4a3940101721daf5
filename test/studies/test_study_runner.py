"""The study runner end to end on four 3-second cases: local processes, resume, failures, Dask.

One module-scoped local run (two spawned processes) is shared by the tests; the Dask test runs the
same study on a LocalCluster of two worker processes on 127.0.0.1 and compares the tables.
"""

import math
import shutil
import sys
from pathlib import Path

import pytest

from tether_sim.io.params import load_config
from tether_sim.scenarios.ropos import static_end_tensions
from tether_sim.studies.case import TIMING_COLUMNS
from tether_sim.studies.results import read_results, read_units, same_physics
from tether_sim.studies.runner import plan, run_study
from tether_sim.studies.spec import load_study

HERE = Path(__file__).resolve().parent
TINY = HERE / "tiny_study.yaml"


@pytest.fixture(scope="module")
def local_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("study") / "local"
    summary = run_study(TINY, out, workers=2)
    return out, summary


def test_local_run_table(local_run):
    out, summary = local_run
    assert (summary["ran"], summary["ok"], summary["failed"]) == (4, 2, 2)
    assert (out / "results.parquet").is_file() and (out / "results.csv").is_file()
    rows = sorted(read_results(out), key=lambda r: r["index"])
    assert [r["var.motion.amplitude"] for r in rows] == [0.1, 3.0, 500.0, 0.1]
    # f is the study's own variable, set to motion.frequency as it is: its column carries Hz
    assert read_units(out)["var.f"] == "Hz" and read_units(out)["var.motion.amplitude"] == "m"
    assert [r["status"] for r in rows] == ["ok", "ok", "failed", "failed"]
    # failed cases keep their error, and did not stop the others
    assert "motion.amplitude" in rows[2]["error"] and "above the maximum" in rows[2]["error"]
    assert "direction" in rows[3]["error"]
    cfg = load_config(HERE.parents[1] / "config" / "ropos_L200.yaml")
    ship, cage = static_end_tensions(cfg)
    for r in rows[:2]:
        assert r["error"] == ""
        assert (r["solver"], r["dg_N"], r["dg_P"], r["sim_s"]) == ("dg", 2, 2, 3.0)
        # static tensions of the solver against the closed form (cage submerged weight; plus the
        # tether's at the ship): within 0.5 %, the acceptance of the ROPOS statics (test_ropos.py)
        assert r["vehicle_static_N"] == pytest.approx(cage, rel=5e-3)
        assert r["ship_static_N"] == pytest.approx(ship, rel=5e-3)
        for end in ("ship", "vehicle"):
            assert r[f"{end}_T_min_N"] <= r[f"{end}_static_N"] * 1.001 <= r[f"{end}_T_max_N"] * 1.001
            assert r[f"{end}_daf"] == pytest.approx(r[f"{end}_T_max_N"] / r[f"{end}_static_N"])
            assert r[f"{end}_dnv_slack_ok"] == (r[f"{end}_T_min_N"] >= 0.1 * r[f"{end}_static_N"])
        assert r["rtf"] > 0 and r["cpu_s"] > 0
    # DNV-style check in closed form. The 0.1 m heave at 0.2 Hz (1 s ramp) accelerates the fairlead by
    # at most 0.54 m/s^2, so accelerating the cage (4995 kg + 9200 kg added mass) takes 7.7 kN. Even
    # doubled by the cage's spring-mass response (omega_n = sqrt(EA/L / m) = 4 rad/s, near the ramp's
    # time scale), that is far below 0.9 x 43 kN: the cage must stay taut. The 3 m heave at 0.5 Hz
    # accelerates the fairlead downwards at a w^2 = 30 m/s^2 > g, while the cage sinks at most at
    # W_sub / (m + m_a) = 3 m/s^2: the tether must go slack there.
    assert rows[0]["vehicle_dnv_slack_ok"] and rows[0]["vehicle_n_slack"] == 0
    assert not rows[1]["vehicle_dnv_slack_ok"] and rows[1]["vehicle_n_slack"] >= 1
    assert 1.0 < rows[0]["vehicle_daf"] < rows[1]["vehicle_daf"]


def test_resume_skips_done_cases(local_run, tmp_path):
    out, _ = local_run
    copy = tmp_path / "copy"
    shutil.copytree(out, copy)
    summary = run_study(TINY, copy, workers=2)  # failed cases stay recorded and are not run again
    assert (summary["ran"], summary["skipped"]) == (0, 4)
    assert same_physics(read_results(out), read_results(copy), ignore=()) == []
    tasks, _, _, _ = plan(load_study(TINY), copy, retry_failed=True)  # --retry-failed: the failed run again
    assert [t["index"] for t in tasks] == [3]


def test_exit_status_says_whether_cases_failed(local_run, tmp_path, capsys):
    from tether_sim.studies.cli import main

    out, _ = local_run
    copy = tmp_path / "copy"
    shutil.copytree(out, copy)
    assert main([str(TINY), "--out", str(copy)]) == 0  # nothing left to run: none of this run failed
    assert "0 case(s) run (0 ok, 0 failed), 4 already in the results" in capsys.readouterr().out
    # case 3 again: its solver still cannot be built, so the study ran to its end with a failure
    assert main([str(TINY), "--out", str(copy), "--retry-failed", "--cases", "3", "--workers", "1"]) == 1
    printed = capsys.readouterr()
    assert "1 case(s) run (0 ok, 1 failed)" in printed.out
    # what it would cost was said before it ran (solvers/work.py run_estimate of the case's configuration)
    assert "[study] 1 case(s) to run: expected about" in printed.err and "on 1 local worker(s)" in printed.err


def test_each_task_carries_the_estimate_of_its_run(tmp_path):
    from tether_sim.solvers.work import run_estimate
    from tether_sim.studies.runner import plan
    from tether_sim.studies.spec import load_study

    tasks, _, _, _ = plan(load_study(TINY), tmp_path)
    config = load_config(HERE.parents[1] / "config" / "ropos_L200_paper.yaml",
                         {**load_study(TINY).cases()[0].overrides})
    assert tasks[0]["index"] == 0 and tasks[0]["expected_cpu"] == pytest.approx(run_estimate(config, 3.0)[0])


def test_dask_local_cluster_matches_local_processes(local_run, tmp_path):
    distributed = pytest.importorskip("distributed")
    out, _ = local_run
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                                  dashboard_address=None, protocol="tcp") as cluster:
        assert cluster.scheduler_address.startswith("tcp://127.0.0.1:")
        summary = run_study(TINY, tmp_path / "dask", scheduler=cluster.scheduler_address)
    assert (summary["ran"], summary["ok"]) == (4, 2)
    dask_rows = read_results(tmp_path / "dask")
    assert len({r["worker"] for r in dask_rows}) >= 1
    # every column except timing and worker identity is identical (the runs are deterministic)
    assert same_physics(read_results(out), dask_rows, ignore=TIMING_COLUMNS) == []


def test_study_module_imports_no_rclpy():
    """The coordinator (and a Dask client) never loads rclpy: only the worker function does."""
    import subprocess

    code = ("import sys, tether_sim.studies.runner, tether_sim.studies.report, tether_sim.studies.cli; "
            "print(any(m == 'rclpy' or m.startswith('rclpy.') for m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "False"


def test_keys_change_with_any_parameter():
    from tether_sim.studies.case import case_key, code_version

    cases = load_study(TINY).cases()
    cfgs = [load_config(c.base, c.overrides) for c in cases if c.index != 2]  # case 2 is invalid
    code = code_version()
    keys = [case_key(c, code) for c in cfgs]
    assert len(set(keys)) == 3 and keys == [case_key(c, code) for c in cfgs]
    assert case_key(cfgs[0], dict(code, source_hash="0" * 16)) != keys[0]
    assert not math.isnan(cfgs[0].cable.length)
