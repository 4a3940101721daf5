"""PE2020 Section 6.2 bending study and Appendix A mesh study for ROPOS, run in parallel.

    python -m tether_sim.scenarios.ropos_study [study] [--lengths 200 500 ...] [--out docs/ropos]
    python -m tether_sim.scenarios.ropos_study mesh  [--out docs/ropos]

Writes PNG figures (Figure 5-, 6- and A1-like, from the full tension histories), markdown tables of
the snap statistics and a pickle of all case results (to redraw figures without re-running).
For studies of your own (any parameters, resumable, Parquet tables, on a cluster) use
``tether-sim-study config/studies/pe2020_sec62.yaml`` (docs/studies.md).
"""

import argparse
import os
import pickle
from multiprocessing import Pool
from pathlib import Path

import numpy as np

from tether_sim.physics.boundary import END_NAMES
from tether_sim.scenarios.ropos import (
    ALPHAS,
    FREQUENCIES,
    LENGTHS,
    ropos_config,
    run_case,
    snap_lag,
)

DEFAULT_OUT = Path(__file__).resolve().parents[2] / "docs" / "ropos"
COLOURS = {200.0: "tab:blue", 500.0: "tab:orange", 975.0: "tab:green", 1730.0: "tab:red"}
STYLES = {0.0: "-", 1.0: "--", 10.0: "-.", 100.0: ":"}


def _run(job):
    kwargs, run_kwargs = job
    return run_case(ropos_config(**kwargs), **run_kwargs)


def run_parallel(jobs, processes=None, desc="ROPOS"):
    """Run (config kwargs, run_case kwargs) jobs on all cores with a progress bar; results in job order."""
    from tqdm import tqdm

    processes = processes or os.cpu_count() or 1
    # Longest jobs first so the pool is not left waiting on one long case at the end.
    order = sorted(range(len(jobs)), key=lambda i: jobs[i][0].get("length", 0.0) < 900.0, reverse=True)
    results = [None] * len(jobs)
    with Pool(processes) as pool:
        it = pool.imap_unordered(_indexed, [(i, jobs[i]) for i in order])
        for i, res in tqdm(it, total=len(jobs), desc=desc, unit="case"):
            results[i] = res
    return results


def _indexed(item):
    i, job = item
    return i, _run(job)


def case_row(r):
    """Snap statistics of one case as a dict (tensions in kN)."""
    snaps = r.snaps("vehicle")
    ship_static = r.static[0]
    row = {
        "L": r.length, "alpha": r.alpha, "f": r.frequency, "N": r.n_elements,
        "slack_cage": len(r.slacks("vehicle")), "snaps_cage": len(snaps),
        "peak_cage_kN": max((e.peak_tension for e in snaps), default=np.nan) / 1e3,
        "ampl_cage": max((e.amplification for e in snaps), default=np.nan),
        "first_snap_s": min((e.time for e in snaps), default=np.nan),
        "cage_min_kN": (r.vehicle_tension.min() / 1e3) if r.vehicle_tension.size else np.nan,
        "snaps_ship": len(r.snaps("ship")),
        "ship_static_kN": ship_static / 1e3,
        "ship_max_kN": (r.ship_tension.max() / 1e3) if r.ship_tension.size else np.nan,
        "ship_min_kN": (r.ship_tension.min() / 1e3) if r.ship_tension.size else np.nan,
        "ship_ampl": (r.ship_tension.max() / ship_static) if r.ship_tension.size and ship_static else np.nan,
        "substeps": r.substeps, "wall_s": r.wall_time, "error": r.error,
    }
    return row


def markdown_table(rows, columns):
    def fmt(v):
        if isinstance(v, float):
            return "-" if np.isnan(v) else ("0" if abs(v) < 1e-9 else f"{v:.4g}")
        return str(v)

    lines = ["| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]
    lines += ["| " + " | ".join(fmt(row[c]) for c in columns) + " |" for row in rows]
    return "\n".join(lines)


def figure_ship_tension(results, path):
    """Figure 5-like: ship tension vs time per f (rows); full run left, last two periods right."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    freqs = sorted({r.frequency for r in results})
    fig, axes = plt.subplots(len(freqs), 2, figsize=(12, 3.2 * len(freqs)), squeeze=False)
    for row, f in enumerate(freqs):
        for r in (r for r in results if r.frequency == f and r.t.size):
            kw = dict(color=COLOURS.get(r.length, "k"), ls=STYLES.get(r.alpha, "-"), lw=0.8)
            label = f"L={r.length:g} m, alpha={r.alpha:g}"
            axes[row, 0].plot(r.t * f, r.ship_tension / 1e3, label=label, **kw)
            last = r.t * f >= r.t[-1] * f - 2.0
            axes[row, 1].plot(r.t[last] * f, r.ship_tension[last] / 1e3, **kw)
        for ax in axes[row]:
            ax.set_xlabel("t f (periods)")
            ax.set_ylabel("ship tension (kN)")
            ax.set_title(f"f = {f:g} Hz, a = 2 m")
            ax.grid(alpha=0.3)
    axes[0, 0].legend(fontsize=6, ncol=2, loc="upper right")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def figure_snap_detail(results, path, length=200.0, frequency=0.2):
    """Figure 6-like: both end tensions and vertical accelerations around the first snap after 8 periods."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    cases = sorted((r for r in results if r.length == length and r.frequency == frequency and r.t.size),
                   key=lambda r: r.alpha)
    if not cases:
        return None
    # The paper looks at period 8.65; runs here may be shorter: take the last snap of the flexible
    # tether that is at least 1 s before the end, and centre the window on its slack end.
    flexible = [e for e in cases[0].snaps("vehicle") if e.time < cases[0].t[-1] - 1.0]
    if not flexible:
        return None
    t0 = flexible[-1].slack_start + flexible[-1].slack_duration
    window = (t0 - 0.4, t0 + 0.8)
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(9, 7), sharex=True)
    for r in cases:
        ls = STYLES.get(r.alpha, "-")
        sel = (r.t >= window[0]) & (r.t <= window[1])
        ax1.plot(r.t[sel] * frequency, r.ship_tension[sel] / 1e3, color="tab:blue", ls=ls, lw=0.9,
                 label=f"ship, alpha={r.alpha:g}")
        ax1.plot(r.t[sel] * frequency, r.vehicle_tension[sel] / 1e3, color="tab:red", ls=ls, lw=0.9,
                 label=f"cage, alpha={r.alpha:g}")
        sel = (r.t_out >= window[0]) & (r.t_out <= window[1])
        ax2.plot(r.t_out[sel] * frequency, r.cage_acceleration[sel, 2], color="tab:red", ls=ls, lw=0.9,
                 label=f"cage, alpha={r.alpha:g}")
        if r.alpha == cases[0].alpha:
            ax2.plot(r.t_out[sel] * frequency, r.ship_acceleration[sel, 2], color="tab:blue", lw=1.2, label="ship")
    ax1.set_ylabel("tension (kN)")
    ax1.set_title(f"L = {length:g} m, f = {frequency:g} Hz: around the re-tensioning at {t0 * frequency:.3f} periods")
    ax2.set_ylabel("vertical acceleration (m/s^2)")
    ax2.set_xlabel("t f (periods)")
    for ax in (ax1, ax2):
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return t0


def lag_rows(results):
    """Measured cage -> ship lag of every cage snap of the L = 1730 m cases vs L/c."""
    rows = []
    for r in results:
        if r.length != 1730.0 or not r.t.size:
            continue
        cfg = ropos_config(r.length, r.alpha, r.frequency)
        wave = r.length / cfg.cable.wave_speed
        for e in r.snaps("vehicle"):
            try:
                lag = snap_lag(r.t, r.ship_tension, r.vehicle_tension, e, wave)
            except ValueError:
                continue
            rows.append({"L": r.length, "alpha": r.alpha, "f": r.frequency, "snap_t": e.time,
                         "lag_s": lag, "L_over_c": wave, "rel_err": lag / wave - 1.0})
    return rows


def snap_timing_rows(results):
    """Per (L, f, alpha > 0): mean shift of the cage snap times against alpha = 0 (matched by cycle).

    Positive shift = the stiffer tether snaps later than the flexible one [PE2020 Sec. 6.2, Fig. 6a].
    """
    rows = []
    flexible = {(r.length, r.frequency): r for r in results if r.alpha == 0.0}
    for r in results:
        ref = flexible.get((r.length, r.frequency))
        if r.alpha == 0.0 or ref is None:
            continue
        t_ref = np.array([e.time for e in ref.snaps("vehicle")])
        t_r = np.array([e.time for e in r.snaps("vehicle")])
        if not t_ref.size or not t_r.size:
            continue
        period = 1.0 / r.frequency
        shifts = [t - t_ref[np.argmin(abs(t_ref - t))] for t in t_r if t > 2 * period]
        shifts = [d for d in shifts if abs(d) < 0.25 * period]
        peaks = [e.peak_tension for e in r.snaps("vehicle") if e.time > 2 * period]
        ref_peaks = [e.peak_tension for e in ref.snaps("vehicle") if e.time > 2 * period]
        rows.append({"L": r.length, "f": r.frequency, "alpha": r.alpha, "n": len(shifts),
                     "mean_shift_ms": 1e3 * float(np.mean(shifts)) if shifts else np.nan,
                     "min_shift_ms": 1e3 * float(np.min(shifts)) if shifts else np.nan,
                     "mean_peak_kN": np.mean(peaks) / 1e3 if peaks else np.nan,
                     "mean_peak_alpha0_kN": np.mean(ref_peaks) / 1e3 if ref_peaks else np.nan})
    return rows


def study(lengths=LENGTHS, alphas=ALPHAS, freqs=FREQUENCIES, out=DEFAULT_OUT, processes=None, periods=12.0,
          cfl=None, tag="all"):
    """Run the L x alpha x f grid; results go to study_results_<tag>.pkl, the report covers all pickles."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    jobs = [({"length": L, "alpha": a, "frequency": f, "periods": periods, "cfl": cfl}, {})
            for L in lengths for a in alphas for f in freqs]
    results = run_parallel(jobs, processes, desc="PE2020 Sec. 6.2 study")
    with open(out / f"study_results_{tag}.pkl", "wb") as fh:
        pickle.dump(results, fh)
    report_study(load_results(out), out)
    return results


def _merge_split_bins(r):
    """Results of runs before the binning fix could hold a bin twice (split at an output time): merge."""
    if r.t.size and np.any(np.diff(r.t) <= 0):
        t, first = np.unique(r.t, return_index=True)
        r.ship_tension = np.maximum.reduceat(r.ship_tension, first)
        r.vehicle_tension = np.maximum.reduceat(r.vehicle_tension, first)
        r.t = t


def redetect(r, config=None):
    """Recompute a case's slack/snap events from its stored 1 kHz tension series with the current detector.

    Batches run at different times used different detector versions; this makes every table use the
    one in :mod:`tether_sim.physics.snap` (bins hold maxima, so dips shorter than 1 ms are not seen).
    """
    from tether_sim.physics.snap import SnapDetector

    cfg = config or ropos_config(r.length, r.alpha, r.frequency)
    det = SnapDetector(cfg.snap, list(END_NAMES), list(r.static), [0.0, r.length])
    r.events = det.update(r.t, np.c_[r.ship_tension, r.vehicle_tension]) + det.flush() if r.t.size else []
    return r


def load_results(out):
    """All study pickles of ``out`` merged; a later file replaces a case (L, alpha, f) of an earlier one."""
    cases = {}
    for path in sorted(Path(out).glob("study_results_*.pkl"), key=lambda p: p.stat().st_mtime):
        with open(path, "rb") as fh:
            for r in pickle.load(fh):
                _merge_split_bins(r)
                redetect(r)
                cases[(r.length, r.alpha, r.frequency)] = r
    return [cases[k] for k in sorted(cases)]


def report_study(results, out):
    out = Path(out)
    rows = [case_row(r) for r in results]
    cols = ["L", "alpha", "f", "cage_min_kN", "slack_cage", "snaps_cage", "peak_cage_kN", "ampl_cage", "first_snap_s",
            "snaps_ship", "ship_static_kN", "ship_max_kN", "ship_min_kN", "ship_ampl", "wall_s", "error"]
    text = ["## Section 6.2 study: snap statistics per case", "", markdown_table(rows, cols), ""]
    lags = lag_rows(results)
    if lags:
        text += ["## Cage -> ship snap lag (L = 1730 m)", "",
                 markdown_table(lags, ["alpha", "f", "snap_t", "lag_s", "L_over_c", "rel_err"]), ""]
    timing = snap_timing_rows(results)
    if timing:
        text += ["## Cage snap timing and size vs the flexible tether (alpha = 0)", "",
                 markdown_table(timing, ["L", "f", "alpha", "n", "mean_shift_ms", "min_shift_ms", "mean_peak_kN",
                                         "mean_peak_alpha0_kN"]), ""]
    (out / "study_table.md").write_text("\n".join(text))
    figure_ship_tension(results, out / "fig5_ship_tension.png")
    figure_snap_detail(results, out / "fig6_snap_detail_L200_f0.2.png")
    print("\n".join(text))


def mesh_study(out=DEFAULT_OUT, elements=(5, 10, 20, 40), processes=None, periods=12.0, cfl=None):
    """Appendix A: ship tension for N = 5, 10, 20, 40 at P = 4, L = 1730 m, a = 2 m, f = 0.2 Hz."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    jobs = [({"length": 1730.0, "alpha": 0.0, "frequency": 0.2, "n_elements": n, "order": 4, "periods": periods,
              "cfl": cfl}, {})
            for n in elements]
    results = run_parallel(jobs, processes, desc="PE2020 App. A mesh study")
    with open(out / "mesh_results.pkl", "wb") as fh:
        pickle.dump(results, fh)
    report_mesh(results, out)
    return results


def _period_peaks(r, period=5.0):
    n = int(round(r.t[-1] / period)) if r.t.size else 0
    return np.array([r.ship_tension[(r.t >= k * period) & (r.t < (k + 1) * period)].max() for k in range(1, n)])


def report_mesh(results, out):
    """Mesh table (global and per-period ship-tension peaks against the finest mesh) and Figure A1."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = Path(out)
    for r in results:
        _merge_split_bins(r)
    ref = max(results, key=lambda r: r.n_elements)
    ref_peaks = _period_peaks(ref)
    rows = []
    for r in results:
        row = case_row(r)
        ok = r.ship_tension.size and ref.ship_tension.size
        row["ship_max_vs_finest_%"] = 100.0 * (r.ship_tension.max() / ref.ship_tension.max() - 1.0) if ok else np.nan
        peaks = _period_peaks(r)
        k = min(peaks.size, ref_peaks.size)
        dev = 100.0 * np.abs(peaks[:k] / ref_peaks[:k] - 1.0) if k else np.array([np.nan])
        row["period_peaks_max_dev_%"], row["period_peaks_mean_dev_%"] = float(dev.max()), float(dev.mean())
        rows.append(row)
    text = ["## Appendix A mesh study (L = 1730 m, P = 4, a = 2 m, f = 0.2 Hz)", "",
            "Deviations are against the finest mesh; 'period peaks' = the largest ship tension of each",
            "forcing period after the first.", "",
            markdown_table(rows, ["N", "ship_static_kN", "ship_max_kN", "ship_min_kN", "ship_max_vs_finest_%",
                                  "period_peaks_max_dev_%", "period_peaks_mean_dev_%", "snaps_cage",
                                  "peak_cage_kN", "substeps", "wall_s", "error"]), ""]
    (out / "mesh_table.md").write_text("\n".join(text))
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(10, 6.5))
    for r in results:
        if r.t.size:
            ax1.plot(r.t * 0.2, r.ship_tension / 1e3, lw=0.8, label=f"N = {r.n_elements}")
            last = r.t * 0.2 >= r.t[-1] * 0.2 - 1.0
            ax2.plot(r.t[last] * 0.2, r.ship_tension[last] / 1e3, lw=0.9, label=f"N = {r.n_elements}")
    for ax in (ax1, ax2):
        ax.set_xlabel("t f (periods)")
        ax.set_ylabel("ship tension (kN)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    ax1.set_title("Ship tension, L = 1730 m, P = 4, a = 2 m, f = 0.2 Hz (PE2020 Fig. A1)")
    fig.tight_layout()
    fig.savefig(out / "figA1_mesh.png", dpi=120)
    plt.close(fig)
    print("\n".join(text))


def axial_table(lengths=LENGTHS, freqs=FREQUENCIES, out=DEFAULT_OUT, periods=12.0):
    """The 1-D lumped-mass cross-check (:mod:`ropos_axial`) over the same L x f grid (no alpha)."""
    from tether_sim.physics.snap import SnapEvent
    from tether_sim.scenarios.ropos_axial import run_axial

    rows = []
    for L in lengths:
        for f in freqs:
            cfg = ropos_config(L, 0.0, f, periods=periods)
            r = run_axial(cfg, n_elements=200, output_rate=1000.0)
            snaps = [e for e in r["events"] if isinstance(e, SnapEvent) and e.location == "vehicle"]
            rows.append({"L": L, "f": f, "slack_cage": sum(not isinstance(e, SnapEvent) and e.location == "vehicle"
                                                           for e in r["events"]),
                         "snaps_cage": len(snaps),
                         "peak_cage_kN": max((e.peak_tension for e in snaps), default=np.nan) / 1e3,
                         "ampl_cage": max((e.amplification for e in snaps), default=np.nan),
                         "ship_static_kN": r["static"][0] / 1e3, "ship_max_kN": r["ship_tension"].max() / 1e3,
                         "ship_min_kN": r["ship_tension"].min() / 1e3})
    text = ["## 1-D lumped-mass cross-check (vertical only, 200 elements)", "",
            markdown_table(rows, ["L", "f", "slack_cage", "snaps_cage", "peak_cage_kN", "ampl_cage",
                                  "ship_static_kN", "ship_max_kN", "ship_min_kN"]), ""]
    Path(out).mkdir(parents=True, exist_ok=True)
    (Path(out) / "axial_table.md").write_text("\n".join(text))
    print("\n".join(text))
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("what", nargs="?", default="study", choices=("study", "mesh", "report", "report-mesh", "axial"),
                    help="what to run (default: study)")
    ap.add_argument("--out", default=str(DEFAULT_OUT))
    ap.add_argument("--lengths", type=float, nargs="+", default=list(LENGTHS))
    ap.add_argument("--alphas", type=float, nargs="+", default=list(ALPHAS))
    ap.add_argument("--freqs", type=float, nargs="+", default=list(FREQUENCIES))
    ap.add_argument("--periods", type=float, default=12.0)
    ap.add_argument("--processes", type=int, default=None)
    ap.add_argument("--cfl", type=float, default=None, help="dg.cfl override (default: the config's)")
    ap.add_argument("--tag", default="all", help="name of this batch's result pickle")
    args = ap.parse_args(argv)
    if args.what == "study":
        study(args.lengths, args.alphas, args.freqs, args.out, args.processes, args.periods, args.cfl, args.tag)
    elif args.what == "axial":
        axial_table(args.lengths, args.freqs, args.out, args.periods)
    elif args.what == "mesh":
        mesh_study(args.out, processes=args.processes, periods=args.periods, cfl=args.cfl)
    elif args.what == "report-mesh":
        with open(Path(args.out) / "mesh_results.pkl", "rb") as fh:
            report_mesh(pickle.load(fh), args.out)
    else:
        report_study(load_results(args.out), args.out)


if __name__ == "__main__":
    main()
