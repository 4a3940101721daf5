"""Lagged ensemble (tether_sim.forecast.lagged): the newest forecast pooled with the members of the
forecasts issued just before it, over the newest one's window."""

import math

import pytest

from tether_sim.forecast.lagged import LaggedEnsemble, lagged_series, pool
from tether_sim.forecast.lookahead import EndForecast, ensemble_median_time


def ef(stamp, snaps, members=8, end="vehicle", horizon=15.0, source="known_sea", degraded=False, reason=""):
    times = [t - stamp for t, _ in snaps]
    return EndForecast(stamp, end, horizon, len(snaps) / members if members else math.nan,
                       ensemble_median_time(times, members), math.nan, math.nan, members, source, degraded, reason,
                       member_snaps=list(snaps), member_troughs=[1.0] * members)


def test_pool_counts_the_older_members_snapping_within_the_newest_window():
    old = ef(10.0, [(11.0, 5e4), (20.0, 6e4), (20.5, 7e4), (26.0, 8e4)])  # 11 s: before the newest stamp
    new = ef(12.0, [(20.2, 6.5e4), (20.4, 7.5e4), (21.0, 7e4), (27.0, 9e4)])
    f = pool([old, new], max_age=3.0)
    assert f.members == 16 and f.stamp == 12.0 and f.horizon == 15.0
    inside = [20.0, 20.5, 26.0, 20.2, 20.4, 21.0, 27.0]  # the older member at 11 s is not in [12, 27]
    assert f.probability == pytest.approx(7 / 16)
    assert math.isnan(f.time_to_snap)  # fewer than half of the 16 snap: the median lies beyond the horizon
    assert sorted(t for t, _ in f.member_snaps) == sorted(inside)
    assert f.predicted_peak == pytest.approx(7e4)  # median of the seven pooled peaks
    assert f.member_troughs == new.member_troughs


def test_pool_of_a_lone_half_and_an_empty_neighbour_falls_below_one_half():
    """The false alarm the pool is for: one forecast at 4 of 8 between forecasts that do not snap."""
    lone = ef(12.0, [(20.0, 5e4), (20.3, 5e4), (20.6, 5e4), (21.0, 5e4)])
    assert lone.probability == 0.5
    f = pool([ef(10.0, []), lone], max_age=3.0)
    assert f.probability == 0.25 and math.isnan(f.time_to_snap)


def test_pool_of_a_sure_snap_first_seen_keeps_its_time():
    """All 8 newest members snap, none of the older: 8 of 16, the time that of the snapping half's last."""
    new = ef(12.0, [(20.0 + 0.1 * i, 5e4) for i in range(8)])
    f = pool([ef(10.0, []), new], max_age=3.0)
    assert f.probability == 0.5 and f.stamp + f.time_to_snap == pytest.approx(20.7)


def test_pool_leaves_out_stale_other_source_and_empty_forecasts():
    new = ef(12.0, [(20.0, 5e4)] * 6)
    for other in (ef(8.0, []), ef(10.0, [], source="poses"), ef(10.0, [], members=0), ef(10.0, [], horizon=20.0),
                  ef(10.0, [], end="ship")):
        assert pool([other, new], max_age=3.0) is new
    assert pool([new], max_age=3.0) is new


def test_pool_is_degraded_when_a_pooled_forecast_is():
    f = pool([ef(10.0, [], degraded=True, reason="1 of 8 members diverged"), ef(12.0, [])], max_age=3.0)
    assert f.degraded and f.reason == "1 of 8 members diverged" and f.members == 16


def test_lagged_series_pools_per_end_and_not_across_a_skipped_forecast():
    raw = [ef(10.0, []), ef(10.0, [], end="ship"), ef(12.0, [(20.0, 5e4)] * 4), ef(12.0, [(20.0, 5e4)] * 8, end="ship"),
           ef(16.0, [(20.0, 5e4)] * 4)]  # 16 s: the forecast at 14 s was skipped
    out = lagged_series(raw, 2, period=2.0)
    assert [f.members for f in out] == [8, 8, 16, 16, 8]
    assert [f.probability for f in out] == [0.0, 0.0, 0.25, 0.5, 0.5]
    assert lagged_series(raw, 1, period=2.0) == raw
    lag = LaggedEnsemble(3, period=2.0)
    assert [lag(f).members for f in [ef(10.0, []), ef(12.0, []), ef(14.0, []), ef(16.0, [])]] == [8, 16, 24, 24]


def test_a_service_with_lagged_forecasts_publishes_the_pool_of_its_own_forecasts():
    """The service pools what its look-aheads return (forecast.lagged 2): the same as pooling afterwards
    the forecasts of a service that does not; on the exact forecast of a regular wave the pooled members
    agree, so the published snap time and peak are still the run's (test_forecast_lookahead.py)."""
    from test_forecast_lookahead import regular_wave_case, run  # test/forecast on the path

    snaps, raw = run(regular_wave_case(), duration=20.0)
    _, published = run(regular_wave_case(lagged=2), duration=20.0)
    assert raw and published == lagged_series(raw, 2, period=1.0)
    pooled = [f for f in published if f.members == 2 and f.probability > 0 and f.stamp + f.horizon + 2.0 <= 20.0]
    assert pooled
    for f in pooled:
        actual = next(s for s in snaps if s.location == f.end and s.time >= f.stamp)
        assert f.stamp + f.time_to_snap == pytest.approx(actual.time, abs=1e-9)
        assert f.predicted_peak == pytest.approx(actual.peak_tension, rel=1e-9)
