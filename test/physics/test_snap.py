"""Snap detector on synthetic tension signals whose events are known exactly."""

import math
from types import SimpleNamespace

import numpy as np
import pytest

from tether_sim.physics.snap import NumericalSnapWarning, SlackStarted, SnapConfig, SnapDetector, SnapEvent, SnapGuard
from tether_sim.studies.stats import end_statistics, event_rows

STATIC = 1000.0
DT = 1e-3


def piecewise(t, knots):
    """Piecewise-linear signal through (time, tension) knots."""
    kt, ky = zip(*knots)
    return np.interp(t, kt, ky)


# Static 1000 N; linear drop 1000 -> 0 over [1, 2] s (crosses 100 N at 1.9 s), slack at 0 until
# 3 s, rise 0 -> 2500 N over [3, 3.05] s (crosses 100 N at 3.002 s), then decay back to 1000 N.
KNOTS = [(0, STATIC), (1, STATIC), (2, 0), (3, 0), (3.05, 2500), (3.5, STATIC), (10, STATIC)]


def run(detector, t, y, chunk=777):
    events = []
    for k in range(0, t.size, chunk):  # odd chunking: results must not depend on it
        events += detector.update(t[k:k + chunk], y[k:k + chunk])
    return events + detector.flush()


def test_single_slack_snap_event_is_measured():
    t = np.arange(0.0, 6.0, DT)
    y = piecewise(t, KNOTS)[:, None]
    det = SnapDetector(SnapConfig(), ["vehicle"], [STATIC], [200.0])
    events = run(det, t, y)
    assert [type(e) for e in events] == [SlackStarted, SnapEvent]
    slack, snap = events
    # Crossing times are interpolated linearly, exact for a piecewise-linear signal (float roundoff only).
    assert slack.time == pytest.approx(1.9, abs=1e-9)
    assert slack.threshold == pytest.approx(100.0)
    assert snap.slack_start == pytest.approx(1.9, abs=1e-9)
    assert snap.slack_duration == pytest.approx(3.002 - 1.9, abs=1e-9)
    assert snap.peak_tension == pytest.approx(2500.0)
    assert snap.time == pytest.approx(3.05, abs=DT / 2)
    assert snap.rise_time == pytest.approx(3.05 - 3.002, abs=DT / 2)
    assert snap.min_tension == 0.0
    assert snap.amplification == pytest.approx(2.5)
    assert snap.static_tension == STATIC and snap.arc_length == 200.0 and snap.location == "vehicle"
    assert "DNV" in snap.criterion


def test_no_event_without_slack_even_with_big_oscillation():
    # Oscillation between 150 N and 1850 N: never below 10% of static -> no slack, no snap.
    t = np.arange(0.0, 21.0, DT)  # the last re-tensioning window closes at ~20.03 s
    y = (STATIC + 850.0 * np.sin(2 * np.pi * 0.2 * t))[:, None]
    det = SnapDetector(SnapConfig(), ["ship"], [STATIC], [0.0])
    assert run(det, t, y) == []
    # The same signal with the threshold raised live to 20% of static goes slack every cycle.
    det = SnapDetector(SnapConfig(), ["ship"], [STATIC], [0.0])
    det.update(t[:1000], y[:1000])
    det.set_config(SnapConfig(slack_fraction=0.2, retension_fraction=0.3))
    events = run(det, t[1000:], y[1000:])
    slacks = [e for e in events if isinstance(e, SlackStarted)]
    snaps = [e for e in events if isinstance(e, SnapEvent)]
    assert len(slacks) == 4 and len(snaps) == 4
    # Minimum at t = 3.75 + 5n; 150 + 850(1 - cos(w dt')) = 200 -> slack lasts 2 acos(1 - 50/850)/w.
    w = 2 * np.pi * 0.2
    assert snaps[0].slack_duration == pytest.approx(2 * np.arccos(1 - 50 / 850) / w, abs=2 * DT)
    assert snaps[0].min_tension == pytest.approx(150.0, abs=1e-3)


def test_locations_are_independent_and_thresholds_absolute():
    t = np.arange(0.0, 6.0, DT)
    cage = piecewise(t, KNOTS)
    ship = cage + 44e3  # a long tether's ship end: offset by its weight, never slack
    det = SnapDetector(SnapConfig(), ["ship", "vehicle"], [44e3 + STATIC, STATIC], [0.0, 1730.0])
    events = run(det, t, np.c_[ship, cage])
    assert {e.location for e in events} == {"vehicle"}
    det = SnapDetector(SnapConfig(slack_threshold=500.0), ["vehicle"], [STATIC], [0.0])
    slack = run(det, t, cage[:, None])[0]
    assert slack.time == pytest.approx(1.5, abs=1e-9) and slack.threshold == 500.0
    assert "absolute" in det.criterion


def test_absolute_retension_and_snap_thresholds_for_a_line_slack_by_design():
    """A slack excursion tether: 3 N at rest (static tension no scale), ringing to 60 N, then jerked to 1.5 kN.
    With slack / re-tension / snap thresholds of 10 N / 100 N / 1 kN: one slack warning at the start, the
    ringing stays inside the slack period, the jerk is the one snap (then slack again); with the re-tension
    and snap fractions of a 3 N static tension the ringing itself would be a 'snap'."""
    t = np.arange(0.0, 6.0, DT)
    knots = [(0, 3.0), (1.0, 3.0), (1.1, 60.0), (1.2, 3.0), (2.0, 3.0), (2.05, 60.0), (2.1, 3.0), (4.0, 3.0),
             (4.05, 1500.0), (4.3, 3.0), (6.0, 3.0)]
    y = piecewise(t, knots)[:, None]
    cfg = SnapConfig(slack_threshold=10.0, retension_threshold=100.0, snap_threshold=1000.0)
    events = run(SnapDetector(cfg, ["vehicle"], [3.0], [30.0]), t, y)
    assert [type(e) for e in events] == [SlackStarted, SnapEvent, SlackStarted]
    assert events[1].peak_tension == pytest.approx(1500.0) and events[1].slack_start == pytest.approx(0.0)
    relative = run(SnapDetector(SnapConfig(slack_threshold=10.0), ["vehicle"], [3.0], [30.0]), t, y)
    # (with a 3 N snap level each ringing is a re-tensioning of its own: the second is under way when the
    # first one's 1 s window closes, so it gets its own window, as it would 0.1 s later)
    assert [round(e.peak_tension) for e in relative if isinstance(e, SnapEvent)] == [60, 60, 1500]
    # the re-tension threshold is never below the slack threshold; 1.4 kN does not reach a 2 kN snap threshold
    det = SnapDetector(SnapConfig(slack_threshold=10.0, retension_threshold=5.0, snap_threshold=2000.0),
                       ["vehicle"], [3.0], [30.0])
    assert det._thresholds[0, 1] == 10.0
    assert not [e for e in run(det, t, y) if isinstance(e, SnapEvent)]


def test_short_slack_ignored_and_dips_inside_the_window_merge():
    t = np.arange(0.0, 4.0, DT)
    # A 20 ms dip below 100 N, then a re-tension to 1500 N: no snap with min_slack_duration = 0.1 s.
    knots = [(0, STATIC), (1.0, STATIC), (1.01, 50), (1.03, 50), (1.04, 1500), (1.3, STATIC), (4, STATIC)]
    y = piecewise(t, knots)[:, None]
    events = run(SnapDetector(SnapConfig(min_slack_duration=0.1), ["vehicle"], [STATIC], [0.0]), t, y)
    assert [type(e) for e in events] == [SlackStarted]
    events = run(SnapDetector(SnapConfig(min_slack_duration=0.0), ["vehicle"], [STATIC], [0.0]), t, y)
    assert [round(e.peak_tension) for e in events if isinstance(e, SnapEvent)] == [1500]
    # A second slack 0.3 s after the first re-tension, inside the 1 s window, then 2000 N at 1.9 s:
    # one slack period (warning once) and one snap with the window's peak [peak over the re-tensioning].
    knots = [(0, STATIC), (1.0, STATIC), (1.01, 50), (1.03, 50), (1.04, 1500), (1.2, 800),
             (1.34, 50), (1.8, 50), (1.9, 2000), (2.5, STATIC), (4, STATIC)]
    y = piecewise(t, knots)[:, None]
    events = run(SnapDetector(SnapConfig(), ["vehicle"], [STATIC], [0.0]), t, y)
    assert [type(e) for e in events] == [SlackStarted, SnapEvent]
    snap = events[1]
    assert snap.peak_tension == pytest.approx(2000.0) and snap.min_tension == pytest.approx(50.0)
    t_exit = 1.8 + 0.1 * 50 / 1950  # last upward crossing of 100 N
    assert snap.slack_duration == pytest.approx(t_exit - snap.slack_start, abs=1e-9)
    assert snap.rise_time == pytest.approx(1.9 - t_exit, abs=DT)


def test_chatter_around_the_threshold_is_one_slack_snap_cycle():
    # Slack from 1.9 s; 0.28 s of chatter (50 N <-> 400 N every 40 ms: above the 200 N re-tension
    # level but far below static), then the real snap to 2500 N at 2.55 s.
    knots = [(0, STATIC), (1, STATIC), (2, 0), (2.2, 50)]
    for k in range(7):
        knots += [(2.22 + 0.04 * k, 400), (2.24 + 0.04 * k, 50)]
    knots += [(2.5, 50), (2.55, 2500), (3.0, STATIC), (6, STATIC)]
    t = np.arange(0.0, 6.0, 1e-4)
    y = piecewise(t, knots)[:, None]
    events = run(SnapDetector(SnapConfig(), ["ship"], [STATIC], [0.0]), t, y)
    assert [type(e) for e in events] == [SlackStarted, SnapEvent]
    snap = events[1]
    assert snap.slack_start == pytest.approx(1.9, abs=1e-6)
    # The slack period ends at the last upward crossing of 100 N: 2.5 + 0.05 * 50/2450 s.
    assert snap.slack_duration == pytest.approx(2.5 + 0.05 * 50 / 2450 - 1.9, abs=1e-6)
    assert snap.peak_tension == pytest.approx(2500.0) and snap.rise_time == pytest.approx(0.05 * 2400 / 2450, abs=2e-4)
    # The same chatter ending in a gentle re-tension (no overshoot of static) is no snap at all.
    gentle = [(a, min(b, 900.0)) for a, b in knots]
    events = run(SnapDetector(SnapConfig(), ["ship"], [STATIC], [0.0]), t, piecewise(t, gentle)[:, None])
    assert [type(e) for e in events] == [SlackStarted]


def test_two_stage_retension_reports_the_whole_peak():
    # make-run shape (lead 07:19): re-tension at 26.6 s, fast first rise to 77 kN, dip (into slack),
    # second rise to 111 kN 0.7 s later; static 43 kN. One warning, one snap with the 111 kN peak.
    static = 43e3
    knots = [(0, static), (20, static), (21, 0), (26.6, 0), (26.63, 77e3), (26.75, 2e3), (26.85, 1e3),
             (27.33, 111e3), (28.5, 60e3), (30, static), (34, static)]
    t = np.arange(0.0, 34.0, 1e-3)
    events = run(SnapDetector(SnapConfig(), ["vehicle"], [static], [1730.0]), t, piecewise(t, knots)[:, None])
    assert [type(e) for e in events] == [SlackStarted, SnapEvent]
    assert events[1].peak_tension == pytest.approx(111e3) and events[1].time == pytest.approx(27.33, abs=1e-3)


def test_slow_monotonic_retension_is_followed_to_its_peak():
    # make run (synthetic record, L = 1730 m): after 1.9 s of slack the cage tension rises without a
    # dip for 1.8 s (longer than peak_window = 1 s) to 111 kN, then falls. The event must carry the
    # 111 kN turning point, not the value at the end of the window (76.6 kN before the fix).
    static = 43e3
    knots = [(0, static), (20, static), (21, 0), (23.6, 0), (25.5, 8e3), (27.3, 111e3), (29.0, 40e3),
             (31, static), (34, static)]
    t = np.arange(0.0, 34.0, 1e-3)
    events = run(SnapDetector(SnapConfig(), ["vehicle"], [static], [1730.0]), t, piecewise(t, knots)[:, None])
    assert [type(e) for e in events] == [SlackStarted, SnapEvent]
    assert events[1].peak_tension == pytest.approx(111e3) and events[1].time == pytest.approx(27.3, abs=1e-3)


# The cage of the 1730 m live file (static 43.06 kN) taken up from slack in stages, one per axial round trip
# 2 L / c = 0.89 s (the front reflecting between the cage and the ship; Saint-Venant's impact of a mass on a
# rod), with small dips between the stages: knots from the run's own end tension (JONSWAP Hs 3 m, seed 11,
# t = 353.4-360 s, benchmarks/forecast_skill.py's sea). The first stage tops at 42.83 kN, 0.5 % under the
# snap level, 0.96 s after the re-tensioning; the largest, 100.07 kN (2.3 x static), comes 2.7 s after it.
STAGED = [(0.0, 43.06e3), (350.0, 43.06e3), (351.0, 0.0), (353.43, 0.0), (353.47, 14.56e3), (353.83, 10.22e3),
          (354.23, 13.67e3), (354.27, 15.37e3), (354.43, 42.83e3), (354.51, 42.44e3), (355.11, 54.70e3),
          (355.35, 81.03e3), (355.59, 78.64e3), (356.19, 100.07e3), (356.83, 87.66e3), (357.07, 96.82e3),
          (357.5, 85.0e3), (360.0, 43.06e3)]


def test_a_staged_rise_is_one_snap_at_its_largest_stage():
    """A re-tensioning that rises in stages without falling back into slack is one event whose peak is
    its largest stage: the window closes once the running maximum is a whole window old. (Before
    2026-11-27 the window closed 1 s after the re-tensioning on the first sample below the running
    maximum, 42.64 kN here, under the snap level: no snap was reported for a 100 kN peak.)"""
    static = 43.06e3
    t = np.arange(0.0, 360.0, 1e-2)
    y = piecewise(t, STAGED)[:, None]
    events = run(SnapDetector(SnapConfig(), ["vehicle"], [static], [1730.0]), t, y)
    assert [type(e) for e in events] == [SlackStarted, SnapEvent]
    snap = events[1]
    assert snap.peak_tension == pytest.approx(100.07e3) and snap.time == pytest.approx(356.19, abs=1e-9)
    t_exit = 353.43 + 0.04 * 4306.0 / 14560.0  # upward crossing of the slack level (10 % of static)
    assert snap.slack_start == pytest.approx(351.0 - 4306.0 / 43060.0, abs=1e-9)
    assert snap.rise_time == pytest.approx(356.19 - t_exit, abs=1e-9)
    # the event is emitted once the peak is a window old (not before: a larger stage could still come)
    det = SnapDetector(SnapConfig(), ["vehicle"], [static], [1730.0])
    upto = t < 356.19 + 0.99
    assert not [e for e in det.update(t[upto], y[upto]) if isinstance(e, SnapEvent)]
    assert [e.peak_tension for e in det.update(t[~upto], y[~upto]) if isinstance(e, SnapEvent)] == [pytest.approx(100.07e3)]
    # the same staged rise that tops out under the snap level is no snap (nothing invented)
    low = [(a, min(b, 0.95 * static) if a > 353.0 else b) for a, b in STAGED]
    events = run(SnapDetector(SnapConfig(), ["vehicle"], [static], [1730.0]), t, piecewise(t, low)[:, None])
    assert [type(e) for e in events] == [SlackStarted]


# The ship end of PE2020 Sec. 6.2's 500 m case (f = 0.2 Hz, alpha = 0, N = 20, P = 4; static 55.70 kN: slack below
# 5.57 kN, re-tension above 11.14 kN, snap from 55.70 kN), t = 10-15 s, knots from the run's own end tension
# (benchmarks/probes/slack_record.py, 2026-11-28). Slack from 10.199 s (least 0.30 kN) while the cage end is slack
# too; at 10.69 s the ship end rises above the re-tension level to the weight of the hanging cable, 6.7-20.4 kN,
# and stays there, never back below the slack level, for 2.3 s (the first stage, 20.43 kN at 10.921 s, 37 % of
# static); the cage is taken up at 13.0 s and the ship re-tensions in stages to 212.11 kN at 13.837 s.
WEAK = [(0.0, 55.70e3), (9.8, 55.70e3), (10.199, 5.57e3), (10.268, 0.30e3), (10.50, 4.35e3), (10.589, 5.57e3),
        (10.712, 12.46e3), (10.921, 20.43e3), (11.146, 6.74e3), (11.369, 15.83e3), (11.659, 11.13e3),
        (11.897, 18.84e3), (12.156, 14.29e3), (12.420, 20.02e3), (12.677, 15.10e3), (12.928, 18.94e3),
        (13.0, 18.48e3), (13.25, 99.40e3), (13.339, 164.50e3), (13.50, 159.34e3), (13.587, 208.46e3),
        (13.837, 212.11e3), (14.089, 189.61e3), (14.50, 114.53e3), (15.5, 55.70e3), (40.0, 55.70e3)]


def test_a_weak_first_stage_that_stays_out_of_slack_does_not_hide_the_snap_after_it():
    """A first stage that rises above the re-tension level but stays below the snap level, and does not fall
    back into slack, is part of the slack period: the end has not left slack until it reaches the snap level,
    so the re-tensioning that follows is this slack period's snap. (Before 2026-11-28 the window closed 1 s
    after the weak stage's maximum, 11.92 s here, the end counted as taut, and the 212 kN snap was not seen:
    500 m, f = 0.2 Hz, 2 snaps in 6 ship slack periods.) An end still below the snap level 10 peak windows after
    its re-tensioning began has left slack without a snap."""
    static = 55.70e3
    t = np.arange(0.0, 40.0, 1e-3)
    events = run(SnapDetector(SnapConfig(), ["ship"], [static], [0.0]), t, piecewise(t, WEAK)[:, None])
    assert [type(e) for e in events] == [SlackStarted, SnapEvent]
    slack, snap = events
    assert slack.time == pytest.approx(10.199, abs=1e-9)
    assert snap.peak_tension == pytest.approx(212.11e3) and snap.time == pytest.approx(13.837, abs=1e-9)
    assert snap.slack_start == pytest.approx(10.199, abs=1e-9) and snap.min_tension == pytest.approx(300.0)
    assert snap.slack_duration == pytest.approx(10.589 - 10.199, abs=1e-9)  # to the last exit from slack
    assert snap.rise_time == pytest.approx(13.837 - 10.589, abs=1e-9)
    # the weak stage does not end the slack period even when the snap peaks 9.2 windows after the re-tensioning
    late = [(a + (6.0 if a >= 12.9 else 0.0), b) for a, b in WEAK[:-1]] + [(40.0, static)]
    late = sorted(late[:15] + [(13.5 + k, 16e3 + 2e3 * (k % 2)) for k in range(6)] + late[15:])
    events = run(SnapDetector(SnapConfig(), ["ship"], [static], [0.0]), t, piecewise(t, late)[:, None])
    assert [type(e) for e in events] == [SlackStarted, SnapEvent] and events[1].time == pytest.approx(19.837, abs=1e-9)
    assert events[1].peak_tension == pytest.approx(212.11e3) and events[1].slack_start == pytest.approx(10.199, abs=1e-9)
    # ... but 10 windows after the re-tensioning began (10.69 + 10 s) an end that never reached the snap level has
    # left slack without one: a rise after that is no snap (no slack period before it)
    later = [(a + (11.0 if a >= 12.9 else 0.0), b) for a, b in WEAK[:-1]] + [(40.0, static)]
    later = sorted(later[:15] + [(13.5 + k, 16e3 + 2e3 * (k % 2)) for k in range(10)] + later[15:])
    events = run(SnapDetector(SnapConfig(), ["ship"], [static], [0.0]), t, piecewise(t, later)[:, None])
    assert [type(e) for e in events] == [SlackStarted]
    # a weak stage that then falls back into slack is merged into the slack period as before (one slack warning)
    dip = sorted(WEAK[:14] + [(12.6, 2.0e3), (12.75, 2.0e3)] + WEAK[16:])
    events = run(SnapDetector(SnapConfig(), ["ship"], [static], [0.0]), t, piecewise(t, dip)[:, None])
    assert [type(e) for e in events] == [SlackStarted, SnapEvent]
    assert events[1].slack_start == pytest.approx(10.199, abs=1e-9) and events[1].peak_tension == pytest.approx(212.11e3)


# The ship end of PE2020 Sec. 6.2's 500 m case at alpha = 1 (f = 0.2 Hz, N = 20, P = 4; static 55.70 kN: slack below
# 5.57 kN, re-tension above 11.14 kN, snap from 55.70 kN), t = 24.6-30 s, knots at the turning points of the run's own
# end tension (`LL=500 FF=0.2 AL=1 NN=20 PERIODS=6 benchmarks/probes/slack_record.py`, 2026-11-28). Slack from 25.69 s
# (least 1.69 kN); while the cage end is slack the ship end holds the hanging cable and rises in stages to a first
# stage that just passes the snap level (57.54 kN = 1.03 x static at 27.151 s), sinks to 15.19 kN without going slack
# again, and is taken up with the cage at 28.839 s: 210.50 kN, the slack period's real snap. A window (1 s) after the
# first stage the tension is at 51.6 kN, still below it: the window closes on the first stage.
FIRST_STAGE = [(0.0, 55.70e3), (24.6, 55.70e3), (25.134, 32.09e3), (25.251, 34.28e3), (25.773, 1.69e3),
               (26.051, 18.43e3), (26.108, 12.65e3), (26.133, 14.73e3), (26.300, 5.63e3), (26.562, 18.65e3),
               (26.811, 10.79e3), (26.892, 39.70e3), (27.046, 35.42e3), (27.151, 57.54e3), (27.322, 42.06e3),
               (27.399, 53.01e3), (27.579, 27.17e3), (27.649, 33.15e3), (27.789, 15.19e3), (27.915, 27.94e3),
               (27.986, 23.65e3), (28.1, 39.29e3), (28.15, 51.37e3), (28.2, 56.73e3), (28.3, 73.17e3),
               (28.4, 108.51e3), (28.5, 136.45e3), (28.6, 175.23e3), (28.7, 204.78e3), (28.839, 210.50e3),
               (29.0, 186.12e3), (29.2, 169.45e3), (29.5, 143.73e3), (29.828, 55.77e3), (30.5, 40.0e3),
               (32.0, 55.70e3), (50.0, 55.70e3)]


def crossing(knots, level, after=0.0, upward=False):
    """The first time after ``after`` at which the piecewise-linear ``knots`` cross ``level`` (down, or up)."""
    for (ta, ya), (tb, yb) in zip(knots, knots[1:]):
        if tb > after and ((ya >= level > yb) if not upward else (ya < level <= yb)):
            return ta + (level - ya) * (tb - ta) / (yb - ya)
    return None


@pytest.mark.jit_off  # `make test` also runs it with NUMBA_DISABLE_JIT=1 (the detector kernel as plain Python)
@pytest.mark.parametrize("chunk", [1, 777, 100_000])
def test_a_larger_peak_later_in_the_same_slack_episode_is_published_as_its_new_maximum(chunk):
    """A first stage that just passes the snap level is published at once (live latency), but it does not end
    the episode: while the re-tensioning window is open (until the end falls back into slack, or 10 peak windows
    after its re-tensioning began) a later peak above the largest one published is the same snap's new maximum
    and is published too, with the same slack period (a consumer tells the episode by its slack_start); the
    episode's largest published peak is its snap load. (Before 2026-11-28 the window closed a window after the
    57.54 kN stage, the end counted as taut, and the 210.50 kN re-tensioning was not published.)"""
    static = 55.70e3
    t = np.arange(0.0, 50.0, 1e-3)
    y = piecewise(t, FIRST_STAGE)[:, None]
    events = run(SnapDetector(SnapConfig(), ["ship"], [static], [0.0]), t, y, chunk)
    assert [type(e) for e in events] == [SlackStarted, SnapEvent, SnapEvent]
    slack, first, larger = events
    start = crossing(FIRST_STAGE, 0.1 * static)
    exit_t = crossing(FIRST_STAGE, 0.1 * static, after=start, upward=True)
    assert slack.time == pytest.approx(start, abs=1e-9)
    assert first.peak_tension == pytest.approx(57.54e3) and first.time == pytest.approx(27.151, abs=1e-9)
    assert larger.peak_tension == pytest.approx(210.50e3) and larger.time == pytest.approx(28.839, abs=1e-9)
    for snap in (first, larger):  # one slack episode: the same slack period, the rise from its last exit
        assert snap.slack_start == pytest.approx(start, abs=1e-9) and snap.min_tension == pytest.approx(1.69e3)
        assert snap.slack_duration == pytest.approx(exit_t - start, abs=1e-9)
        assert snap.rise_time == pytest.approx(snap.time - exit_t, abs=1e-9)
    # a study table counts the episode once, at its maximum (the per-case peak, the per-event rows)
    tap = SimpleNamespace(t_max=[210.50e3, static], t_min=[1.69e3, static])
    row = end_statistics(events, [static, static], tap)
    assert row["ship_n_snap"] == 1 and row["ship_snap_peak_N"] == pytest.approx(210.50e3) and row["ship_n_slack"] == 1
    assert row["ship_slack_total_s"] == pytest.approx(exit_t - start, abs=1e-9)
    assert [r["peak_N"] for r in event_rows(events)] == [pytest.approx(210.50e3)]
    # the same event as the detector publishes when the first stage stays under the snap level (a window whose
    # maximum is below it stays open): the new maximum does not depend on where the first stage tops out
    under = [(a, 55.0e3 if b == 57.54e3 else b) for a, b in FIRST_STAGE]
    events = run(SnapDetector(SnapConfig(), ["ship"], [static], [0.0]), t, piecewise(t, under)[:, None], chunk)
    assert [type(e) for e in events] == [SlackStarted, SnapEvent] and events[1] == larger
    # the first event is not held back for the second: it is out a window after its peak
    det = SnapDetector(SnapConfig(), ["ship"], [static], [0.0])
    early = det.update(t[t < 28.2], y[t < 28.2])
    assert [e.peak_tension for e in early if isinstance(e, SnapEvent)] == [pytest.approx(57.54e3)]
    # ringing after the snap decays (each swing below the largest published peak): nothing more is published,
    # nor is a larger taut peak of a later cycle once 10 windows have passed since the re-tensioning began
    ringing = [k for k in FIRST_STAGE if k[0] <= 28.839] + [(29.1, 150e3), (29.3, 195e3), (29.5, 120e3), (29.7, 180e3), (30.0, 110e3),
                                   (30.4, 160e3), (31.0, 100e3), (36.5, 150e3), (37.5, 260e3), (39.0, 55.70e3),
                                   (50.0, 55.70e3)]
    events = run(SnapDetector(SnapConfig(), ["ship"], [static], [0.0]), t, piecewise(t, ringing)[:, None], chunk)
    assert [type(e) for e in events] == [SlackStarted, SnapEvent, SnapEvent]
    assert [e.peak_tension for e in events[1:]] == [pytest.approx(57.54e3), pytest.approx(210.50e3)]
    # the episode's re-tensioning is over once the tension falls back below the re-tension level (11.14 kN) after
    # the snap: the next cycle's larger peak, with no slack period before it, is no snap (975 m, 0.2 Hz, N 20 ship:
    # 171.9 kN at 33.96 s, down to 10 kN at 35.8 s, between the slack and re-tension levels, 179.0 kN at 39.04 s)
    cycle = [k for k in FIRST_STAGE if k[0] <= 29.5] + [(30.8, 9.0e3), (31.5, 9.5e3), (33.0, 60e3), (33.8, 230e3),
                                                         (35.0, 55.70e3), (50.0, 55.70e3)]
    events = run(SnapDetector(SnapConfig(), ["ship"], [static], [0.0]), t, piecewise(t, cycle)[:, None], chunk)
    assert [type(e) for e in events] == [SlackStarted, SnapEvent, SnapEvent]
    assert [e.peak_tension for e in events[1:]] == [pytest.approx(57.54e3), pytest.approx(210.50e3)]
    # an end that falls back into slack after the first stage ends the episode: what follows is a new slack
    # period with its own snap (the first stage's re-tensioning reached the snap level)
    dip = sorted([k for k in FIRST_STAGE if not 27.6 < k[0] < 27.9] + [(27.70, 2.0e3), (27.80, 2.0e3)])
    events = run(SnapDetector(SnapConfig(), ["ship"], [static], [0.0]), t, piecewise(t, dip)[:, None], chunk)
    assert [type(e) for e in events] == [SlackStarted, SnapEvent, SlackStarted, SnapEvent]
    assert events[2].time == pytest.approx(crossing(dip, 0.1 * static, after=27.2), abs=1e-9)
    assert events[3].slack_start == pytest.approx(events[2].time, abs=1e-9)
    assert events[3].peak_tension == pytest.approx(210.50e3)
    # the guard judges every published peak: with no relative end speed its bound is 1.5 x 2 x static = 167.1 kN,
    # which passes the first stage and rejects the 210.50 kN new maximum
    guard = SnapGuard(impedance=1e4, stiffness=1e5, mass=1e4, crossing_time=1e-3)
    events = run(SnapDetector(SnapConfig(), ["ship"], [static], [0.0], guard), t, y, chunk)
    assert [type(e) for e in events] == [SlackStarted, SnapEvent, NumericalSnapWarning]
    assert events[2].tension_peak == pytest.approx(210.50e3) and events[2].bound == pytest.approx(3.0 * static)


# The cage end of the 500 m, alpha = 0 run of WEAK above (static 43.06 kN: slack below 4.31 kN, re-tension above
# 8.61 kN): slack from 10.17 s, at 0 kN until the cable is taken up at 13.0 s, then its snap (knots rounded from the
# run's end tension up to 11 s; the take-up as the ship's, 0.3 s later at the peak).
CAGE = [(0.0, 43.06e3), (9.6, 89.18e3), (9.8, 65.32e3), (10.0, 40.93e3), (10.1, 11.00e3), (10.2, 5.47e3),
        (10.3, 0.0), (13.0, 0.0), (13.3, 120.0e3), (13.6, 190.0e3), (14.0, 150.0e3), (15.0, 43.06e3),
        (40.0, 43.06e3)]


@pytest.mark.jit_off  # `make test` also runs it with NUMBA_DISABLE_JIT=1 (the detector kernel as plain Python)
@pytest.mark.parametrize("chunk", [1, 777, 100_000])
def test_a_first_stage_that_sags_below_the_retension_level_while_the_other_end_is_slack_keeps_its_episode(chunk):
    """The ship's hover of WEAK (holding the hanging cable while the cage end is slack) with its first stage at
    10.921 s just past the snap level (57.0 kN), published a window later, and a later sag of the hover (12.156 s)
    to 9.0 kN: below the re-tension level (11.14 kN), not into slack (5.57 kN). The cage end is slack all along:
    the cable has not been taken up, the ship holds only its hanging part. The take-up of the whole cable from
    13.0 s is the same slack episode's snap, published as its new maximum (same slack_start), as it is when the
    sag stays above the re-tension level. (Before: the fall below the re-tension level after the published first
    stage ended the episode, and the 212.11 kN re-tensioning was withheld, no slack period being before it.)"""
    static = [55.70e3, 43.06e3]
    t = np.arange(0.0, 40.0, 1e-3)
    knots = [(a, {20.43e3: 57.0e3, 14.29e3: 9.0e3}.get(b, b)) for a, b in WEAK]
    y = np.column_stack([piecewise(t, knots), piecewise(t, CAGE)])
    events = run(SnapDetector(SnapConfig(), ["ship", "vehicle"], static, [0.0, 500.0]), t, y, chunk)
    ship = [e for e in events if e.location == "ship"]
    assert [type(e) for e in ship] == [SlackStarted, SnapEvent, SnapEvent]
    slack, first, larger = ship
    assert first.peak_tension == pytest.approx(57.0e3) and first.time == pytest.approx(10.921, abs=1e-9)
    assert larger.peak_tension == pytest.approx(212.11e3) and larger.time == pytest.approx(13.837, abs=1e-9)
    assert larger.slack_start == first.slack_start == pytest.approx(slack.time, abs=1e-9)
    # the cage's own events are those it has alone (one slack period, one snap)
    cage = [e for e in events if e.location == "vehicle"]
    alone = run(SnapDetector(SnapConfig(), ["vehicle"], static[1:], [500.0]), t, y[:, 1:], chunk)
    assert cage == alone and [type(e) for e in cage] == [SlackStarted, SnapEvent]
    assert cage[1].peak_tension == pytest.approx(190.0e3)
    # the guard judges the new maximum: with no relative end speed its bound is 1.5 x 2 x static = 167.1 kN at the
    # ship, which passes the first stage and rejects the 212.11 kN take-up (a warning, the snap before it stands)
    guard = SnapGuard(impedance=1e4, stiffness=1e5, mass=1e4, crossing_time=1e-3)
    events = run(SnapDetector(SnapConfig(), ["ship", "vehicle"], static, [0.0, 500.0], guard), t, y, chunk)
    ship = [e for e in events if e.location == "ship"]
    assert [type(e) for e in ship] == [SlackStarted, SnapEvent, NumericalSnapWarning]
    assert ship[2].tension_peak == pytest.approx(212.11e3) and ship[2].bound == pytest.approx(3.0 * static[0])
    # the detector sees only the locations it monitors: the ship end alone cannot know the cage is slack, and its
    # sag below the re-tension level ends the episode (the take-up withheld, as before)
    alone = run(SnapDetector(SnapConfig(), ["ship"], static[:1], [0.0]), t, y[:, :1], chunk)
    assert [type(e) for e in alone] == [SlackStarted, SnapEvent] and alone[1].peak_tension == pytest.approx(57.0e3)
    # once the cable has been taken up the episode ends as before at a fall below the re-tension level: the ship
    # down to 9 kN at 16.5 s (as at 975 m, 0.2 Hz: 10 kN 1.8 s after the snap) while the cage is slack again, in a
    # slack period of its own that began after the ship's re-tensioning (16.0 s); the next cycle's 230 kN at the
    # ship is no snap (no slack period before it), the cage's own snap of that cycle is
    cycle = [k for k in knots if k[0] <= 14.5] + [(16.5, 9.0e3), (17.2, 9.5e3), (18.5, 60e3), (19.0, 230e3),
                                                 (20.0, 55.70e3), (40.0, 55.70e3)]
    cage_cycle = [k for k in CAGE if k[0] <= 14.0] + [(15.0, 43.06e3), (15.9, 5.0e3), (16.0, 0.0), (18.4, 0.0),
                                                      (19.0, 180e3), (20.0, 43.06e3), (40.0, 43.06e3)]
    y = np.column_stack([piecewise(t, cycle), piecewise(t, cage_cycle)])
    events = run(SnapDetector(SnapConfig(), ["ship", "vehicle"], static, [0.0, 500.0]), t, y, chunk)
    ship = [e for e in events if e.location == "ship"]
    assert [type(e) for e in ship] == [SlackStarted, SnapEvent, SnapEvent]
    assert [e.peak_tension for e in ship[1:]] == [pytest.approx(57.0e3), pytest.approx(212.11e3)]
    cage = [e for e in events if e.location == "vehicle"]
    assert [type(e) for e in cage] == [SlackStarted, SnapEvent, SlackStarted, SnapEvent]
    assert cage[3].peak_tension == pytest.approx(180e3)


def test_bad_input_is_rejected_clearly():
    with pytest.raises(ValueError, match="2 locations"):
        SnapDetector(SnapConfig(), ["ship", "vehicle"], [1.0], [0.0, 1.0])
    det = SnapDetector(SnapConfig(), ["ship"], [1.0], [0.0])
    with pytest.raises(ValueError, match="shape"):
        det.update(np.zeros(3), np.zeros((3, 2)))
    with pytest.raises(ValueError, match="non-finite"):
        det.update(np.zeros(2), np.array([[1.0], [np.nan]]))


def test_slack_now_clears_when_a_slack_period_ends_without_a_snap():
    """The diagnostics' slack flag is the state now: a slack period that re-tensions gently (no snap event,
    so no event would clear an event-latched flag) leaves the location not slack."""
    knots = [(0, STATIC), (1, STATIC), (2, 0), (3, 0), (5, 0.9 * STATIC), (10, 0.9 * STATIC)]
    t = np.arange(0.0, 8.0, DT)
    y = piecewise(t, knots)[:, None]
    det = SnapDetector(SnapConfig(), ["vehicle"], [STATIC], [200.0])
    during = det.update(t[t < 2.5], y[t < 2.5])
    assert [type(e) for e in during] == [SlackStarted] and det.slack_now() == {"vehicle": True}
    after = det.update(t[t >= 2.5], y[t >= 2.5]) + det.flush()
    assert not any(isinstance(e, SnapEvent) for e in after)
    assert det.slack_now() == {"vehicle": False}


@pytest.mark.parametrize("speed", [math.nan, math.inf, np.array([0.5, math.nan])])
def test_a_non_finite_relative_end_speed_is_refused_whether_one_number_or_an_array(speed):
    # a NaN speed would make the snap guard's bound NaN, and "peak > NaN" never rejects: refused instead
    det = SnapDetector(SnapConfig(), ["ship"], [1000.0], [0.0])
    with pytest.raises(ValueError, match="non-finite relative end speed"):
        det.update(np.array([0.0, 0.001]), np.array([1000.0, 1000.0]), speed)
    assert det.update(np.array([0.002, 0.003]), np.array([1000.0, 1000.0]), 0.5) == []
