"""The winch part of tether-sim-report: tension against length and against time, slack periods and
snap loads with the length at which they happened (no rclpy).

Read from the ``tether_sim_msgs/msg/WinchState`` topic (found by type) and the scheduled or topic
``WinchCommand`` messages; nothing is added to a report of a run without a winch. Figures (PNG):
``winch_time.png`` (drum-side tension, both end tensions with the slack periods and snap peaks of
the report, length and pay-out speed against time, commands marked) and ``winch_tension_length.png``
(both end tensions against the length, coloured by time, slack samples and snap peaks marked).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from tether_sim.io.mcap_log import read_messages, read_summary
from tether_sim.physics.boundary import END_NAMES

WINCH_TYPE = "tether_sim_msgs/msg/WinchState"
COMMAND_TYPE = "tether_sim_msgs/msg/WinchCommand"
LIMITS = ("speed_limited", "acceleration_limited", "at_min_length", "at_max_length")


@dataclass
class WinchSeries:
    """The winch/state messages of a run, times relative to the report's t0."""

    end: str
    t: np.ndarray
    length: np.ndarray  # m
    speed: np.ndarray  # m/s
    tension: np.ndarray  # drum-side, N
    mode: list
    setpoint: np.ndarray
    limits: dict  # name -> (n,) bool
    commands: list = field(default_factory=list)  # (t, mode, setpoint)

    def length_at(self, t):
        return np.interp(t, self.t, self.length)


def _seconds(stamp) -> float:
    return float(stamp.sec) + 1e-9 * float(stamp.nanosec)


def load_winch(path, t0: float, line: str | None = None) -> WinchSeries | None:
    """The winch series of an MCAP (None when it has no WinchState topic); ``line``: the winch of
    that line of a network recording (``/winch/<line>/state``, ``/winch/<line>/command``)."""
    summary = read_summary(Path(path))
    mine = (lambda t: t.startswith(f"/winch/{line}/")) if line else (lambda t: True)
    states = sorted(t for t, info in summary.topics.items() if info.type_name == WINCH_TYPE and mine(t))
    if not states:
        return None
    commands = [t for t, info in summary.topics.items() if info.type_name == COMMAND_TYPE and mine(t)]
    rows, cmds, end = [], [], "ship"
    for topic, _, _, msg in read_messages(Path(path), [states[0], *commands]):
        if topic == states[0]:
            end = msg.end or end
            rows.append((_seconds(msg.header.stamp) - t0, msg.length, msg.speed, msg.tension, msg.mode, msg.setpoint,
                         *(bool(getattr(msg, k)) for k in LIMITS)))
        else:
            cmds.append((_seconds(msg.header.stamp) - t0, msg.mode, float(msg.setpoint)))
    if not rows:
        return None
    rows.sort(key=lambda r: r[0])
    col = list(zip(*rows))
    return WinchSeries(end, np.array(col[0]), np.array(col[1]), np.array(col[2]), np.array(col[3]), list(col[4]),
                       np.array(col[5]), {k: np.array(col[6 + i], bool) for i, k in enumerate(LIMITS)}, sorted(cmds))


def winch_markdown(run, periods) -> list:
    """Markdown lines of the winch section ([] without a winch)."""
    wi = getattr(run, "winch", None)
    if wi is None:
        return []
    lines = ["", "## Winch", "",
             f"Winch at the {wi.end} end: length {wi.length[0]:.1f} m at the start, {wi.length.min():.1f} to "
             f"{wi.length.max():.1f} m over the run, {wi.length[-1]:.1f} m at the end; pay-out speed "
             f"{wi.speed.min():.2f} to {wi.speed.max():.2f} m/s; drum-side tension {wi.tension.min() / 1e3:.1f} to "
             f"{wi.tension.max() / 1e3:.1f} kN. States with a limit cutting the rate: "
             + ", ".join(f"{k.replace('_', ' ')} {int(v.sum())}" for k, v in wi.limits.items()) + f" (of {len(wi.t)})."]
    if wi.commands:
        lines += ["", "| command at [s] | mode | setpoint | length then [m] |", "|---|---|---|---|"]
        units = {"speed": "m/s", "length": "m", "tension": "N"}
        lines += [f"| {t:.2f} | {m} | {sp:g} {units.get(m, '')} | {wi.length_at(t):.1f} |" for t, m, sp in wi.commands]
    lines += ["", "Slack periods and snap loads with the length at which they happened:", "",
              "| end | kind | start or peak [s] | end [s] | length [m] | tension [kN] |", "|---|---|---|---|---|---|"]
    rows = []
    for end, items in periods.items():
        for p in items:
            rows.append((p["start"], f"| {end} | slack | {p['start']:.2f} | {p['end']:.2f} | "
                                     f"{wi.length_at(p['start']):.1f} | {p['min_tension'] / 1e3:.2f} (min) |"))
    for e in run.snaps:
        rows.append((e["t_peak"], f"| {e['end']} | snap | {e['t_peak']:.2f} | | {wi.length_at(e['t_peak']):.1f} | "
                                  f"{e['peak'] / 1e3:.2f} (peak, x{e['amplification']:.2f}) |"))
    lines += [r for _, r in sorted(rows)] or ["| (none) | | | | | |"]
    return lines


def winch_figures(run, periods, out_dir: Path) -> dict:
    """{name: path} of the two winch figures ({} without a winch)."""
    if getattr(run, "winch", None) is None:
        return {}
    return {"winch: tension and length against time": plot_winch_time(run, periods, out_dir / "winch_time.png"),
            "winch: tension against length": plot_tension_length(run, periods, out_dir / "winch_tension_length.png")}


def _shade(ax, run, periods, end):
    for i, p in enumerate(periods.get(end, [])):
        ax.axvspan(p["start"], max(p["end"], p["start"] + 1e-3), color="tab:red", alpha=0.2, lw=0,
                   label=f"{end} slack period" if i == 0 else None)


def plot_winch_time(run, periods, path: Path) -> Path:
    from tether_sim.report_figures import END_COLOURS, plt

    wi = run.winch
    fig, axes = plt.subplots(3, 1, figsize=(11, 8.5), sharex=True, constrained_layout=True)
    ax = axes[0]
    for end in END_NAMES:
        ax.plot(run.t, run.end_tension[end] / 1e3, color=END_COLOURS[end], lw=0.8, label=f"{end} end tension")
        _shade(ax, run, periods, end)
        snaps = [e for e in run.snaps if e["end"] == end]
        if snaps:
            ax.plot([e["t_peak"] for e in snaps], [e["peak"] / 1e3 for e in snaps], "v", color="tab:red", ms=7,
                    mec="k", label=f"snap load at the {end} end (peak)")
    ax.set_ylabel("tension [kN]")
    ax.set_title(f"Winch at the {wi.end} end — {run.path.name}")
    axes[1].plot(wi.t, wi.length, color="k", lw=1.2)
    axes[1].set_ylabel("unstretched length L [m]")
    axes[2].plot(wi.t, wi.speed, color="tab:green", lw=1.0, label="pay-out speed (> 0 pays out)")
    limited = np.zeros(len(wi.t), bool)
    for v in wi.limits.values():
        limited |= v
    if limited.any():
        axes[2].plot(wi.t[limited], wi.speed[limited], ".", color="tab:orange", ms=2, label="a limit cut the rate")
    axes[2].set_ylabel("dL/dt [m/s]")
    axes[2].set_xlabel(f"{run.time_label} [s]")
    for t, mode, sp in wi.commands:
        for a in axes[1:]:
            a.axvline(t, color="0.4", lw=0.7, ls="--")
        axes[1].annotate(f"{mode} {sp:g}", (t, axes[1].get_ylim()[1]), fontsize=7, rotation=90, va="top", ha="right")
    for a in axes:
        a.grid(alpha=0.3)
        if a.get_legend_handles_labels()[0]:
            a.legend(loc="upper right", fontsize=8)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def plot_tension_length(run, periods, path: Path) -> Path:
    from tether_sim.report_figures import plt

    wi = run.winch
    length = wi.length_at(run.t)
    fig, axes = plt.subplots(1, 2, figsize=(12, 5.5), sharex=True, constrained_layout=True)
    for ax, end in zip(axes, END_NAMES):
        points = ax.scatter(length, run.end_tension[end] / 1e3, c=run.t, s=2, cmap="viridis", lw=0)
        slack = np.zeros(len(run.t), bool)
        for p in periods.get(end, []):
            slack |= (run.t >= p["start"]) & (run.t <= p["end"])
        if slack.any():
            ax.plot(length[slack], run.end_tension[end][slack] / 1e3, "x", color="tab:red", ms=4, label="slack")
        snaps = [e for e in run.snaps if e["end"] == end]
        if snaps:
            ax.plot(wi.length_at([e["t_peak"] for e in snaps]), [e["peak"] / 1e3 for e in snaps], "v", color="tab:red",
                    ms=8, mec="k", label="snap load (peak)")
        ax.set_xlabel("unstretched length L [m]")
        ax.set_ylabel(f"{end} end tension [kN]" + (" (drum side)" if end == wi.end else ""))
        ax.grid(alpha=0.3)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(loc="upper left", fontsize=8)
    fig.colorbar(points, ax=axes, label=f"{run.time_label} [s]")
    fig.suptitle(f"End tensions against the paid-out length — {run.path.name}")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
