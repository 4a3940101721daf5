"""The PE2020 Sec. 6.2 tables of benchmarks/studies/pe2020_sec62_figures.py (``--study``): built from a study's results
and events, a re-tensioning the snap guard rejected is listed as rejected and never counted or shown as a snap, and
the shifts against alpha = 0 pair each snap with the alpha = 0 snap of the same end nearest in time (docs/dg_solver.md,
"Slack with bending", part 9)."""

import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from benchmarks.studies.pe2020_sec62_figures import alpha_shift_table, study_cases, study_table


def _write(tmp_path, rows, events):
    pq.write_table(pa.Table.from_pylist(rows), tmp_path / "results.parquet")
    pq.write_table(pa.Table.from_pylist(events), tmp_path / "events.parquet")


def _row(key, alpha):
    return {"key": key, "var.L": 200.0, "var.f": 0.2, "var.alpha": alpha, "status": "ok", "divergences": 0,
            "cpu_s": 10.0}


def _ev(key, kind, where, t, peak, rise=0.5, bound=None):
    return {"key": key, "kind": kind, "location": where, "time_s": t, "peak_N": peak, "rise_time_s": rise,
            "bound_N": bound}


@pytest.fixture
def cases(tmp_path):
    _write(tmp_path, [_row("a", 0.0), _row("b", 100.0)], [
        _ev("a", "snap", "ship", 8.2479, 231.43e3), _ev("a", "snap", "vehicle", 8.2003, 224.62e3),
        _ev("a", "snap", "ship", 13.1876, 223.91e3),
        # alpha 100: the first ship peak one wave round trip (2L/c, ~0.1 s) earlier, the second 2 ms later
        _ev("b", "snap", "ship", 8.1542, 232.14e3, rise=1.68), _ev("b", "snap", "vehicle", 8.2026, 225.11e3),
        _ev("b", "snap", "ship", 13.1896, 224.00e3),
        _ev("b", "numerical", "vehicle", 7.6610, 415.5e3, rise=17e-6, bound=252.3e3)])
    return study_cases(tmp_path)


def test_rejected_events_are_never_snaps(cases):
    lines = study_table(cases)
    row100 = next(x for x in lines if x.startswith("| 200 | 0.2 | 100 |")).split(" | ")
    assert row100[3] == "2" and row100[6] == "1"  # ship and cage snap counts: the rejected event is not one
    assert "415.50 kN" not in " ".join(row100[3:9])  # nor the largest cage snap
    assert "cage 7.661 s, 415.5 kN, 17 us, bound 252 kN" in row100[9]
    assert row100[8] == "8.203 s, 225.11 kN"


def test_shift_against_alpha_0_pairs_nearest_snaps(cases):
    lines = alpha_shift_table(cases)
    ship = next(x for x in lines if x.startswith("| 200 | 0.2 | 100 | ship |")).split(" | ")
    assert ship[4] == "-93.7, +0.31"  # the first snaps: 93.7 ms apart (one wave round trip), +0.31 %
    assert ship[5] == "2 / 2"
    # peak time shifts -93.7 ms and +2.0 ms, their median -45.85 ms
    assert ship[6] == "-45.8 [-93.7, +2.0]"
    assert ship[8].startswith("+0.17 [+0.04, +0.31]")  # +0.31 % and +0.04 %
    cage = next(x for x in lines if x.startswith("| 200 | 0.2 | 100 | cage |")).split(" | ")
    assert cage[5] == "1 / 1" and cage[6] == "+2.3 [+2.3, +2.3]"
    # a pair further apart than the window (0.05 periods: 0.25 s here) is not the same re-tensioning
    assert alpha_shift_table(cases, window=0.01)[2].split(" | ")[5] == "1 / 2"
