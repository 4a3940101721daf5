"""tether-sim-report: figures and an event table from an output MCAP (no rclpy).

Works on any file holding the node's outputs (the recorder's or the offline runner's): topics are
found by type, so remapped names work. Times are header stamps (simulation time) relative to the
first TetherState. Figures (PNG): ``end_tensions.png`` (ship and vehicle end tension vs time, slack
periods shaded, snap-load peaks marked, |force| of the wrench topics overlaid as a cross-check),
``shapes.png`` (cable shape snapshots, x-z and y-z, ENU), ``tension_map.png`` (tension along the
cable over time, s-t colour map), ``tension_envelope.png`` (largest and smallest tension at each
point over the run, with the breaking load ``cable.breaking_load`` when given). ``report.md`` holds
the summary, the tension envelope and utilisation, and the event tables; ``report.json`` the same
numbers, units in the key names.

Slack periods of an end are the intervals where its recorded tension is below the slack threshold
the node reported for that end (SlackWarning.threshold; 0 N when it reported none), merged with
the slack interval of each SnapLoadEvent (slack_start .. slack_start + slack_duration). The
threshold is that of the latest warning at each instant (the first one before it): with a winch
the node's threshold follows the length (docs/winch.md), so one value for the whole run would
misjudge every length but one.

A line network's recording (docs/network.md: ``/tether/<line>/state`` ... per line) gets one report
per line, in ``<out-dir>/<line>/``, each from that line's own state, snap, slack, description and
winch topics (``--line`` picks one), all on the time axis of the first line's first state, and a
``report.md`` in ``<out-dir>`` linking them; each body (the cage) gets ``<out-dir>/<body>/``
(``motion.png``, ``forces.png``, ``report.json``: tether_sim/report_body.py) and a section there.
"""

from __future__ import annotations

import argparse
import json
import sys
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from tether_sim.errors import TetherSimError
from tether_sim.io.mcap_log import McapLogError, read_messages, read_summary
from tether_sim.io.mcap_scan import CorruptMcapWarning
from tether_sim.physics.boundary import END_NAMES
from tether_sim.solvers.resolution import bending_mesh_warning, mesh_summary
from tether_sim.report_body import body_figures, body_markdown, body_summary, load_body, network_bodies
from tether_sim.report_winch import load_winch, winch_figures, winch_markdown
from tether_sim.report_forecast import forecast_figures, forecast_markdown, load_forecasts

STATE_TYPE = "tether_sim_msgs/msg/TetherState"
SNAP_TYPE = "tether_sim_msgs/msg/SnapLoadEvent"
SLACK_TYPE = "tether_sim_msgs/msg/SlackWarning"
WRENCH_TYPE = "geometry_msgs/msg/WrenchStamped"
DIAGNOSTICS_TYPE = "diagnostic_msgs/msg/DiagnosticArray"
DESCRIPTION_TYPE = "tether_sim_msgs/msg/TetherDescription"


class ReportError(TetherSimError, ValueError):
    """The MCAP holds nothing a report can be made from (message names the file)."""


def stamp_seconds(value) -> float:
    """builtin_interfaces/Time (sec, nanosec) or a plain number -> seconds."""
    if hasattr(value, "sec"):
        return float(value.sec) + 1e-9 * float(value.nanosec)
    return float(value)


@dataclass
class RunData:
    """Everything the report reads from one MCAP, times in s from the first state."""

    path: Path
    t0: float                           # clock time of t = 0, s
    solver: str
    t: np.ndarray                       # (n_t,)
    arc_length: np.ndarray              # (n_s,)
    positions: np.ndarray               # (n_t, n_s, 3)
    tension: np.ndarray                 # (n_t, n_s)
    end_tension: dict                   # end -> (n_t,)
    snaps: list = field(default_factory=list)      # dicts, times relative to t0
    warnings: list = field(default_factory=list)   # dicts
    wrench: dict = field(default_factory=dict)     # end -> (t (n,), |F| (n,))
    diagnostics: dict = field(default_factory=dict)  # status name -> {key: value} (last seen)
    time_label: str = "time since the first state"
    parameters: dict = field(default_factory=dict)  # key -> value text of the last TetherDescription
    degraded: np.ndarray | None = None  # (n_t,) bool: the node marked the state degraded (late/blended)
    truncation: str | None = None  # what a crash cut off the file (None: complete)
    arc_history: np.ndarray | None = None  # (n_t, n_s) output points of each state when they move (winch), else None
    winch: object = None  # report_winch.WinchSeries of the winch/state topic, or None
    forecast: list | None = None  # the SnapForecast messages (report_forecast.py), or None


def _topics_of(summary, type_name):
    return sorted(t for t, info in summary.topics.items() if info.type_name == type_name)


def network_lines(path) -> list:
    """The lines of a line-network recording (``/tether/<line>/state`` topics, no ``/tether/state``);
    [] for a single-line recording."""
    topics = _topics_of(read_summary(Path(path)), STATE_TYPE)
    if "/tether/state" in topics:
        return []
    return [t.split("/")[2] for t in topics if t.count("/") == 3 and t.startswith("/tether/") and t.endswith("/state")]


def load_run(path, t0_s: float | None = None, line: str | None = None) -> RunData:
    """Read states, events, warnings and wrenches from an output MCAP; times relative to t0_s
    (clock time, s; default: the first state's stamp). ``line``: that line of a network recording
    (its own topics only). A file with a corrupt chunk (CRC) is read again chunk by chunk: the
    report covers every intact chunk and says what was dropped."""
    try:
        return _load_run(Path(path), t0_s, skip_corrupt=False, line=line)
    except McapLogError as exc:
        if "corrupt" not in str(exc):
            raise
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CorruptMcapWarning)  # said in the report instead
        return _load_run(Path(path), t0_s, skip_corrupt=True, line=line)


def _load_run(path, t0_s, skip_corrupt, line=None) -> RunData:
    summary = read_summary(path)
    state_topics = _topics_of(summary, STATE_TYPE)
    lost = f" ({summary.damage.describe()})" if summary.damage is not None else ""
    if not state_topics:
        found = ", ".join(f"{t} ({i.type_name})" for t, i in sorted(summary.topics.items())) or "none"
        raise ReportError(f"{path}: no {STATE_TYPE} topic to report on (topics: {found}){lost}")
    if line is not None:
        state_topic = f"/tether/{line}/state"
        if state_topic not in state_topics:
            raise ReportError(f"{path}: no line {line!r} (no {state_topic}); state topics: {', '.join(state_topics)}")
        mine = lambda t: t.startswith(f"/tether/{line}/")  # noqa: E731
        wrench_topics = {}  # the wrenches belong to points and bodies, not to one line
    else:
        state_topic = "/tether/state" if "/tether/state" in state_topics else state_topics[0]
        mine = lambda t: True  # noqa: E731
        wrench_topics = {end: t for t in _topics_of(summary, WRENCH_TYPE) for end in END_NAMES if end in t}
    wanted = [state_topic, *filter(mine, _topics_of(summary, SNAP_TYPE)), *filter(mine, _topics_of(summary, SLACK_TYPE)),
              *wrench_topics.values(), *_topics_of(summary, DIAGNOSTICS_TYPE),
              *filter(mine, _topics_of(summary, DESCRIPTION_TYPE))]
    parameters = {}
    diagnostics = {}
    times, positions, tensions, ends, snaps, warns = [], [], [], {e: [] for e in END_NAMES}, [], []
    arcs = []
    degraded = []
    wrench = {end: ([], []) for end in wrench_topics}
    arc, solver = None, ""
    damage, n_read = [], 0
    for topic, type_name, _, msg in read_messages(path, wanted, skip_corrupt=skip_corrupt, damage=damage):
        n_read += 1
        if topic == state_topic:
            s = np.asarray(msg.arc_length, dtype=float)
            if arc is None:
                arc, solver = s, msg.solver
            if s.shape != arc.shape:
                continue  # a resized output grid cannot share the s-t map; skip such states
            times.append(stamp_seconds(msg.header.stamp))
            arcs.append(s)
            positions.append([(p.x, p.y, p.z) for p in msg.position])
            tensions.append(np.asarray(msg.tension, dtype=float))
            ends["ship"].append(msg.ship_end_tension)
            ends["vehicle"].append(msg.vehicle_end_tension)
            degraded.append(bool(getattr(msg, "degraded", False)))  # recordings before the field: False
        elif type_name == SNAP_TYPE:
            snaps.append({"end": msg.end, "arc_length": msg.arc_length,
                          "t_peak": stamp_seconds(msg.header.stamp), "peak": msg.peak_tension,
                          "min": msg.min_tension, "slack_start": stamp_seconds(msg.slack_start),
                          "slack_duration": msg.slack_duration, "rise_time": msg.rise_time,
                          "static": msg.static_tension, "amplification": msg.amplification,
                          "criterion": msg.criterion})
        elif type_name == SLACK_TYPE:
            warns.append({"end": msg.end, "arc_length": msg.arc_length,
                          "t": stamp_seconds(msg.header.stamp), "tension": msg.tension,
                          "threshold": msg.threshold})
        elif type_name == DESCRIPTION_TYPE:
            parameters = {kv.key: kv.value for kv in msg.parameters}
        elif type_name == DIAGNOSTICS_TYPE:
            for status in msg.status:
                diagnostics[status.name] = {"message": status.message,
                                            **{kv.key: kv.value for kv in status.values}}
        elif type_name == WRENCH_TYPE:
            end = next(e for e, t in wrench_topics.items() if t == topic)
            f = msg.wrench.force
            wrench[end][0].append(stamp_seconds(msg.header.stamp))
            wrench[end][1].append(float(np.sqrt(f.x * f.x + f.y * f.y + f.z * f.z)))
    truncation = summary.damage.describe() if summary.damage is not None else None
    if damage and damage[0].corrupt:
        if summary.complete:
            damage[0].messages_lost = max(0, sum(summary.topics[w].message_count for w in set(wanted)) - n_read)
        truncation = damage[0].describe()
        lost = f" ({truncation})"
    if not times:
        raise ReportError(f"{path}: topic {state_topic} holds no TetherState messages{lost}")
    t = np.asarray(times)
    order = np.argsort(t, kind="stable")
    t0 = float(t[order[0]]) if t0_s is None else float(t0_s)
    for item in snaps:
        item["t_peak"] -= t0
        item["slack_start"] -= t0
    for item in warns:
        item["t"] -= t0
    return RunData(path, t0, solver, t[order] - t0, arc, np.asarray(positions)[order],
                   np.asarray(tensions)[order],
                   {e: np.asarray(v, dtype=float)[order] for e, v in ends.items()}, snaps, warns,
                   {e: (np.asarray(tw) - t0, np.asarray(fw)) for e, (tw, fw) in wrench.items()},
                   diagnostics, parameters=parameters, degraded=np.asarray(degraded, bool)[order],
                   truncation=truncation,
                   arc_history=_moving(np.asarray(arcs)[order]))


def _moving(arcs):
    """The (n_t, n_s) output points when they change over the run (a winch), else None."""
    return arcs if len(arcs) and np.ptp(arcs[:, -1]) > 0.0 else None


def below_intervals(t: np.ndarray, values: np.ndarray, threshold: float) -> list[tuple[float, float]]:
    """Maximal [start, end] time intervals of consecutive samples with values < threshold."""
    below = np.concatenate([[False], values < threshold, [False]])
    edges = np.flatnonzero(np.diff(below.astype(np.int8)))
    return [(float(t[a]), float(t[b - 1])) for a, b in zip(edges[::2], edges[1::2])]


def _merge(intervals):
    merged = []
    for a, b in sorted(intervals):
        if merged and a <= merged[-1][1]:
            merged[-1] = (merged[-1][0], max(b, merged[-1][1]))
        else:
            merged.append((a, b))
    return merged


def threshold_series(t: np.ndarray, warned: list) -> np.ndarray:
    """The slack threshold at every time of ``t`` from the (time, threshold) of the warnings: that
    of the latest warning at or before each time, the first warning's before it; 0 N without any."""
    if not warned:
        return np.zeros(len(t))
    times = np.array([w[0] for w in warned], float)
    values = np.array([w[1] for w in warned], float)
    order = np.argsort(times, kind="stable")
    times, values = times[order], values[order]
    k = np.clip(np.searchsorted(times, t, side="right") - 1, 0, len(times) - 1)
    return values[k]


def slack_periods(run: RunData) -> dict:
    """end -> list of {start, end, duration, min_tension, threshold} (see module docstring)."""
    out = {}
    for end in END_NAMES:
        warned = [(w["t"], w["threshold"]) for w in run.warnings if w["end"] == end]
        threshold = threshold_series(run.t, warned)
        series = run.end_tension[end]
        spans = below_intervals(run.t, series, threshold)
        spans += [(e["slack_start"], e["slack_start"] + e["slack_duration"])
                  for e in run.snaps if e["end"] == end]
        periods = []
        for a, b in _merge(spans):
            inside = (run.t >= a) & (run.t <= b)
            event_mins = [e["min"] for e in run.snaps if e["end"] == end
                          and a <= e["slack_start"] <= b]
            lows = list(series[inside]) + event_mins  # events see every substep; states do not
            low = float(min(lows)) if lows else float("nan")
            at = threshold[min(int(np.searchsorted(run.t, a)), len(run.t) - 1)] if len(run.t) else 0.0
            periods.append({"start": a, "end": b, "duration": b - a, "min_tension": low,
                            "threshold": float(at)})
        out[end] = periods
    return out


def node_health(run: RunData) -> dict | None:
    """From the node's last /diagnostics: real-time factor, clock time skipped, recoveries."""
    for name, values in run.diagnostics.items():
        if "dropped_total" in values:
            def number(key):
                try:
                    return float(values.get(key, "nan"))
                except ValueError:
                    return float("nan")
            return {"status": name, "real_time_factor": number("real_time_factor"),
                    "dropped_s": number("dropped_total"), "divergences": number("divergences"),
                    "capped_ticks": number("capped_ticks"), "numerical_snaps": number("numerical_snaps"),
                    "last_numerical_snap": values.get("last_numerical_snap", "")}
    return None


def static_tensions(run: RunData) -> dict:
    """end -> tension of the first state (the initial static equilibrium), N."""
    return {end: float(run.end_tension[end][0]) for end in END_NAMES}


def _mesh_line(parameters: dict) -> str:
    """" DG mesh: N = 3, P = 4, dg.cfl 0.8 (dg.resolution auto, ...)." from the description, or ""."""
    p = parameters
    if p.get("solver") != "dg" or "dg.n_elements" not in p:
        return ""
    line = " DG mesh: " + mesh_summary(p["dg.n_elements"], p["dg.order"], p["dg.cfl"], p.get("dg.resolution", "manual"),
                                       p.get("dg.snap_tolerance", "nan")) + "."
    if "cable.length" in p and "cable.EI" in p:
        lengths = p.get("dg.element_lengths")
        lengths = tuple(float(x) for x in lengths) if isinstance(lengths, (list, tuple)) else ()
        caution = bending_mesh_warning(p["cable.length"], p["dg.n_elements"], p["dg.order"], float(p["cable.EI"]),
                                       lengths, damping=str(p.get("dg.damping", "explicit")))
        if caution:
            line += " Caution: " + caution + "."
    return line


def tension_envelope(run: RunData) -> dict:
    """Largest and smallest tension at each output point over the run, where and when the largest
    occurs, and the utilisation against ``cable.breaking_load`` of the description (None when not
    given). Output instants only (the snap events carry the substep peaks at the ends). With a
    winch the output points move with L(t): the curve is by output point, s of the first state."""
    tension = run.tension
    k_t, k_s = np.unravel_index(int(np.argmax(tension)), tension.shape)
    arcs = run.arc_history if run.arc_history is not None else np.broadcast_to(run.arc_length, tension.shape)
    try:
        mbl = float(run.parameters.get("cable.breaking_load", "0") or 0.0)
    except ValueError:
        mbl = 0.0
    largest = float(tension[k_t, k_s])
    return {"arc_length_m": [float(x) for x in arcs[0]], "max_N": [float(x) for x in tension.max(axis=0)],
            "min_N": [float(x) for x in tension.min(axis=0)],
            "largest": {"tension_N": largest, "arc_length_m": float(arcs[k_t, k_s]), "time_s": float(run.t[k_t])},
            "smallest_N": float(tension.min()),
            "end_max_N": {end: float(run.end_tension[end].max()) for end in END_NAMES},
            "breaking_load_N": mbl if mbl > 0 else None, "utilisation": largest / mbl if mbl > 0 else None}


def envelope_markdown(envelope: dict) -> list:
    peak, ends = envelope["largest"], envelope["end_max_N"]
    lines = ["", "## Tension along the cable", "",
             f"Largest tension anywhere on the cable: **{peak['tension_N']:.1f} N** at s = {peak['arc_length_m']:.1f} m, "
             f"t = {peak['time_s']:.3f} s (largest at the ship end {ends['ship']:.1f} N, at the vehicle end "
             f"{ends['vehicle']:.1f} N; output instants). Smallest: {envelope['smallest_N']:.1f} N."]
    if envelope["breaking_load_N"]:
        lines.append(f"Utilisation: {100 * envelope['utilisation']:.1f} % of the breaking load "
                     f"(`cable.breaking_load` {envelope['breaking_load_N']:.0f} N).")
    else:
        lines.append("Utilisation: not computed (`cable.breaking_load` not given in the parameters).")
    s, hi, lo = envelope["arc_length_m"], envelope["max_N"], envelope["min_N"]
    picks = sorted(set(np.linspace(0, len(s) - 1, min(len(s), 9)).round().astype(int).tolist()))
    lines += ["", "| s [m] | max tension [N] | min tension [N] |", "|---|---|---|"]
    lines += [f"| {s[i]:.1f} | {hi[i]:.1f} | {lo[i]:.1f} |" for i in picks]
    return lines


def summary_json(run: RunData, periods: dict, envelope: dict, figures: dict) -> dict:
    """What report.md says, as numbers with their units in the names (report.json)."""
    health = node_health(run)
    return {
        "file": str(run.path), "solver": run.solver, "time_origin": run.time_label,
        "states": int(len(run.t)), "duration_s": float(run.t[-1] - run.t[0]) if len(run.t) else 0.0,
        "length_m": float(run.arc_length[-1]), "degraded_states": int(run.degraded.sum()) if run.degraded is not None else 0,
        "truncation": run.truncation,
        "end_tension_N": {end: {"static": float(run.end_tension[end][0]), "mean": float(run.end_tension[end].mean()),
                                "min": float(run.end_tension[end].min()), "max": float(run.end_tension[end].max())}
                          for end in END_NAMES},
        "tension_envelope": {"largest_N": envelope["largest"]["tension_N"],
                             "largest_at_arc_length_m": envelope["largest"]["arc_length_m"],
                             "largest_at_time_s": envelope["largest"]["time_s"], "smallest_N": envelope["smallest_N"],
                             "arc_length_m": envelope["arc_length_m"], "max_N": envelope["max_N"], "min_N": envelope["min_N"]},
        "breaking_load_N": envelope["breaking_load_N"], "utilisation": envelope["utilisation"],
        "slack_periods": {end: [{"start_s": p["start"], "end_s": p["end"], "duration_s": p["duration"],
                                 "min_tension_N": p["min_tension"], "threshold_N": p["threshold"]} for p in periods[end]]
                          for end in END_NAMES},
        "snap_events": [{"end": e["end"], "arc_length_m": e["arc_length"], "peak_time_s": e["t_peak"], "peak_N": e["peak"],
                         "static_N": e["static"], "amplification": e["amplification"], "min_tension_N": e["min"],
                         "slack_start_s": e["slack_start"], "slack_duration_s": e["slack_duration"],
                         "rise_time_s": e["rise_time"], "criterion": e["criterion"]}
                        for e in sorted(run.snaps, key=lambda e: e["t_peak"])],
        "slack_warnings": {end: sum(w["end"] == end for w in run.warnings) for end in (*END_NAMES, "span")},
        "node_health": None if health is None else {"real_time_factor": health["real_time_factor"],
                                                    "clock_time_skipped_s": health["dropped_s"],
                                                    "divergences": health["divergences"],
                                                    "capped_ticks": health["capped_ticks"]},
        "figures": {name: str(path) for name, path in figures.items()},
    }


def _length_text(run: RunData) -> str:
    arcs = run.arc_history
    if arcs is None:
        return f"L = {run.arc_length[-1]:.1f} m"
    return f"L = {arcs[0, -1]:.1f} m at the start, {arcs[:, -1].min():.1f} to {arcs[:, -1].max():.1f} m (winch)"


def summary_markdown(run: RunData, periods: dict, figures: dict, envelope: dict | None = None) -> str:
    """The summary and event tables as markdown."""
    duration = float(run.t[-1] - run.t[0]) if len(run.t) else 0.0
    rate = (len(run.t) - 1) / duration if duration > 0 else float("nan")
    lines = [f"# Tether report: `{run.path.name}`", "",
             f"Solver `{run.solver}`, {len(run.t)} states over {duration:.2f} s "
             f"({rate:.1f} Hz), {len(run.arc_length)} output points, {_length_text(run)}. "
             f"Times below: {run.time_label}, s.{_mesh_line(run.parameters)}", ""]
    if run.truncation:
        kind = "Damaged" if "corrupt" in run.truncation else "Truncated"
        lines += [f"**{kind} recording.** {run.truncation}. This report covers what was kept; "
                  "`tether-sim-recover` rewrites the file into a complete MCAP.", ""]
    if run.degraded is not None and run.degraded.any():
        lines += [f"**Degraded states: {int(run.degraded.sum())} of {len(run.t)}** (the node was behind the clock, "
                  "blending an end onto its input after a gap, or had snap detection suspended; docs/node.md). "
                  "Shaded grey in the end-tension figure.", ""]
    lines += ["| end | static (first state) [N] | mean [N] | min [N] | max [N] |",
             "|---|---|---|---|---|"]
    for end, value in static_tensions(run).items():
        series = run.end_tension[end]
        lines.append(f"| {end} | {value:.1f} | {series.mean():.1f} | {series.min():.1f} | "
                     f"{series.max():.1f} |")
    lines += ["", "Static, mean, min and max come from the recorded TetherState messages (one per "
              f"output, {rate:.1f} Hz here). The snap-event peaks below come from the solver's end "
              "tension at every substep, so a snap peak can exceed the max of its end above, which "
              "sees the tension only at the output instants."]
    lines += envelope_markdown(envelope if envelope is not None else tension_envelope(run))
    lines += ["", "## Slack periods", "", "| end | start [s] | end [s] | duration [s] | "
              "min tension [N] | threshold [N] |", "|---|---|---|---|---|---|"]
    for end in END_NAMES:
        for p in periods[end]:
            lines.append(f"| {end} | {p['start']:.3f} | {p['end']:.3f} | {p['duration']:.3f} | "
                         f"{p['min_tension']:.1f} | {p['threshold']:.1f} |")
    if not any(periods.values()):
        lines.append("| (none) | | | | | |")
    lines += ["", "## Snap-load events", "", "| # | end | s [m] | peak at [s] | peak [N] | "
              "static [N] | amplification | min [N] | slack start [s] | slack [s] | rise [s] | "
              "criterion |", "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for i, e in enumerate(sorted(run.snaps, key=lambda e: e["t_peak"]), 1):
        lines.append(f"| {i} | {e['end']} | {e['arc_length']:.1f} | {e['t_peak']:.3f} | "
                     f"{e['peak']:.1f} | {e['static']:.1f} | {e['amplification']:.2f} | "
                     f"{e['min']:.1f} | {e['slack_start']:.3f} | {e['slack_duration']:.3f} | "
                     f"{e['rise_time']:.3f} | {e['criterion']} |")
    if not run.snaps:
        lines.append("| (none) | | | | | | | | | | | |")
    health = node_health(run)
    if health and health["numerical_snaps"] > 0:
        lines += ["", f"**Numerical re-tensioning warnings: {health['numerical_snaps']:.0f}** (peaks the snap guard "
                  "rejected as physically impossible: above the impedance/energy bound of the cable or rising faster "
                  "than the axial wave crosses an element, docs/snap_guard.md; not snap loads, not in the table "
                  f"above). Last: {health['last_numerical_snap']}."]
    if health:
        lines += ["", "## Node health (last /diagnostics)", "",
                  f"Real-time factor {health['real_time_factor']:.2f}; clock time skipped because the "
                  f"solver was behind: {health['dropped_s']:.1f} s of {duration:.1f} s; divergence "
                  f"recoveries: {health['divergences']:.0f}; ticks capped: {health['capped_ticks']:.0f}."]
    counts = {end: sum(w["end"] == end for w in run.warnings) for end in (*END_NAMES, "span")}
    lines += winch_markdown(run, periods)
    lines += forecast_markdown(run)  # snap forecast runs: skill against the snaps above
    lines += ["", "Slack warnings: " + ", ".join(f"{k} {v}" for k, v in counts.items()) + ".",
              "", "## Figures", ""] + [f"- {name}: `{path}`" for name, path in figures.items()]
    return "\n".join(lines) + "\n"


def render(run: RunData, periods: dict, out_dir: Path, n_snapshots: int = 8, envelope: dict | None = None) -> dict:
    """Write the PNG figures; returns {name: path}."""
    from tether_sim.report_figures import plot_end_tensions, plot_shapes, plot_tension_envelope, plot_tension_map

    out_dir.mkdir(parents=True, exist_ok=True)
    envelope = envelope if envelope is not None else tension_envelope(run)
    return {"end tensions": plot_end_tensions(run, periods, out_dir / "end_tensions.png"),
            "shape snapshots": plot_shapes(run, out_dir / "shapes.png", n_snapshots),
            "tension map": plot_tension_map(run, out_dir / "tension_map.png"),
            "tension envelope": plot_tension_envelope(run, envelope, out_dir / "tension_envelope.png"),
            **winch_figures(run, periods, out_dir),  # winch runs: tension against length and time
            **forecast_figures(run, out_dir)}  # snap forecast runs: probability against the snaps


def make_network_report(mcap_path, out_dir=None, n_snapshots: int = 8, t0_s: float | None = None,
                        time_label: str = "time since the first state", lines=None) -> dict:
    """One report per line of a network recording in ``<out_dir>/<line>/`` (module doc) and an
    index ``<out_dir>/report.md``; returns {lines: {line: make_report result}, markdown, report_path}."""
    mcap_path = Path(mcap_path)
    out_dir = Path(out_dir) if out_dir is not None else mcap_path.parent / "figures"
    lines = list(lines or network_lines(mcap_path))
    if not lines:
        raise ReportError(f"{mcap_path}: not a line-network recording (no /tether/<line>/state topics)")
    results = {}
    for line in lines:
        results[line] = make_report(mcap_path, out_dir / line, n_snapshots, t0_s, time_label, line=line)
        t0_s = results[line]["run"].t0  # one time axis for every line
    md = [f"# Line network report: `{mcap_path.name}`", "", f"Lines: {', '.join(lines)}; times: {time_label}, s.", "",
          "| line | solver | states | snap events | max end tension [N] | report |", "|---|---|---|---|---|---|"]
    for line, r in results.items():
        run = r["run"]
        top = max(float(np.max(v)) for v in run.end_tension.values())
        md.append(f"| {line} | {run.solver} | {len(run.t)} | {len(run.snaps)} | {top:.1f} | `{line}/report.md` |")
    bodies = {}
    for name in network_bodies(mcap_path):  # the cage: its motion and the forces on it
        series = load_body(mcap_path, name, t0_s)
        if series is None:
            continue
        figures = body_figures(series, out_dir / name, time_label)
        summary = body_summary(series)
        (out_dir / name / "report.json").write_text(json.dumps(summary, indent=1, allow_nan=False) + "\n")
        md += body_markdown(series, summary, figures, out_dir)
        bodies[name] = {"series": series, "figures": figures, "summary": summary}
    markdown = "\n".join(md) + "\n"
    out_dir.mkdir(parents=True, exist_ok=True)
    report_path = out_dir / "report.md"
    report_path.write_text(markdown)
    return {"lines": results, "bodies": bodies, "markdown": markdown, "report_path": report_path}


def make_report(mcap_path, out_dir=None, n_snapshots: int = 8, t0_s: float | None = None,
                time_label: str = "time since the first state", line: str | None = None) -> dict:
    """Load, plot and summarise; returns {run, periods, static, figures, markdown, report_path}.
    ``line``: one line of a network recording (make_network_report reports them all)."""
    mcap_path = Path(mcap_path)
    out_dir = Path(out_dir) if out_dir is not None else mcap_path.parent / "figures"
    run = load_run(mcap_path, t0_s, line=line)
    if line is not None:
        run.path = Path(f"{mcap_path.name}: line {line}")
    run.time_label = time_label
    run.winch = load_winch(mcap_path, run.t0, line=line)  # None without a winch/state topic
    run.forecast = load_forecasts(mcap_path, run.t0)  # None without a SnapForecast topic
    periods = slack_periods(run)
    envelope = tension_envelope(run)
    figures = render(run, periods, out_dir, n_snapshots, envelope)
    markdown = summary_markdown(run, periods, figures, envelope)
    report_path = out_dir / "report.md"
    report_path.write_text(markdown)
    summary = summary_json(run, periods, envelope, figures)
    json_path = out_dir / "report.json"
    json_path.write_text(json.dumps(summary, indent=1, allow_nan=False, default=_json_number) + "\n")
    return {"run": run, "periods": periods, "static": static_tensions(run), "figures": figures,
            "markdown": markdown, "report_path": report_path, "envelope": envelope, "summary": summary,
            "json_path": json_path}


def _json_number(value):
    """numpy scalars for json.dumps."""
    if isinstance(value, np.generic):
        return value.item()
    raise TypeError(f"{type(value).__name__} is not JSON serialisable")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="tether-sim-report", description=__doc__.split("\n")[0])
    parser.add_argument("mcap", help="output MCAP (recorder or offline runner)")
    parser.add_argument("--out-dir", help="where figures and report.md go (default: <mcap dir>/figures)")
    parser.add_argument("--snapshots", type=int, default=8, help="number of shape snapshots (default: %(default)s)")
    parser.add_argument("--t0", type=float, help="clock time (s) taken as t = 0 (default: first state)")
    parser.add_argument("--line", action="append", help="a line of a network recording (repeatable; default: every line)")
    args = parser.parse_args(argv)
    label = "time since the first state" if args.t0 is None else f"time since {args.t0:.3f} s"
    try:
        if args.line or network_lines(args.mcap):
            result = make_network_report(args.mcap, args.out_dir, args.snapshots, args.t0, label, args.line)
        else:
            result = make_report(args.mcap, args.out_dir, args.snapshots, args.t0, label)
    except (McapLogError, ReportError) as exc:
        print(f"tether-sim-report: {exc}", file=sys.stderr)
        return 2
    print(result["markdown"])
    print(f"report written to {result['report_path']}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
