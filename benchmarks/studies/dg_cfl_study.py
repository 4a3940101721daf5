"""Is dg.cfl = 0.9 safe through slack and snap? ROPOS with the cage body, several safety factors.

For each length and alpha the run at cfl = 0.5 (the old default) is the reference; every other
cfl is compared on the snap figures of ``ropos_case.snap_metrics`` (first full-amplitude peak,
per-period peaks) of the ship tension, the largest vehicle tension, and the largest difference of
the ship-tension records resampled on a common 1 ms grid (relative to the largest tension).

Usage: PYTHONPATH=. python benchmarks/studies/dg_cfl_study.py [--lengths 1730 200] [--alphas 0 1]
       [--cfls 0.5 0.9 1.0 1.1] [--duration 20]
"""

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from benchmarks import drive  # noqa: E402
from benchmarks import ropos_case as rc  # noqa: E402


def one_run(length, alpha, cfl, duration):
    cfg = rc.ropos_config(length, alpha=alpha, cfl=cfl)
    try:
        res = drive.run(cfg, duration, motion=rc.fairlead_motion)
    except Exception as exc:  # divergence is a result here
        return {"error": f"{type(exc).__name__}: {exc}"}
    return res


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lengths", type=float, nargs="+", default=[1730.0, 200.0])
    ap.add_argument("--alphas", type=float, nargs="+", default=[0.0, 1.0])
    ap.add_argument("--cfls", type=float, nargs="+", default=[0.5, 0.9, 1.0, 1.1])
    ap.add_argument("--duration", type=float, default=20.0)
    args = ap.parse_args(argv)
    print(f"dg_cfl_study {args.duration} s, f = {rc.ORBIT_FREQUENCY} Hz, a = {rc.ORBIT_AMPLITUDE} m, cage body, "
          f"N = 20, P = 4, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load {os.getloadavg()[0]:.1f}",
          flush=True)
    window = (5.0, args.duration)
    for length in args.lengths:
        for alpha in args.alphas:
            ref = None
            for cfl in args.cfls:
                res = one_run(length, alpha, cfl, args.duration)
                tag = f"L={length:.0f} alpha={alpha:g} cfl={cfl:g}"
                if "error" in res:
                    print(f"  {tag}: {res['error']}", flush=True)
                    continue
                t, ship, veh = res["t"], res["ship"], res["vehicle"]
                m = rc.snap_metrics(t, ship, window=window)
                grid = np.arange(0.0, args.duration - 1e-3, 1e-3)
                ship_g = drive.resample(t, ship, grid)
                row = {"first": m["first_peak"], "max": m["max_peak"], "cycles": m["cycle_peaks"],
                       "veh_max": float(veh.max()), "ship_min": float(ship.min()), "veh_min": float(veh.min()),
                       "grid": ship_g}
                line = (f"  {tag}: dt={res['time_step']:.3g} s substeps={res['substeps']} cpu={res['cpu']:.1f} s "
                        f"first peak {row['first'] / 1e3:.2f} kN, max {row['max'] / 1e3:.2f} kN, "
                        f"vehicle max {row['veh_max'] / 1e3:.2f} kN, ship min {row['ship_min'] / 1e3:.3f} kN, "
                        f"vehicle min {row['veh_min'] / 1e3:.3f} kN")
                if ref is None:
                    ref = row
                else:
                    dpk = max(abs(a - b) / b for a, b in zip(row["cycles"], ref["cycles"])) if ref["cycles"] else np.nan
                    drec = float(np.max(np.abs(ship_g - ref["grid"])) / np.max(ref["grid"]))
                    line += (f"\n      vs cfl={args.cfls[0]:g}: first peak {100 * (row['first'] / ref['first'] - 1):+.3f} %, "
                             f"worst cycle peak {100 * dpk:.3f} %, vehicle max "
                             f"{100 * (row['veh_max'] / ref['veh_max'] - 1):+.3f} %, record max diff {100 * drec:.3f} %")
                print(line, flush=True)


if __name__ == "__main__":
    main()
