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

A line-network study (rows of ``case.run_network_task``) gets its tables per line and of the point forces, and the
same figures per line, per body and for the points (:func:`network_figures`).
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


# the single-line figures' series: (column, label, column of the DNV slack flag or None)
SINGLE_LINE = (("ship_T_max_N", "ship", "ship_dnv_slack_ok"), ("vehicle_T_max_N", "cage", "vehicle_dnv_slack_ok"))


def _cell(value):
    """A heat map cell's text: whole kN from 100 kN on, three significant digits below (a vehicle's 0.41 kN)."""
    return f"{value:.0f}" if abs(value) >= 100.0 else f"{value:.3g}"


def _series_data(artists):
    """{label: (x, y)} of what the figure plots, read back from its artists (label -> list of Line2D)."""
    out = {}
    for label, lines in artists.items():
        x = np.concatenate([np.asarray(a.get_xdata(), float) for a in lines])
        y = np.concatenate([np.asarray(a.get_ydata(), float) for a in lines])
        out[label] = (x, y)
    return out


def heatmap(rows, axes, path, series=SINGLE_LINE, title="Peak tension", quantity="largest tension"):
    """Largest ship and cage tension (``series``: (column, label, slack-flag column or None), values in N, shown in
    kN) over the first two axes (faceted by a third of <= 6 values). Returns {(label, facet value): grid} (kN,
    rows: second axis, columns: first)."""
    plt = _plt()
    (xc, xl), (yc, yl) = axes[0], axes[1]
    facet = axes[2] if len(axes) > 2 and len({_key(r[axes[2][0]]) for r in rows}) <= 6 else None
    rest = [label for c, label in axes[2:] if facet is None or c != facet[0]]
    values = sorted({_key(r[facet[0]]) for r in rows}) if facet else [None]
    xs = sorted({_key(r[xc]) for r in rows})
    ys = sorted({_key(r[yc]) for r in rows})
    fig, axs = plt.subplots(len(series), len(values), figsize=(max(6.0, 3.4 * len(values) + 1.2),
                                                               2.6 + 1.1 * len(ys) * len(series)), squeeze=False)
    grids = {}
    for col, v in enumerate(values):
        sub = [r for r in rows if facet is None or _key(r[facet[0]]) == v]
        for row, (column, label, flag) in enumerate(series):
            grid = np.full((len(ys), len(xs)), np.nan)
            bad = np.zeros_like(grid, dtype=bool)
            for r in sub:
                i, j = ys.index(_key(r[yc])), xs.index(_key(r[xc]))
                grid[i, j] = np.fmax(grid[i, j], r[column] / 1e3)
                bad[i, j] |= flag is not None and not r[flag]
            ax = axs[row, col]
            im = ax.imshow(grid, origin="lower", aspect="auto", cmap="viridis")
            grids[(label, v)] = np.ma.filled(im.get_array().astype(float), np.nan)  # as plotted
            for i in range(len(ys)):
                for j in range(len(xs)):
                    if np.isfinite(grid[i, j]):
                        ax.text(j, i, _cell(grid[i, j]) + ("*" if bad[i, j] else ""), ha="center", va="center",
                                color="w" if grid[i, j] < np.nanmean(grid) else "k", fontsize=8)
            ax.set_xticks(range(len(xs)), [_fmt_value(x) for x in xs])
            ax.set_yticks(range(len(ys)), [_fmt_value(y) for y in ys])
            ax.set_xlabel(xl)
            ax.set_ylabel(yl)
            ax.set_title(f"{label}: {quantity} (kN)" + (f"\n{facet[1]} = {_fmt_value(v)}" if facet else ""), fontsize=9)
            fig.colorbar(im, ax=ax, shrink=0.85)
    over = f"; largest over {', '.join(rest)}" if rest else ""
    slack = (f"\n(* = slack: T_min < {DNV_SLACK_FRACTION:g} T_static, DNV-RP-H103 criterion not met)"
             if any(flag for _, _, flag in series) else "")
    fig.suptitle(f"{title}{over}{slack}", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return grids


def peak_figure(rows, axis, path, series=SINGLE_LINE, title="Peak tension", quantity="largest tension"):
    """One axis: largest ship and cage tension (``series``, as :func:`heatmap`) of every case against it (seeds side
    by side). Returns {label: (x, kN)} as plotted."""
    plt = _plt()
    column, label = axis
    fig, ax = plt.subplots(figsize=(7.5, 4.5))
    x = np.array([r[column] for r in rows], float)
    artists = {}
    for (value, name, flag), marker in zip(series, "so^vDP<>"):
        t = np.array([r[value] for r in rows], float) / 1e3
        if flag is None:
            artists[name] = ax.plot(x, t, marker, ls="none", ms=5, label=name)
            continue
        ok = np.array([bool(r[flag]) for r in rows])
        line = ax.plot(x[ok], t[ok], marker, ls="none", ms=5, label=f"{name} (DNV slack criterion met)")[0]
        artists[name] = [line, ax.plot(x[~ok], t[~ok], marker, ls="none", ms=7, mfc="none", color=line.get_color(),
                                       label=f"{name}, slack (criterion not met)")[0]]
    ax.set_xlabel(label)
    ax.set_ylabel(f"{quantity} over the run (kN)")
    ax.set_title(f"{title}, every case ({len(rows)})", fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return _series_data(artists)


def daf_figure(rows, axes, path, ends=(("vehicle_", "cage"),), title=None):
    """DAF (T_max / static) at each of ``ends`` ((column prefix, label); the single line's: its cage end) against
    the first axis, one line per value of the second (and per end). Returns {label: (x, DAF)} as plotted."""
    plt = _plt()
    xc, xl = axes[0]
    fig, ax = plt.subplots(figsize=(7.5, 4.5))
    groups = sorted({_key(r[axes[1][0]]) for r in rows}) if len(axes) > 1 else [None]
    artists = {}
    for (prefix, name), style in zip(ends, ("o-", "s--", "^:", "v-.")):
        for g in groups:
            sub = [r for r in rows if g is None or _key(r[axes[1][0]]) == g]
            xs = sorted({_key(r[xc]) for r in sub})
            worst = [max(r[f"{prefix}daf"] for r in sub if _key(r[xc]) == x) for x in xs]
            label = ", ".join(([name] if len(ends) > 1 else []) + ([] if g is None else
                                                                   [f"{axes[1][1]} = {_fmt_value(g)}"])) or None
            artists[label or name] = ax.plot(xs, worst, style, label=label)
            bad = [(x, max(r[f"{prefix}daf"] for r in sub if _key(r[xc]) == x)) for x in xs
                   if any(not r[f"{prefix}dnv_slack_ok"] for r in sub if _key(r[xc]) == x)]
            if bad:
                ax.plot(*zip(*bad), "X", color="k", ms=7, mfc="none")
    ax.axhline(1.0, color="0.5", lw=0.8)
    plotted = _series_data(artists)
    values = np.concatenate([y for _, y in plotted.values()])
    values = values[np.isfinite(values) & (values > 0)]
    if values.size and values.max() > 20.0 * values.min():  # (a slack line's DAF of hundreds beside a taut one's 2)
        ax.set_yscale("log")
    ax.set_xlabel(xl)
    ax.set_ylabel(f"{ends[0][1]} DAF = T_max / T_static" if len(ends) == 1 else "DAF = T_max / T_static")
    rest = [label for _, label in axes[2:]] + (["seed"] if SEED in _varied(rows) else [])
    title = title or f"{ends[0][1].capitalize()} DAF"
    ax.set_title(title + (f", largest over {', '.join(rest)}" if rest else "") +
                 " (x: slack, DNV criterion not met)", fontsize=9)
    ax.grid(alpha=0.3)
    if len(artists) > 1:
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return plotted


def exceedance_groups(rows, column="vehicle_T_max_N"):
    """{condition: per-case maxima of ``column`` (the cage tension, N)} for a study with seeds, every condition
    (cases that differ only by their seed) with >= 5 cases, at most 6 conditions; None otherwise: a
    deterministic sweep's cases are different conditions, whose maxima are no sample of one
    distribution."""
    if SEED not in _varied(rows):
        return None
    varied = [c for c in _varied(rows) if c != SEED]
    groups = {}
    for r in rows:
        label = ", ".join(f"{c[4:]}={_fmt_value(r[c])}" for c in varied) or "all cases"
        groups.setdefault(label, []).append(r[column])
    if not all(len(v) >= 5 for v in groups.values()):
        return None
    return dict(sorted(groups.items(), key=lambda kv: -len(kv[1]))[:6])


def gumbel_fit(maxima):
    """(loc, scale) of the maximum-likelihood Gumbel fit (scipy.stats.gumbel_r.fit)."""
    from scipy.stats import gumbel_r

    return tuple(float(x) for x in gumbel_r.fit(np.asarray(maxima, float)))


def exceedance_figure(groups, path, what="the cage tension"):
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
                        label=f"Gumbel fit: mu = {loc / 1e3:.4g} kN, beta = {scale / 1e3:.3g} kN")
    ax.set_xlabel(f"per-case maximum of {what} (kN)")
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


def _end_names(rows, line):
    """Labels of a network line's two ends: s = 0 and s = L with the point or body each is on (the rows'
    ``<line>.from`` / ``<line>.to``, case.run_network_task)."""
    r = rows[0]
    return tuple(f"{line} {s}" + (f" ({r[k]})" if r.get(k) else "") for s, k in (("s = 0", f"{line}.from"),
                                                                                  ("s = L", f"{line}.to")))


def _axis_figures(rows, axes, out, stem, series, title, quantity="largest tension"):
    """The peak figure of ``series`` over the study's axes (heatmap for two or more, points for one); returns
    (file name, {what is plotted})."""
    if len(axes) >= 2:
        name = f"{stem}_peak_heatmap.png"
        return name, heatmap(rows, axes, out / name, series, title, quantity)
    name = f"{stem}_peak.png"
    return name, peak_figure(rows, axes[0], out / name, series, title, quantity)


def network_figures(ok, units, out) -> tuple:
    """The single-line figures per line of a network study, and those of the bodies and points: (markdown lines,
    {file name: what it plots}). Per line ``<line>_peak(_heatmap).png`` (largest tension at both ends, slack
    cases starred or hollow as in the single-line figure), ``<line>_daf.png`` (both ends) and, with seeds,
    ``<line>_exceedance.png`` (its s = L end); per body ``<body>_loads_peak(_heatmap).png`` (the largest tension
    of each line end on it); ``points_force_peak(_heatmap).png`` (the largest |force| of the lines on each point,
    the node's ``tether/<point>_wrench``). Nothing when the study varies nothing but the seed."""
    axes = study_axes(ok, units)
    text, plotted = [], {}
    if not axes:
        return text, plotted
    rows = ok
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    for line in network_lines(rows):
        s0, sL = _end_names(rows, line)
        series = ((f"{line}.ship_T_max_N", s0, f"{line}.ship_dnv_slack_ok"),
                  (f"{line}.vehicle_T_max_N", sL, f"{line}.vehicle_dnv_slack_ok"))
        text += [f"### Line `{line}`", ""]
        name, data = _axis_figures(rows, axes, out, line, series, f"Line {line}: peak tension")
        plotted[name] = data
        text += [f"![{line} peak tension]({name})", ""]
        name = f"{line}_daf.png"
        plotted[name] = daf_figure(rows, axes, out / name, ((f"{line}.ship_", s0), (f"{line}.vehicle_", sL)),
                                   title=f"Line {line}: DAF at both ends")
        text += [f"![{line} DAF]({name})", ""]
        groups = exceedance_groups(rows, f"{line}.vehicle_T_max_N")
        if groups:
            name = f"{line}_exceedance.png"
            exceedance_figure(groups, out / name, what=f"the tension at {sL}")
            plotted[name] = groups
            text += [f"![{line} exceedance]({name})", ""]
    bodies = [c[:-len(".mass_kg")] for c in rows[0] if c.endswith(".mass_kg")]
    for body in bodies:
        series = []
        for line in network_lines(rows):
            for end, key, s in (("ship", "from", "s = 0"), ("vehicle", "to", "s = L")):
                if rows[0].get(f"{line}.{key}") == body:
                    series.append((f"{line}.{end}_T_max_N", f"{line} ({s})", f"{line}.{end}_dnv_slack_ok"))
        if series:
            text += [f"### Body `{body}`: the tension of each line at it", ""]
            name, data = _axis_figures(rows, axes, out, f"{body}_loads", series, f"Body {body}: line tensions at it")
            plotted[name] = data
            text += [f"![{body} loads]({name})", ""]
    points = [c[:-len("_force_max_N")] for c in rows[0] if c.endswith("_force_max_N")]
    if points:
        text += ["### Force of the lines on each point", ""]
        name, data = _axis_figures(rows, axes, out, "points_force", [(f"{p}_force_max_N", p, None) for p in points],
                                   "Force of the lines on each point", "largest |F|")
        plotted[name] = data
        text += [f"![point forces]({name})", ""]
    return text, plotted


def network_tables(ok, units) -> list:
    """Markdown of a line-network study (case.run_network_task's columns): per line, both ends' largest
    tension, snaps and largest snap peak; the largest force on each point; no figures yet."""
    varied = _varied(ok)
    head = ["case"] + [_unit_label(c, units) for c in varied]
    text = ["Line network: per line, its s = 0 end (`ship` columns: the end its `from` names) and its s = L end "
            "(`vehicle`: its `to`). T_max over every substep; snaps as the node's detector publishes them (one per "
            "slack episode, its largest peak); numerical: re-tensioning peaks the snap guard rejected "
            "(docs/snap_guard.md), never counted as snaps. DAF = T_max / static tension at that end. Figures: "
            "\"Figures\" below.", ""]
    for line in network_lines(ok):
        cols = ["index"] + varied + [
            lambda r, p=f"{line}.ship_": r[p + "T_max_N"] / 1e3, lambda r, p=f"{line}.vehicle_": r[p + "T_max_N"] / 1e3,
            f"{line}.ship_daf", f"{line}.vehicle_daf",
            f"{line}.ship_n_snap", lambda r, p=f"{line}.ship_": r[p + "snap_peak_N"] / 1e3,
            f"{line}.vehicle_n_snap", lambda r, p=f"{line}.vehicle_": r[p + "snap_peak_N"] / 1e3,
            f"{line}.ship_n_slack", f"{line}.vehicle_n_slack",
            lambda r, p=line: (r.get(f"{p}.ship_n_numerical") or 0) + (r.get(f"{p}.vehicle_n_numerical") or 0)]
        names = head + ["T_max s=0 kN", "T_max s=L kN", "DAF s=0", "DAF s=L", "snaps s=0", "snap peak s=0 kN", "snaps s=L",
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
        units = read_units(results)
        text += network_tables(ok, units)
        figures, _ = network_figures(ok, units, out)
        if figures:
            axes = study_axes(ok, units)
            text += ["## Figures", "", "Varied: " + ", ".join(label for _, label in axes) +
                     (f" and the seed ({len({r[SEED] for r in ok})} seeds)" if SEED in _varied(ok) else "") + ".",
                     ""] + figures
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
