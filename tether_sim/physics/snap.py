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
                           Only a re-tensioning that reaches the snap level ends a slack period: a
                           window whose maximum stays below it and that has not fallen back into
                           slack stays open (a weak first stage, e.g. a ship end holding the hanging
                           cable while the cage end is slack), so the re-tensioning that follows is
                           the slack period's snap; an end still below the snap level 10 windows
                           after its re-tensioning began has left slack without a snap (taut).
                           A snap ends its slack episode only when the end is done with it: the
                           peak is published when it is a window old (no waiting), but while the
                           tension stays out of slack, within the same 10 windows, a later peak
                           above the largest one published is the same snap's new maximum and is
                           published too (a further :class:`SnapEvent` with the same
                           ``slack_start``; a first stage just past the snap level, the end taken
                           up fully later). Ringing after a snap decays and publishes nothing.
                           A fall below the re-tension level after a published peak ends the
                           episode (what rises after it, with no slack before it, is the next
                           cycle), unless another location of the detector (one cable) is still
                           slack in the same episode: the cable has not been taken up, this end
                           holds only its hanging part, and the take-up that follows is the
                           episode's snap (its new maximum when larger).

A plausibility guard (:class:`SnapGuard`, :mod:`tether_sim.physics.snap_guard`, docs/snap_guard.md)
checks every snap event against what the cable's axial impedance, the system's kinetic energy and
the relative end speed allow, and against the shortest rise the discretisation can carry (the axial wave crossing one element).
An event that fails it is returned as a :class:`NumericalSnapWarning` instead of a
:class:`SnapEvent`: reported, never published as a snap; so is a re-tensioning at another location
that peaks when the front of a rejected one in the same slack episode arrives there
(:meth:`SnapGuard.same_episode`).
The rise rule is also applied to the running maximum as it comes: one element crossing after a maximum that rose
from the re-tension level faster than that, with nothing larger since and the tension out of slack, the window
forgets it (reported then as a numerical warning) and goes on from the current sample, slack again when that is
below the re-tension level, else with that level as a floor that is never a snap; so a spike larger than the real
re-tensioning after it does not hold the window (docs/snap_guard.md, "Each peak judged as it comes").
A rejected re-tensioning did not end its slack period: the slack period the kernel restarted after
it is merged back (start, least tension, relative speed record), so the real re-tensioning that
ends it later is measured, and judged, over the whole slack period (the kernel stops after each
sample that closed a snap event, so the guard rules on it before the samples that follow).

Slack duration runs from the downward crossing of the slack threshold to the last upward crossing
of it (linear interpolation between samples); the rise time runs from the upward crossing that
started the re-tensioning holding the peak to the peak. The per-sample work is a compiled kernel
over the whole chunk of samples (:mod:`tether_sim.physics.snap_kernel`).
"""

import math
from dataclasses import dataclass, replace

import numpy as np

from tether_sim.physics.snap_guard import KINEMATIC_END_KINDS, NumericalSnapWarning, SnapGuard, snap_guard  # noqa: F401
from tether_sim.physics.snap_kernel import (_MIN_T, _MODE, _N_EVENT, _N_STATE, _NEW_MAXIMUM, _PUBLISHED, _RISING, _SLACK,
                                            _SLACK_START, _SNAP, _SPIKE, _TAUT, _TIME_COLUMNS, snap_detector_close,
                                            snap_detector_step)
from tether_sim.spec import param


@dataclass(frozen=True)
class SnapConfig:
    """Thresholds of the slack/snap detector (DNV-RP-H103 style: slack below 10% of static)."""

    slack_fraction: float = param(0.1, doc="slack begins when tension < slack_fraction * static tension", min=0.0, max=1.0, live=True)
    slack_threshold: float = param(0.0, unit="N", doc="absolute slack threshold; > 0 overrides slack_fraction", min=0.0, max=1e9, live=True)
    retension_fraction: float = param(0.2, doc="slack ends when tension rises above retension_fraction * static (hysteresis)", min=0.0, max=10.0, live=True)
    min_slack_duration: float = param(0.1, unit="s", doc="no snap event after a slack period shorter than this", min=0.0, max=1e4, live=True)
    peak_window: float = param(1.0, unit="s", doc="after re-tensioning, the snap peak is the largest tension until none larger follows within this window (a staged rise is one event; one below the snap level is followed until it reaches it or falls back into slack; a larger peak of the same episode after a published one is published as its new maximum; at most 10 windows); keep it above the cable's axial round trip 2 L / c, the spacing of the stages", min=1e-6, max=1e4, live=True)
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


def episode_maxima(snaps) -> list:
    """One :class:`SnapEvent` per slack episode, its largest: the detector publishes a later, larger peak of a slack
    episode whose snap is out as a further event of the same location with the same ``slack_start`` (the
    snap's new maximum); a table of snaps counts the episode once, at its maximum. In the order of the episodes'
    first events."""
    best = {}
    for e in snaps:
        key = (e.location, e.slack_start)
        if key not in best or e.peak_tension > best[key].peak_tension:
            best[key] = e
    return list(best.values())


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
        return dict(zip(self.locations, self.is_slack().tolist()))  # (tolist: Python bools)

    def is_rising(self) -> np.ndarray:
        """(n_loc,) bool: a re-tensioning window is open at the location and its snap event is pending (not a
        window whose snap is out and that is only watched for a new maximum)."""
        return (self._state[:, _MODE] == _RISING) & (self._state[:, _PUBLISHED] == -np.inf)

    def is_watching(self) -> np.ndarray:
        """(n_loc,) bool: a re-tensioning window whose snap is out is still open at the location: a later, larger
        peak would be published as the snap's new maximum (a further event of the same slack episode)."""
        return (self._state[:, _MODE] == _RISING) & (self._state[:, _PUBLISHED] > -np.inf)

    def update(self, times, tensions, relative_speed=None) -> list:
        """Feed samples ``times`` (k,) and ``tensions`` (k, n_loc) (time-ordered); return new events.

        ``relative_speed``: the relative speed of the two cable ends over these samples (m/s, a number
        or (k,) samples) for the guard's bound; without it the guard keeps the largest speed it was
        given, so a guarded detector must be fed speeds from the start. A function of no arguments
        that returns the number is called only when the speed is read: when a location is out of its
        taut state at the start of these samples (its largest speed since its slack began is kept up),
        or when they start a slack period or close a window (its events); while every location stays
        taut the largest speed is read by nothing (a slack start sets it anew), so the events are those
        of the number given every time."""
        if callable(relative_speed):
            lazy = relative_speed
            relative_speed = lazy() if (self._state[:, _MODE] != _TAUT).any() else None
        else:
            lazy = None
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
                                             self._crossing(), self._events)
            if n_ev and speed is None and lazy is not None:  # (every location was taut: its events read it)
                lazy, speed = None, abs(lazy())
                if not math.isfinite(speed):
                    raise ValueError("snap detector: non-finite relative end speed")
            out += self._rows(n_ev, speed)
        return out

    def _crossing(self) -> float:
        """The guard's element crossing time (s) for the kernel's spike rule; 0 (off) without a guard or with its
        margin 0."""
        if self.guard is None or self.guard.margin <= 0.0:
            return 0.0
        return float(self.guard.crossing_time)

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
            if row[0] == _SPIKE and not isinstance(checked, NumericalSnapWarning):
                continue  # (the guard rejects every spike row by its rise; a forgotten maximum is never a snap)
            if isinstance(checked, NumericalSnapWarning) and row[0] == _SNAP:  # (a rejected new maximum: the
                merged[j] = event  # published snap before it ended the slack period all the same)
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
        if row[0] != _SNAP and row[0] != _NEW_MAXIMUM and row[0] != _SPIKE:
            return SlackStarted(time=float(row[2]), location=self.locations[j], arc_length=float(self.arc_lengths[j]),
                                tension=float(row[3]), threshold=float(self._thresholds[j, 0]))
        static = float(self.static_tensions[j])
        return SnapEvent(time=float(row[2]), location=self.locations[j], arc_length=float(self.arc_lengths[j]),
                         peak_tension=float(row[3]), min_tension=float(row[4]), slack_start=float(row[5]),
                         slack_duration=float(row[6] - row[5]), rise_time=float(row[2] - row[7]),
                         static_tension=static, amplification=float(row[3]) / static if static != 0.0 else float("inf"),
                         criterion=self.criterion)
