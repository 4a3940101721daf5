"""The report's snap-forecast part (``tether-sim-report``; docs/forecast.md): a timeline of the forecast
probability of each end against the snaps that happened (``snap_forecast.png``), and the skill table
(tether_sim.forecast.skill: warned >= 5 s ahead within +-1.5 s, false alarms per 10 min). Only for
recordings holding a SnapForecast topic."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np

from tether_sim.forecast.skill import score
from tether_sim.io.mcap_log import read_messages, read_summary
from tether_sim.physics.boundary import END_NAMES

FORECAST_TYPE = "tether_sim_msgs/msg/SnapForecast"


def load_forecasts(path, t0: float) -> list | None:
    """The SnapForecast messages of an MCAP as namespaces (times relative to ``t0``), or None."""
    topics = sorted(t for t, info in read_summary(path).topics.items() if info.type_name == FORECAST_TYPE)
    if not topics:
        return None
    out = []
    for _topic, _type, _log, msg in read_messages(Path(path), topics):
        stamp = float(msg.header.stamp.sec) + 1e-9 * float(msg.header.stamp.nanosec) - t0
        out.append(SimpleNamespace(stamp=stamp, end=msg.end, horizon=msg.horizon, probability=msg.probability,
                                   time_to_snap=msg.time_to_snap, predicted_peak=msg.predicted_peak,
                                   members=msg.members, source=msg.source, degraded=msg.degraded, reason=msg.reason))
    return out


def warn_probability(run) -> float:
    """The run's alarm threshold (``forecast.warn_probability`` of its recorded parameters; the
    default when the recording does not carry it)."""
    from tether_sim.forecast.config import ForecastConfig

    text = run.parameters.get("forecast.warn_probability", "")
    try:
        return float(text)
    except ValueError:
        return ForecastConfig.warn_probability


def plot_forecast(run, path: Path) -> Path:
    """Per end: forecast probability against the stamp; the snaps that happened as vertical lines;
    each warning (p >= the run's ``forecast.warn_probability``) also as a dot at its predicted snap time."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    warn_p = warn_probability(run)
    fig, axes = plt.subplots(2, 1, figsize=(11, 5.5), sharex=True)
    for ax, end in zip(axes, END_NAMES):
        fc = [f for f in run.forecast if f.end == end]
        t = np.array([f.stamp for f in fc])
        p = np.array([f.probability for f in fc])
        ax.step(t, p, where="post", color="C0", lw=1.2, label="forecast probability (at its stamp)")
        warn = [(f.stamp + f.time_to_snap) for f in fc if f.probability >= warn_p]
        if warn:
            ax.plot(warn, np.full(len(warn), 1.04), "v", color="C1", ms=4, alpha=0.6,
                    label=f"predicted snap time of a warning (p >= {warn_p:g})")
        degraded = [f.stamp for f in fc if f.degraded]
        if degraded:
            ax.plot(degraded, np.full(len(degraded), -0.04), "s", color="0.6", ms=3, label="degraded forecast")
        for i, s in enumerate(e for e in run.snaps if e["end"] == end):
            ax.axvline(s["t_peak"], color="C3", lw=1.0, alpha=0.8, label="snap that happened" if i == 0 else None)
        ax.axhline(warn_p, color="0.5", lw=0.6, ls=":")
        ax.set_ylim(-0.1, 1.1)
        ax.set_ylabel(f"{end}: P(snap)")
        ax.legend(loc="upper left", fontsize=7, ncol=2)
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel(f"{run.time_label} [s]")
    horizon = run.forecast[0].horizon if run.forecast else float("nan")
    fig.suptitle(f"Snap forecast (horizon {horizon:g} s) against the snaps that happened")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def forecast_figures(run, out_dir: Path) -> dict:
    if not run.forecast:
        return {}
    return {"snap forecast": plot_forecast(run, Path(out_dir) / "snap_forecast.png")}


def forecast_markdown(run) -> list:
    """Lines of the report's snap-forecast section (empty without forecasts)."""
    if not run.forecast:
        return []
    # a snap published in stages (the detector's new maxima of one slack episode) is one snap, at its largest peak
    episodes = {}
    for e in run.snaps:
        episodes.setdefault((e["end"], round(e["slack_start"], 6)), []).append(e)
    snaps = [(end, max(g, key=lambda e: e["peak"])["t_peak"], tuple(e["t_peak"] for e in g)) for (end, _), g in episodes.items()]
    fc = run.forecast
    sources = sorted({f.source for f in fc})
    degraded = sum(f.degraded for f in fc)
    warn_p = warn_probability(run)
    thresholds = sorted({0.5, warn_p})
    lines = ["", "## Snap forecast", "",
             f"{len(fc)} forecasts (horizon {fc[0].horizon:g} s, {max(f.members for f in fc)} members, source "
             f"{', '.join(sources)}); {degraded} degraded. A snap is warned when a forecast with probability "
             "at least the threshold stamped >= 5 s before it predicted it within +-1.5 s; a false alarm is such "
             "a forecast with no snap within +-1.5 s of its predicted time (an episode: consecutive ones "
             f"predicting the same instant). Threshold 0.5: any forecast that makes a snap more likely than not; "
             f"{warn_p:g}: the run's alarm (`forecast.warn_probability`, what /diagnostics warns at).", "",
             "| end | threshold | snaps scored | warned >= 5 s ahead | warnings | false alarms | per 10 min | episodes per 10 min |",
             "|---|---|---|---|---|---|---|---|"]
    for end in END_NAMES:
        for threshold in thresholds:
            s = score(fc, snaps, end, until=float(run.t[-1]), threshold=threshold)
            frac = f"{s.warned} ({100 * s.warned_fraction:.0f} %)" if s.snaps else "-"
            alarm = " (alarm)" if threshold == warn_p else ""
            lines.append(f"| {end} | {threshold:g}{alarm} | {s.snaps} | {frac} | {s.warnings} | {s.false_alarms} | "
                         f"{s.false_alarms_per_10min:.1f} | {s.episodes_per_10min:.1f} |")
    reasons = sorted({f.reason for f in fc if f.degraded})
    if reasons:
        lines += ["", "Degraded because: " + "; ".join(reasons[:5]) + ("; ..." if len(reasons) > 5 else "") + "."]
    return lines
