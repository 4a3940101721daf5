"""The PNG figures of tether-sim-report (matplotlib, Agg backend). Inputs: report.RunData."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

END_COLOURS = {"ship": "tab:blue", "vehicle": "tab:orange"}
ANNOTATED = 5  # snap peaks labelled per end (the largest); all are marked


def plot_end_tensions(run, periods: dict, path: Path) -> Path:
    """Ship and vehicle end tension vs time; slack periods shaded, snap peaks marked."""
    fig, axes = plt.subplots(2, 1, figsize=(10, 6.5), sharex=True, constrained_layout=True)
    for ax, end in zip(axes, ("ship", "vehicle")):
        ax.plot(run.t, run.end_tension[end] / 1e3, color=END_COLOURS[end], lw=1.2,
                label=f"{end} end tension (TetherState)")
        if end in run.wrench and len(run.wrench[end][0]):
            tw, fw = run.wrench[end]
            ax.plot(tw, fw / 1e3, color="k", lw=0.7, ls="--", alpha=0.7,
                    label=f"|force| of the {end} wrench")
        for i, p in enumerate(periods[end]):
            ax.axvspan(p["start"], max(p["end"], p["start"] + 1e-3), color="tab:red", alpha=0.15,
                       lw=0, label="slack period" if i == 0 else None)
        if periods[end]:
            ax.axhline(periods[end][0]["threshold"] / 1e3, color="tab:red", lw=0.6, ls=":",
                       label="slack threshold")
        snaps = [e for e in run.snaps if e["end"] == end]
        if snaps:
            ax.plot([e["t_peak"] for e in snaps], [e["peak"] / 1e3 for e in snaps], "v",
                    color="tab:red", ms=8, label="snap load (peak)")
            for e in sorted(snaps, key=lambda e: -e["peak"])[:ANNOTATED]:
                ax.annotate(f"{e['peak'] / 1e3:.1f} kN\n×{e['amplification']:.2f}",
                            (e["t_peak"], e["peak"] / 1e3), textcoords="offset points",
                            xytext=(4, 6), fontsize=8, color="tab:red")
        for e in (e for e in run.snaps if e["end"] == "span"):
            ax.axvline(e["t_peak"], color="tab:purple", lw=0.8, ls="--")
        ax.set_ylabel(f"{end} end tension [kN]")
        ax.grid(alpha=0.3)
        ax.legend(loc="upper right", fontsize=8)
    axes[-1].set_xlabel("time since first state [s]")
    axes[0].set_title(f"End tensions — {run.path.name} (solver {run.solver})")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def plot_shapes(run, path: Path, n_snapshots: int = 8) -> Path:
    """Cable shape at n_snapshots evenly spaced times: x-z and y-z views (ENU, z up)."""
    n = max(1, min(n_snapshots, len(run.t)))
    picks = np.unique(np.linspace(0, len(run.t) - 1, n).round().astype(int))
    fig, axes = plt.subplots(1, 2, figsize=(11, 6), sharey=True, constrained_layout=True)
    colours = plt.cm.viridis(np.linspace(0.0, 0.9, len(picks)))
    for k, colour in zip(picks, colours):
        xyz = run.positions[k]
        for ax, col in zip(axes, (0, 1)):
            ax.plot(xyz[:, col], xyz[:, 2], color=colour, lw=1.3, label=f"t = {run.t[k]:.1f} s")
            ax.plot(xyz[[0, -1], col], xyz[[0, -1], 2], "o", color=colour, ms=3)
    for ax, name in zip(axes, ("x (east)", "y (north)")):
        ax.set_xlabel(f"{name} [m]")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("z (up) [m]")
    axes[0].axhline(0.0, color="tab:cyan", lw=0.8)
    axes[1].axhline(0.0, color="tab:cyan", lw=0.8)
    axes[1].legend(fontsize=8, loc="best")
    fig.suptitle(f"Cable shape snapshots (ship end at s = 0, dots = ends) — {run.path.name}")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def plot_tension_map(run, path: Path) -> Path:
    """Axial tension T(s, t) as a colour map; snap-load peaks marked at their arc length."""
    fig, ax = plt.subplots(figsize=(10, 5.5), constrained_layout=True)
    tension = run.tension / 1e3
    if len(run.t) > 1:
        mesh = ax.pcolormesh(run.t, run.arc_length, tension.T, shading="nearest", cmap="magma")
    else:
        mesh = ax.scatter(np.repeat(run.t, len(run.arc_length)), run.arc_length, c=tension[0],
                          cmap="magma")
    fig.colorbar(mesh, ax=ax, label="axial tension [kN]")
    if run.snaps:
        ax.plot([e["t_peak"] for e in run.snaps], [e["arc_length"] for e in run.snaps], "v",
                color="cyan", ms=8, mec="k", label="snap load (peak)")
        ax.legend(loc="upper right", fontsize=8)
    ax.set_xlabel("time since first state [s]")
    ax.set_ylabel("arc length s from the ship [m]")
    ax.set_title(f"Tension along the cable over time — {run.path.name}")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
