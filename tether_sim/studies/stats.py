"""Snap statistics of one run in engineering terms (a study table row; tensions in N, times in s).

Per end (``ship`` at s = 0, ``vehicle`` at s = L), from the run's slack/snap events
(:mod:`tether_sim.physics.snap`, the detector the node and ``tether-sim-offline`` use) and from the
tension at every solver substep:

``n_slack``          slack periods (tension fell below the detector's slack threshold)
``n_snap``           snaps (re-tensionings after a slack period that reached the snap level; a
                     slack episode counts once, at its largest published peak: ``episode_maxima``)
``snap_peak_N``      largest snap peak; ``snap_daf`` = that peak / static tension
``T_max_N``, ``T_min_N``  extremes over every substep; ``daf`` = T_max / static (dynamic
                     amplification factor of the run, snap or not)
``slack_max_s``      longest slack period that ended in a snap; ``slack_total_s`` their sum
``rise_time_s``      rise time of the largest snap (upward threshold crossing -> peak)
``n_numerical``      re-tensionings the snap guard rejected as numerical (docs/snap_guard.md): never
                     counted as snaps; ``numerical_peak_N`` the largest of them (``T_max_N`` and
                     ``daf`` are the raw solution's and include such peaks)
``dnv_slack_ok``     DNV-RP-H103 slack criterion met: T_min >= 0.1 x static tension (see below)

DNV-RP-H103 (Modelling and Analysis of Marine Operations, April 2011), Sec. 3.4.3 "slack sling
criterion": snap loads are avoided when the hydrodynamic (dynamic) force stays below 90 % of the
minimum static force, F_hydro <= 0.9 F_static-min. In a time-domain run of a line with a static
tension T_static at an end this is T(t) >= T_static - 0.9 T_static = 0.1 T_static at every substep,
which is what is checked here (the threshold is fixed at 10 %, independent of ``snap.slack_fraction``,
which only drives the event detector).
"""

import math

from tether_sim.physics.boundary import END_NAMES
from tether_sim.physics.snap import NumericalSnapWarning, SnapEvent, SlackStarted, episode_maxima

DNV_SLACK_FRACTION = 0.1  # T >= 0.1 T_static <=> F_hydro <= 0.9 F_static [DNV-RP-H103 Sec. 3.4.3]


class TensionTap:
    """Wraps a solver; keeps the extremes of the end tensions of every substep it hands out.

    Used as ``solver_factory`` of the offline runner so the case runs the same driver loop and
    still sees every substep (the driver drains them for snap detection; so does this)."""

    def __init__(self, factory):
        self._factory = factory
        self.solvers = []
        self.t_max = [-math.inf, -math.inf]
        self.t_min = [math.inf, math.inf]
        self.samples = 0

    def __call__(self, config):
        solver = self._factory(config)
        self.solvers.append(solver)
        return _Tapped(solver, self)

    def take(self, times, ship, vehicle):
        if len(times):
            self.samples += len(times)
            for j, series in enumerate((ship, vehicle)):
                self.t_max[j] = max(self.t_max[j], float(max(series)))
                self.t_min[j] = min(self.t_min[j], float(min(series)))


class _Tapped:
    def __init__(self, solver, tap):
        object.__setattr__(self, "_solver", solver)
        object.__setattr__(self, "_tap", tap)

    def __getattr__(self, name):
        return getattr(self._solver, name)

    def __setattr__(self, name, value):
        setattr(self._solver, name, value)

    def advance_to(self, t):
        object.__setattr__(self, "_advanced", False)
        n = self._solver.advance_to(t)
        object.__setattr__(self, "_advanced", True)
        return n

    def drain_end_tensions(self):
        """Samples after a completed advance count; those the driver drains to discard them (after
        the static solve, after a divergence and restore) do not."""
        times, ship, vehicle = self._solver.drain_end_tensions()
        if self.__dict__.get("_advanced"):
            self._tap.take(times, ship, vehicle)
        object.__setattr__(self, "_advanced", False)
        return times, ship, vehicle


def end_statistics(events, static_tensions, tap) -> dict:
    """Columns ``<end>_<statistic>`` for both ends (NaN where a statistic does not exist)."""
    row = {}
    for j, end in enumerate(END_NAMES):
        static = float(static_tensions[j])
        snaps = episode_maxima(e for e in events if isinstance(e, SnapEvent) and e.location == end)
        slacks = [e for e in events if isinstance(e, SlackStarted) and e.location == end]
        largest = max(snaps, key=lambda e: e.peak_tension, default=None)
        numerical = [e for e in events if isinstance(e, NumericalSnapWarning) and e.location == end]
        t_max, t_min = tap.t_max[j], tap.t_min[j]
        finite = math.isfinite(t_max)
        row.update({
            f"{end}_static_N": static,
            f"{end}_T_max_N": t_max if finite else math.nan,
            f"{end}_T_min_N": t_min if finite else math.nan,
            f"{end}_daf": t_max / static if finite and static > 0 else math.nan,
            f"{end}_n_slack": len(slacks),
            f"{end}_n_snap": len(snaps),
            f"{end}_snap_peak_N": largest.peak_tension if largest else math.nan,
            f"{end}_snap_daf": largest.amplification if largest else math.nan,
            f"{end}_rise_time_s": largest.rise_time if largest else math.nan,
            f"{end}_slack_max_s": max((e.slack_duration for e in snaps), default=0.0),
            f"{end}_slack_total_s": sum(e.slack_duration for e in snaps),
            f"{end}_n_numerical": len(numerical),
            f"{end}_numerical_peak_N": max((e.tension_peak for e in numerical), default=math.nan),
            f"{end}_dnv_slack_ok": bool(finite and static > 0 and t_min >= DNV_SLACK_FRACTION * static),
        })
    return row


def event_rows(events) -> list:
    """Every snap of a run as a row (one per slack episode, at its largest published peak: ``episode_maxima``;
    for the per-event table and exceedance of snap peaks), then
    every re-tensioning the snap guard rejected (``kind`` "numerical", with its ``bound_N`` and reason)."""
    rows = [{"kind": "snap", "location": e.location, "time_s": e.time, "peak_N": e.peak_tension,
             "static_N": e.static_tension, "daf": e.amplification, "slack_s": e.slack_duration,
             "rise_time_s": e.rise_time, "min_N": e.min_tension}
            for e in episode_maxima(e for e in events if isinstance(e, SnapEvent))]
    rows += [{"kind": "numerical", "location": e.location, "time_s": e.time, "peak_N": e.tension_peak,
              "static_N": e.static_tension, "bound_N": e.bound, "rise_time_s": e.rise_time, "reason": e.reason}
             for e in events if isinstance(e, NumericalSnapWarning)]
    return rows
