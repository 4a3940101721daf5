"""Look-ahead runs: copies of the solver restarted from the current state, stepped over the horizon
like the driver steps the live one, with the snap detector of the run (docs/forecast.md).

A :class:`ForecastRequest` is what the live run hands over (cheap to build in the tick: a solver
snapshot, a copy of the snap detector, the commanded end states and the members' ship motions); a
:class:`LookAhead` owns one solver of its own (built once from the run's configuration, then only
restored) and turns a request into one :class:`EndForecast` per end:

- every member restarts from the snapshot and is stepped at the node's output rate, the ship end
  commanded with the member's motion at each tick time exactly as the driver commands the live end
  (``set_end_motion`` at the tick's target, Hermite interpolation by the solver in between), a
  prescribed vehicle end eased to rest from its current velocity (``p0 + v0 tau_e (1 - exp(-tau / tau_e))``,
  tau_e = 1 s; its future is not forecast);
- the end tensions of every substep go through a copy of the run's detector (same thresholds, same
  state: a slack period already under way is continued), so a forecast snap is what the node would
  report; after the horizon a member is stepped on (at most 10 peak windows) only to close a
  re-tensioning window already open, and a snap counts when its first published peak lies within
  the horizon; its time and peak are those of the snap's largest peak, the last new maximum the
  detector publishes for its slack episode (as the run's snaps are scored and tabulated:
  ``episode_maxima``). A staged re-tensioning (the cage bouncing on the tether, whose stages lie
  about its natural period 2 pi sqrt((m + m_a) L / EA) apart: 1.6 s on the 200 m file) publishes its
  first stage or not depending on whether the next stage passes it within a peak window, which a
  small error in the motion flips: the first event's time is not a property of the snap, its
  maximum is (docs/forecast.md, "Why the false alarms");
- per end: ``probability`` = members with a snap / members that finished; ``time_to_snap`` = the
  median snap time of the whole ensemble, the members without a snap counted as snapping after the
  horizon (:func:`ensemble_median_time`: NaN when fewer than half the members snap; the median, not
  the mean: members that first snap on different waves would average to an instant between them).
  Over the snapping members alone it would be biased early whenever some do not snap: a member
  whose sea is milder snaps later, after the horizon or not at all, so a median over the members
  that snap within the horizon drops the late tail of the ensemble's snap times. ``predicted_peak`` = median peak over the members that snap (the
  peak if it snaps; NaN when none does), with the standard deviation of their times; members whose
  solver diverges are left out and make the forecast degraded.

Times: members' motions are functions of solver time; the detector and the results use the clock
(``clock = anchor + solver time``), as the driver does.
"""

import collections
import copy
import math
from dataclasses import dataclass, field

import numpy as np

from tether_sim.errors import SolverDivergedError
from tether_sim.physics.boundary import END_NAMES
from tether_sim.physics.snap import SnapEvent
from tether_sim.solvers.base import relative_end_speed

VEHICLE_EASE_TIME = 1.0  # s, a prescribed vehicle end is eased to rest over this time constant


@dataclass
class ForecastRequest:
    """Everything a look-ahead needs, copied from the live run at one instant."""

    issued: float  # clock time of the state (the forecast's stamp), s
    solver_time: float  # the snapshot's solver time, s
    anchor: float  # clock = anchor + solver time
    snapshot: object  # solver.snapshot()
    detector: object  # a copy of the run's SnapDetector (ends)
    end_state: dict  # prescribed end -> (position, velocity) commanded at solver_time
    members: list  # ship motions: objects with at(solver_time) -> (position, velocity)
    horizon: float  # s
    tick: float  # output period, s (the driver's tick)
    source: str  # which forecast drives the ship
    degraded: str = ""  # why the ship-motion forecast is degraded ("" when it is not)
    clock_origin: float | None = None  # tick k of the look-ahead ends at clock origin + (tick_index + k) x tick
    tick_index: int = 0  # (the driver's own clock grid, so an exact forecast repeats the run; None: issued)


@dataclass
class EndForecast:
    """The forecast for one end (what tether_sim_msgs/SnapForecast carries)."""

    stamp: float  # clock time of the state the forecast starts from, s
    end: str
    horizon: float  # s
    probability: float  # of a snap at this end within the horizon
    time_to_snap: float  # s after the stamp, median over the members that snap (NaN: none)
    time_to_snap_std: float  # s, spread of the members' snap times (0 with one; NaN: none)
    predicted_peak: float  # N, median peak over the members that snap (NaN: none)
    members: int  # members that finished
    source: str
    degraded: bool = False
    reason: str = ""
    member_snaps: list = field(default_factory=list)  # (time s clock, peak N) of each member's snap, at its episode's maximum
    member_first_stages: list = field(default_factory=list)  # (time, peak) of the same snaps' first published events
    member_troughs: list = field(default_factory=list)  # N, each finished member's least end tension in [stamp, stamp + horizon)
    member_slack_depths: list = field(default_factory=list)  # N, each finished member's least end tension from the stamp to its snap's peak (NaN: no snap)
    slack_at_stamp: bool = False  # the end was slack or re-tensioning (the run's detector) at the stamp


class LookAhead:
    """One solver of its own, restored from each request's snapshot (module doc)."""

    def __init__(self, config, solver_factory):
        self.config = config
        self.solver = solver_factory(config)
        self.prescribed = {end: getattr(config, f"{end}_end").kind == "prescribed" for end in END_NAMES}

    def run(self, request: ForecastRequest) -> list:
        """One :class:`EndForecast` per end."""
        results = [self._member(request, motion) for motion in request.members]
        finished = [r for r in results if r is not None]
        reasons = [request.degraded] if request.degraded else []
        if len(finished) < len(results):
            reasons.append(f"{len(results) - len(finished)} of {len(results)} members diverged")
        margin = getattr(getattr(self.config, "forecast", None), "slack_margin", 0.0)
        slack = dict(zip(request.detector.locations, request.detector.thresholds))
        # a slack already under way at the stamp is the run's own, not forecast: no correction for it
        observed = dict(zip(request.detector.locations, request.detector.is_slack() | request.detector.is_rising()))
        out = []
        for end in END_NAMES:
            depths = [r["depth"][end] for r in finished]
            snaps = [r[end] for r in finished if r[end] is not None]
            stages = [r["first_stage"][end] for r in finished if r[end] is not None]
            if margin > 0.0 and not observed[end]:
                snaps = deep_snaps(snaps, depths, slack[end], margin)
                stages = deep_snaps(stages, depths, slack[end], margin)
            out.append(summarise(request.issued, end, request.horizon, snaps, len(finished), request.source,
                                 reasons, member_troughs=[r["trough"][end] for r in finished], member_slack_depths=depths,
                                 slack_at_stamp=bool(observed[end]), member_first_stages=stages))
        return out

    def _member(self, request, motion):
        """{end: (clock time, peak) of the first snap within the horizon, or None, "trough": {end: least
        tension within the horizon}, "depth": {end: least tension from the stamp to that snap's peak, NaN
        without one}}; None on divergence."""
        solver = self.solver
        solver.restore(request.snapshot)
        solver.drain_end_tensions()
        detector = copy.deepcopy(request.detector)
        first = {end: None for end in END_NAMES}
        trough = {end: math.inf for end in END_NAMES}
        depth = {end: math.nan for end in END_NAMES}
        stage = {end: None for end in END_NAMES}  # the snap's first published event (first[end] ends at its maximum)
        episode = {end: None for end in END_NAMES}  # the snap's slack_start
        history = _History(10.0 * detector.config.peak_window + 2.0 * request.tick)  # for the depth before a snap
        end_clock = request.issued + request.horizon
        t0 = request.solver_time
        n_ticks = max(1, int(math.ceil(request.horizon / request.tick - 1e-9)))
        extra = int(math.ceil(10.0 * detector.config.peak_window / request.tick))
        vehicle = request.end_state.get("vehicle") if self.prescribed["vehicle"] else None
        origin = request.issued if request.clock_origin is None else request.clock_origin
        index = 0 if request.clock_origin is None else request.tick_index
        rate = 1.0 / request.tick
        # the driver's expression for its tick targets (now = origin + k / rate; target = now - anchor)
        targets = [(origin + (index + k) / rate) - request.anchor for k in range(1, n_ticks + extra + 1)]
        ship_motion = _ShipPlan(motion, targets, n_ticks) if self.prescribed["ship"] else None
        for k in range(1, n_ticks + extra + 1):
            if k > n_ticks and not _window_open(detector, first):
                break
            t = targets[k - 1]
            if t <= solver.time:
                continue
            ship = ship_motion.at(k - 1) if ship_motion is not None else None
            veh = _eased(vehicle, t - t0) if vehicle is not None else None
            try:
                out = solver.tick(t, ship=ship, vehicle=veh)
            except SolverDivergedError:
                return None
            if out.count:
                tensions = np.column_stack([out.ship_tension, out.vehicle_tension])
                clock = out.times + request.anchor
                inside = clock < end_clock - 1e-9  # the horizon [issued, issued + horizon) of the samples' times
                if inside.any():
                    least = (tensions if inside.all() else tensions[inside]).min(axis=0)
                    for j, end in enumerate(END_NAMES):
                        trough[end] = min(trough[end], float(least[j]))
                if any(first[end] is None for end in END_NAMES):
                    history.append(clock, tensions)
                events = detector.update(clock, tensions, relative_end_speed(solver, self.config.cable.length))
                for ev in events:
                    if not isinstance(ev, SnapEvent):
                        continue
                    end = ev.location
                    if first[end] is None and request.issued - 1e-9 <= ev.time <= end_clock + 1e-9:
                        first[end] = stage[end] = (ev.time, ev.peak_tension)
                        episode[end] = ev.slack_start
                        depth[end] = history.least_before(END_NAMES.index(end), ev.time)
                    elif first[end] is not None and ev.slack_start == episode[end] and ev.peak_tension > first[end][1]:
                        first[end] = (ev.time, ev.peak_tension)  # the snap's new maximum (same slack episode)
        first["trough"] = trough
        first["depth"] = depth
        first["first_stage"] = stage
        return first


class _ShipPlan:
    """A member's ship motion at the look-ahead's tick targets, evaluated a horizon at a time where the
    member can (``at_many``: the same numbers as ``at`` one tick at a time, fewer interpreter calls);
    the ticks after the horizon, stepped only to close a re-tensioning window, are evaluated when first
    needed."""

    def __init__(self, motion, targets, n_first):
        self.motion, self.targets, self.n_first = motion, targets, n_first
        self.many = getattr(motion, "at_many", None)
        self.p = self.v = None
        self.done = 0

    def at(self, i):
        if self.many is None:
            return self.motion.at(self.targets[i])
        while i >= self.done:
            upto = self.n_first if self.done < self.n_first else len(self.targets)
            p, v = self.many(np.asarray(self.targets[self.done:upto], float))
            self.p = p if self.p is None else np.concatenate([self.p, p])
            self.v = v if self.v is None else np.concatenate([self.v, v])
            self.done = upto
        return self.p[i], self.v[i]


def summarise(stamp, end, horizon, snaps, n, source, reasons=(), **members):
    """The EndForecast of ``n`` finished members of which those in ``snaps`` ((clock time, peak) each)
    snap at ``end`` within the horizon (module doc: probability, whole-ensemble median time, median peak)."""
    times = np.array([t for t, _ in snaps]) - stamp
    peaks = np.array([p for _, p in snaps])
    return EndForecast(
        stamp=stamp, end=end, horizon=horizon,
        probability=len(snaps) / n if n else math.nan,
        time_to_snap=ensemble_median_time(times, n),
        time_to_snap_std=float(times.std()) if snaps else math.nan,
        predicted_peak=float(np.median(peaks)) if snaps else math.nan,
        members=n, source=source, degraded=bool(reasons) or n == 0,
        reason="; ".join(reasons) if reasons else ("" if n else "no member finished"),
        member_snaps=[(float(t), float(p)) for t, p in snaps], **members)


def deep_snaps(snaps, depths, slack_level, margin):
    """The snaps (one per snapping member, in member order) of the members whose least tension before
    the snap (``depths``: every finished member's, NaN for those without a snap) lies below (1 -
    ``margin``) x ``slack_level``: ``forecast.slack_margin``, the members' slack corrected for their
    measured bias against the run (docs/forecast.md, "Calibration of the members' slack")."""
    deep = [d for d in depths if not math.isnan(d)]
    if len(deep) != len(snaps):
        raise ValueError(f"{len(snaps)} member snaps but {len(deep)} depths before a snap")
    return [s for s, d in zip(snaps, deep) if d < (1.0 - margin) * slack_level]


def ensemble_median_time(times, members):
    """Median snap time of the whole ensemble of ``members`` members, of which those with a snap
    within the horizon snapped at ``times`` and the others later (after the horizon, or never): NaN
    when fewer than half of them snap (the median lies beyond the horizon); with exactly half of an
    even ensemble snapping, the last of those (the median interval's finite end). Not the median
    over the snapping members alone: that drops the ensemble's late tail (module doc)."""
    times = np.sort(np.asarray(times, float))
    k = times.size
    if members <= 0 or 2 * k < members:
        return math.nan
    if 2 * k == members:
        return float(times[-1])
    return float(np.median(np.concatenate([times, np.full(members - k, math.inf)])))


class _History:
    """The end tensions of a member's ticks, for the least tension from the stamp to a snap's peak:
    the ticks within ``keep`` s of the newest sample kept whole, the older ones folded into a least
    tension per end. Exact for a snap reported within ``keep`` s of its peak: the detector closes a
    re-tensioning window at the latest 10 peak windows after it opened, and its peak lies inside it,
    so ``keep`` = 10 peak windows and two ticks (the samples of the tick that closes it)."""

    def __init__(self, keep):
        self.keep = keep
        self.chunks = collections.deque()  # (clock times, tensions) of the recent ticks, oldest first
        self.folded = None  # least tension per end over the older ticks
        self.folded_until = -math.inf  # clock time of the newest folded sample

    def append(self, clock, tensions):
        self.chunks.append((clock, tensions))
        newest = clock[-1]
        while len(self.chunks) > 1 and self.chunks[0][0][-1] < newest - self.keep:
            old_clock, old = self.chunks.popleft()
            least = old.min(axis=0)
            self.folded = least if self.folded is None else np.minimum(self.folded, least)
            self.folded_until = float(old_clock[-1])

    def least_before(self, column, until):
        """The least tension of ``column`` over the samples at clock times <= ``until``."""
        if until < self.folded_until:
            raise ValueError(f"a snap peak at {until} s lies before the folded tension history ({self.folded_until} s)")
        least = math.inf if self.folded is None else float(self.folded[column])
        for clock, tensions in self.chunks:
            upto = clock <= until + 1e-12
            if upto.any():
                least = min(least, float(tensions[upto, column].min()))
        return least


def _window_open(detector, first):
    """A re-tensioning window is open at an end whose snap is not yet found, or at an end whose snap is
    out and may still publish a new maximum (a larger, later peak of the same slack episode)."""
    rising, watching = detector.is_rising(), detector.is_watching()
    return any((first[end] is None and bool(rising[j])) or (first[end] is not None and bool(watching[j]))
               for j, end in enumerate(detector.locations))


def _eased(state, tau):
    p0, v0 = state
    e = math.exp(-max(tau, 0.0) / VEHICLE_EASE_TIME)
    return p0 + v0 * VEHICLE_EASE_TIME * (1.0 - e), v0 * e
