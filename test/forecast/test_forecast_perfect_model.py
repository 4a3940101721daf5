"""The perfect-model check's scorer (benchmarks/forecast_perfect_model.py) on synthetic ensembles whose
counts are worked out by hand: alarms, false alarms, truth snaps >= 5 s ahead and warned ones. The member
counts are powers of two, so every weighted count is exact in binary and compared with ==."""
import json

from benchmarks import forecast_perfect_model as pm


def _counts(c):
    return (c.alarms, c.false, c.snaps, c.warned)


def test_one_forecast_against_a_truth():
    members = [110.0, 110.5, 111.0, 120.0]  # median 110.75
    # a snap 0.55 s from the predicted time, 10.2 s ahead: warned, no false alarm
    assert _counts(pm.score_one(100.0, 15.0, 0.75, members, [110.2])) == (1, 0, 1, 1)
    # 2.25 s off: a false alarm and an unwarned snap
    assert _counts(pm.score_one(100.0, 15.0, 0.75, members, [113.0])) == (1, 1, 1, 0)
    # a snap under 5 s ahead is not scored as a snap; the alarm is false (7.75 s off)
    assert _counts(pm.score_one(100.0, 15.0, 0.75, members, [103.0])) == (1, 1, 0, 0)
    # no snap at all: false alarm
    assert _counts(pm.score_one(100.0, 15.0, 0.75, members, [])) == (1, 1, 0, 0)
    # below the threshold: no alarm, the snap unwarned
    assert _counts(pm.score_one(100.0, 15.0, 0.25, members, [110.2])) == (0, 0, 1, 0)
    # the bounds are inclusive: exactly 5 s ahead and exactly 1.5 s off (median of 103.0 and 104.0: 103.5)
    assert _counts(pm.score_one(100.0, 15.0, 0.5, [103.0, 104.0], [105.0])) == (1, 0, 1, 1)
    # after the horizon: not a scored snap, but it still makes the alarm true
    assert _counts(pm.score_one(100.0, 15.0, 0.5, [115.5, 116.5], [116.0])) == (1, 0, 0, 0)


def _row(stamp, p, times, end="vehicle"):
    return [end, stamp, p, float("nan"), 4, [[t, 1.0e5] for t in times]]


def test_perfect_model_holds_out_each_member():
    # three of four members snap close together; the fourth does not:
    # held out 10 -> others 10.5, 11 (p 2/3, median 10.75): warned; 10.5 -> 10, 11 (10.5): warned;
    # 11 -> 10, 10.5 (10.25): warned; the quiet member -> p 1, median 10.5: a false alarm
    assert _counts(pm.score_perfect_model([_row(0.0, 0.75, [10.0, 10.5, 11.0])], 4, 15.0)) == (1, 0.25, 0.75, 0.75)
    # one member far off: held out 10 -> median 12.25 (2.25 off): false; 10.5 -> median 12 (1.5): warned;
    # 14 -> median 10.25: false; the quiet member: false
    assert _counts(pm.score_perfect_model([_row(0.0, 0.75, [10.0, 10.5, 14.0])], 4, 15.0)) == (1, 0.75, 0.75, 0.25)
    # two of four snap: a snapping truth leaves p 1/3 (no alarm, its snap unwarned); a quiet truth leaves
    # p 2/3 and a false alarm
    assert _counts(pm.score_perfect_model([_row(0.0, 0.5, [10.0, 10.2])], 4, 15.0)) == (0.5, 0.5, 0.5, 0)
    # one of four: never an alarm
    assert _counts(pm.score_perfect_model([_row(0.0, 0.25, [10.0])], 4, 15.0)) == (0, 0, 0.25, 0)
    # forecasts add up
    both = [_row(0.0, 0.75, [10.0, 10.5, 11.0]), _row(2.0, 0.5, [12.0, 12.2])]
    assert _counts(pm.score_perfect_model(both, 4, 15.0)) == (1.5, 0.75, 1.25, 0.75)


def test_real_score_uses_the_dumped_probability_and_the_members_median():
    rows = [_row(0.0, 0.75, [10.0, 10.5, 11.0]),  # median 10.5: warns the snap at 10.4
            _row(2.0, 0.5, [14.0, 14.2]),  # median 14.1: false, and the snap at 10.4 (8.4 s ahead) unwarned
            _row(4.0, 0.25, [10.4]),  # below the threshold; the snap 6.4 s ahead unwarned
            _row(6.0, 0.75, [10.0, 10.4])]  # the snap only 4.4 s ahead: not scored; the alarm true
    assert _counts(pm.score_real(rows, [10.4], 4, 15.0)) == (3, 1, 3, 1)


def test_main_prints_the_pooled_counts(tmp_path, capsys):
    dump = {"args": {"members": 4, "horizon": 15.0, "minutes": 5.0},
            "runs": [{"seed": s, "snaps": [["vehicle", 10.4]],
                      "forecasts": {"known_sea": [_row(0.0, 0.75, [10.0, 10.5, 11.0]), _row(2.0, 0.5, [14.0, 14.2])]}}
                     for s in (1, 2)]}
    path = tmp_path / "dump.json"
    path.write_text(json.dumps(dump))
    pm.main([str(path)])
    pooled = [line for line in capsys.readouterr().out.splitlines() if "pooled" in line]
    # real per seed: 2 alarms, 1 false, 2 snaps, 1 warned; perfect model per seed: the first row (1, 0.25, 0.75,
    # 0.75) and the second (0.5, 0.5, 0.5, 0): pooled over 10 min
    assert pooled == ["dump.json pooled vehicle (10 min): false per 10 min real 2.00 pm 1.50; "
                      "warned per forecast real 2/4 = 0.500, pm 1.500/2.500 = 0.600"]
