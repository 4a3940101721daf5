"""Scoring of snap forecasts (tether_sim.forecast.skill): the definitions of docs/forecast.md."""

import math
from types import SimpleNamespace as F

import numpy as np
import pytest

from tether_sim.forecast.skill import score


def fc(stamp, p, pred, end="vehicle", horizon=20.0, members=4):
    return F(stamp=stamp, end=end, horizon=horizon, probability=p, time_to_snap=pred - stamp, members=members)


def test_warned_late_false_alarms_episodes_and_unscored():
    forecasts = [
        fc(-30.0, float("nan"), float("nan"), members=0),  # no ship-motion forecast yet: not scored
        fc(0.0, 0.0, 0.0),
        fc(10.0, 0.8, 20.5),   # warns the 20 s snap 10 s ahead, 0.5 s off: warned
        fc(12.0, 0.6, 30.0),   # no snap near 30 s: false alarm ...
        fc(13.0, 0.6, 30.2),   # ... the same instant again: same episode
        fc(14.0, 0.4, 20.0),   # below the threshold: not a warning
        fc(17.0, 0.9, 20.0),   # right but 3 s ahead only: neither warned-by nor a false alarm
        fc(40.0, 0.7, 43.4),   # near 45 s but off by 1.6 s: false alarm (a new episode); 45 s not warned
        fc(58.0, 0.9, 61.0),   # predicts after the run's end (60 s): not scored
        fc(60.0, 0.0, 60.0),
        fc(10.0, 0.9, 20.0, end="ship"),  # another end's warning: not a vehicle warning
    ]
    snaps = [("vehicle", 20.0), ("vehicle", 45.0), ("ship", 3.0), ("vehicle", 2.0)]
    s = score(forecasts, snaps, "vehicle", until=60.0)
    assert s.snaps == 2  # 2 s is less than 5 s after the first forecast: not scorable
    assert s.warned == 1 and s.warned_fraction == 0.5
    assert s.warnings == 5 and s.false_alarms == 3 and s.false_alarm_episodes == 2
    assert s.minutes == pytest.approx(1.0)
    assert s.false_alarms_per_10min == pytest.approx(30.0) and s.episodes_per_10min == pytest.approx(20.0)
    ship = score(forecasts, snaps, "ship", until=60.0)
    assert ship.snaps == 0 and ship.warnings == 1 and ship.false_alarms == 1


def test_exact_tolerance_and_lead_are_inclusive():
    """Stamped exactly 5 s before the snap, off by exactly 1.5 s: warned, and not a false alarm."""
    s = score([fc(0.0, 0.0, 0.0), fc(10.0, 0.5, 16.5)], [("vehicle", 15.0)], "vehicle", until=40.0)
    assert (s.snaps, s.warned, s.warnings, s.false_alarms) == (1, 1, 1, 0)
    s = score([fc(0.0, 0.0, 0.0), fc(10.5, 0.5, 16.5)], [("vehicle", 15.0)], "vehicle", until=40.0)
    assert (s.snaps, s.warned, s.false_alarms) == (1, 0, 0)  # 4.5 s ahead: too late, but right


def test_reliability_bins_the_probability_against_the_snaps_within_each_horizon():
    from tether_sim.forecast.skill import reliability

    forecasts = [fc(0.0, 0.0, 0.0, horizon=10.0), fc(2.0, 0.1, 0.0, horizon=10.0),  # bin [0, .125): 1 of 2 held a snap
                 fc(4.0, 0.5, 11.0, horizon=10.0), fc(20.0, 0.5, 25.0, horizon=10.0),  # [.375, .625): 1 of 2
                 fc(6.0, 1.0, 11.0, horizon=10.0),  # the last bin includes 1
                 fc(8.0, 1.0, 11.0, horizon=10.0, members=0),  # no members: left out
                 fc(45.0, 0.0, 0.0, horizon=10.0)]  # its horizon runs past the run's end: left out
    bins = reliability(forecasts, [("vehicle", 11.0), ("ship", 25.0)], "vehicle", until=50.0)
    assert [b.forecasts for b in bins] == [2, 0, 2, 0, 1]
    assert bins[0].observed == 0.5 and bins[0].mean_probability == pytest.approx(0.05)
    assert bins[2].observed == 0.5 and bins[4].observed == 1.0
    assert bins[1].observed != bins[1].observed  # empty: NaN


def test_interval_bounds_of_few_events_are_the_exact_poisson_and_binomial_ones():
    from tether_sim.forecast.skill import fraction_interval, rate_interval

    # no event in 10 min: the upper 97.5 % Poisson bound is -ln(0.025) = 3.689 events
    low, high = rate_interval(0, 10.0)
    assert low == 0.0 and abs(high - (-math.log(0.025))) < 1e-9
    # one event: the lower bound solves P(N >= 1) = 0.025, 1 - exp(-m) = 0.025
    low, _ = rate_interval(1, 10.0)
    assert abs(low - (-math.log(0.975))) < 1e-9
    assert rate_interval(3, 20.0)[1] == rate_interval(3, 10.0)[1] / 2.0  # per 10 min
    # all of n warned: the lower bound solves p^n = 0.025
    low, high = fraction_interval(7, 7)
    assert abs(low - 0.025 ** (1 / 7)) < 1e-9 and high == 1.0
    low, high = fraction_interval(0, 4)
    assert low == 0.0 and abs(high - (1.0 - 0.025 ** (1 / 4))) < 1e-9


def test_trough_rank_spreads_ties_and_a_calibrated_ensemble_gives_a_flat_histogram():
    """In slack the end tension is round-off of either sign: the run and the members tied at "zero" must
    not all fall on rank 0 (run below every member), nor a least tension at the stamp shared by all."""
    import numpy as np

    from tether_sim.forecast.skill import trough_rank

    tol = 1e-6 * 4305.6  # the 1730 m file's slack level, N
    slack = np.array([-9.3e-12, -4.8e-12, 2.0e-13, -1.1e-11])  # members in slack: round-off
    assert trough_rank(slack, -4.3e-12, tol).tolist() == [0.2] * 5
    assert trough_rank([0.0, 5.0, 7.0], 3.0, tol).tolist() == [0.0, 1.0, 0.0, 0.0]
    assert trough_rank([1.0, 1.0, 2.0], 1.0, tol).tolist() == pytest.approx([1 / 3, 1 / 3, 1 / 3, 0.0])
    # run and 8 members exchangeable, with ties at the slack floor in a third of the draws: flat within noise
    rng = np.random.default_rng(5)
    hist = np.zeros(9)
    for _ in range(9000):
        x = rng.normal(size=9)
        if rng.random() < 1 / 3:
            x = np.where(x < 0.5, rng.normal(0.0, 1e-11, 9), x)  # slack: round-off
        hist += trough_rank(x[1:], x[0], tol)
    assert np.all(np.abs(hist / 1000.0 - 1.0) < 0.1), hist
    strict = np.zeros(9)  # what counting "members < run" made of the same kind of draws: rank 0 inflated
    rng = np.random.default_rng(5)
    for _ in range(9000):
        x = rng.normal(size=9)
        if rng.random() < 1 / 3:
            x = np.where(x < 0.5, 0.0, x)
        strict[int(np.sum(x[1:] < x[0]))] += 1
    assert strict[0] > 1.5 * strict[4]


def test_a_slack_episode_is_one_snap_at_its_maximum_whatever_event_was_predicted():
    """The detector publishes a first stage past the snap level and then the episode's larger take-up as a further
    event with the same slack_start (the 500 m, 0.2 Hz ship end: 57.54 kN at 27.151 s, 210.50 kN at 28.839 s,
    slack from 25.686 s). The run had one snap there, not two: counted once, at its maximum; a warning that
    predicted either event warned it and is no false alarm."""
    from tether_sim.forecast.skill import episode_snaps, reliability
    from tether_sim.physics.snap import NumericalSnapWarning, SlackStarted, SnapEvent

    def snap(t, peak, start, where="ship"):
        return SnapEvent(time=t, location=where, arc_length=0.0, peak_tension=peak, min_tension=1.69e3,
                         slack_start=start, slack_duration=0.156, rise_time=t - start - 0.156, static_tension=55.70e3,
                         amplification=peak / 55.70e3, criterion="T < 0.1 x static tension (DNV-RP-H103)")

    events = [SlackStarted(25.686, "ship", 0.0, 5.57e3, 5.57e3), snap(27.151, 57.54e3, 25.686),
              snap(28.839, 210.50e3, 25.686),
              NumericalSnapWarning(time=30.0, location="ship", arc_length=0.0, tension_peak=1e6, bound=2e5,
                                   rise_time=1e-4, crossing_time=2.6e-3, relative_speed=3.0, static_tension=55.70e3,
                                   slack_start=25.686, reason="one step"),
              snap(38.5, 200.0e3, 35.2), snap(28.9, 188.37e3, 25.53, "vehicle")]
    snaps = episode_snaps(events)
    assert snaps == [("ship", 28.839, (27.151, 28.839)), ("ship", 38.5, (38.5,)), ("vehicle", 28.9, (28.9,))]
    forecasts = [fc(0.0, 0.0, 0.0, end="ship"), fc(20.0, 0.75, 27.3, end="ship"), fc(30.0, 0.75, 38.0, end="ship")]
    s = score(forecasts, snaps, "ship", until=60.0)
    assert (s.snaps, s.warned, s.warnings, s.false_alarms) == (2, 2, 2, 0)
    # counted per event, the take-up 1.7 s after the predicted first stage was a second, unwarned snap
    per_event = [(e.location, e.time) for e in events if isinstance(e, SnapEvent)]
    s = score(forecasts, per_event, "ship", until=60.0)
    assert (s.snaps, s.warned) == (3, 2)
    # reliability: a forecast whose horizon holds any event of the episode saw the snap
    late = [fc(9.0, 0.75, 28.0, end="ship", horizon=18.5)]  # (9, 27.5] holds the first stage only
    assert reliability(late, snaps, "ship", until=60.0)[3].observed == 1.0


def test_false_alarms_are_classified_against_the_runs_tension_and_events():
    from tether_sim.forecast.skill import classify_false_alarm

    t = np.arange(0.0, 30.0, 0.01)
    slack, level = 10.0, 100.0

    def run(trough, peak):  # a trough at 10 s, a re-tensioning peak at 12 s
        return np.where(t < 12.0, 50.0 - (50.0 - trough) * np.exp(-((t - 10.0) / 0.5) ** 2),
                        50.0 + (peak - 50.0) * np.exp(-((t - 12.0) / 0.2) ** 2))

    args = dict(slack_level=slack, snap_level=level)
    # the run snapped at 14.5 s, inside the horizon: the predicted 12 s is a timing error
    assert classify_false_alarm(0.0, 12.0, 15.0, t, run(0.0, 150.0), snaps=[14.5], events=[(14.5, 9.0)], **args)[0] == "timing"
    # a snap 1.5 s after the horizon still counts as within it (the tolerance)
    assert classify_false_alarm(0.0, 12.0, 15.0, t, run(0.0, 150.0), snaps=[16.5], events=[], **args)[0] == "timing"
    # into the hysteresis band (1.5 x the slack level) and a peak at 1.5 x the snap level: a near miss
    kind, depth, peak = classify_false_alarm(0.0, 12.0, 15.0, t, run(15.0, 150.0), snaps=[], events=[], **args)
    assert kind == "near miss" and depth == pytest.approx(1.5, abs=1e-3) and peak == pytest.approx(1.5, abs=1e-3)
    # the same trough without a peak at the snap level: other
    assert classify_false_alarm(0.0, 12.0, 15.0, t, run(15.0, 90.0), snaps=[], events=[], **args)[0] == "other"
    # the run stayed above the re-tension level (2 x the slack level)
    kind, depth, _ = classify_false_alarm(0.0, 12.0, 15.0, t, run(25.0, 150.0), snaps=[], events=[], **args)
    assert kind == "members slack, run not" and depth == pytest.approx(2.5, abs=1e-3)
    # a published event at the predicted time that the scored snaps leave out
    assert classify_false_alarm(0.0, 12.0, 15.0, t, run(0.0, 150.0), snaps=[], events=[(12.0, 9.0)], **args)[0] == "uncounted event"
    # the run slack, no peak at the snap level, no snap: other
    assert classify_false_alarm(0.0, 12.0, 15.0, t, run(0.0, 80.0), snaps=[], events=[], **args)[0] == "other"

