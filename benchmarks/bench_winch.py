"""Cost of the DG winch: ROPOS with the cage, fairlead orbit a = 2 m, f = 0.2 Hz, fed at 50 Hz.

A micro-benchmark of one right-hand side with and without the winch terms, then three runs per
length in one process, thread CPU time of the ticks only (drive.run), interleaved, best of
--repeats: no winch,
winch enabled but idle (rate 0: the winch code is skipped, bit-identical results), and paying out
at 1 m/s (ramped over the first tick). Prints the real-time factor and the cost per substep
relative to the run without a winch (the substep counts differ a little: paying out lengthens
the elements and the substep grows with them).

Usage: PYTHONPATH=. python benchmarks/bench_winch.py [--lengths 200 1730] [--duration 4] [--repeats 3]
"""

import argparse
import os
import sys
import time
from dataclasses import replace
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks import drive  # noqa: E402
from benchmarks import ropos_case as rc  # noqa: E402
from tether_sim.physics.winch import WinchConfig  # noqa: E402
from tether_sim.solvers.dg.solver import DGCableSolver  # noqa: E402


def run(length, duration, rate):
    cfg = rc.ropos_config(length)
    if rate is not None:
        cfg = replace(cfg, winch=WinchConfig(enabled=True, end="ship"))
    build = drive.build_solver

    def factory(config):
        s = DGCableSolver(config)
        if rate:
            s.set_pay_out_rate(rate)
        return s

    drive.build_solver = factory
    try:
        res = drive.run(cfg, duration, motion=rc.fairlead_motion)
    finally:
        drive.build_solver = build
    return res


def rhs_cost(length, n=2000, repeats=5):
    """Thread CPU of one right-hand-side evaluation (tick.evaluate_now) with the winch terms off
    (rate 0) and on (rate 1 m/s), interleaved, best of ``repeats``."""
    from tether_sim.solvers.dg import layout as Y
    from tether_sim.solvers.dg.tick import evaluate_now
    s = DGCableSolver(replace(rc.ropos_config(length), winch=WinchConfig(enabled=True, end="ship")))
    best = {0.0: float("inf"), 1.0: float("inf")}
    ws = s.ws
    for _ in range(repeats):
        for rate in best:
            s.ws.prm[Y.P_WLDOT] = rate
            evaluate_now(ws.F, ws.I, ws.spec, s.time)
            c = time.thread_time()
            for _ in range(n):
                evaluate_now(ws.F, ws.I, ws.spec, s.time)
            best[rate] = min(best[rate], (time.thread_time() - c) / n)
    return best


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lengths", type=float, nargs="+", default=[200.0, 1730.0])
    ap.add_argument("--duration", type=float, default=4.0)
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args(argv)
    print(f"load {os.getloadavg()[0]:.1f}; ROPOS N = 20, P = 4, cage body, {args.duration:g} s at 50 Hz")
    for L in args.lengths:
        cost = rhs_cost(L)
        print(f"L = {L:g} m, one right-hand side: {cost[0.0] * 1e6:.2f} us without the winch terms, "
              f"{cost[1.0] * 1e6:.2f} us with them (x{cost[1.0] / cost[0.0]:.3f})")
        run(L, 0.2, 1.0)  # compile / warm the paths
        cases = (("no winch", None), ("winch idle", 0.0), ("paying out 1 m/s", 1.0))
        best = {}
        for _ in range(args.repeats):  # interleaved, best of the repeats (a shared, loaded machine)
            for name, rate in cases:
                r = run(L, args.duration, rate)
                if name not in best or r["cpu"] < best[name]["cpu"]:
                    best[name] = r
        per0 = best["no winch"]["cpu"] / best["no winch"]["substeps"]
        for name, _ in cases:
            r = best[name]
            print(f"L = {L:g} m, {name:17s}: {r['substeps']:7d} substeps, cpu {r['cpu']:.2f} s, RTF {args.duration / r['cpu']:.2f},"
                  f" cost per substep x{r['cpu'] / r['substeps'] / per0:.3f}, final L {r['solver'].L:.2f} m")


if __name__ == "__main__":
    main()
