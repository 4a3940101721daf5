"""``tether-sim-study report`` on a synthetic results table (no simulation)."""

import math

import numpy as np
import pyarrow.parquet as pq
import pytest
from scipy.stats import gumbel_r

from tether_sim.studies.cli import main
from tether_sim.studies.report import exceedance_groups, gumbel_fit
from tether_sim.studies.results import to_table

MU, BETA = 120e3, 8e3  # N: the Gumbel distribution the synthetic per-case maxima are drawn from


def synthetic_rows(n_seeds=200):
    rng = np.random.default_rng(5)
    rows = []
    for level in (1.0, 1.5):
        for seed in range(n_seeds):
            t_max = float(gumbel_r.rvs(MU * level, BETA * level, random_state=rng))
            static = 60e3
            rows.append({
                "key": f"k{level}-{seed}", "index": len(rows), "study": "synthetic", "status": "ok", "error": "",
                "var.level": level, "var.seed": seed, "cable.length": 1730.0,
                "fairlead_frequency_Hz": 0.1 + 0.05 * (seed % 3), "fairlead_amplitude_m": level,
                "ship_T_max_N": t_max + 44e3, "vehicle_T_max_N": t_max, "ship_static_N": static + 44e3,
                "vehicle_static_N": static, "vehicle_daf": t_max / static, "ship_daf": (t_max + 44e3) / (static + 44e3),
                "vehicle_dnv_slack_ok": seed % 2 == 0, "ship_dnv_slack_ok": True, "vehicle_n_slack": seed % 2,
                "vehicle_n_snap": seed % 2, "vehicle_snap_peak_N": t_max if seed % 2 else math.nan,
                "vehicle_snap_daf": t_max / static if seed % 2 else math.nan, "vehicle_slack_max_s": 0.5 * (seed % 2),
                "vehicle_rise_time_s": 0.1 if seed % 2 else math.nan, "rtf": 10.0, "cpu_s": 6.0, "sim_s": 60.0})
    rows.append({"key": "bad", "index": len(rows), "study": "synthetic", "status": "failed",
                 "error": "SolverDivergedError: boom", "var.level": 1.0, "var.seed": 999})
    return rows


def test_gumbel_fit_recovers_the_distribution():
    rows = synthetic_rows()
    groups, per_seed = exceedance_groups([r for r in rows if r["status"] == "ok"])
    assert per_seed and sorted(groups) == ["level=1", "level=1.5"]
    loc, scale = gumbel_fit(groups["level=1"])
    # maximum likelihood from n = 200 samples: standard errors ~1.1 beta / sqrt(n) for mu and
    # ~0.78 beta / sqrt(n) for beta, i.e. ~8 % and ~6 % of beta; 4 standard errors allowed
    assert loc == pytest.approx(MU, abs=4 * 1.1 * BETA / math.sqrt(200))
    assert scale == pytest.approx(BETA, abs=4 * 0.78 * BETA / math.sqrt(200))


def test_report_writes_figures_and_summary(tmp_path, capsys):
    pq.write_table(to_table(synthetic_rows(20)), tmp_path / "results.parquet")
    assert main(["report", str(tmp_path)]) == 0
    out = tmp_path / "report"
    for name in ("peak_tension_heatmap.png", "daf_sea_state.png", "exceedance.png"):
        assert (out / name).stat().st_size > 10_000
    text = (out / "report.md").read_text()
    assert "41 cases in the results: 40 ok, 1 failed." in text
    assert "SolverDivergedError: boom" in text
    assert "| level=1 | 20 |" in text and "cases per core-hour" in text
    assert "600 cases per core-hour" in text  # 40 cases x 6 s of CPU = 1/15 h
