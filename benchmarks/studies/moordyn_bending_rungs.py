"""MoorDyn's first-snap-peak segment ladder with and without bending stiffness.

bench_vs_moordyn takes MoorDyn N = 40 as MoorDyn's 1 % rung (BENCHMARKS.md "Accuracy against
cost", measured with EI = 0). Since 2026-11-25 it times MoorDyn with the DG row's bending stiffness
EI = alpha * EI_STAR, so this script checks that N = 40 is still within 1 % with alpha = 1: for
each length, one run per segment count N and alpha (0 and 1) of ``bench_moordyn.run_moordyn``
(``--duration`` s, 200 Hz coupling, RK2 at ``ropos_case.moordyn_time_step``, as bench_moordyn.ladder
runs its accuracy rungs), the first snap peak of ``ropos_case.snap_metrics`` (largest ship tension
in 5-10 s) and its relative error against the finest N of the same alpha. Also printed: the
bending effect on the peak at each N (alpha 1 against alpha 0) and the thread CPU inside
moordyn.Step per simulated s of these 200 Hz runs (one run each: indicative only).

Usage: PYTHONPATH=. python benchmarks/studies/moordyn_bending_rungs.py [--lengths 1730 200]
       [--segments 20 40 80 160] [--duration 10.2]
"""

import argparse
import os
import platform
import sys
import time
from importlib.metadata import version
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from benchmarks import bench_moordyn  # noqa: E402
from benchmarks import ropos_case as rc  # noqa: E402

ALPHAS = (0.0, 1.0)


def first_peaks(length, segments, duration, workdir):
    """{(alpha, N): (first snap peak N, thread CPU s per simulated s)} for one length."""
    out = {}
    for n_seg in segments:
        for alpha in ALPHAS:
            res = bench_moordyn.run_moordyn(length, n_seg, duration, alpha=alpha, workdir=workdir)
            peak = rc.snap_metrics(res["t"], res["tension"])["first_peak"]
            out[(alpha, n_seg)] = (peak, res["step_cpu"] / duration)
    return out


def table(length, segments, peaks):
    """Lines of the table for one length; errors against the finest N of the same alpha."""
    ref = {alpha: peaks[(alpha, segments[-1])][0] for alpha in ALPHAS}
    lines = [f"L = {length:g} m (reference: N = {segments[-1]} of the same alpha)",
             "     N | first peak EI=0 (kN) | error EI=0 | first peak EI=EI* (kN) | error EI=EI* "
             "| EI*/EI=0 - 1 | Step CPU EI=0 / EI* (ms/s)"]
    for n_seg in segments:
        p0, c0 = peaks[(0.0, n_seg)]
        p1, c1 = peaks[(1.0, n_seg)]
        e0 = abs(p0 - ref[0.0]) / ref[0.0]
        e1 = abs(p1 - ref[1.0]) / ref[1.0]
        err = "  (ref)   " if n_seg == segments[-1] else f"{100 * e0:8.3f} %"
        err1 = "  (ref)   " if n_seg == segments[-1] else f"{100 * e1:8.3f} %"
        lines.append(f"  {n_seg:4d} | {p0 / 1e3:20.3f} | {err:>10} | {p1 / 1e3:22.3f} | {err1:>12} "
                     f"| {100 * (p1 / p0 - 1):+10.3f} % | {1e3 * c0:8.2f} / {1e3 * c1:8.2f}")
    return lines


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lengths", type=float, nargs="+", default=[1730.0, 200.0])
    ap.add_argument("--segments", type=int, nargs="+", default=[20, 40, 80, 160])
    ap.add_argument("--duration", type=float, default=10.2)
    ap.add_argument("--workdir", default="out/moordyn")
    args = ap.parse_args(argv)
    if args.duration < rc.FIRST_SNAP_WINDOW[1]:
        ap.error(f"--duration must cover the first-snap window (>= {rc.FIRST_SNAP_WINDOW[1]:g} s)")
    segments = sorted(args.segments)
    Path(args.workdir).mkdir(parents=True, exist_ok=True)
    print(f"moordyn_bending_rungs: MoorDyn {version('moordyn')} on {platform.machine()}, {os.cpu_count()} cores, "
          f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load {os.getloadavg()[0]:.1f}; "
          f"{args.duration:g} s runs, coupling {bench_moordyn.COUPLING_STEP:g} s, RK2, "
          f"EI* = {rc.EI_STAR:g} N m^2; first snap peak = largest ship tension in "
          f"{rc.FIRST_SNAP_WINDOW[0]:g}-{rc.FIRST_SNAP_WINDOW[1]:g} s", flush=True)
    for length in args.lengths:
        peaks = first_peaks(length, segments, args.duration, args.workdir)
        for line in table(length, segments, peaks):
            print(line, flush=True)
    print(f"done {time.strftime('%H:%M UTC', time.gmtime())}, load {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
