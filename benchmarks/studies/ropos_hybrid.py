"""ROPOS tether with the hybrid solver: tension amplitude / snap peaks vs the implicit time step.

Taut case (L = 1730 m, f = 0.1 Hz, no slack), ship-tension amplitude per step size:

    PYTHONPATH=. python benchmarks/studies/ropos_hybrid.py config/ropos_L1730.yaml --frequency 0.1 --steps 0.05 0.1 0.2

Slack-snap case (L = 200 m, f = 0.2 Hz, EI = 2620 N m^2, the shared case of benchmarks/ropos_case.py:
orbit centre 3 m deep, one-period ramp), snap peaks per step size against the DG explicit solver
(N = 20, P = 4; its record is cached in out/, computed once with --dg-reference, ~5 min CPU):

    PYTHONPATH=. python benchmarks/studies/ropos_hybrid.py --slack --steps 0.05 0.02 0.01 0.005 --duration 30 --save out
    PYTHONPATH=. python benchmarks/studies/ropos_hybrid.py --plot-only --steps 0.05 0.02 0.01 0.005 --save out

Fairlead commanded once per implicit step through set_end_motion (as the node does when it ticks at 1/dt).
"""

import argparse
import json
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from benchmarks import drive
from benchmarks import ropos_case as rc
from tether_sim.io.params import load_config
from tether_sim.physics.motion import build_motion

DG_CACHE = Path("out/ropos_L200_dg_N20P4_alpha1.npz")


def run(cfg, duration, command_dt=0.05):
    """Hybrid solver driven with one command per implicit step (benchmarks/drive.py)."""
    motion = build_motion(cfg.motion, np.asarray(cfg.ship_end.position, dtype=float))
    res = drive.run(replace(cfg, solver="hybrid"), duration, rate=1.0 / command_dt,
                    motion=lambda t: motion.at(t)[:2])
    return res["t"], res["ship"], res["cpu"], res["solver"]


def taut_study(args):
    base = load_config(args.config)
    period = 1.0 / args.frequency
    for dt in args.steps:
        cfg = replace(base, solver="hybrid", motion=replace(base.motion, frequency=args.frequency),
                      hybrid=replace(base.hybrid, time_step=dt, n_segments=args.segments, zoning=args.zoning,
                                     static_relax_time=20.0),
                      initial=replace(base.initial, kind="static"))
        t, T, cpu, solver = run(cfg, args.periods * period, command_dt=dt)  # one implicit step per command
        last = t > t[-1] - 2 * period
        amp = 0.5 * (T[last].max() - T[last].min())
        print(f"dt {dt:g} s: ship tension mean {T[last].mean():.1f} N, amplitude {amp:.1f} N, max {T.max():.1f} N, "
              f"min {T.min():.1f} N; cpu {cpu:.1f} s for {t[-1]:.0f} s; Newton {solver.stats}", flush=True)


def slack_config(dt, segments, rho, softening, alpha=1.0, solver="hybrid", zoning_interval=0.01):
    """The shared L = 200 m slack-snap case (benchmarks/ropos_case.py) with hybrid options."""
    cfg = rc.ropos_config(200.0, alpha=alpha, solver=solver, hybrid_segments=segments, hybrid_dt=dt)
    return replace(cfg, hybrid=replace(cfg.hybrid, rho_inf=rho, compression_softening=softening,
                                       zoning_interval=zoning_interval))


def dg_reference(duration):
    """Ship-tension record of the DG solver, N = 20, P = 4, 200 Hz commands (cached)."""
    if not DG_CACHE.exists():
        cfg = slack_config(0.01, 50, 0.0, 1e4, solver="dg")
        res = drive.run(cfg, duration, rate=200.0, motion=rc.fairlead_motion)
        DG_CACHE.parent.mkdir(parents=True, exist_ok=True)
        np.savez(DG_CACHE, t=res["t"], ship=res["ship"], vehicle=res["vehicle"], cpu=res["cpu"])
    d = np.load(DG_CACHE)
    return d["t"], d["ship"], d["vehicle"]


def slack_run(dt, duration, segments, rho, softening, zoning_interval=0.01):
    """One hybrid run of the slack case; dict of records and figures."""
    cfg = slack_config(dt, segments, rho, softening, zoning_interval=zoning_interval)
    res = drive.run(cfg, duration, rate=1.0 / dt, motion=rc.fairlead_motion)
    st = res["solver"].stats
    return {"t": res["t"], "ship": res["ship"], "vehicle": res["vehicle"], "cpu": res["cpu"], "stats": dict(st)}


def slack_study(args):
    tg, Tg, _ = dg_reference(max(args.duration, 35.0))
    dg = rc.snap_metrics(tg, Tg, window=(10.0, args.duration))
    rows = []
    print(f"DG N=20 P=4: first snap {dg['first_peak'] / 1e3:.2f} kN, cycle peaks 10-{args.duration:g} s "
          f"{[round(p / 1e3, 1) for p in dg['cycle_peaks']]}", flush=True)
    for dt in args.steps:
        w0 = time.perf_counter()
        r = slack_run(dt, args.duration, args.segments, args.rho, args.softening, args.zoning_interval)
        m = rc.snap_metrics(r["t"], r["ship"], window=(10.0, args.duration))
        st = r["stats"]
        row = {"dt": dt, "rho_inf": args.rho, "segments": args.segments, "softening": args.softening,
               "zoning_interval": args.zoning_interval,
               "first_peak": m["first_peak"], "first_err": m["first_peak"] / dg["first_peak"] - 1.0,
               "mean_peak": m["mean_peak"], "mean_err": m["mean_peak"] / dg["mean_peak"] - 1.0,
               "cycle_peaks": m["cycle_peaks"], "cpu": r["cpu"], "wall": time.perf_counter() - w0,
               "it_per_step": st["newton_iterations"] / max(st["steps"], 1), "max_it": st["max_iterations"],
               "halvings": st["halvings"], "rezonings": st["rezonings"], "steps": st["steps"]}
        rows.append(row)
        print(json.dumps(row), flush=True)
        if args.save:
            np.savez(Path(args.save) / f"hybrid_L200_dt{dt:g}_rho{args.rho:g}.npz", t=r["t"], ship=r["ship"],
                     vehicle=r["vehicle"])
    print("| dt (s) | first snap (kN) | vs DG | mean peak 10-%g s (kN) | vs DG | Newton it./step (max) | step halvings | CPU for %g s |"
          % (args.duration, args.duration))
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['dt']:g} | {r['first_peak'] / 1e3:.1f} | {100 * r['first_err']:+.1f} % | {r['mean_peak'] / 1e3:.1f} | "
              f"{100 * r['mean_err']:+.1f} % | {r['it_per_step']:.1f} ({r['max_it']}) | {r['halvings']} | {r['cpu']:.0f} s |")
    print(f"| DG N=20 P=4 | {dg['first_peak'] / 1e3:.1f} | | {dg['mean_peak'] / 1e3:.1f} | | | | |")


def plot_records(directory, steps, rho, duration, out="docs/figures/ropos_L200_hybrid_steps.png"):
    """Ship tension of the saved hybrid records (--save) against DG: whole run and the first snap."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    tg, Tg, _ = dg_reference(max(duration, 35.0))
    fig, ax = plt.subplots(1, 2, figsize=(13, 4.5), gridspec_kw={"width_ratios": [2, 1]})
    for a, (lo, hi) in zip(ax, ((0.0, duration), (7.4, 8.8))):
        m = (tg >= lo) & (tg <= hi)
        a.plot(tg[m], Tg[m] / 1e3, color="0.55", lw=2.5, label="DG N=20 P=4 (explicit, dt 1.8e-5 s)")
        for dt in steps:
            d = np.load(Path(directory) / f"hybrid_L200_dt{dt:g}_rho{rho:g}.npz")
            m = (d["t"] >= lo) & (d["t"] <= hi)
            a.plot(d["t"][m], d["ship"][m] / 1e3, lw=1, label=f"hybrid dt = {dt:g} s")
        a.set(xlabel="t (s)", ylabel="ship tension (kN)")
        a.grid(alpha=0.3)
    ax[0].set_title("ROPOS L = 200 m, a = 2 m, f = 0.2 Hz, EI* = 2620 N m$^2$, cage simulated")
    ax[1].set_title("first snap")
    ax[1].legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    fig.savefig(out, dpi=100)
    print(f"wrote {out}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("config", nargs="?", default="config/ropos_L1730.yaml")
    ap.add_argument("--slack", action="store_true", help="L = 200 m slack-snap study against DG")
    ap.add_argument("--frequency", type=float, default=0.1)
    ap.add_argument("--segments", type=int, default=None)
    ap.add_argument("--periods", type=float, default=6.0)
    ap.add_argument("--zoning", default="adaptive")
    ap.add_argument("--steps", type=float, nargs="+", default=[0.05])
    ap.add_argument("--duration", type=float, default=30.0)
    ap.add_argument("--rho", type=float, default=0.0)
    ap.add_argument("--softening", type=float, default=1e4)
    ap.add_argument("--zoning-interval", type=float, default=0.01)
    ap.add_argument("--save", default="", help="directory for the hybrid records (npz)")
    ap.add_argument("--plot-only", action="store_true", help="only plot the records saved in --save")
    args = ap.parse_args()
    if args.plot_only:
        plot_records(args.save, args.steps, args.rho, args.duration)
    elif args.slack:
        args.segments = args.segments or 50
        slack_study(args)
    else:
        args.segments = args.segments or 40
        taut_study(args)


if __name__ == "__main__":
    main()
