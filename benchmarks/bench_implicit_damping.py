"""Implicit vs explicit damping of the DG solver on the ROPOS case (BENCHMARKS.md).

ROPOS tether + cage body, N = 20, P = 4, circular fairlead a = 2 m, f = 0.2 Hz through slack and
snap (ropos_case). For each length both damping treatments run in the same process, alternately,
and report: substep, thread-CPU per simulated second (time.thread_time, robust on the shared
machine), static ship tension (first recorded substep), first snap peak (5-10 s) and their
relative differences.

``PYTHONPATH=. python benchmarks/bench_implicit_damping.py [--lengths 1730 200] [--duration 10]``
"""

import argparse
import dataclasses
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import drive  # noqa: E402
import ropos_case as rc  # noqa: E402


def config(length, damping, alpha=0.0, n_elements=20, order=4, cfl=0.5):
    cfg = rc.ropos_config(length, alpha=alpha, n_elements=n_elements, order=order, cfl=cfl)
    return dataclasses.replace(cfg, dg=dataclasses.replace(cfg.dg, damping=damping))


def measure(length, damping, duration, alpha=0.0, n_elements=20, order=4, cfl=0.5):
    res = drive.run(config(length, damping, alpha, n_elements, order, cfl), duration, motion=rc.fairlead_motion)
    first = rc.snap_peak(res["t"], res["ship"], *rc.FIRST_SNAP_WINDOW) if duration > 10.0 else (np.nan, np.nan)
    return {"damping": damping, "dt": res["time_step"], "cpu_per_s": res["cpu"] / duration,
            "static": float(res["ship"][0]), "first_peak": first[0], "first_peak_t": first[1],
            "substeps": res["substeps"], "t": res["t"], "ship": res["ship"]}


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--lengths", type=float, nargs="+", default=[1730.0, 200.0])
    p.add_argument("--duration", type=float, default=10.5)
    p.add_argument("--alpha", type=float, default=0.0)
    p.add_argument("--elements", type=int, default=20)
    p.add_argument("--order", type=int, default=4)
    p.add_argument("--cfl", type=float, default=0.5)
    p.add_argument("--save", default=None, help="npz file for the tension records")
    a = p.parse_args(argv)
    for mode in ("explicit", "implicit"):  # compile both paths before timing
        measure(200.0, mode, 0.04, a.alpha, a.elements, a.order, a.cfl)
    rows, records = [], {}
    for L in a.lengths:
        ex = measure(L, "explicit", a.duration, a.alpha, a.elements, a.order, a.cfl)
        ims = [measure(L, "implicit", a.duration, a.alpha, a.elements, a.order, a.cfl)]
        rows.append((L, ex, ims))
        for x in [ex] + ims:
            key = x["damping"]
            records[f"L{int(L)}_{key}_t"] = x["t"]
            records[f"L{int(L)}_{key}_ship"] = x["ship"]
        print(f"L = {L:g} m, N = {a.elements}, P = {a.order}, alpha = {a.alpha:g}, cfl = {a.cfl:g}, "
              f"{a.duration:g} s simulated, load {os.getloadavg()[0]:.1f}")
        print("  damping      | dt (s)   | CPU s / sim s | speed-up | static T (kN) | first snap peak (kN) at t (s) | vs explicit")
        for x in [ex] + ims:
            print(f"  {x['damping']:12s} | {x['dt']:.2e} | {x['cpu_per_s']:13.3f} | x{ex['cpu_per_s'] / x['cpu_per_s']:7.2f} | "
                  f"{x['static'] / 1e3:13.3f} | {x['first_peak'] / 1e3:10.3f} at {x['first_peak_t']:.3f}     | "
                  f"{x['first_peak'] / ex['first_peak'] - 1:+.3%}", flush=True)
    if a.save:
        np.savez(a.save, **records)
    return rows


if __name__ == "__main__":
    main()
