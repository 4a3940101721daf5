"""Streaming slack and snap-load detection (constant work per sample).

Per monitored location (cable ends, chosen arc lengths) a three-state machine runs over the
tension samples [DNV-RP-H103 slack criterion; PE2020 Sec. 6]:

``taut``   -> ``slack``   when T drops below the slack threshold (default 10% of the static
                           tension there); a :class:`SlackStarted` early warning is emitted.
``slack``  -> ``rising``  when T rises above the re-tension threshold (hysteresis).
``rising`` -> ``taut``    after ``peak_window`` seconds, once the running maximum is ``peak_window``
                           seconds old (no larger tension for a whole window after it: a
                           re-tensioning that rises in stages, or is still rising, is followed to its
                           largest stage, at most 10 windows after it began) or, when the tension
                           fell back into slack after it, lies behind the current sample: the largest
                           tension since leaving slack is the snap peak; a :class:`SnapEvent` is emitted if it reaches
                           ``snap_fraction`` x static and the slack lasted ``min_slack_duration``.
                           (``slack_threshold``, ``retension_threshold``, ``snap_threshold``: the
                           three thresholds in N instead, for a line slack by design.)
                           Dips back below the slack threshold inside the window (chatter, a weak
                           first re-tension) belong to the same slack period: no new warning, and
                           the slack period ends at the last upward crossing. When the tension has
                           fallen back below the slack threshold after the window's peak, what
                           follows is kept apart: a re-tensioning that rises above the re-tension
                           level again after that drop is followed with its own running maximum,
                           and when the window closes it gets its own window (a smaller real snap
                           after a one-step spike is not swallowed by the spike's larger peak). A
                           closed re-tensioning that reached the snap level ended its slack period:
                           a new one began where the tension fell (a :class:`SlackStarted` with that
                           time); one that did not is merged into the slack period. A third rise
                           after two drops closes the window at once (its peak is final).

A plausibility guard (:class:`SnapGuard`, :mod:`tether_sim.physics.snap_guard`, docs/snap_guard.md)
checks every snap event against what the cable's axial impedance, the system's kinetic energy and
the relative end speed allow, and against the shortest rise the discretisation can carry (the axial wave crossing one element).
An event that fails it is returned as a :class:`NumericalSnapWarning` instead of a
:class:`SnapEvent`: reported, never published as a snap; so is a re-tensioning at another location
that peaks when the front of a rejected one in the same slack episode arrives there
(:meth:`SnapGuard.same_episode`).
A rejected re-tensioning did not end its slack period: the slack period the kernel restarted after
it is merged back (start, least tension, relative speed record), so the real re-tensioning that
ends it later is measured, and judged, over the whole slack period (the kernel stops after each
sample that closed a snap event, so the guard rules on it before the samples that follow).

Slack duration runs from the downward crossing of the slack threshold to the last upward crossing
of it (linear interpolation between samples); the rise time runs from the upward crossing that
started the re-tensioning holding the peak to the peak. The per-sample work is a compiled kernel
over the whole chunk of samples.
"""

import math
from dataclasses import dataclass, replace

import numpy as np

from tether_sim.numerics.jit import jit
from tether_sim.physics.snap_guard import KINEMATIC_END_KINDS, NumericalSnapWarning, SnapGuard, snap_guard  # noqa: F401
from tether_sim.spec import param


@dataclass(frozen=True)
class SnapConfig:
    """Thresholds of the slack/snap detector (DNV-RP-H103 style: slack below 10% of static)."""

    slack_fraction: float = param(0.1, doc="slack begins when tension < slack_fraction * static tension", min=0.0, max=1.0, live=True)
    slack_threshold: float = param(0.0, unit="N", doc="absolute slack threshold; > 0 overrides slack_fraction", min=0.0, max=1e9, live=True)
    retension_fraction: float = param(0.2, doc="slack ends when tension rises above retension_fraction * static (hysteresis)", min=0.0, max=10.0, live=True)
    min_slack_duration: float = param(0.1, unit="s", doc="no snap event after a slack period shorter than this", min=0.0, max=1e4, live=True)
    peak_window: float = param(1.0, unit="s", doc="after re-tensioning, the snap peak is the largest tension until none larger follows within this window (a staged rise is one event; at most 10 windows); keep it above the cable's axial round trip 2 L / c, the spacing of the stages", min=1e-6, max=1e4, live=True)
    snap_fraction: float = param(1.0, doc="a re-tensioning is a snap only if its peak reaches snap_fraction * static; weaker ones that fall back into slack are merged into the slack period", min=0.0, max=100.0, live=True)
    retension_threshold: float = param(0.0, unit="N", doc="absolute re-tension threshold: slack ends when the tension rises above it; > 0 overrides retension_fraction (never below the slack threshold)", min=0.0, max=1e9, live=True)
    snap_threshold: float = param(0.0, unit="N", doc="absolute snap threshold: a re-tensioning is a snap only if its peak reaches it; > 0 overrides snap_fraction (for a line that hangs slack by design, e.g. an excursion tether, whose static tension is no scale)", min=0.0, max=1e9, live=True)
    monitor_arc_lengths: tuple = param((), unit="m", doc="extra arc lengths (span points) monitored besides both ends")
    guard_margin: float = param(1.5, doc="plausibility guard: a re-tensioning peak above guard_margin x the impedance/energy bound (docs/snap_guard.md), or rising faster than the axial wave crosses an element, is a numerical warning, never a snap; 0 turns the guard off", min=0.0, max=100.0, live=True)


@dataclass(frozen=True)
class SlackStarted:
    """Early warning: tension at ``location`` fell below ``threshold`` at ``time``."""

    time: float
    location: str
    arc_length: float
    tension: float
    threshold: float


@dataclass(frozen=True)
class SnapEvent:
    """The re-tensioning peak that ended a slack period (all times in s, tensions in N)."""

    time: float  # time of the peak
    location: str
    arc_length: float
    peak_tension: float
    min_tension: float  # lowest tension during the slack period
    slack_start: float
    slack_duration: float
    rise_time: float  # from leaving slack (upward threshold crossing) to the peak
    static_tension: float
    amplification: float  # peak / static
    criterion: str


# Per-location machine state columns.
(_MODE, _SLACK_START, _MIN_T, _EXIT_T, _RETENSION_T, _PREV_T, _PREV_TENSION, _HAS_PREV, _FRONT_T, _NEXT_RET,
 # a stage of a re-tensioning window: its running maximum (tension, time, slack exit and front at it) and its
 # drop back into slack (time, tension there, least since); the window's own stage, then the next one's, in
 # the same order (_NEXT: the offset between the two; _stage_peak / _stage_drop serve both)
 _PEAK, _PEAK_T, _PEAK_EXIT, _PEAK_FRONT, _DROP_T, _DROP_Y, _DROP_MIN,
 _NEXT_PEAK, _NEXT_PEAK_T, _NEXT_PEAK_EXIT, _NEXT_PEAK_FRONT, _NEXT_DROP_T, _NEXT_DROP_Y, _NEXT_DROP_MIN) = range(24)
_N_STATE = 24
_STAGE_SIZE = _NEXT_PEAK - _PEAK  # the columns of one stage
_NEXT = _STAGE_SIZE  # offset of the next stage's columns from the window's
_TIME_COLUMNS = [_SLACK_START, _EXIT_T, _PEAK_T, _RETENSION_T, _PREV_T, _PEAK_EXIT, _DROP_T, _FRONT_T, _PEAK_FRONT,
                 _NEXT_RET, _NEXT_PEAK_T, _NEXT_PEAK_EXIT, _NEXT_PEAK_FRONT, _NEXT_DROP_T]  # (shift_time)
# _FRONT_T: the last upward crossing of the re-tension level (the start of the front now rising); _PEAK_FRONT
# its value at the running maximum (the guard's rise: SnapGuard.check).
# _DROP_T: within a re-tensioning window, when the tension first fell back below the slack threshold after
# the window's running maximum (NaN while it has not); _DROP_Y the sample there, _DROP_MIN the least since
# (until a next re-tensioning begins).
# _NEXT_*: after that drop, the re-tensioning that rose above the re-tension level again (_NEXT_RET its start,
# NaN while none), with its own running maximum (time, slack exit and front at it) and its own drop: kept
# beside the window's larger earlier peak so that it gets its own window when that one closes (a one-step
# spike early in a slack period must not swallow the smaller real snap that follows it).
_TAUT, _SLACK, _RISING = 0.0, 1.0, 2.0
# Event rows: kind (0 slack started, 1 snap, 2 slack restarted where the tension fell back after a closed
# re-tensioning), location, time, tension/peak, min, slack_start, exit time, start of the re-tensioning
# holding the peak, start of the front holding the peak (re-tension level).
_N_EVENT = 9


@jit
def _crossing_time(t0, y0, t1, y1, level):
    """Linear interpolation of the time where y crosses ``level`` between two samples."""
    if y1 == y0:
        return t1
    return t0 + (level - y0) * (t1 - t0) / (y1 - y0)


@jit
def _emit(events, n, kind, loc, time, value, min_t, start, exit_t, rise_start, front_start):
    events[n, 0] = kind
    events[n, 1] = loc
    events[n, 2] = time
    events[n, 3] = value
    events[n, 4] = min_t
    events[n, 5] = start
    events[n, 6] = exit_t
    events[n, 7] = rise_start
    events[n, 8] = front_start
    return n + 1


@jit
def _stage_peak(s, o, t, y):
    """A larger maximum (t, y) of the stage at column offset ``o`` (0: the window's, _NEXT: the next one's):
    whatever rose after a drop belongs to it, so its drop is forgotten."""
    s[_PEAK + o] = y
    s[_PEAK_T + o] = t
    s[_PEAK_EXIT + o] = s[_EXIT_T]
    s[_PEAK_FRONT + o] = s[_FRONT_T]
    s[_DROP_T + o] = np.nan


@jit
def _stage_drop(s, o, has_prev, t0, y0, t, y, lo):
    """Watch the stage at offset ``o`` for its first fall below the slack level ``lo`` after its maximum."""
    if has_prev and y0 >= lo > y:
        s[_DROP_T + o] = _crossing_time(t0, y0, t, y, lo)
        s[_DROP_Y + o] = y
        s[_DROP_MIN + o] = y


@jit
def _start_next(s, t, y):
    """The re-tensioning rising above the re-tension level at (t, y) after the window's drop."""
    s[_NEXT_RET] = t
    _stage_peak(s, _NEXT, t, y)


@jit
def _close_window(s, j, y, lo, snap_level, min_duration, events, n_ev):
    """Close location ``j``'s re-tensioning window (current sample ``y``): emit its snap event when its peak
    reaches ``snap_level`` and the slack before it lasted ``min_duration``, then set what follows. Returns the
    number of event rows."""
    reached = s[_PEAK] >= snap_level
    if reached and s[_PEAK_EXIT] - s[_SLACK_START] >= min_duration:
        n_ev = _emit(events, n_ev, 1.0, j, s[_PEAK_T], s[_PEAK], s[_MIN_T], s[_SLACK_START], s[_PEAK_EXIT],
                     s[_PEAK_EXIT], s[_PEAK_FRONT])
    if np.isnan(s[_DROP_T]):  # taut since the peak
        s[_MODE] = _TAUT
        return n_ev
    # The tension fell back below the slack level after the peak. A re-tensioning that reached the snap level
    # ended the slack period: a new one began where it fell (row kind 2; SnapDetector.update merges it back
    # into the old one when the guard rejects the re-tensioning). A weaker one is merged into the slack period.
    if reached:
        s[_SLACK_START] = s[_DROP_T]
        s[_MIN_T] = s[_DROP_MIN]
        n_ev = _emit(events, n_ev, 2.0, j, s[_DROP_T], s[_DROP_Y], s[_DROP_Y], s[_DROP_T], s[_DROP_T], s[_DROP_T],
                     s[_DROP_T])
    if not np.isnan(s[_NEXT_RET]):  # what rose again after the drop gets its own window, from its own start
        s[_MODE] = _RISING
        s[_RETENSION_T] = s[_NEXT_RET]
        for k in range(_STAGE_SIZE):  # the next stage becomes the window's
            s[_PEAK + k] = s[_PEAK + _NEXT + k]
        s[_NEXT_RET] = np.nan
    else:  # slack now (or between the slack and re-tension levels: not re-tensioned yet)
        s[_MODE] = _SLACK
        s[_PEAK] = -np.inf
        if y < lo:
            s[_EXIT_T] = s[_SLACK_START]
    return n_ev


@jit
def snap_detector_close(st, j, thresholds, min_duration, events):
    """Close location ``j``'s open window at its last sample (end of a run); returns the number of event rows."""
    s = st[j]
    return _close_window(s, j, s[_PREV_TENSION], thresholds[j, 0], thresholds[j, 2], min_duration, events, 0)


@jit
def snap_detector_step(times, tensions, start, st, thresholds, peak_window, min_duration, events):
    """Advance every location's state machine over samples ``start..``; stop when ``events`` is full, or after
    a sample that closed a snap event (so that the guard can rule on it before the samples that follow).

    times (k,), tensions (k, n_loc), st (n_loc, _N_STATE) state, thresholds (n_loc, 3) = (slack, re-tension,
    snap level). Returns (next sample index, number of event rows written).
    """
    n_ev = 0
    cap = events.shape[0]
    n_loc = tensions.shape[1]
    i = start
    while i < times.shape[0]:
        if n_ev + 2 * n_loc > cap:
            break
        t = times[i]
        snapped = False
        for j in range(n_loc):
            y = tensions[i, j]
            lo = thresholds[j, 0]
            hi = thresholds[j, 1]
            snap_level = thresholds[j, 2]
            s = st[j]
            has_prev = s[_HAS_PREV] > 0.0
            t0 = s[_PREV_T]
            y0 = s[_PREV_TENSION]
            mode = s[_MODE]
            if mode == _RISING:
                # The whole window belongs to this re-tensioning: dips back into slack (chatter,
                # a first weak re-tension) extend the slack period instead of ending the event.
                if y < s[_MIN_T]:
                    s[_MIN_T] = y
                if has_prev and y0 < lo <= y:
                    s[_EXIT_T] = _crossing_time(t0, y0, t, y, lo)
                if has_prev and y0 <= hi < y:
                    s[_FRONT_T] = _crossing_time(t0, y0, t, y, hi)
                third = False
                if y > s[_PEAK]:  # a larger stage: whatever rose after a drop belongs to it
                    _stage_peak(s, 0, t, y)
                    s[_NEXT_RET] = np.nan
                elif np.isnan(s[_DROP_T]):
                    _stage_drop(s, 0, has_prev, t0, y0, t, y, lo)
                elif np.isnan(s[_NEXT_RET]):
                    if y < s[_DROP_MIN]:
                        s[_DROP_MIN] = y
                    if y > hi:
                        _start_next(s, t, y)
                elif y > s[_NEXT_PEAK]:
                    _stage_peak(s, _NEXT, t, y)
                elif np.isnan(s[_NEXT_DROP_T]):
                    _stage_drop(s, _NEXT, has_prev, t0, y0, t, y, lo)
                else:
                    if y < s[_NEXT_DROP_MIN]:
                        s[_NEXT_DROP_MIN] = y
                    # a third re-tensioning: the window's peak is final (two drops into slack behind it)
                    third = y > hi
                elapsed = t - s[_RETENSION_T]
                # Close once the window has passed and the running maximum lies behind the current sample;
                # while the tension has stayed out of slack since that maximum, only once the maximum is a
                # whole window old (no larger tension for a window after it): a re-tensioning that rises in
                # stages (a heavy end taken up step by step, one step per axial round trip of the cable,
                # with small dips between them) is one event whose peak is its largest stage. A tension
                # back in slack after the maximum closes at the window's end, and what rose again after
                # that drop continues in its own window (_close_window). At most 10 windows.
                if third or (elapsed >= peak_window and s[_PEAK_T] < t
                             and (t - s[_PEAK_T] >= peak_window or not np.isnan(s[_DROP_T]))) \
                        or elapsed >= 10.0 * peak_window:
                    n0 = n_ev
                    n_ev = _close_window(s, j, y, lo, snap_level, min_duration, events, n_ev)
                    snapped = snapped or (n_ev > n0 and events[n0, 0] == 1.0)
                    if third:
                        _start_next(s, t, y)
                    mode = s[_MODE]
            if mode == _TAUT:
                if y < lo:
                    tc = _crossing_time(t0, y0, t, y, lo) if has_prev and y0 >= lo else t
                    s[_MODE] = _SLACK
                    s[_SLACK_START] = tc
                    s[_MIN_T] = y
                    s[_EXIT_T] = tc
                    s[_PEAK] = -np.inf
                    n_ev = _emit(events, n_ev, 0.0, j, tc, y, y, tc, tc, tc, tc)
            elif mode == _SLACK:
                if y < s[_MIN_T]:
                    s[_MIN_T] = y
                if has_prev and y0 < lo <= y:
                    s[_EXIT_T] = _crossing_time(t0, y0, t, y, lo)
                if y > hi:
                    s[_MODE] = _RISING
                    s[_RETENSION_T] = t
                    s[_DROP_T] = np.nan
                    s[_NEXT_RET] = np.nan
                    s[_FRONT_T] = _crossing_time(t0, y0, t, y, hi) if has_prev and y0 <= hi else t
                    if y > s[_PEAK]:
                        s[_PEAK] = y
                        s[_PEAK_T] = t
                        s[_PEAK_EXIT] = s[_EXIT_T]
                        s[_PEAK_FRONT] = s[_FRONT_T]
            s[_PREV_T] = t
            s[_PREV_TENSION] = y
            s[_HAS_PREV] = 1.0
        i += 1
        if snapped:
            break
    return i, n_ev


class SnapDetector:
    """Streaming slack/snap detector over several locations (see the module docstring)."""

    def __init__(self, config: SnapConfig, locations: list, static_tensions: list, arc_lengths: list,
                 guard: SnapGuard | None = None):
        self.guard = guard
        self.locations = [str(name) for name in locations]
        self.static_tensions = np.asarray(static_tensions, dtype=np.float64).reshape(-1)
        self.arc_lengths = np.asarray(arc_lengths, dtype=np.float64).reshape(-1)
        n = len(self.locations)
        if self.static_tensions.shape != (n,) or self.arc_lengths.shape != (n,):
            raise ValueError(
                f"snap detector: {n} locations need {n} static tensions and {n} arc lengths, "
                f"got {self.static_tensions.size} and {self.arc_lengths.size}")
        if not np.all(np.isfinite(self.static_tensions)):
            raise ValueError("snap detector: static tensions must be finite")
        self._state = np.zeros((n, _N_STATE))
        self._thresholds = np.zeros((n, 3))
        self._events = np.zeros((64, _N_EVENT))
        self._speed = np.zeros(n)  # largest relative end speed since each location's slack began
        self._rejected = []  # the latest NumericalSnapWarning of each location (one episode, one verdict)
        self.set_config(config)

    def set_config(self, config: SnapConfig) -> None:
        """Change thresholds live; the state (slack or not) of every location is kept."""
        self.config = config
        if self.guard is not None and self.guard.margin != config.guard_margin:
            self.guard = replace(self.guard, margin=float(config.guard_margin))
        if config.slack_threshold > 0.0:
            slack = np.full(len(self.locations), float(config.slack_threshold))
            self.criterion = f"T < {config.slack_threshold:g} N (absolute threshold)"
        else:
            slack = config.slack_fraction * np.abs(self.static_tensions)
            self.criterion = f"T < {config.slack_fraction:g} x static tension (DNV-RP-H103)"
        self._thresholds[:, 0] = slack
        retension = (np.full(len(self.locations), float(config.retension_threshold)) if config.retension_threshold > 0.0
                     else config.retension_fraction * np.abs(self.static_tensions))
        self._thresholds[:, 1] = np.maximum(retension, slack)
        if config.snap_threshold > 0.0:
            self._thresholds[:, 2] = float(config.snap_threshold)
        else:
            self._thresholds[:, 2] = config.snap_fraction * np.abs(self.static_tensions)

    def set_static_tensions(self, static_tensions) -> None:
        """New reference (static) tensions, e.g. as a winch changes the length; thresholds follow, the
        state (slack or not, an open re-tensioning window) of every location is kept."""
        values = np.asarray(static_tensions, dtype=np.float64).reshape(-1)
        if values.shape != self.static_tensions.shape or not np.all(np.isfinite(values)):
            raise ValueError(f"snap detector: {self.static_tensions.size} finite static tensions needed, got {values}")
        self.static_tensions = values
        self.set_config(self.config)

    @property
    def thresholds(self) -> np.ndarray:
        """(n_loc,) slack thresholds in N."""
        return self._thresholds[:, 0].copy()

    def is_slack(self) -> np.ndarray:
        """(n_loc,) bool: the location is slack now."""
        return self._state[:, _MODE] == _SLACK

    def slack_now(self) -> dict:
        """{location: bool}: slack now (the diagnostics' flag: it clears when the tension is back above the
        re-tension level, snap or not)."""
        return dict(zip(self.locations, (bool(x) for x in self.is_slack())))

    def is_rising(self) -> np.ndarray:
        """(n_loc,) bool: a re-tensioning window is open at the location (its snap event is pending)."""
        return self._state[:, _MODE] == _RISING

    def update(self, times, tensions, relative_speed=None) -> list:
        """Feed samples ``times`` (k,) and ``tensions`` (k, n_loc) (time-ordered); return new events.

        ``relative_speed``: the relative speed of the two cable ends over these samples (m/s, a number
        or (k,) samples) for the guard's bound; without it the guard keeps the largest speed it was
        given, so a guarded detector must be fed speeds from the start."""
        times = np.ascontiguousarray(times, dtype=np.float64).reshape(-1)
        tensions = np.ascontiguousarray(tensions, dtype=np.float64)
        if tensions.ndim == 1 and len(self.locations) == 1:
            tensions = tensions.reshape(-1, 1)
        if tensions.shape != (times.size, len(self.locations)):
            raise ValueError(f"snap detector: tensions must have shape ({times.size}, {len(self.locations)}), got {tensions.shape}")
        if not (np.isfinite(times).all() and np.isfinite(tensions).all()):  # (the methods: np.all's wrapper costs ~3 us)
            raise ValueError("snap detector: non-finite time or tension sample")
        speed = None
        if relative_speed is not None:
            if type(relative_speed) is float:  # one number (the drivers'): what the line below makes of it
                speed = abs(relative_speed)
            else:
                speed = float(np.max(np.abs(np.asarray(relative_speed, dtype=np.float64)), initial=0.0))
            if not math.isfinite(speed):  # (a NaN would turn the guard's bound off)
                raise ValueError("snap detector: non-finite relative end speed")
        if speed is not None:
            np.maximum(self._speed, speed, out=self._speed)
        out = []
        start = 0
        while start < times.size:
            start, n_ev = snap_detector_step(times, tensions, start, self._state, self._thresholds,
                                             float(self.config.peak_window), float(self.config.min_slack_duration),
                                             self._events)
            out += self._rows(n_ev, speed)
        return out

    def _rows(self, n_ev, speed):
        """The events of the first ``n_ev`` rows of the kernel's event table, each snap guarded. A rejected
        re-tensioning did not end its slack period: the slack the kernel restarted where the tension fell back
        after it (a row of kind 2, emitted with it) is merged back into the slack period before it (its start
        and least tension; the relative speed since that start is kept), so that the real re-tensioning that
        ends it later is measured over the whole slack period."""
        out = []
        merged = {}
        for row in self._events[:n_ev]:
            j = int(row[1])
            if row[0] == 2.0 and j in merged:
                rejected = merged.pop(j)
                s = self._state[j]
                s[_SLACK_START] = rejected.slack_start
                s[_MIN_T] = min(s[_MIN_T], rejected.min_tension)
                continue
            event = self._event(row)
            checked = self._guarded(event, speed, float(row[2] - row[8]))
            if isinstance(checked, NumericalSnapWarning):
                merged[j] = event
            out.append(checked)
        return out

    def _guarded(self, event, speed, front_time=None):
        """A snap event checked by the guard (a NumericalSnapWarning if it fails; ``front_time``: its
        rise from the re-tension level, :meth:`SnapGuard.check`); a slack start resets the location's
        speed record to this chunk's speed (kept when no speed was given)."""
        j = self.locations.index(event.location)
        if isinstance(event, SlackStarted):
            if speed is not None:
                self._speed[j] = speed
            return event
        if self.guard is None:
            return event
        warning = self.guard.check(event, float(self._speed[j]), front_time)
        if warning is None:
            origin = next((w for w in self._rejected if self.guard.same_episode(event, w)), None)
            if origin is not None:
                warning = self.guard.carried(event, origin, float(self._speed[j]))
        if warning is None:
            return event
        self._rejected = [w for w in self._rejected if w.location != event.location] + [warning]
        return warning

    def shift_time(self, dt: float) -> None:
        """Move the time axis of everything held (slack starts, crossings, peaks, the last sample,
        rejected re-tensionings) ``dt`` s later: the samples that follow come on a clock that skipped
        ``dt`` s the cable did not live through (a node's re-synchronisation), and a slack period
        open across the skip keeps its simulated duration."""
        dt = float(dt)
        self._state[:, _TIME_COLUMNS] += dt  # (NaN stays NaN)
        self._rejected = [replace(w, time=w.time + dt, slack_start=w.slack_start + dt) for w in self._rejected]

    def flush(self) -> list:
        """Close every open re-tensioning window now (end of a run) and return those snap events (a window
        holding a second re-tensioning after a drop into slack closes as two)."""
        out = []
        for j in range(len(self.locations)):
            for _ in range(3):
                if self._state[j, _MODE] != _RISING:
                    break
                n_ev = snap_detector_close(self._state, j, self._thresholds, float(self.config.min_slack_duration),
                                           self._events)
                out += self._rows(n_ev, None)
        return out

    def _event(self, row):
        j = int(row[1])
        if row[0] != 1.0:
            return SlackStarted(time=float(row[2]), location=self.locations[j], arc_length=float(self.arc_lengths[j]),
                                tension=float(row[3]), threshold=float(self._thresholds[j, 0]))
        static = float(self.static_tensions[j])
        return SnapEvent(time=float(row[2]), location=self.locations[j], arc_length=float(self.arc_lengths[j]),
                         peak_tension=float(row[3]), min_tension=float(row[4]), slack_start=float(row[5]),
                         slack_duration=float(row[6] - row[5]), rise_time=float(row[2] - row[7]),
                         static_tension=static, amplification=float(row[3]) / static if static != 0.0 else float("inf"),
                         criterion=self.criterion)
