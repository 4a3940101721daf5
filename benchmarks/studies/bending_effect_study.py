"""Bending effect on the first snap peak at L = 200 m: DG mesh refinement against MoorDyn.

Question (2026-11-25): at L = 200 m MoorDyn's bending effect on the first snap peak,
(peak(EI*) - peak(0)) / peak(0), is +0.05 % at N = 40 segments but +0.58 / +0.64 % at N = 80 / 160
(benchmarks/studies/moordyn_bending_rungs.py), whereas the DG ladder's reference (N = 10, P = 4, dg.cfl 0.5)
gives +0.03 %. Does the DG effect grow with refinement towards MoorDyn's?

For each DG rung 'N:P:cfl' (default 10, 20, 40 elements at P = 4, dg.cfl 0.5) and alpha = 0, 1
(EI = alpha * EI_STAR) the ROPOS slack-snap case ``200:stiff:alpha:cage`` is run exactly as a rung of
benchmarks/studies/resolution_ladder.py (``resolution_ladder.run_rung``: untimed 0.1 s warm-up, then
``--duration`` s of 50 Hz ticks through ``advance_to``; first snap peak = largest end tension in
5-10 s on the 200 Hz grid, both ends; thread CPU of the ticks). MoorDyn runs at ``--moordyn``
segment counts (``bench_moordyn.run_moordyn``, 200 Hz coupling, RK2; ship end only, first peak of
``ropos_case.snap_metrics``). Rows go to ``--csv`` at once and are skipped when present (resume);
the end-tension records (npz, 5 s on) go to ``--records``. ``--figure`` plots the ship tension
6.5-9 s of the finest DG rung and the finest MoorDyn N, each with and without bending, the
difference alpha 1 - alpha 0, and the slack phase 5-7.8 s of every MoorDyn N against the finest DG
rung.

Usage: PYTHONPATH=. python benchmarks/studies/bending_effect_study.py [--dg 10:4:0.5 20:4:0.5 40:4:0.5]
       [--moordyn 40 80 160] [--duration 10.2] [--figure docs/figures/bending_effect_L200.png]
"""

import argparse
import csv
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from benchmarks import bench_moordyn  # noqa: E402
from benchmarks.studies import resolution_ladder as rl  # noqa: E402
from benchmarks import ropos_case as rc  # noqa: E402

LENGTH = 200.0
ALPHAS = (0.0, 1.0)
FIELDS = ("model", "alpha", "n", "order", "cfl", "ship_grid", "ship_raw", "ship_t", "vehicle_grid", "vehicle_raw",
          "vehicle_t", "time_step", "cpu_per_s", "load", "date", "commit")
PLOT_WINDOW = (6.5, 9.0)


def _case(alpha):
    return f"{LENGTH:g}:stiff:{alpha:g}:cage"


def _read(path):
    if not Path(path).exists():
        return []
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def _append(path, row):
    new = not Path(path).exists()
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    with open(path, "a", newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS, extrasaction="ignore")
        if new:
            w.writeheader()
        w.writerow(row)


def _key(model, alpha, n, order, cfl):
    return (model, round(float(alpha), 3), int(n), int(order), round(float(cfl), 3))


def dg_row(alpha, n, order, cfl, duration):
    r = rl.run_rung(_case(alpha), n, order, cfl, duration, False)
    return {"model": "dg", "alpha": alpha, "n": n, "order": order, "cfl": cfl, **{k: r[k] for k in FIELDS if k in r}}


def moordyn_row(alpha, n, duration, records):
    res = bench_moordyn.run_moordyn(LENGTH, n, duration, alpha=alpha, workdir=records)
    t, ship = res["t"], res["tension"]
    keep = t >= rc.FIRST_SNAP_WINDOW[0] - 1.0
    np.savez_compressed(Path(records) / f"moordyn_L{LENGTH:g}_N{n}_a{alpha:g}.npz", t=t[keep], ship=ship[keep])
    peak, t_peak = rc.snap_peak(t, ship, *rc.FIRST_SNAP_WINDOW)
    return {"model": "moordyn", "alpha": alpha, "n": n, "order": 0, "cfl": 0.0, "ship_grid": peak, "ship_raw": peak,
            "ship_t": t_peak, "vehicle_grid": float("nan"), "vehicle_raw": float("nan"), "vehicle_t": float("nan"),
            "time_step": res["dt"], "cpu_per_s": res["step_cpu"] / duration, "load": os.getloadavg()[0],
            "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "commit": rl._commit()}


def table(rows):
    """Lines of the bending-effect table: per model and rung, peaks at alpha 0 / 1 and the effect."""
    by = {_key(r["model"], r["alpha"], r["n"], r["order"], r["cfl"]): r for r in rows}
    rungs = sorted({k[:1] + k[2:] for k in by}, key=lambda k: (k[0], k[2], k[1], -k[3]))
    lines = ["model    rung              | ship peak a=0 / a=1 (kN)  effect    | vehicle peak a=0 / a=1 (kN) effect    "
             "| CPU a=0 / a=1 (s per sim s)"]
    for model, n, p, c in rungs:
        r0, r1 = by.get((model, 0.0, n, p, c)), by.get((model, 1.0, n, p, c))
        if r0 is None or r1 is None:
            continue
        f = {k: (float(r0[k]), float(r1[k])) for k in ("ship_grid", "vehicle_grid", "cpu_per_s")}
        name = f"N={n:3d} P={p} cfl {c:.2f}" if model == "dg" else f"N={n:3d} segments"
        s0, s1 = f["ship_grid"]
        v0, v1 = f["vehicle_grid"]
        veh = (f"{v0 / 1e3:9.3f} / {v1 / 1e3:9.3f}  {100 * (v1 / v0 - 1):+7.3f} %" if np.isfinite(v0)
               else f"{'-':>21}  {'':>9}")
        lines.append(f"{model:8s} {name:17s} | {s0 / 1e3:9.3f} / {s1 / 1e3:9.3f}  {100 * (s1 / s0 - 1):+7.3f} % "
                     f"| {veh}   | {f['cpu_per_s'][0]:7.3f} / {f['cpu_per_s'][1]:7.3f}")
    return lines


def _trace(records, model, alpha, rung):
    if model == "dg":
        n, p, c = rung
        d = np.load(Path(records) / f"{_case(alpha).replace(':', '_')}_N{n}P{p}c{c:g}.npz")
    else:
        d = np.load(Path(records) / f"moordyn_L{LENGTH:g}_N{rung}_a{alpha:g}.npz")
    return d["t"], d["ship"]


def figure(path, records, dg_rung, md_segments):
    """Top: ship tension 6.5-9 s, finest DG rung and finest MoorDyn N, EI = 0 and EI*. Middle: the
    difference T(EI*) - T(0). Bottom: the slack phase 5-7.8 s zoomed, MoorDyn at every N (EI = 0
    dashed, EI* solid) against the finest DG rung."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n, p, c = dg_rung
    md_n = max(md_segments)
    fig, (ax, bx, cx) = plt.subplots(3, 1, figsize=(9, 11), gridspec_kw={"height_ratios": [3, 2, 3]})
    grid = np.arange(PLOT_WINDOW[0], PLOT_WINDOW[1] + 1e-9, rl.GRID_STEP)
    for model, rung, label, style in (("dg", dg_rung, f"DG N={n} P={p}", "-"),
                                      ("moordyn", md_n, f"MoorDyn N={md_n}", "--")):
        traces = {}
        for alpha, color in zip(ALPHAS, ("C0", "C3") if model == "dg" else ("C2", "C1")):
            t, ship = _trace(records, model, alpha, rung)
            traces[alpha] = np.interp(grid, t, ship)
            ax.plot(grid, traces[alpha] / 1e3, style, color=color, lw=1.0,
                    label=f"{label}, EI = {'EI*' if alpha else '0'}")
        bx.plot(grid, (traces[1.0] - traces[0.0]) / 1e3, style, color="C0" if model == "dg" else "C2", lw=1.0,
                label=f"{label}: T(EI*) - T(0)")
    zoom = np.arange(5.0, 7.8 + 1e-9, rl.GRID_STEP)
    for alpha in ALPHAS:
        t, ship = _trace(records, "dg", alpha, dg_rung)
        cx.plot(zoom, np.interp(zoom, t, ship) / 1e3, "-" if alpha else ":", color="k", lw=1.6 if alpha else 2.0,
                label=f"DG N={n} P={p}, EI = {'EI*' if alpha else '0'}")
    for k, m in enumerate(sorted(md_segments)):
        for alpha in ALPHAS:
            t, ship = _trace(records, "moordyn", alpha, m)
            cx.plot(zoom, np.interp(zoom, t, ship) / 1e3, "-" if alpha else "--", color=f"C{k + 4}", lw=1.0,
                    label=f"MoorDyn N={m}, EI = {'EI*' if alpha else '0'}")
    ax.set_ylabel("ship-end tension (kN)")
    ax.set_title(f"ROPOS slack-snap, L = {LENGTH:g} m: bending (EI* = {rc.EI_STAR:g} N m$^2$) and the ship tension")
    bx.set_ylabel("T(EI*) - T(0) (kN)")
    bx.set_xlabel("t (s)")
    cx.set_ylabel("ship-end tension (kN)")
    cx.set_xlabel("t (s)")
    cx.set_ylim(0.0, 16.0)
    cx.set_title("slack phase before the snap (zoom): MoorDyn at each N, EI = 0 dashed, EI* solid", fontsize=9)
    for a in (ax, bx, cx):
        a.legend(fontsize=7, loc="upper left", ncol=2 if a is cx else 1)
        a.grid(alpha=0.3)
    fig.tight_layout()
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    print(f"wrote {path}")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dg", nargs="*", default=["10:4:0.5", "20:4:0.5", "40:4:0.5"], help="DG rungs N:P:cfl")
    ap.add_argument("--moordyn", type=int, nargs="*", default=[40, 80, 160], help="MoorDyn segment counts")
    ap.add_argument("--duration", type=float, default=10.2)
    ap.add_argument("--csv", default="out/bending_effect/runs.csv")
    ap.add_argument("--records", default="out/bending_effect")
    ap.add_argument("--figure", default="", help="PNG of the ship tension 6.5-9 s (finest DG rung, finest MoorDyn)")
    ap.add_argument("--figure-rung", default="", help="DG rung N:P:cfl of the figure (default: the finest of --dg)")
    args = ap.parse_args(argv)
    rl.RECORDS = args.records
    Path(args.records).mkdir(parents=True, exist_ok=True)
    print(f"bending_effect_study: {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, {platform.machine()}, "
          f"{os.cpu_count()} cores, load {os.getloadavg()[0]:.1f}, commit {rl._commit()}; L = {LENGTH:g} m, "
          f"EI* = {rc.EI_STAR:g} N m^2, {args.duration:g} s runs; first snap peak = largest end tension in "
          f"{rc.FIRST_SNAP_WINDOW[0]:g}-{rc.FIRST_SNAP_WINDOW[1]:g} s (DG: 200 Hz grid; MoorDyn: 200 Hz coupling)",
          flush=True)
    done = {_key(r["model"], r["alpha"], r["n"], r["order"], r["cfl"]) for r in _read(args.csv)}
    plan = [("moordyn", a, n, 0, 0.0) for n in args.moordyn for a in ALPHAS]
    plan += [("dg", a, int(n), int(p), float(c)) for n, p, c in (x.split(":") for x in args.dg) for a in ALPHAS]
    for model, alpha, n, p, c in plan:
        if _key(model, alpha, n, p, c) in done:
            continue
        row = dg_row(alpha, n, p, c, args.duration) if model == "dg" else moordyn_row(alpha, n, args.duration,
                                                                                      args.records)
        _append(args.csv, row)
        print(f"  ran {model:8s} alpha={alpha:g} N={n:3d} P={p} cfl={c:.2f}: ship {row['ship_grid'] / 1e3:.3f} kN, "
              f"CPU {row['cpu_per_s']:.3f} s per sim s, load {row['load']:.1f}", flush=True)
    rows = [r for r in _read(args.csv) if _key(r["model"], r["alpha"], r["n"], r["order"], r["cfl"])
            in {_key(*k) for k in plan}]
    for line in table(rows):
        print(line)
    if args.figure:
        n, p, c = max(((int(n), int(p), float(c)) for n, p, c in (x.split(":") for x in args.dg)),
                      key=lambda r: r[0] * (r[1] + 1))
        if args.figure_rung:
            n, p, c = (f(x) for f, x in zip((int, int, float), args.figure_rung.split(":")))
        figure(args.figure, args.records, (n, p, c), args.moordyn)
    print(f"done {time.strftime('%H:%M UTC', time.gmtime())}, load {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
