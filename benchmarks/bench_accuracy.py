"""Snap-peak accuracy against cost: our solvers' resolution ladders next to MoorDyn's, one run.

For each length: the MoorDyn segment ladder (``bench_moordyn.ladder``) and the ladder of our
solver (DG: (N, P) pairs; hybrid: segment counts), each against the converged reference of the
same code (its finest rung). The accuracy metric is ``ropos_case.snap_metrics``' ``first_peak``
(the ship-tension peak of the first slack-snap event, 5-10 s) computed on the same 200 Hz
sampling for both codes (our substep record is interpolated onto it); the default duration
(12 s) covers it, longer runs add the per-cycle figures. Cost is the wall time per simulated
second (best of 3 runs of 20 s, same machine, same process). Then "wall time at equal accuracy"
(1 % and 5 %) is read off both ladders and printed as a ratio (ours / MoorDyn).

Usage: PYTHONPATH=. python benchmarks/bench_accuracy.py [--lengths 200 1730]
       [--dg 5:4 10:4 20:4 40:4 80:4] [--moordyn 20 40 80 160 320] [--solver dg]
       [--json out/bench_accuracy.json]
"""

import argparse
import json
import os
import platform
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks import bench_moordyn, drive  # noqa: E402
from benchmarks import ropos_case as rc  # noqa: E402

GRID_STEP = bench_moordyn.COUPLING_STEP  # s, the common sampling of the ship tension


def our_config(solver, length, rung, alpha, damping="explicit", cfl=0.5):
    """SimConfig of one rung: DG rung 'N:P' (damping: dg.damping, cfl: dg.cfl), hybrid rung 'segments[:dt]'."""
    if solver == "dg":
        n, p = (int(v) for v in rung.split(":"))
        return rc.ropos_config(length, alpha=alpha, solver="dg", n_elements=n, order=p, damping=damping, cfl=cfl)
    parts = rung.split(":")
    cfg = rc.ropos_config(length, alpha=alpha, solver="hybrid", hybrid_segments=int(parts[0]))
    if len(parts) > 1:
        cfg = replace(cfg, hybrid=replace(cfg.hybrid, time_step=float(parts[1])))
    return cfg


def our_ladder(solver, length, rungs, duration, alpha=0.0, repeats=3, speed_duration=20.0, damping="explicit",
               cfl=0.5):
    """Accuracy and cost of our solver's ladder; the last rung is the reference."""
    grid = np.arange(1, int(round(duration / GRID_STEP)) + 1) * GRID_STEP
    rows = []
    for rung in rungs:
        cfg = our_config(solver, length, rung, alpha, damping, cfl)
        drive.run(cfg, 0.1, motion=rc.fairlead_motion)  # warm the JIT cache, untimed
        res = drive.run(cfg, duration, motion=rc.fairlead_motion)
        tension = drive.resample(res["t"], res["ship"], grid)
        metrics = rc.snap_metrics(grid, tension)
        walls, cpus = [res["wall"] / duration], [res["cpu"] / duration]
        if res["wall"] < 60.0:
            for _ in range(repeats):
                again = drive.run(cfg, speed_duration, motion=rc.fairlead_motion)
                walls.append(again["wall"] / speed_duration)
                cpus.append(again["cpu"] / speed_duration)
        rows.append({"rung": rung, "length": length, "time_step": res["time_step"], **metrics,
                     "substep_max": float(np.max(res["ship"])),
                     "wall_per_s": min(walls), "rtf": 1.0 / min(walls),
                     "cpu_per_s": min(cpus), "rtf_cpu": 1.0 / min(cpus), "load": os.getloadavg()[0]})
        r = rows[-1]
        print(f"  {solver} L={length:6.0f} {rung:>8s} dt={r['time_step']:.3g}s first={r['first_peak'] / 1e3:8.2f} kN "
              f"mean={r['mean_peak'] / 1e3:8.2f} max={r['max_peak'] / 1e3:8.2f} kN  "
              f"wall/sim-s={1e3 * r['wall_per_s']:9.2f} ms cpu/sim-s={1e3 * r['cpu_per_s']:9.2f} ms "
              f"RTF={r['rtf']:8.2f} load={r['load']:.1f}", flush=True)
    for key in bench_moordyn.METRICS:
        ref = rows[-1][key]
        for r in rows:
            r[key + "_error"] = abs(r[key] - ref) / ref
    return rows


def _print_ladder(label, rows, name_key):
    for r in rows:
        print(f"    {label} {str(r[name_key]):>8s}  first-peak={r['first_peak'] / 1e3:8.2f} kN  "
              f"err={100 * r['first_peak_error']:6.2f} % (mean {100 * r['mean_peak_error']:6.2f} %, "
              f"max {100 * r['max_peak_error']:6.2f} %)  wall/sim-s={1e3 * r['wall_per_s']:9.2f} ms  "
              f"cpu/sim-s={1e3 * r['cpu_per_s']:9.2f} ms")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lengths", type=float, nargs="+", default=[200.0, 1730.0])
    ap.add_argument("--solver", default="dg", choices=("dg", "hybrid"))
    ap.add_argument("--dg", nargs="+", default=["5:4", "10:4", "20:4", "40:4", "80:4"])
    ap.add_argument("--hybrid", nargs="+", default=["25", "50", "100", "200", "400"])
    ap.add_argument("--moordyn", type=int, nargs="+", default=[20, 40, 80, 160, 320])
    ap.add_argument("--alpha", type=float, default=0.0)
    ap.add_argument("--duration", type=float, default=12.0)
    ap.add_argument("--damping", default="explicit", choices=("explicit", "implicit"), help="dg.damping of the DG ladder")
    ap.add_argument("--cfl", type=float, default=0.5, help="dg.cfl of the DG ladder")
    ap.add_argument("--repeats", type=int, default=3, help="speed re-runs per rung (best of; 0 = the accuracy run only)")
    ap.add_argument("--moordyn-repeats", type=int, default=3, help="MoorDyn speed re-runs per rung (best of)")
    ap.add_argument("--speed-duration", type=float, default=20.0, help="simulated s of each speed re-run")
    ap.add_argument("--json", default="out/bench_accuracy.json")
    ap.add_argument("--workdir", default="out/moordyn")
    args = ap.parse_args(argv)
    Path(args.workdir).mkdir(parents=True, exist_ok=True)
    print(f"bench_accuracy on {platform.machine()}, {os.cpu_count()} cores, "
          f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}; metric: ship-tension peak of the first "
          f"snap ({rc.FIRST_SNAP_WINDOW} s), sampled every {GRID_STEP} s; alpha={args.alpha:g}")
    rungs = args.dg if args.solver == "dg" else args.hybrid
    out = {}
    for length in args.lengths:
        ours = our_ladder(args.solver, length, rungs, args.duration, alpha=args.alpha, repeats=args.repeats,
                          speed_duration=args.speed_duration, damping=args.damping, cfl=args.cfl)
        md = bench_moordyn.ladder(length, sorted(args.moordyn), args.duration, args.workdir,
                                  repeats=args.moordyn_repeats, speed_duration=args.speed_duration)
        print(f"L={length:.0f} m  (errors against each code's finest rung)")
        _print_ladder(args.solver, ours, "rung")
        _print_ladder("MoorDyn N=", md, "segments")
        ref_gap = abs(ours[-1]["first_peak"] - md[-1]["first_peak"]) / md[-1]["first_peak"]
        print(f"    references differ by {100 * ref_gap:.2f} % ({args.solver} {ours[-1]['first_peak'] / 1e3:.2f} kN, "
              f"MoorDyn {md[-1]['first_peak'] / 1e3:.2f} kN)")
        equal = {}
        for tol in (0.01, 0.05):
            for cost in ("wall_per_s", "cpu_per_s"):
                a = bench_moordyn.wall_at_accuracy(ours, tol, cost=cost)
                b = bench_moordyn.wall_at_accuracy(md, tol, cost=cost)
                fa = f"{args.solver} {a['rung']}: {1e3 * a[cost]:.2f} ms/s" if a else f"{args.solver}: not reached"
                fb = f"MoorDyn N={b['segments']}: {1e3 * b[cost]:.2f} ms/s" if b else "MoorDyn: not reached"
                ratio = a[cost] / b[cost] if (a and b) else None
                rtxt = f"ratio ours/MoorDyn = {ratio:.2f}" if ratio else "ratio n/a"
                print(f"    at {100 * tol:.0f} % ({cost[:-6]}): {fa} | {fb} | {rtxt}")
                equal[f"{tol}_{cost}"] = {"ours": a, "moordyn": b, "ratio": ratio}
        out[str(int(length))] = {"ours": ours, "moordyn": md, "equal_accuracy": equal, "reference_gap": ref_gap}
    Path(args.json).parent.mkdir(parents=True, exist_ok=True)
    Path(args.json).write_text(json.dumps(out, indent=1, default=float))
    print(f"wrote {args.json}")


if __name__ == "__main__":
    main()
