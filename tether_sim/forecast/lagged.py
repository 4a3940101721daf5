"""Lagged ensemble: the newest forecast pooled with the members of the forecasts just before it.

Forecasts issued every 1 / ``forecast.rate`` seconds overlap: the one issued a period earlier ran its
members over almost the same window from a state a period older. Pooling their members, each member's
snap time on the common clock, is the lagged-average forecast of numerical weather prediction
(Hoffman & Kalnay 1983, "Lagged average forecasting, an alternative to Monte Carlo forecasting",
Tellus 35A): an ensemble twice as large at no extra look-ahead, its older half less informed by
a period. With 8 members an event of probability 0.3 reads p >= 0.5 in 19 % of single forecasts; in
a pool of 16 independent members, 7 % (binomial). The pooled half is not independent of the newest
(the same wave group, seen from states a period apart), so the gain lies between those figures; the
skill benchmark measures it (docs/forecast.md, "Lagged ensemble").

:func:`pool` combines one end's forecasts, the newest last, over the newest one's window
[stamp, stamp + horizon]:

- ``members``: every finished member of the pooled forecasts;
- ``probability``: members whose (first) snap peak lies in that window / members. An older member whose
  snap lies before the newest stamp, or whose horizon ended before the window's end and which had not
  snapped by then, counts as not snapping in the window (the only thing known of it): the pool leans
  towards no snap;
- ``time_to_snap``, its spread and ``predicted_peak``: as for one forecast (the whole ensemble's median
  time, lookahead.ensemble_median_time; the median peak), over the pooled members;
- degraded when any pooled forecast is, with the reasons.

Forecasts are pooled only when their stamps lie within ``max_age`` of the newest one and they have the
newest one's source and horizon; otherwise the newest one is published as it is. ``member_troughs`` are
the newest forecast's own (the others' cover another window).
"""

import math
from dataclasses import replace

import numpy as np

from tether_sim.forecast.lookahead import ensemble_median_time


def pool(forecasts, max_age):
    """One EndForecast from ``forecasts`` (one end, oldest first, the newest last): see the module doc."""
    newest = forecasts[-1]
    used = [f for f in forecasts[:-1]
            if f.members > 0 and newest.stamp - max_age - 1e-9 <= f.stamp < newest.stamp
            and f.source == newest.source and f.horizon == newest.horizon and f.end == newest.end]
    if not used or newest.members <= 0:
        return newest
    start, stop = newest.stamp, newest.stamp + newest.horizon
    snaps = [(t, p) for f in used for t, p in f.member_snaps if start < t <= stop] + list(newest.member_snaps)
    used.append(newest)
    n = sum(f.members for f in used)
    times = np.array([t for t, _ in snaps]) - start
    peaks = np.array([p for _, p in snaps])
    reasons = [f.reason for f in used if f.degraded and f.reason]
    return replace(newest, probability=len(snaps) / n, time_to_snap=ensemble_median_time(times, n),
                   time_to_snap_std=float(times.std()) if snaps else math.nan,
                   predicted_peak=float(np.median(peaks)) if snaps else math.nan, members=n,
                   degraded=any(f.degraded for f in used),
                   reason="; ".join(dict.fromkeys(reasons)) if reasons else "",
                   member_snaps=[(float(t), float(p)) for t, p in snaps])


class LaggedEnsemble:
    """Keeps the last ``count`` raw forecasts per end and pools each new one with them (module doc);
    ``count`` 1 passes every forecast through unchanged."""

    def __init__(self, count, period):
        self.count = int(count)
        self.max_age = (self.count - 1) * float(period) * 1.5  # a skipped forecast leaves a gap: not pooled across it
        self._held = {}

    def __call__(self, forecast):
        if self.count <= 1:
            return forecast
        held = self._held.setdefault(forecast.end, [])
        held.append(forecast)
        del held[:-self.count]
        return pool(held, self.max_age)


def lagged_series(forecasts, count, period):
    """The published forecasts of a lagged ensemble of ``count`` from the raw ``forecasts`` (any ends,
    in order of issue): what a service with ``forecast.lagged`` = count publishes."""
    lag = LaggedEnsemble(count, period)
    return [lag(f) for f in forecasts]
