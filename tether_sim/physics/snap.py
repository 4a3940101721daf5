"""Streaming slack and snap-load detection (constant work per sample).

Per monitored location (cable ends, chosen arc lengths) a three-state machine runs over the
tension samples [DNV-RP-H103 slack criterion; PE2020 Sec. 6]:

``taut``   -> ``slack``   when T drops below the slack threshold (default 10% of the static
                           tension there); a :class:`SlackStarted` early warning is emitted.
``slack``  -> ``rising``  when T rises above the re-tension threshold (hysteresis).
``rising`` -> ``taut``    after ``peak_window`` seconds, once the running maximum lies behind the
                           current sample (a re-tensioning still rising at the end of the window
                           is followed until it turns, at most 10 windows): the largest tension since leaving slack
                           is the snap peak; a :class:`SnapEvent` is emitted if it reaches
                           ``snap_fraction`` x static and the slack lasted ``min_slack_duration``.
                           Dips back below the slack threshold inside the window (chatter, a weak
                           first re-tension) belong to the same slack period: no new warning, and
                           the slack period ends at the last upward crossing.

Slack duration runs from the downward crossing of the slack threshold to the last upward crossing
of it (linear interpolation between samples); the rise time runs from the upward crossing that
started the re-tensioning holding the peak to the peak. The per-sample work is a compiled kernel
over the whole chunk of samples.
"""

from dataclasses import dataclass

import numpy as np

from tether_sim.numerics.jit import jit
from tether_sim.spec import param


@dataclass(frozen=True)
class SnapConfig:
    """Thresholds of the slack/snap detector (DNV-RP-H103 style: slack below 10% of static)."""

    slack_fraction: float = param(0.1, doc="slack begins when tension < slack_fraction * static tension", min=0.0, max=1.0, live=True)
    slack_threshold: float = param(0.0, unit="N", doc="absolute slack threshold; > 0 overrides slack_fraction", min=0.0, max=1e9, live=True)
    retension_fraction: float = param(0.2, doc="slack ends when tension rises above retension_fraction * static (hysteresis)", min=0.0, max=10.0, live=True)
    min_slack_duration: float = param(0.1, unit="s", doc="no snap event after a slack period shorter than this", min=0.0, max=1e4, live=True)
    peak_window: float = param(1.0, unit="s", doc="after re-tensioning, the snap peak is the largest tension within this window (extended while the tension has not yet turned, up to 10 windows)", min=1e-6, max=1e4, live=True)
    snap_fraction: float = param(1.0, doc="a re-tensioning is a snap only if its peak reaches snap_fraction * static; weaker ones that fall back into slack are merged into the slack period", min=0.0, max=100.0, live=True)
    monitor_arc_lengths: tuple = param((), unit="m", doc="extra arc lengths (span points) monitored besides both ends")


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
(_MODE, _SLACK_START, _MIN_T, _EXIT_T, _PEAK, _PEAK_T, _RETENSION_T, _PREV_T, _PREV_TENSION, _HAS_PREV,
 _PEAK_EXIT) = range(11)
_N_STATE = 11
_TAUT, _SLACK, _RISING = 0.0, 1.0, 2.0
# Event rows: kind (0 slack, 1 snap), location, time, tension/peak, min, slack_start, exit time,
# start of the re-tensioning holding the peak.
_N_EVENT = 8


@jit
def _crossing_time(t0, y0, t1, y1, level):
    """Linear interpolation of the time where y crosses ``level`` between two samples."""
    if y1 == y0:
        return t1
    return t0 + (level - y0) * (t1 - t0) / (y1 - y0)


@jit
def _emit(events, n, kind, loc, time, value, min_t, start, exit_t, rise_start):
    events[n, 0] = kind
    events[n, 1] = loc
    events[n, 2] = time
    events[n, 3] = value
    events[n, 4] = min_t
    events[n, 5] = start
    events[n, 6] = exit_t
    events[n, 7] = rise_start
    return n + 1


@jit
def snap_detector_step(times, tensions, start, st, thresholds, peak_window, min_duration, events):
    """Advance every location's state machine over samples ``start..``; stop when ``events`` is full.

    times (k,), tensions (k, n_loc), st (n_loc, 11) state, thresholds (n_loc, 3) = (slack, re-tension,
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
                if y > s[_PEAK]:
                    s[_PEAK] = y
                    s[_PEAK_T] = t
                    s[_PEAK_EXIT] = s[_EXIT_T]
                elapsed = t - s[_RETENSION_T]
                # Close once the window has passed and the running maximum lies behind the current
                # sample (the tension has turned or levelled off); a re-tensioning still rising at the
                # end of the window is followed to its turning point, for at most 10 windows.
                if (elapsed >= peak_window and s[_PEAK_T] < t) or elapsed >= 10.0 * peak_window:
                    if s[_PEAK] >= snap_level and s[_EXIT_T] - s[_SLACK_START] >= min_duration:
                        n_ev = _emit(events, n_ev, 1.0, j, s[_PEAK_T], s[_PEAK], s[_MIN_T], s[_SLACK_START],
                                     s[_EXIT_T], s[_PEAK_EXIT])
                    s[_MODE] = _TAUT
                    mode = _TAUT
            if mode == _TAUT:
                if y < lo:
                    tc = _crossing_time(t0, y0, t, y, lo) if has_prev and y0 >= lo else t
                    s[_MODE] = _SLACK
                    s[_SLACK_START] = tc
                    s[_MIN_T] = y
                    s[_EXIT_T] = tc
                    s[_PEAK] = -np.inf
                    n_ev = _emit(events, n_ev, 0.0, j, tc, y, y, tc, tc, tc)
            elif mode == _SLACK:
                if y < s[_MIN_T]:
                    s[_MIN_T] = y
                if has_prev and y0 < lo <= y:
                    s[_EXIT_T] = _crossing_time(t0, y0, t, y, lo)
                if y > hi:
                    s[_MODE] = _RISING
                    s[_RETENSION_T] = t
                    if y > s[_PEAK]:
                        s[_PEAK] = y
                        s[_PEAK_T] = t
                        s[_PEAK_EXIT] = s[_EXIT_T]
            s[_PREV_T] = t
            s[_PREV_TENSION] = y
            s[_HAS_PREV] = 1.0
        i += 1
    return i, n_ev


class SnapDetector:
    """Streaming slack/snap detector over several locations (see the module docstring)."""

    def __init__(self, config: SnapConfig, locations: list, static_tensions: list, arc_lengths: list):
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
        self.set_config(config)

    def set_config(self, config: SnapConfig) -> None:
        """Change thresholds live; the state (slack or not) of every location is kept."""
        self.config = config
        if config.slack_threshold > 0.0:
            slack = np.full(len(self.locations), float(config.slack_threshold))
            self.criterion = f"T < {config.slack_threshold:g} N (absolute threshold)"
        else:
            slack = config.slack_fraction * np.abs(self.static_tensions)
            self.criterion = f"T < {config.slack_fraction:g} x static tension (DNV-RP-H103)"
        self._thresholds[:, 0] = slack
        self._thresholds[:, 1] = np.maximum(config.retension_fraction * np.abs(self.static_tensions), slack)
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

    def is_rising(self) -> np.ndarray:
        """(n_loc,) bool: a re-tensioning window is open at the location (its snap event is pending)."""
        return self._state[:, _MODE] == _RISING

    def update(self, times, tensions) -> list:
        """Feed samples ``times`` (k,) and ``tensions`` (k, n_loc) (time-ordered); return new events."""
        times = np.ascontiguousarray(times, dtype=np.float64).reshape(-1)
        tensions = np.ascontiguousarray(tensions, dtype=np.float64)
        if tensions.ndim == 1 and len(self.locations) == 1:
            tensions = tensions.reshape(-1, 1)
        if tensions.shape != (times.size, len(self.locations)):
            raise ValueError(f"snap detector: tensions must have shape ({times.size}, {len(self.locations)}), got {tensions.shape}")
        if not (np.all(np.isfinite(times)) and np.all(np.isfinite(tensions))):
            raise ValueError("snap detector: non-finite time or tension sample")
        out = []
        start = 0
        while start < times.size:
            start, n_ev = snap_detector_step(times, tensions, start, self._state, self._thresholds,
                                             float(self.config.peak_window), float(self.config.min_slack_duration),
                                             self._events)
            out.extend(self._event(row) for row in self._events[:n_ev])
        return out

    def flush(self) -> list:
        """Close every open re-tensioning window now (end of a run) and return those snap events."""
        out = []
        for j in np.nonzero(self._state[:, _MODE] == _RISING)[0]:
            s = self._state[j]
            if s[_EXIT_T] - s[_SLACK_START] >= self.config.min_slack_duration and s[_PEAK] >= self._thresholds[j, 2]:
                out.append(self._event(np.array([1.0, j, s[_PEAK_T], s[_PEAK], s[_MIN_T], s[_SLACK_START], s[_EXIT_T],
                                                 s[_PEAK_EXIT]])))
            s[_MODE] = _TAUT
        return out

    def _event(self, row):
        j = int(row[1])
        if row[0] == 0.0:
            return SlackStarted(time=float(row[2]), location=self.locations[j], arc_length=float(self.arc_lengths[j]),
                                tension=float(row[3]), threshold=float(self._thresholds[j, 0]))
        static = float(self.static_tensions[j])
        return SnapEvent(time=float(row[2]), location=self.locations[j], arc_length=float(self.arc_lengths[j]),
                         peak_tension=float(row[3]), min_tension=float(row[4]), slack_start=float(row[5]),
                         slack_duration=float(row[6] - row[5]), rise_time=float(row[2] - row[7]),
                         static_tension=static, amplification=float(row[3]) / static if static != 0.0 else float("inf"),
                         criterion=self.criterion)
