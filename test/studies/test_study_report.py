"""``tether-sim-study report`` on synthetic results tables (no simulation): the figures follow what the
study varies (seeded levels, an amplitude x frequency sweep, the PE2020 L x EI x f grid), the Gumbel
fit is made per seeded condition and never for a deterministic sweep, and the Parquet table carries
each column's unit."""

import math

import numpy as np
import pyarrow.parquet as pq
import pytest
from scipy.stats import gumbel_r

from tether_sim.studies.cli import main
from tether_sim.studies.report import exceedance_groups, gumbel_fit, study_axes
from tether_sim.studies.results import column_unit, read_units, to_table

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
                "var.level": level, "var.seed": seed, "cable_length_m": 1730.0,
                # the sines' mean frequency, equal up to rounding in the last digit (one value, not three)
                "fairlead_frequency_Hz": 0.190775 * (1 + 2e-16 * (seed % 3)), "fairlead_amplitude_m": 1.5 * level,
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
    groups = exceedance_groups([r for r in rows if r["status"] == "ok"])
    assert sorted(groups) == ["level=1", "level=1.5"]
    loc, scale = gumbel_fit(groups["level=1"])
    # maximum likelihood from n = 200 samples: standard errors ~1.1 beta / sqrt(n) for mu and
    # ~0.78 beta / sqrt(n) for beta, i.e. ~8 % and ~6 % of beta; 4 standard errors allowed
    assert loc == pytest.approx(MU, abs=4 * 1.1 * BETA / math.sqrt(200))
    assert scale == pytest.approx(BETA, abs=4 * 0.78 * BETA / math.sqrt(200))


def test_report_writes_figures_and_summary(tmp_path, capsys):
    pq.write_table(to_table(synthetic_rows(20)), tmp_path / "results.parquet")
    assert main(["report", str(tmp_path)]) == 0
    out = tmp_path / "report"
    # one axis: the amplitude (the level expresses nothing else; the frequency differs only by rounding)
    assert sorted(p.name for p in out.glob("*.png")) == ["daf_sea_state.png", "exceedance.png", "peak_tension.png"]
    for p in out.glob("*.png"):
        assert p.stat().st_size > 10_000
    text = (out / "report.md").read_text()
    assert "Varied: fairlead amplitude a (m) and the seed (20 seeds)." in text
    assert "41 cases in the results: 40 ok, 1 failed." in text
    assert "SolverDivergedError: boom" in text
    assert "| level=1 | 20 |" in text and "cases per core-hour" in text
    assert "600 cases per core-hour" in text  # 40 cases x 6 s of CPU = 1/15 h


def sweep_rows(grid: dict, columns) -> list:
    """A deterministic sweep: every combination of the grid's variables, ``columns(values)`` the
    resolved columns of a case; tensions made up from them (no seed)."""
    import itertools

    rows = []
    for values in itertools.product(*grid.values()):
        v = dict(zip(grid, values))
        c = columns(v)
        t_max = 50e3 * (1 + c["fairlead_amplitude_m"] * c["fairlead_frequency_Hz"]) + 10 * c["cable_length_m"]
        rows.append({"key": f"k{len(rows)}", "index": len(rows), "study": "sweep", "status": "ok", "error": "",
                     **{f"var.{k}": x for k, x in v.items()}, **c,
                     "ship_T_max_N": t_max + 40e3, "vehicle_T_max_N": t_max, "vehicle_daf": t_max / 50e3,
                     "vehicle_dnv_slack_ok": t_max < 80e3, "ship_dnv_slack_ok": True, "vehicle_n_slack": 0,
                     "vehicle_n_snap": 0, "vehicle_snap_peak_N": math.nan, "vehicle_snap_daf": math.nan,
                     "vehicle_slack_max_s": 0.0, "vehicle_rise_time_s": math.nan, "rtf": 5.0, "cpu_s": 12.0,
                     "sim_s": 60.0})
    return rows


def heave_sweep(v):  # config/studies/heave_sweep.yaml: motion.amplitude x f
    return {"cable_length_m": 1730.0, "cable_EI_Nm2": 0.0, "fairlead_amplitude_m": v["motion.amplitude"],
            "fairlead_frequency_Hz": v["f"], "duration_s": 12 / v["f"]}


def pe2020(v):  # config/studies/pe2020_sec62.yaml: L x alpha x f
    return {"cable_length_m": float(v["L"]), "cable_EI_Nm2": v["alpha"] * 2620.0, "fairlead_amplitude_m": 2.0,
            "fairlead_frequency_Hz": v["f"], "duration_s": 12 / v["f"]}


def test_figures_follow_what_the_study_varies(tmp_path):
    heave = sweep_rows({"motion.amplitude": [0.5, 1.0, 1.5, 2.0, 2.5, 3.0], "f": [0.1, 0.15, 0.2, 0.25, 0.3]},
                       heave_sweep)
    # frequency across, amplitude up: one heat map per end, not six one-row panels per amplitude
    assert study_axes(heave) == [("fairlead_frequency_Hz", "fairlead frequency f (Hz)"),
                                 ("fairlead_amplitude_m", "fairlead amplitude a (m)")]
    assert exceedance_groups(heave) is None  # different conditions: no extreme-value sample
    grid = sweep_rows({"L": [200, 500, 975, 1730], "alpha": [0, 1, 10, 100], "f": [0.1, 0.2, 0.25]}, pe2020)
    assert [c for c, _ in study_axes(grid)] == ["fairlead_frequency_Hz", "cable_length_m", "cable_EI_Nm2"]
    # a variable no resolved column expresses is an axis of its own, with its parameter's unit
    extra = sweep_rows({"f": [0.1, 0.2], "snap.slack_fraction": [0.05, 0.1, 0.2]}, lambda v: heave_sweep(
        {"motion.amplitude": 2.0, "f": v["f"]}))
    assert [label for _, label in study_axes(extra)] == ["fairlead frequency f (Hz)", "snap.slack_fraction"]

    pq.write_table(to_table(heave), tmp_path / "results.parquet")
    assert main(["report", str(tmp_path)]) == 0
    out = tmp_path / "report"
    assert sorted(p.name for p in out.glob("*.png")) == ["daf_sea_state.png", "peak_tension_heatmap.png"]
    text = (out / "report.md").read_text()
    assert "Varied: fairlead frequency f (Hz), fairlead amplitude a (m)." in text
    assert "None: the cases are different conditions (no seeds)" in text and "exceedance.png" not in text


def test_results_table_carries_units(tmp_path):
    rows = sweep_rows({"motion.amplitude": [0.5, 1.0], "f": [0.1, 0.2]}, heave_sweep)
    pq.write_table(to_table(rows), tmp_path / "results.parquet")
    schema = pq.read_schema(tmp_path / "results.parquet")
    units = {f.name: (f.metadata or {}).get(b"unit", b"").decode() for f in schema}
    assert units["vehicle_T_max_N"] == "N" and units["cable_length_m"] == "m" and units["cable_EI_Nm2"] == "N m^2"
    assert units["fairlead_frequency_Hz"] == "Hz" and units["duration_s"] == "s" and units["cpu_s"] == "s"
    assert units["vehicle_daf"] == units["rtf"] == "1"
    assert units["var.motion.amplitude"] == "m"  # a study variable that names a parameter
    assert units["var.f"] == units["key"] == units["vehicle_n_snap"] == ""  # free variable, identity, count
    # the study's own variables with the units of its file (Study.column_units): in the table and the report
    pq.write_table(to_table(rows, {"var.f": "Hz"}), tmp_path / "results.parquet")
    assert read_units(tmp_path)["var.f"] == "Hz" and read_units(tmp_path)["var.motion.amplitude"] == "m"
    assert main(["report", str(tmp_path)]) == 0
    assert "| case | motion.amplitude (m) | f (Hz) |" in (tmp_path / "report" / "report.md").read_text()
    grid = sweep_rows({"L": [200, 1730], "alpha": [0, 1, 10]}, lambda v: pe2020({**v, "f": 0.2}))
    for r in grid:
        r["cable_length_m"] = 500.0  # (a resolved column that no longer expresses L: L is an axis of its own)
    assert study_axes(grid, {"var.L": "m", "var.alpha": "1"})[1:] == [("var.L", "L (m)")]
    assert study_axes(grid)[1:] == [("var.L", "L")]  # a table without the unit
    assert column_unit("ship_snap_daf") == "1" and column_unit("hybrid_dt_s") == "s"


def network_rows(grid: dict) -> list:
    """Rows of a line-network study (case.run_network_task's columns) over ``grid`` (the cage mass x the heave
    amplitude, as config/studies/ropos_tms_cage.yaml): lines ``tether`` (ship -> cage) and ``excursion`` (cage ->
    vehicle), body ``cage``, points ``ship`` and ``vehicle``; tensions made up from the variables."""
    import itertools

    rows = []
    for mass, a in itertools.product(*grid.values()):
        row = {"key": f"k{len(rows)}", "index": len(rows), "study": "net", "status": "ok", "error": "", "network": True,
               "var.network.bodies.cage.mass": mass, "var.motion.amplitude": a, "motion.kind": "heave",
               "fairlead_amplitude_m": a, "fairlead_frequency_Hz": 0.2, "duration_s": 60.0, "cage.mass_kg": mass,
               "ship_force_max_N": 9.0e4 * a + 20.0 * mass, "vehicle_force_max_N": 300.0 * a + 0.01 * mass,
               "rtf": 12.0, "cpu_s": 5.0, "sim_s": 60.0}
        for line, ends, static in (("tether", ("ship", "cage"), (8.0e4 + 8.0 * mass, 4.0e4 + 8.0 * mass)),
                                   ("excursion", ("cage", "vehicle"), (40.0, 25.0))):
            row.update({f"{line}.length_m": 30.0 if line == "excursion" else 1730.0, f"{line}.solver": "dg",
                        f"{line}.from": ends[0], f"{line}.to": ends[1]})
            for end, st, k in (("ship", static[0], 1.0), ("vehicle", static[1], 1.5)):
                t_max = st * (1.0 + 0.3 * k * a) + 0.001 * mass
                row.update({f"{line}.{end}_static_N": st, f"{line}.{end}_T_max_N": t_max,
                            f"{line}.{end}_T_min_N": st * (1.0 - 0.6 * a), f"{line}.{end}_daf": t_max / st,
                            f"{line}.{end}_dnv_slack_ok": a < 1.5, f"{line}.{end}_n_slack": int(a > 1.5),
                            f"{line}.{end}_n_snap": int(a > 1.5), f"{line}.{end}_snap_peak_N": t_max if a > 1.5 else math.nan,
                            f"{line}.{end}_n_numerical": 0})
        rows.append(row)
    return rows


def _table_column(md, section, header):
    """The values of column ``header`` of the first table after ``section`` in a report's markdown."""
    lines = md[md.index(section):].splitlines()
    start = next(i for i, x in enumerate(lines) if x.startswith("|"))
    names = [c.strip() for c in lines[start].strip("|").split("|")]
    col = names.index(header)
    out = []
    for x in lines[start + 2:]:
        if not x.startswith("|"):
            break
        out.append(float(x.strip("|").split("|")[col]))
    return np.array(out)


def test_a_network_study_report_has_the_figures_per_line_body_and_point(tmp_path):
    """A network study's report: per line its peak-tension figure (both ends) and its DAF figure, the tension of
    each line at the cage, the force on each point, as the single-line report gives them over what the study
    varies (heat maps over cage mass x amplitude, points over one axis); what a figure plots is the table's column
    (to the table's 4 significant digits, and exactly the rows' values)."""
    from tether_sim.studies.report import network_figures

    rows = network_rows({"mass": [4995.0, 7500.0], "a": [1.0, 2.0]})
    pq.write_table(to_table(rows), tmp_path / "results.parquet")
    assert main(["report", str(tmp_path)]) == 0
    out = tmp_path / "report"
    names = ["cage_loads_peak_heatmap.png", "excursion_daf.png", "excursion_peak_heatmap.png",
             "points_force_peak_heatmap.png", "tether_daf.png", "tether_peak_heatmap.png"]
    assert sorted(p.name for p in out.glob("*.png")) == names
    md = (out / "report.md").read_text()
    for n in names:
        assert (out / n).stat().st_size > 10_000 and f"]({n})" in md
    assert "No figures" not in md
    # the excursion tether's s = L end as the heat map shows it: rows = amplitude (second axis), columns = mass
    axes = study_axes(rows)
    assert [c for c, _ in axes] == ["fairlead_amplitude_m", "var.network.bodies.cage.mass"]
    _, plotted = network_figures(rows, {}, tmp_path / "again")
    grid = plotted["excursion_peak_heatmap.png"][("excursion s = L (vehicle)", None)]
    by_case = {(r["var.network.bodies.cage.mass"], r["fairlead_amplitude_m"]): r for r in rows}
    expect = np.array([[by_case[(m, a)]["excursion.vehicle_T_max_N"] / 1e3 for a in (1.0, 2.0)] for m in (4995.0, 7500.0)])
    assert np.array_equal(grid, expect)  # (heat map rows: the second axis, the mass)
    table = _table_column(md, "## Line `excursion`", "T_max s=L kN")
    assert np.allclose(table, [r["excursion.vehicle_T_max_N"] / 1e3 for r in rows], rtol=5e-4, atol=0)
    assert np.allclose(grid.T.ravel(), table.reshape(2, 2).T.ravel(), rtol=5e-4)  # (table: mass slowest)
    assert plotted["cage_loads_peak_heatmap.png"].keys() == {("tether (s = L)", None), ("excursion (s = 0)", None)}

    # one axis (the amplitude only): points, read back from the figure's artists, equal the table's columns
    one = network_rows({"mass": [4995.0], "a": [0.5, 1.0, 2.0]})
    _, plotted = network_figures(one, {}, tmp_path / "one")
    assert sorted(p.name for p in (tmp_path / "one").glob("*.png")) == [
        "cage_loads_peak.png", "excursion_daf.png", "excursion_peak.png", "points_force_peak.png", "tether_daf.png",
        "tether_peak.png"]
    x, y = plotted["points_force_peak.png"]["vehicle"]
    order = np.argsort(x)
    assert np.array_equal(x[order], [0.5, 1.0, 2.0])
    assert np.array_equal(y[order], [r["vehicle_force_max_N"] / 1e3 for r in one])
    x, y = plotted["tether_daf.png"]["tether s = 0 (ship)"]
    assert np.array_equal(y, [r["tether.ship_daf"] for r in one])
    # slack cases (a = 2) are plotted too, hollow: the series holds every case
    x, y = plotted["tether_peak.png"]["tether s = L (cage)"]
    assert sorted(y) == sorted(r["tether.vehicle_T_max_N"] / 1e3 for r in one)


def test_a_seeded_network_study_gets_an_exceedance_figure_per_line(tmp_path):
    """With seeds, each line's per-case maxima at its s = L end get the exceedance figure and Gumbel fit of the
    single-line report; the groups it plots are the table's column."""
    from tether_sim.studies.report import network_figures

    rows = []
    for seed in range(6):
        for r in network_rows({"mass": [4995.0], "a": [1.0, 2.0]}):
            r.update({"key": f"{r['key']}-{seed}", "index": len(rows), "var.seed": seed})
            r["excursion.vehicle_T_max_N"] *= 1.0 + 0.05 * seed
            rows.append(r)
    _, plotted = network_figures(rows, {}, tmp_path)
    assert {"tether_exceedance.png", "excursion_exceedance.png"} <= set(plotted)
    groups = plotted["excursion_exceedance.png"]
    assert sorted(groups) == ["motion.amplitude=1", "motion.amplitude=2"]
    assert groups["motion.amplitude=2"] == [r["excursion.vehicle_T_max_N"] for r in rows if r["var.motion.amplitude"] == 2.0]
    assert (tmp_path / "excursion_exceedance.png").stat().st_size > 10_000
