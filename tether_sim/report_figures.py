"""The PNG figures of tether-sim-report (matplotlib, Agg backend). Inputs: report.RunData."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from tether_sim.physics.boundary import END_NAMES  # noqa: E402

END_COLOURS = {"ship": "tab:blue", "vehicle": "tab:orange"}
ANNOTATED = 5  # snap peaks labelled per end (the largest); all are marked


def _label_peaks(ax, snaps, run) -> None:
    """Peak value and amplification next to each marker, kept inside the frame: headroom above the
    highest peak, and labels near the right edge placed to the left of their marker."""
    lo, hi = ax.get_ylim()
    top = max(e["peak"] / 1e3 for e in snaps)
    ax.set_ylim(lo, max(hi, top + 0.25 * (top - lo)))
    t_lo, t_hi = float(run.t[0]), float(run.t[-1])
    for e in snaps:
        right = e["t_peak"] > t_lo + 0.85 * (t_hi - t_lo)
        ax.annotate(f"{e['peak'] / 1e3:.1f} kN\n×{e['amplification']:.2f}",
                    (e["t_peak"], e["peak"] / 1e3), textcoords="offset points",
                    xytext=(-4 if right else 4, 4), ha="right" if right else "left", va="bottom",
                    fontsize=8, color="tab:red", annotation_clip=True)


def degraded_intervals(run) -> list:
    """(start, end) times of the runs of states the node marked degraded."""
    flags = getattr(run, "degraded", None)
    if flags is None or not len(flags) or not flags.any():
        return []
    out, start = [], None
    for t, d in zip(run.t, flags):
        if d and start is None:
            start = t
        elif not d and start is not None:
            out.append((start, t))
            start = None
    if start is not None:
        out.append((start, run.t[-1]))
    return out


def plot_end_tensions(run, periods: dict, path: Path) -> Path:
    """Ship and vehicle end tension vs time; slack periods shaded, snap peaks marked."""
    fig, axes = plt.subplots(2, 1, figsize=(10, 6.5), sharex=True, constrained_layout=True)
    for ax, end in zip(axes, END_NAMES):
        ax.plot(run.t, run.end_tension[end] / 1e3, color=END_COLOURS[end], lw=1.2,
                label=f"{end} end tension (TetherState)")
        if end in run.wrench and len(run.wrench[end][0]):
            tw, fw = run.wrench[end]
            ax.plot(tw, fw / 1e3, color="k", lw=0.7, ls="--", alpha=0.7,
                    label=f"|force| of the {end} wrench")
        for i, (a, b) in enumerate(degraded_intervals(run)):
            ax.axvspan(a, b, color="0.5", alpha=0.2, lw=0,
                       label="degraded (late, end blended or snap detection off)" if i == 0 else None)
        for i, p in enumerate(periods[end]):
            ax.axvspan(p["start"], max(p["end"], p["start"] + 1e-3), color="tab:red", alpha=0.15,
                       lw=0, label="slack period" if i == 0 else None)
        levels = [p["threshold"] for p in periods[end]]
        if levels and max(levels) == min(levels):
            ax.axhline(levels[0] / 1e3, color="tab:red", lw=0.6, ls=":", label="slack threshold")
        elif levels:  # a winch run: the threshold follows the length (report.threshold_series)
            ax.step([p["start"] for p in periods[end]], [x / 1e3 for x in levels], where="post", color="tab:red",
                    lw=0.6, ls=":", label="slack threshold (follows the length)")
        snaps = [e for e in run.snaps if e["end"] == end]
        if snaps:
            ax.plot([e["t_peak"] for e in snaps], [e["peak"] / 1e3 for e in snaps], "v",
                    color="tab:red", ms=8, label="snap load (peak)")
            _label_peaks(ax, sorted(snaps, key=lambda e: -e["peak"])[:ANNOTATED], run)
        for e in (e for e in run.snaps if e["end"] == "span"):
            ax.axvline(e["t_peak"], color="tab:purple", lw=0.8, ls="--")
        ax.set_ylabel(f"{end} end tension [kN]")
        ax.grid(alpha=0.3)
        ax.legend(loc="upper right", fontsize=8)
    axes[-1].set_xlabel(f"{run.time_label} [s]")
    axes[0].set_title(f"End tensions — {run.path.name} (solver {run.solver})")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def plot_shapes(run, path: Path, n_snapshots: int = 8) -> Path:
    """Shape snapshots at evenly spaced times (and at the largest snap peak, red): x-z view (ENU)
    and the displacement from the first state along the cable, which shows heave-driven motion
    even when the cable hangs straight down."""
    n = max(1, min(n_snapshots, len(run.t)))
    picks = list(np.unique(np.linspace(0, len(run.t) - 1, n).round().astype(int)))
    colours = list(plt.cm.viridis(np.linspace(0.0, 0.9, len(picks))))
    labels = [f"t = {run.t[k]:.1f} s" for k in picks]
    if run.snaps:
        biggest = max(run.snaps, key=lambda e: e["peak"])
        picks.append(int(np.argmin(np.abs(run.t - biggest["t_peak"]))))
        colours.append("tab:red")
        labels.append(f"t = {run.t[picks[-1]]:.1f} s (largest snap, {biggest['end']})")
    fig, (ax_shape, ax_disp) = plt.subplots(1, 2, figsize=(11, 6), constrained_layout=True)
    reference = run.positions[0]
    for k, colour, label in zip(picks, colours, labels):
        xyz = run.positions[k]
        ax_shape.plot(xyz[:, 0], xyz[:, 2], color=colour, lw=1.3, label=label)
        ax_shape.plot(xyz[[0, -1], 0], xyz[[0, -1], 2], "o", color=colour, ms=3)
        if getattr(run, "arc_history", None) is not None:  # a winch: points move along s, show T(s) instead
            ax_disp.plot(run.tension[k] / 1e3, run.arc_history[k], color=colour, lw=1.3)
            continue
        ax_disp.plot(xyz[:, 2] - reference[:, 2], run.arc_length, color=colour, lw=1.3)
        horizontal = np.hypot(xyz[:, 0] - reference[:, 0], xyz[:, 1] - reference[:, 1])
        ax_disp.plot(horizontal, run.arc_length, color=colour, lw=0.8, ls=":")
    ax_shape.axhline(0.0, color="tab:cyan", lw=0.8)
    _min_span(ax_shape, run.positions)
    ax_shape.set_xlabel("x (east) [m]")
    ax_shape.set_ylabel("z (up) [m]")
    ax_shape.set_title("shape (x-z), dots = ends")
    ax_shape.legend(fontsize=8, loc="best")
    ax_disp.invert_yaxis()
    ax_disp.axvline(0.0, color="k", lw=0.6)
    if getattr(run, "arc_history", None) is not None:
        ax_disp.set_xlabel("axial tension [kN]")
        ax_disp.set_title("tension along the cable (its length changes: winch)")
    else:
        ax_disp.set_xlabel("displacement from the first state [m]\nvertical (solid), horizontal (dotted)")
        ax_disp.set_title("motion along the cable")
    ax_disp.set_ylabel("arc length s from the ship [m]")
    for ax in (ax_shape, ax_disp):
        ax.grid(alpha=0.3)
    fig.suptitle(f"Cable shape snapshots — {run.path.name}")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def _min_span(ax, positions) -> None:
    """Widen the x axis of an x-z view to at least a fifth of the vertical extent, centred: a cable
    hanging straight down otherwise shows on a +-0.05 m axis that magnifies millimetres."""
    x, z = positions[..., 0], positions[..., 2]
    need = 0.2 * float(z.max() - z.min())
    lo, hi = ax.get_xlim()
    if hi - lo < need:
        mid = 0.5 * (float(x.max()) + float(x.min()))
        ax.set_xlim(mid - 0.5 * need, mid + 0.5 * need)


def plot_tension_envelope(run, envelope: dict, path: Path) -> Path:
    """Largest and smallest tension at each output point over the run (kN), against arc length;
    the breaking load as a line when the description gives one."""
    fig, ax = plt.subplots(figsize=(10, 5.0), constrained_layout=True)
    s = envelope["arc_length_m"]
    ax.fill_between(s, np.asarray(envelope["min_N"]) / 1e3, np.asarray(envelope["max_N"]) / 1e3,
                    color="tab:blue", alpha=0.2, label="range over the run")
    ax.plot(s, np.asarray(envelope["max_N"]) / 1e3, color="tab:red", lw=1.6, label="max over time")
    ax.plot(s, np.asarray(envelope["min_N"]) / 1e3, color="tab:blue", lw=1.2, label="min over time")
    peak = envelope["largest"]
    ax.plot([peak["arc_length_m"]], [peak["tension_N"] / 1e3], "v", color="k", ms=8,
            label=f"largest {peak['tension_N'] / 1e3:.1f} kN at s = {peak['arc_length_m']:.1f} m, t = {peak['time_s']:.2f} s")
    if envelope.get("breaking_load_N"):
        mbl = envelope["breaking_load_N"] / 1e3
        ax.axhline(mbl, color="k", ls="--", lw=1.0, label=f"breaking load {mbl:.0f} kN")
    ax.set_xlabel("arc length s from the ship [m]" + (" (fraction of L(t) x L at the start: winch)"
                                                      if getattr(run, "arc_history", None) is not None else ""))
    ax.set_ylabel("axial tension [kN]")
    ax.set_title(f"Tension envelope along the cable (output instants) — {run.path.name}")
    ax.legend(loc="best", fontsize=8)
    ax.grid(alpha=0.3)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def plot_tension_map(run, path: Path) -> Path:
    """Axial tension T(s, t) as a colour map; snap-load peaks marked at their arc length."""
    fig, ax = plt.subplots(figsize=(10, 5.5), constrained_layout=True)
    tension = run.tension / 1e3
    arcs = getattr(run, "arc_history", None)
    if arcs is not None and len(run.t) > 1:  # a winch: the points follow L(t); at most ~2000 states drawn
        k = slice(None, None, max(1, len(run.t) // 2000))
        mesh = ax.pcolormesh(np.repeat(run.t[k, None], arcs.shape[1], 1), arcs[k], tension[k], shading="gouraud",
                             cmap="magma")
    elif len(run.t) > 1:
        mesh = ax.pcolormesh(run.t, run.arc_length, tension.T, shading="nearest", cmap="magma")
    else:
        mesh = ax.scatter(np.repeat(run.t, len(run.arc_length)), run.arc_length, c=tension[0],
                          cmap="magma")
    fig.colorbar(mesh, ax=ax, label="axial tension [kN]")
    if run.snaps:
        ax.plot([e["t_peak"] for e in run.snaps], [e["arc_length"] for e in run.snaps], "v",
                color="cyan", ms=8, mec="k", label="snap load (peak)")
        ax.legend(loc="upper right", fontsize=8)
    ax.set_xlabel(f"{run.time_label} [s]")
    ax.set_ylabel("arc length s from the ship [m]")
    ax.set_title(f"Tension along the cable over time — {run.path.name}")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
