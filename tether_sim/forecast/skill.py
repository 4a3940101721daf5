"""Skill of snap forecasts against the snaps that happened (docs/forecast.md, benchmarks/forecast_skill.py).

A forecast *warns* when its probability is >= ``threshold``; its predicted snap time is its stamp plus
``time_to_snap``. A snap (at one end) counts as **warned** when a warning for that end stamped
``lead`` seconds or more before the snap predicted it within +-``tolerance`` s. A **false alarm** is
a warning with no snap at its end within +-``tolerance`` s of its predicted time; consecutive false
alarms predicting the same instant (within ``tolerance``) form one false-alarm *episode* (a forecast
issued every second repeats its mistake until the predicted time has passed).

A slack episode is one snap: the detector publishes a later, larger peak of an episode whose snap is out
as a further event (its new maximum, same location and ``slack_start``), and :func:`episode_snaps`
makes one snap of them, at its largest peak (as the study tables count, ``episode_maxima``), with the
times of all its events: a warning that predicted any of them warned that snap and is no false alarm
(the look-ahead reports a member's snap at its own episode's largest peak, tether_sim.forecast.lookahead).

Forecasts without members (no ship-motion forecast could be made) are not forecasts and are left out.
Only snaps that could have been warned are scored: peaks at least ``lead`` s after the first forecast
and at most one horizon after the last one (and within the run); warnings predicting an instant
after the run (less than ``tolerance`` before its end) are not scored either.
"""

import math
from dataclasses import dataclass

import numpy as np

from tether_sim.physics.snap import SnapEvent, episode_maxima


@dataclass
class Skill:
    end: str
    snaps: int  # snaps scored
    warned: int  # of which warned (module doc)
    warnings: int  # forecasts with probability >= threshold
    false_alarms: int  # warnings with no snap within +-tolerance of their predicted time
    false_alarm_episodes: int
    minutes: float  # span of the forecasts, min
    lead: float
    tolerance: float
    threshold: float

    @property
    def warned_fraction(self) -> float:
        return self.warned / self.snaps if self.snaps else float("nan")

    @property
    def false_alarms_per_10min(self) -> float:
        return 10.0 * self.false_alarms / self.minutes if self.minutes > 0 else float("nan")

    @property
    def episodes_per_10min(self) -> float:
        return 10.0 * self.false_alarm_episodes / self.minutes if self.minutes > 0 else float("nan")


def episode_snaps(events) -> list:
    """The snaps of a run's detector ``events`` (snap events; slack starts and numerical warnings are left
    out): one per slack episode, ``(location, time of its largest peak, times of all its events)``, in the
    order of the episodes' first events (module doc)."""
    snaps = [e for e in events if isinstance(e, SnapEvent)]
    return [(m.location, m.time, tuple(e.time for e in snaps if (e.location, e.slack_start) == (m.location, m.slack_start)))
            for m in episode_maxima(snaps)]


def _snap_times(snaps, end):
    """[(time, times of its events)] of the snaps at ``end``: ``snaps`` holds (end, time) pairs (one event
    each) or (end, time, event times) triples (:func:`episode_snaps`)."""
    return sorted((float(s[1]), tuple(float(x) for x in s[2]) if len(s) > 2 else (float(s[1]),))
                  for s in snaps if s[0] == end)


def score(forecasts, snaps, end, *, lead=5.0, tolerance=1.5, threshold=0.5, until=None) -> Skill:
    """Skill at ``end`` of ``forecasts`` (objects with stamp, end, horizon, probability, time_to_snap)
    against ``snaps`` ((end, peak time) pairs, or the (end, time, event times) of :func:`episode_snaps`;
    same clock) of a run that ended at ``until`` (default: the last forecast's horizon): warnings
    predicting a time after the run, and snaps after it, are not scored."""
    fc = sorted((f for f in forecasts if f.end == end and f.members > 0), key=lambda f: f.stamp)
    entries = _snap_times(snaps, end)
    if not fc:
        return Skill(end, 0, 0, 0, 0, 0, 0.0, lead, tolerance, threshold)
    first, last = fc[0].stamp, fc[-1].stamp + fc[-1].horizon
    if until is not None:
        last = min(last, until)
    scored = [times for t, times in entries if first + lead <= t <= last]
    warnings = [(f.stamp, f.stamp + f.time_to_snap) for f in fc
                if f.probability >= threshold and f.stamp + f.time_to_snap <= last - tolerance]
    warned = sum(any(stamp <= t - lead and abs(pred - t) <= tolerance for stamp, pred in warnings for t in times)
                 for times in scored)
    every = [t for _, times in entries for t in times]
    false = [pred for _, pred in warnings if not any(abs(pred - t) <= tolerance for t in every)]
    episodes, last_pred = 0, None
    for pred in false:
        if last_pred is None or abs(pred - last_pred) > tolerance:
            episodes += 1
        last_pred = pred
    minutes = (fc[-1].stamp - first) / 60.0
    return Skill(end, len(scored), warned, len(warnings), len(false), episodes, minutes, lead, tolerance, threshold)


@dataclass
class ReliabilityBin:
    low: float  # probability bin [low, high)
    high: float
    forecasts: int
    mean_probability: float  # NaN when empty
    observed: float  # fraction of these forecasts with a snap at the end within their horizon (NaN when empty)


def reliability(forecasts, snaps, end, *, edges=(0.0, 0.125, 0.375, 0.625, 0.875, 1.0), until=None) -> list:
    """Reliability of the forecast ``probability`` at ``end``: the forecasts binned by probability
    (``edges``; the last bin includes 1), and per bin the fraction whose horizon (stamp, stamp +
    horizon] held a snap at that end. A calibrated forecast has ``observed`` close to
    ``mean_probability`` in every bin. Forecasts without members, and those whose horizon runs past
    ``until`` (the run's end), are left out."""
    times = [t for _, ts in _snap_times(snaps, end) for t in ts]
    fc = [f for f in forecasts if f.end == end and f.members > 0
          and (until is None or f.stamp + f.horizon <= until)]
    out = []
    for i, (low, high) in enumerate(zip(edges[:-1], edges[1:])):
        last = i == len(edges) - 2
        sel = [f for f in fc if low <= f.probability < high or (last and f.probability == high)]
        hits = [any(f.stamp < t <= f.stamp + f.horizon for t in times) for f in sel]
        n = len(sel)
        out.append(ReliabilityBin(low, high, n, sum(f.probability for f in sel) / n if n else float("nan"),
                                  sum(hits) / n if n else float("nan")))
    return out


def rate_interval(count: int, minutes: float, confidence: float = 0.95):
    """Two-sided ``confidence`` interval (exact Poisson, Garwood) of an event rate per 10 min from
    ``count`` events in ``minutes``: few events bound the rate only loosely (0 events in 10 min: up to
    3.7 per 10 min at 95 %). The events must be independent: count false-alarm episodes, not the
    consecutive forecasts that repeat one mistake."""
    from scipy.stats import chi2

    if minutes <= 0:
        return float("nan"), float("nan")
    a = 1.0 - confidence
    low = 0.5 * chi2.ppf(a / 2.0, 2 * count) if count > 0 else 0.0
    high = 0.5 * chi2.ppf(1.0 - a / 2.0, 2 * count + 2)
    return 10.0 * low / minutes, 10.0 * high / minutes


def fraction_interval(successes: int, trials: int, confidence: float = 0.95):
    """Two-sided ``confidence`` interval (exact binomial, Clopper-Pearson) of a fraction from
    ``successes`` of ``trials`` (7 of 7 warned: the fraction is >= 59 % at 95 %, two-sided)."""
    from scipy.stats import beta

    if trials <= 0:
        return float("nan"), float("nan")
    a = 1.0 - confidence
    low = beta.ppf(a / 2.0, successes, trials - successes + 1) if successes > 0 else 0.0
    high = beta.ppf(1.0 - a / 2.0, successes + 1, trials - successes) if successes < trials else 1.0
    return float(low), float(high)


def trough_rank(members, run, tolerance):
    """The rank of the run's least tension ``run`` among the members' ``members`` (0: below all), for a
    rank histogram: a fraction for each rank from the members strictly below the run to those within
    ``tolerance`` of it, summing to 1. Ties are real here: in slack the end tension is round-off
    (1e-11 N on the 1730 m file), and a least tension at the stamp is every member's and the run's;
    counted as strictly below, every tie fell on rank 0, "the run slacker than every member"
    (docs/forecast.md, "The members' bias")."""
    m = np.asarray(members, float).reshape(-1)
    out = np.zeros(m.size + 1)
    below = int(np.sum(m < run - tolerance))
    tied = int(np.sum(np.abs(m - run) <= tolerance))
    out[below:below + tied + 1] = 1.0 / (tied + 1)
    return out


TIE_TOLERANCE = 1e-6  # slack levels: tensions closer than this are equal (round-off in slack is ~1e-15 slack levels)


FALSE_ALARM_KINDS = ("timing", "near miss", "members slack, run not", "uncounted event", "other")


def classify_false_alarm(stamp, predicted, horizon, t, tension, slack_level, snap_level, snaps, events, *,
                         tolerance=1.5, retension_ratio=2.0):
    """Why a warning predicting a snap at ``predicted`` (stamped ``stamp``) found none within
    +-``tolerance`` s: (kind, least tension of the run from the stamp to the predicted time / slack
    level, the run's largest tension within +-``tolerance`` of the predicted time / snap level). ``t``,
    ``tension``: the run's end tension at every substep; ``snaps``: the scored snap times at this end;
    ``events``: every snap event the run's detector published at this end (time, slack_start), the
    further events of an episode included. Kinds (``FALSE_ALARM_KINDS``), first that applies:

    - "uncounted event": the detector published a snap within +-tolerance that is not among ``snaps``;
    - "timing": the run snapped at this end within the forecast's horizon (+tolerance), elsewhere;
    - "near miss": the run's least tension came below ``retension_ratio`` x the slack level (the
      detector's re-tension level: into the hysteresis band, not into slack) and its tension reached
      the snap level within +-tolerance of the predicted time;
    - "members slack, run not": the run stayed above the re-tension level;
    - "other" (the run slack without a peak at the snap level, or a near miss without the peak)."""
    t = np.asarray(t, float)
    tension = np.asarray(tension, float)
    if any(abs(predicted - x) <= tolerance for x, _ in events) and not any(abs(predicted - x) <= tolerance for x in snaps):
        kind = "uncounted event"
    else:
        kind = None
    before = (t >= stamp - 1e-9) & (t <= predicted + 1e-9)
    near = (t >= predicted - tolerance) & (t <= predicted + tolerance)
    depth = float(tension[before].min()) / slack_level if before.any() else math.nan
    peak = float(tension[near].max()) / snap_level if near.any() else math.nan
    if kind is None:
        if any(stamp < x <= stamp + horizon + tolerance for x in snaps):
            kind = "timing"
        elif depth >= retension_ratio:
            kind = "members slack, run not"
        elif depth >= 1.0 and peak >= 1.0:
            kind = "near miss"
        else:
            kind = "other"
    return kind, depth, peak
