"""dg.resolution auto: the rule is the measured ladder table, applied with its stated margin and limits.

The table in tether_sim/solvers/resolution.py must be what docs/data/resolution_ladder.csv
(benchmarks/studies/resolution_ladder.py) measured, rounded up to 1e-4: a test of provenance, so the rule
cannot drift from its data. No solver runs here (the ladders are a benchmark: minutes of CPU).
"""

import math
from dataclasses import replace
from pathlib import Path

import pytest

from benchmarks.studies.resolution_report import read_rows, worst_errors
from tether_sim.errors import ConfigError
from tether_sim.io.params import from_flat, load_config, to_flat
from tether_sim.solvers import resolution as res

ROOT = Path(__file__).resolve().parents[2]
CSV = ROOT / "docs" / "data" / "resolution_ladder.csv"
TABLE = res.WORST_ERROR


def test_table_is_the_measured_ladder_rounded_up():
    measured = worst_errors(read_rows(CSV))
    assert set(TABLE) == set(measured) == {"body", "free"}
    for kind, table in TABLE.items():
        assert set(table) == set(measured[kind])
        for length, ladders in table.items():
            assert set(ladders) == set(measured[kind][length]), (kind, length)
            for fam, errs in ladders.items():
                assert set(errs) == set(measured[kind][length][fam]), (kind, length, fam)
                for n, err in errs.items():
                    assert err == math.ceil(measured[kind][length][fam][n] * 1e4) / 1e4, (kind, length, fam, n)


def _settled_rungs(ladder, tolerance):
    """Rungs N >= 2 of one measured ladder within half the tolerance together with every finer rung."""
    return [n for n in ladder if n >= 2 and all(ladder[m] <= 0.5 * tolerance for m in ladder if m >= n)]


@pytest.mark.parametrize("tolerance", [0.01, 0.02, 0.05])
def test_cheapest_settled_rung_of_a_complete_ladder_at_every_measured_length(tolerance):
    for kind, table in TABLE.items():
        for length, ladders in table.items():
            chosen = res.choose(length, tolerance, kind)
            ladder = ladders[(chosen.order, chosen.cfl)]
            assert chosen.cfl <= 0.8  # never at or beyond the calibrated stability limit
            assert chosen.n_elements == min(_settled_rungs(ladder, tolerance))
            # complete: every rung from N = 2 to the finest below the reference was measured
            assert {n for n in res.LADDER_NS if 2 <= n <= res.finest_rung(length)} <= set(ladder)
            # no other complete ladder at cfl <= 0.8 has a settled rung the cost model puts cheaper
            for (p, c), other in ladders.items():
                complete = {n for n in res.LADDER_NS if 2 <= n <= res.finest_rung(length)} <= set(other)
                settled = _settled_rungs(other, tolerance)
                if c <= 0.8 and complete and settled:
                    assert res.cost(length, min(settled), p, c) >= chosen.cost, (kind, length, p, c)


def test_between_measured_lengths_both_neighbours_hold():
    table = TABLE["body"]
    lengths = sorted(table)
    for a, b in zip(lengths, lengths[1:]):
        chosen = res.choose(0.5 * (a + b), 0.01)
        fam = (chosen.order, chosen.cfl)
        for x in (a, b):
            assert all(err <= 0.005 for n, err in table[x][fam].items() if n >= chosen.n_elements), (a, b, x)


def test_cost_constants_are_the_fit_to_the_ladders_thread_cpu():
    from benchmarks.studies.resolution_report import cost_fit

    (fixed, node, bending), n_rows = cost_fit(read_rows(CSV))
    assert n_rows > 500
    assert (res.COST_FIXED, res.COST_NODE, res.COST_NODE_BENDING) == pytest.approx((fixed, node, bending), rel=5e-3)


def test_cost_model_is_the_substep_rate_times_the_substep_cost():
    """cost = (fixed + per node x N (P + 1)) / (cfl x the solver's stability limit): doubling N
    about doubles the substep rate (the axial wave term dominates at these element sizes)."""
    one = res.cost(1730.0, 4, 4, 0.8)
    assert res.cost(1730.0, 4, 4, 0.4) == pytest.approx(2.0 * one)
    assert 2.0 < res.cost(1730.0, 8, 4, 0.8) / one < 3.0
    assert res.cost(1730.0, 4, 4, 0.8, {"EI": 2620.0}) > one


def _auto(**changes):
    cfg = load_config(ROOT / "config" / "ropos_L200_paper.yaml")
    return replace(cfg, dg=replace(cfg.dg, resolution="auto"), **changes)


def test_refuses_what_was_not_measured():
    cfg = _auto()
    with pytest.raises(ConfigError, match="cable.length 3000 m is outside the range measured"):
        res.resolve(replace(cfg, cable=replace(cfg.cable, length=3000.0)))
    with pytest.raises(ConfigError, match="cable.EA"):
        res.resolve(replace(cfg, cable=replace(cfg.cable, EA=2e8)))
    with pytest.raises(ConfigError, match="cable.EI"):
        res.resolve(replace(cfg, cable=replace(cfg.cable, EI=26200.0)))
    with pytest.raises(ConfigError, match="vehicle_end.kind clamped"):
        res.resolve(replace(cfg, vehicle_end=replace(cfg.vehicle_end, kind="clamped")))
    with pytest.raises(ConfigError, match="implicit"):
        res.resolve(replace(cfg, dg=replace(cfg.dg, damping="implicit")))
    with pytest.raises(ConfigError, match="snap_tolerance 0.0001"):
        res.choose(200.0, 1e-4)


def test_manual_and_hybrid_are_untouched():
    paper = load_config(ROOT / "config" / "ropos_L200_paper.yaml")
    assert res.resolve(paper) is paper and (paper.dg.n_elements, paper.dg.order, paper.dg.cfl) == (20, 4, 0.5)
    hybrid = replace(_auto(), solver="hybrid")
    assert res.resolve(hybrid) is hybrid


def test_parameter_files_get_the_rule_and_refuse_a_second_answer():
    cfg = load_config(ROOT / "config" / "ropos_L200.yaml")
    chosen = res.choose(200.0, 0.01)
    assert (cfg.dg.n_elements, cfg.dg.order, cfg.dg.cfl) == (chosen.n_elements, chosen.order, chosen.cfl)
    bent = load_config(ROOT / "config" / "ropos_L200.yaml", overrides={"cable.EI": 2620.0})
    want = res.choose(200.0, 0.01, cable={"EI": 2620.0})  # the rule sees the configuration's own cable
    assert (bent.dg.n_elements, bent.dg.order, bent.dg.cfl) == (want.n_elements, want.order, want.cfl)
    assert from_flat(to_flat(cfg)) == cfg  # the resolved numbers round-trip (the node reads them back)
    with pytest.raises(ConfigError, match="dg.n_elements = 20 is set while dg.resolution is auto"):
        load_config(ROOT / "config" / "ropos_L200.yaml", overrides={"dg.n_elements": 20})
    tight = load_config(ROOT / "config" / "ropos_L200.yaml", overrides={"dg.snap_tolerance": 0.002})
    assert tight.dg.n_elements >= cfg.dg.n_elements


def test_mesh_summary_names_mesh_and_rule():
    text = res.mesh_summary(3, 4, 0.8, "auto", 0.01)
    assert text == "N = 3, P = 4, dg.cfl 0.8 (dg.resolution auto, first-snap-peak tolerance 1 %)"
    assert res.mesh_summary(20, 4, 0.5, "manual", 0.01).endswith("(dg.resolution manual)")


# --- winch runs: one fixed mesh over a varying length (config/ropos_descent.yaml) ---

def test_a_range_at_one_measured_length_is_the_single_length_rule():
    from tether_sim.solvers.resolution import WORST_ERROR, choose

    for length in sorted(WORST_ERROR["body"]):
        for tol in (0.01, 0.02):
            try:
                single = choose(float(length), tol)
            except ConfigError:
                continue
            ranged = choose(float(length), tol, up_to=float(length))
            assert (ranged.n_elements, ranged.order, ranged.cfl) == (single.n_elements, single.order, single.cfl)
            # the range rule reports the worst error over the settled rungs, not only at N
            assert single.measured_error <= ranged.measured_error <= res.SAFETY * tol


def test_a_winch_range_gets_a_mesh_settled_at_every_measured_length_inside_it():
    """At every measured length of the range, each measured rung of the chosen family at or above the
    chosen N (or, where the ladder stops below N, its finest rungs) is within half the tolerance."""
    from tether_sim.solvers.resolution import SAFETY, WORST_ERROR, choose

    table = WORST_ERROR["body"]
    for lo, hi, tol in ((200.0, 1800.0, 0.01), (200.0, 1800.0, 0.02), (200.0, 500.0, 0.01)):
        r = choose(lo, tol, up_to=hi)
        for x in (x for x in table if lo <= x <= hi):
            errs = table[x][(r.order, r.cfl)]
            above = [e for m, e in errs.items() if m >= min(r.n_elements, max(errs))]
            assert max(above) <= SAFETY * tol, (lo, hi, tol, x)
    # the ROPOS descent (200-1800 m) at 1 % needs the 975 m mesh, N = 24, P = 4
    assert (choose(200.0, 0.01, up_to=1800.0).n_elements, choose(200.0, 0.01, up_to=1800.0).order) == (24, 4)


def test_a_winch_range_outside_the_measured_lengths_is_refused():
    from tether_sim.solvers.resolution import resolve

    cfg = load_config(Path(__file__).resolve().parents[2] / "config" / "ropos_descent.yaml")
    assert (cfg.dg.n_elements, cfg.dg.order) == (12, 2)
    with pytest.raises(ConfigError, match="shortest winch length 50"):
        resolve(replace(cfg, winch=replace(cfg.winch, min_length=50.0)))


def test_fine_mesh_warning_at_the_measured_spacings():
    """The fine-mesh caution (docs/dg_solver.md "Slack with bending" (6)): ROPOS 200 m, P = 4, bending factor 100 --
    the one-step cage event of Eq. 22's damping switch grows as the node spacing shrinks (87 kN at N = 20, 2.5 m
    between nodes; 264 kN at N = 40, 1.25 m; 2026-11-27), implicit damping at 1.25 m not clean."""
    assert res.bending_mesh_warning(200.0, 20, 4, 2620.0) == ""
    text = res.bending_mesh_warning(200.0, 40, 4, 2620.0)
    assert "1.25 m" in text and "slack" in text and "bending" in text
    assert res.bending_mesh_warning(200.0, 80, 4, 0.0) == ""  # no bending, explicit: nothing to warn about
    text = res.bending_mesh_warning(200.0, 40, 4, 0.0, damping="implicit")
    assert "dg.damping implicit" in text and "EI" not in text
    assert res.bending_mesh_warning(200.0, 20, 4, 0.0, damping="implicit") == ""
    # non-uniform meshes: the smallest element decides; dg.element_lengths are weights scaled to the length
    assert res.bending_mesh_warning(200.0, 3, 4, 2620.0, element_lengths=(190.0, 5.0, 5.0)) != ""
    assert "1.25 m" in res.bending_mesh_warning(200.0, 3, 4, 2620.0, element_lengths=(38.0, 1.0, 1.0))  # 5 m / 4
    assert res.bending_mesh_warning(200.0, 3, 4, 2620.0, element_lengths=(1.0, 1.0, 2.0)) == ""  # 50 m: 12.5 m
    # the live files' meshes (the rule's) are far coarser than the caution
    for length in (200.0, 500.0, 1730.0):
        r = res.choose(length, 0.01)
        assert res.bending_mesh_warning(length, r.n_elements, r.order, 2620.0) == ""
