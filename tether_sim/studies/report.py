"""``tether-sim-study report RESULTS``: the figures a snap-load engineer reads, and a markdown summary.

- ``peak_tension_heatmap.png``: largest tension (ship and cage) against cable length and fairlead
  frequency, one column of panels per value of a third varied quantity (PE2020 Sec. 6.2 / Fig. 5-6
  grid: L x f, per alpha); cells that violate the DNV-RP-H103 slack criterion are hatched.
- ``daf_sea_state.png``: dynamic amplification factor at the cage against the sea state. Until
  waves and RAOs exist the sea state is the fairlead motion: amplitude and frequency.
- ``exceedance.png``: exceedance probability of the per-case maxima of the cage tension (Weibull
  plotting positions i / (n + 1)) with a Gumbel fit (``scipy.stats.gumbel_r``, maximum likelihood);
  per condition when the study has seeds (cases that differ only by their seed), else pooled.
- ``report.md``: cases, failures, the table of headline statistics, Gumbel parameters, throughput.
"""

import math
from pathlib import Path

import numpy as np

from tether_sim.studies.results import read_results
from tether_sim.studies.stats import DNV_SLACK_FRACTION

L_KEY, F_KEY, A_KEY = "cable.length", "fairlead_frequency_Hz", "fairlead_amplitude_m"


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _ok(rows):
    return [r for r in rows if r.get("status") == "ok"]


def _varied(rows):
    """Variable columns (``var.*``) that take more than one value, in table order."""
    cols = [c for c in (rows[0] if rows else {}) if c.startswith("var.")]
    return [c for c in cols if len({repr(r.get(c)) for r in rows}) > 1]


def _facet(rows):
    """The varied quantity (other than length, frequency, seed) to split the heat maps by, if any."""
    for c in _varied(rows):
        values = {r[c] for r in rows}
        if c != "var.seed" and c not in ("var." + L_KEY, "var." + F_KEY) and 1 < len(values) <= 6:
            if all(isinstance(x, (int, float)) for x in values) and not all(len({r[c] for r in rows if (r[L_KEY], r[F_KEY]) == key}) == 1
                       for key in {(r[L_KEY], r[F_KEY]) for r in rows}):
                return c
    return None


def heatmap(rows, path):
    """Largest ship and cage tension on the (frequency, length) grid; max over unlisted variables."""
    plt = _plt()
    facet = _facet(rows)
    values = sorted({r[facet] for r in rows}) if facet else [None]
    lengths = sorted({r[L_KEY] for r in rows})
    freqs = sorted({r[F_KEY] for r in rows})
    fig, axes = plt.subplots(2, len(values), figsize=(max(6.0, 3.4 * len(values) + 1.2), 2.6 + 1.1 * len(lengths) * 2),
                             squeeze=False)
    for col, v in enumerate(values):
        sub = [r for r in rows if facet is None or r[facet] == v]
        for row, (end, label) in enumerate((("ship", "ship"), ("vehicle", "cage"))):
            grid = np.full((len(lengths), len(freqs)), np.nan)
            bad = np.zeros_like(grid, dtype=bool)
            for r in sub:
                i, j = lengths.index(r[L_KEY]), freqs.index(r[F_KEY])
                grid[i, j] = np.fmax(grid[i, j], r[f"{end}_T_max_N"] / 1e3)
                bad[i, j] |= not r[f"{end}_dnv_slack_ok"]
            ax = axes[row, col]
            im = ax.imshow(grid, origin="lower", aspect="auto", cmap="viridis")
            for i in range(len(lengths)):
                for j in range(len(freqs)):
                    if np.isfinite(grid[i, j]):
                        ax.text(j, i, f"{grid[i, j]:.0f}" + ("*" if bad[i, j] else ""), ha="center", va="center",
                                color="w" if grid[i, j] < np.nanmean(grid) else "k", fontsize=8)
            ax.set_xticks(range(len(freqs)), [f"{f:g}" for f in freqs])
            ax.set_yticks(range(len(lengths)), [f"{L:g}" for L in lengths])
            ax.set_xlabel("fairlead frequency f (Hz)")
            ax.set_ylabel("cable length L (m)")
            title = f"{label}: largest tension (kN)"
            ax.set_title(title + (f"\n{facet[4:]} = {v:g}" if facet else ""), fontsize=9)
            fig.colorbar(im, ax=ax, shrink=0.85)
    fig.suptitle(f"Peak tension against length and frequency\n(* = slack: T_min < {DNV_SLACK_FRACTION:g} T_static, "
                 "DNV-RP-H103 criterion not met)", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def daf_figure(rows, path):
    """Cage DAF (T_max / static) against fairlead amplitude and frequency (the sea state until waves)."""
    plt = _plt()
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    f = np.array([r[F_KEY] for r in rows])
    a = np.array([r[A_KEY] for r in rows])
    daf = np.array([r["vehicle_daf"] for r in rows])
    ok = np.array([bool(r["vehicle_dnv_slack_ok"]) for r in rows])
    sc = ax1.scatter(f[ok], a[ok], c=daf[ok], cmap="plasma", vmin=np.nanmin(daf), vmax=np.nanmax(daf), s=60,
                     marker="o", label="DNV slack criterion met")
    ax1.scatter(f[~ok], a[~ok], c=daf[~ok], cmap="plasma", vmin=np.nanmin(daf), vmax=np.nanmax(daf), s=70,
                marker="X", edgecolors="k", linewidths=0.5, label="slack (criterion not met)")
    fig.colorbar(sc, ax=ax1, label="cage DAF = T_max / T_static")
    ax1.set_xlabel("fairlead frequency f (Hz)")
    ax1.set_ylabel("fairlead amplitude a (m)")
    ax1.set_title("Cage DAF against the fairlead motion (max over other variables at a point)", fontsize=9)
    ax1.legend(fontsize=7, loc="best")
    group_key = A_KEY if len(set(a)) > 1 else L_KEY
    for g in sorted({r[group_key] for r in rows}):
        sub = sorted((r for r in rows if r[group_key] == g), key=lambda r: r[F_KEY])
        fs = sorted({r[F_KEY] for r in sub})
        worst = [max(r["vehicle_daf"] for r in sub if r[F_KEY] == x) for x in fs]
        ax2.plot(fs, worst, "o-", label=f"{'a' if group_key == A_KEY else 'L'} = {g:g} m")
    ax2.axhline(1.0, color="0.5", lw=0.8)
    ax2.set_xlabel("fairlead frequency f (Hz)")
    ax2.set_ylabel("cage DAF (largest over the other variables)")
    ax2.set_title("DAF against frequency", fontsize=9)
    ax2.grid(alpha=0.3)
    ax2.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def exceedance_groups(rows):
    """{label: per-case maxima of the cage tension (N)}: per seed group if every group has >= 5 cases."""
    varied = [c for c in _varied(rows) if c != "var.seed"]
    if "var.seed" in (rows[0] if rows else {}):
        groups = {}
        for r in rows:
            label = ", ".join(f"{c[4:]}={r[c]:g}" if isinstance(r[c], (int, float)) else f"{c[4:]}={r[c]}"
                              for c in varied) or "all cases"
            groups.setdefault(label, []).append(r["vehicle_T_max_N"])
        if all(len(v) >= 5 for v in groups.values()):
            return dict(sorted(groups.items(), key=lambda kv: -len(kv[1]))[:6]), True
    return {"all cases (pooled)": [r["vehicle_T_max_N"] for r in rows]}, False


def gumbel_fit(maxima):
    """(loc, scale) of the maximum-likelihood Gumbel fit (scipy.stats.gumbel_r.fit)."""
    from scipy.stats import gumbel_r

    return tuple(float(x) for x in gumbel_r.fit(np.asarray(maxima, float)))


def exceedance_figure(rows, path):
    from scipy.stats import gumbel_r

    plt = _plt()
    groups, per_seed = exceedance_groups(rows)
    fits = {}
    fig, ax = plt.subplots(figsize=(7.5, 4.8))
    for label, maxima in groups.items():
        x = np.sort(np.asarray([m for m in maxima if np.isfinite(m)], float))
        if x.size == 0:
            continue
        p = 1.0 - np.arange(1, x.size + 1) / (x.size + 1.0)  # P(X > x_(i)) = 1 - i / (n + 1)
        line = ax.semilogy(x / 1e3, p, "o", ms=4, label=f"{label} (n = {x.size})")[0]
        if x.size >= 3 and np.ptp(x) > 0:
            loc, scale = gumbel_fit(x)
            fits[label] = (loc, scale, x.size)
            xs = np.linspace(x[0] - 0.1 * np.ptp(x), x[-1] + 0.5 * np.ptp(x), 200)
            ax.semilogy(xs / 1e3, gumbel_r.sf(xs, loc, scale), "-", color=line.get_color(), lw=1,
                        label=f"Gumbel fit: mu = {loc / 1e3:.1f} kN, beta = {scale / 1e3:.2f} kN")
    ax.set_xlabel("per-case maximum of the cage tension (kN)")
    ax.set_ylabel("exceedance probability P(T_max > x)")
    ax.set_title("Exceedance of per-case maxima" + (" per condition (seeds)" if per_seed else
                                                       " (pooled over all cases)"), fontsize=9)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return fits, per_seed


def _fmt(v):
    if isinstance(v, bool):
        return "yes" if v else "NO"
    if isinstance(v, float):
        return "-" if math.isnan(v) else f"{v:.4g}"
    return str(v)


def _table(rows, cols, names):
    lines = ["| " + " | ".join(names) + " |", "|" + "---|" * len(names)]
    lines += ["| " + " | ".join(_fmt(c(r) if callable(c) else r.get(c)) for c in cols) + " |" for r in rows]
    return lines


def write_report(results, out=None) -> Path:
    """Figures and report.md for a results folder; returns the path of report.md."""
    results = Path(results)
    folder = results if results.is_dir() else results.parent
    out = Path(out) if out else folder / "report"
    out.mkdir(parents=True, exist_ok=True)
    rows = sorted(read_results(results), key=lambda r: r["index"])
    ok = _ok(rows)
    failed = [r for r in rows if r.get("status") != "ok"]
    name = rows[0]["study"] if rows else folder.name
    text = [f"# Study {name}: snap-load summary", "",
            f"{len(rows)} cases in the results: {len(ok)} ok, {len(failed)} failed.", ""]
    if ok:
        heatmap(ok, out / "peak_tension_heatmap.png")
        daf_figure(ok, out / "daf_sea_state.png")
        fits, per_seed = exceedance_figure(ok, out / "exceedance.png")
        varied = _varied(ok)
        cols = ["index"] + varied + [
            lambda r: r["ship_T_max_N"] / 1e3, lambda r: r["vehicle_T_max_N"] / 1e3, "vehicle_daf",
            "vehicle_n_slack", "vehicle_n_snap", lambda r: r["vehicle_snap_peak_N"] / 1e3, "vehicle_snap_daf",
            "vehicle_slack_max_s", "vehicle_rise_time_s", "vehicle_dnv_slack_ok", "ship_dnv_slack_ok",
            lambda r: (r.get("ship_n_numerical") or 0) + (r.get("vehicle_n_numerical") or 0), "rtf"]
        names = ["case"] + [c[4:] for c in varied] + [
            "ship T_max kN", "cage T_max kN", "cage DAF", "cage slack", "cage snaps", "cage snap peak kN",
            "snap DAF", "longest slack s", "rise time s", "DNV ok cage", "DNV ok ship", "numerical warnings", "RT factor"]
        cpu_h = sum(r["cpu_s"] for r in ok) / 3600.0
        text += ["![peak tension](peak_tension_heatmap.png)", "", "![DAF](daf_sea_state.png)", "",
                 "![exceedance](exceedance.png)", "", "## Cases", "",
                 f"DNV-RP-H103 slack criterion (Sec. 3.4.3, F_hydro <= 0.9 F_static): met when the tension at "
                 f"that end never fell below {DNV_SLACK_FRACTION:g} x its static value. DAF = largest tension / "
                 "static tension; snap DAF = largest snap peak / static. Numerical warnings: re-tensioning peaks "
                 "(both ends) the snap guard rejected as physically impossible (docs/snap_guard.md); they are not "
                 "counted as snaps, but T_max and DAF of such a case are the raw solution's and include them.", ""]
        text += _table(ok, cols, names) + [""]
        text += ["## Gumbel fit of the per-case maxima of the cage tension", "",
                 "Per condition (cases differing only by their seed)." if per_seed else
                 "Pooled over all cases: the cases are different conditions, so this describes the spread of the "
                 "study, not the extreme-value distribution of one sea state (use seeds for that).", ""]
        from scipy.stats import gumbel_r

        if not fits:
            text += ["No fit: fewer than 3 distinct per-case maxima.", ""]
        text += _table([{"g": k, "n": n, "mu": loc / 1e3, "beta": s / 1e3,
                         "q": gumbel_r.ppf(0.9, loc, s) / 1e3} for k, (loc, s, n) in fits.items()],
                       ["g", "n", "mu", "beta", "q"],
                       ["condition", "n", "mu (kN)", "beta (kN)", "90 % quantile (kN)"]) + [""]
        text += ["## Throughput", "",
                 f"{len(ok)} cases, {sum(r['sim_s'] for r in ok):.4g} s simulated, {cpu_h * 3600:.4g} s of "
                 f"thread-CPU time: {len(ok) / cpu_h if cpu_h > 0 else math.nan:.4g} cases per core-hour "
                 f"(median real-time factor {float(np.median([r['rtf'] for r in ok])):.3g}).", ""]
    if failed:
        text += ["## Failed cases", ""] + _table(failed, ["index", "key", "error"], ["case", "key", "error"]) + [""]
    md = out / "report.md"
    md.write_text("\n".join(text))
    return md
