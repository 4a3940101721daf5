"""``tether-sim-study report RESULTS``: the figures a snap-load engineer reads, and a markdown summary.

The figures follow what the study varies (its axes, :func:`study_axes`): the varied resolved
quantities (fairlead frequency, fairlead amplitude, cable length, bending stiffness, preferred in
that order) and the varied study variables that none of them already expresses; the seed is never
an axis, and values equal to 10 significant digits are one value.

- ``peak_tension_heatmap.png`` (two axes or more): largest tension (ship and cage) over the first
  two axes, one column of panels per value of a third axis of at most 6 values (PE2020 Sec. 6.2 /
  Fig. 5-6 grid: f x L, per EI), else the largest over the remaining ones; cells that violate the
  DNV-RP-H103 slack criterion are starred. ``peak_tension.png`` instead for one axis: largest
  tension against it, every case a point (the seeds of a condition side by side).
- ``daf_sea_state.png``: dynamic amplification factor at the cage against the first axis, one line
  per value of the second (largest over the rest).
- ``exceedance.png``: only for a study with seeds (cases that differ only by their seed): exceedance
  probability of the per-case maxima of the cage tension (Weibull plotting positions i / (n + 1))
  with a Gumbel fit (``scipy.stats.gumbel_r``, maximum likelihood) per condition. A deterministic
  sweep has no such figure: its cases are different conditions, not samples of one sea state.
- ``report.md``: cases, failures, the table of headline statistics, Gumbel parameters, throughput.
"""

import math
from pathlib import Path

import numpy as np

from tether_sim.studies.results import column_unit, read_results, read_units
from tether_sim.studies.stats import DNV_SLACK_FRACTION

# resolved quantities (case.py) that can be axes, in order of preference, with their axis labels
AXES = {"fairlead_frequency_Hz": "fairlead frequency f (Hz)", "fairlead_amplitude_m": "fairlead amplitude a (m)",
        "cable_length_m": "cable length L (m)", "cable_EI_Nm2": "bending stiffness EI (N m^2)"}
SEED = "var.seed"


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _ok(rows):
    return [r for r in rows if r.get("status") == "ok"]


def _key(value):
    """A value as the figures group it: numbers to 10 significant digits (0.19077500000000001 and
    0.190775 are one column), anything else as its text."""
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return float(f"{value:.10g}")
    return repr(value)


def _varied(rows):
    """Variable columns (``var.*``) that take more than one value, in table order."""
    cols = [c for c in (rows[0] if rows else {}) if c.startswith("var.")]
    return [c for c in cols if len({_key(r.get(c)) for r in rows}) > 1]


def _expresses(rows, a, b) -> bool:
    """Column a's values determine column b's and the other way round (one-to-one over the rows)."""
    pairs = {(_key(r.get(a)), _key(r.get(b))) for r in rows}
    return len(pairs) == len({x for x, _ in pairs}) == len({y for _, y in pairs})


def _unit_label(column, units=None):
    """Axis label of a study variable: its name, with its unit (that of the parameter it names, or
    the one the results table carries for the study's own variables; "-" for a ratio)."""
    unit = column_unit(column, units)
    return f"{column[4:]} ({'-' if unit == '1' else unit})" if unit else column[4:]


def study_axes(rows, units=None) -> list:
    """[(column, label)] of what the study varies, preferred axes first (module docstring); ``units``:
    column -> unit of the results table (:func:`read_units`)."""
    numeric = [c for c in rows[0] if all(isinstance(r.get(c), (int, float)) and not isinstance(r.get(c), bool)
                                         and math.isfinite(r.get(c)) for r in rows)] if rows else []
    axes = [(c, AXES[c]) for c in AXES if c in numeric and len({_key(r[c]) for r in rows}) > 1]
    for c in _varied(rows):
        if c != SEED and c in numeric and not any(_expresses(rows, c, a) for a, _ in axes):
            axes.append((c, _unit_label(c, units)))
    return axes


def _fmt_value(v):
    return f"{v:g}" if isinstance(v, float) else str(v)


def heatmap(rows, axes, path):
    """Largest ship and cage tension over the first two axes (faceted by a third of <= 6 values)."""
    plt = _plt()
    (xc, xl), (yc, yl) = axes[0], axes[1]
    facet = axes[2] if len(axes) > 2 and len({_key(r[axes[2][0]]) for r in rows}) <= 6 else None
    rest = [label for c, label in axes[2:] if facet is None or c != facet[0]]
    values = sorted({_key(r[facet[0]]) for r in rows}) if facet else [None]
    xs = sorted({_key(r[xc]) for r in rows})
    ys = sorted({_key(r[yc]) for r in rows})
    fig, axs = plt.subplots(2, len(values), figsize=(max(6.0, 3.4 * len(values) + 1.2), 2.6 + 1.1 * len(ys) * 2),
                            squeeze=False)
    for col, v in enumerate(values):
        sub = [r for r in rows if facet is None or _key(r[facet[0]]) == v]
        for row, (end, label) in enumerate((("ship", "ship"), ("vehicle", "cage"))):
            grid = np.full((len(ys), len(xs)), np.nan)
            bad = np.zeros_like(grid, dtype=bool)
            for r in sub:
                i, j = ys.index(_key(r[yc])), xs.index(_key(r[xc]))
                grid[i, j] = np.fmax(grid[i, j], r[f"{end}_T_max_N"] / 1e3)
                bad[i, j] |= not r[f"{end}_dnv_slack_ok"]
            ax = axs[row, col]
            im = ax.imshow(grid, origin="lower", aspect="auto", cmap="viridis")
            for i in range(len(ys)):
                for j in range(len(xs)):
                    if np.isfinite(grid[i, j]):
                        ax.text(j, i, f"{grid[i, j]:.0f}" + ("*" if bad[i, j] else ""), ha="center", va="center",
                                color="w" if grid[i, j] < np.nanmean(grid) else "k", fontsize=8)
            ax.set_xticks(range(len(xs)), [_fmt_value(x) for x in xs])
            ax.set_yticks(range(len(ys)), [_fmt_value(y) for y in ys])
            ax.set_xlabel(xl)
            ax.set_ylabel(yl)
            title = f"{label}: largest tension (kN)"
            ax.set_title(title + (f"\n{facet[1]} = {_fmt_value(v)}" if facet else ""), fontsize=9)
            fig.colorbar(im, ax=ax, shrink=0.85)
    over = f"; largest over {', '.join(rest)}" if rest else ""
    fig.suptitle(f"Peak tension{over}\n(* = slack: T_min < {DNV_SLACK_FRACTION:g} T_static, "
                 "DNV-RP-H103 criterion not met)", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def peak_figure(rows, axis, path):
    """One axis: largest ship and cage tension of every case against it (seeds side by side)."""
    plt = _plt()
    column, label = axis
    fig, ax = plt.subplots(figsize=(7.5, 4.5))
    x = np.array([r[column] for r in rows], float)
    for end, name, marker in (("ship", "ship", "s"), ("vehicle", "cage", "o")):
        t = np.array([r[f"{end}_T_max_N"] for r in rows], float) / 1e3
        ok = np.array([bool(r[f"{end}_dnv_slack_ok"]) for r in rows])
        line = ax.plot(x[ok], t[ok], marker, ls="none", ms=5, label=f"{name} (DNV slack criterion met)")[0]
        ax.plot(x[~ok], t[~ok], marker, ls="none", ms=7, mfc="none", color=line.get_color(),
                label=f"{name}, slack (criterion not met)")
    ax.set_xlabel(label)
    ax.set_ylabel("largest tension over the run (kN)")
    ax.set_title(f"Peak tension, every case ({len(rows)})", fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def daf_figure(rows, axes, path):
    """Cage DAF (T_max / static) against the first axis, one line per value of the second."""
    plt = _plt()
    xc, xl = axes[0]
    fig, ax = plt.subplots(figsize=(7.5, 4.5))
    groups = sorted({_key(r[axes[1][0]]) for r in rows}) if len(axes) > 1 else [None]
    for g in groups:
        sub = [r for r in rows if g is None or _key(r[axes[1][0]]) == g]
        xs = sorted({_key(r[xc]) for r in sub})
        worst = [max(r["vehicle_daf"] for r in sub if _key(r[xc]) == x) for x in xs]
        ax.plot(xs, worst, "o-", label=None if g is None else f"{axes[1][1]} = {_fmt_value(g)}")
        bad = [(x, max(r["vehicle_daf"] for r in sub if _key(r[xc]) == x)) for x in xs
               if any(not r["vehicle_dnv_slack_ok"] for r in sub if _key(r[xc]) == x)]
        if bad:
            ax.plot(*zip(*bad), "X", color="k", ms=7, mfc="none")
    ax.axhline(1.0, color="0.5", lw=0.8)
    ax.set_xlabel(xl)
    ax.set_ylabel("cage DAF = T_max / T_static")
    rest = [label for _, label in axes[2:]] + (["seed"] if SEED in _varied(rows) else [])
    ax.set_title("Cage DAF" + (f", largest over {', '.join(rest)}" if rest else "") +
                 " (x: slack, DNV criterion not met)", fontsize=9)
    ax.grid(alpha=0.3)
    if len(groups) > 1:
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def exceedance_groups(rows):
    """{condition: per-case maxima of the cage tension (N)} for a study with seeds, every condition
    (cases that differ only by their seed) with >= 5 cases, at most 6 conditions; None otherwise: a
    deterministic sweep's cases are different conditions, whose maxima are no sample of one
    distribution."""
    if SEED not in _varied(rows):
        return None
    varied = [c for c in _varied(rows) if c != SEED]
    groups = {}
    for r in rows:
        label = ", ".join(f"{c[4:]}={_fmt_value(r[c])}" for c in varied) or "all cases"
        groups.setdefault(label, []).append(r["vehicle_T_max_N"])
    if not all(len(v) >= 5 for v in groups.values()):
        return None
    return dict(sorted(groups.items(), key=lambda kv: -len(kv[1]))[:6])


def gumbel_fit(maxima):
    """(loc, scale) of the maximum-likelihood Gumbel fit (scipy.stats.gumbel_r.fit)."""
    from scipy.stats import gumbel_r

    return tuple(float(x) for x in gumbel_r.fit(np.asarray(maxima, float)))


def exceedance_figure(groups, path):
    from scipy.stats import gumbel_r

    plt = _plt()
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
    ax.set_title("Exceedance of per-case maxima per condition (over its seeds)", fontsize=9)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return fits


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


def network_lines(rows) -> list:
    """The lines of a network study's rows (their ``<line>.ship_T_max_N`` columns), in table order."""
    return [c[:-len(".ship_T_max_N")] for c in rows[0] if c.endswith(".ship_T_max_N")]


def network_tables(ok, units) -> list:
    """Markdown of a line-network study (case.run_network_task's columns): per line, both ends' largest
    tension, snaps and largest snap peak; the largest force on each point; no figures yet."""
    varied = _varied(ok)
    head = ["case"] + [_unit_label(c, units) for c in varied]
    text = ["Line network: per line, its s = 0 end (`ship` columns: the end its `from` names) and its s = L end "
            "(`vehicle`: its `to`). T_max over every substep; snaps as the node's detector publishes them (one per "
            "slack episode, its largest peak); numerical: re-tensioning peaks the snap guard rejected "
            "(docs/snap_guard.md), never counted as snaps. No figures for network studies yet.", ""]
    for line in network_lines(ok):
        cols = ["index"] + varied + [
            lambda r, p=f"{line}.ship_": r[p + "T_max_N"] / 1e3, lambda r, p=f"{line}.vehicle_": r[p + "T_max_N"] / 1e3,
            f"{line}.ship_n_snap", lambda r, p=f"{line}.ship_": r[p + "snap_peak_N"] / 1e3,
            f"{line}.vehicle_n_snap", lambda r, p=f"{line}.vehicle_": r[p + "snap_peak_N"] / 1e3,
            f"{line}.ship_n_slack", f"{line}.vehicle_n_slack",
            lambda r, p=line: (r.get(f"{p}.ship_n_numerical") or 0) + (r.get(f"{p}.vehicle_n_numerical") or 0)]
        names = head + ["T_max s=0 kN", "T_max s=L kN", "snaps s=0", "snap peak s=0 kN", "snaps s=L",
                        "snap peak s=L kN", "slack s=0", "slack s=L", "numerical warnings"]
        text += [f"## Line `{line}`", ""] + _table(ok, cols, names) + [""]
    points = [c[:-len("_force_max_N")] for c in ok[0] if c.endswith("_force_max_N")]
    if points:
        text += ["## Force of the lines on each point (largest |F| at the output instants)", ""]
        text += _table(ok, ["index"] + varied + [lambda r, p=p: r[f"{p}_force_max_N"] / 1e3 for p in points] + ["rtf"],
                       head + [f"{p} kN" for p in points] + ["RT factor"]) + [""]
    return text


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
    if ok and ok[0].get("network"):
        text += network_tables(ok, read_units(results))
    elif ok:
        units = read_units(results)
        axes = study_axes(ok, units)
        figures = []
        if len(axes) >= 2:
            heatmap(ok, axes, out / "peak_tension_heatmap.png")
            figures.append("![peak tension](peak_tension_heatmap.png)")
        elif axes:
            peak_figure(ok, axes[0], out / "peak_tension.png")
            figures.append("![peak tension](peak_tension.png)")
        if axes:
            daf_figure(ok, axes, out / "daf_sea_state.png")
            figures.append("![DAF](daf_sea_state.png)")
        groups = exceedance_groups(ok)
        fits = exceedance_figure(groups, out / "exceedance.png") if groups else {}
        if groups:
            figures.append("![exceedance](exceedance.png)")
        varied = _varied(ok)
        cols = ["index"] + varied + [
            lambda r: r["ship_T_max_N"] / 1e3, lambda r: r["vehicle_T_max_N"] / 1e3, "vehicle_daf",
            "vehicle_n_slack", "vehicle_n_snap", lambda r: r["vehicle_snap_peak_N"] / 1e3, "vehicle_snap_daf",
            "vehicle_slack_max_s", "vehicle_rise_time_s", "vehicle_dnv_slack_ok", "ship_dnv_slack_ok",
            lambda r: (r.get("ship_n_numerical") or 0) + (r.get("vehicle_n_numerical") or 0), "rtf"]
        names = ["case"] + [_unit_label(c, units) for c in varied] + [
            "ship T_max kN", "cage T_max kN", "cage DAF", "cage slack", "cage snaps", "cage snap peak kN",
            "snap DAF", "longest slack s", "rise time s", "DNV ok cage", "DNV ok ship", "numerical warnings", "RT factor"]
        cpu_h = sum(r["cpu_s"] for r in ok) / 3600.0
        text += ["Varied: " + (", ".join(label for _, label in axes) or "nothing but the seed") +
                 (f" and the seed ({len({r[SEED] for r in ok})} seeds)" if axes and SEED in _varied(ok) else "") + ".", ""]
        text += [x for f in figures for x in (f, "")] + ["## Cases", "",
                 f"DNV-RP-H103 slack criterion (Sec. 3.4.3, F_hydro <= 0.9 F_static): met when the tension at "
                 f"that end never fell below {DNV_SLACK_FRACTION:g} x its static value. DAF = largest tension / "
                 "static tension; snap DAF = largest snap peak / static. Numerical warnings: re-tensioning peaks "
                 "(both ends) the snap guard rejected as physically impossible (docs/snap_guard.md); they are not "
                 "counted as snaps, but T_max and DAF of such a case are the raw solution's and include them.", ""]
        text += _table(ok, cols, names) + [""]
        text += ["## Gumbel fit of the per-case maxima of the cage tension", ""]
        if groups is None:
            text += ["None: " + ("the cases are different conditions (no seeds), whose maxima are no sample of "
                                 "one sea state; add `seeds:` to the study for an extreme-value fit." if SEED not in
                                 _varied(ok) else "a condition has fewer than 5 seeds."), ""]
        else:
            from scipy.stats import gumbel_r

            text += ["Per condition (cases differing only by their seed).", ""]
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
