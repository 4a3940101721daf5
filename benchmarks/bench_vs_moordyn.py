"""DG against MoorDyn at equal first-snap accuracy (1 %), both coupled at the node's 50 Hz, one process.

The 1 % rungs are those of BENCHMARKS.md "Accuracy against cost" (bench_accuracy.py, session 2):
DG N = 2, P = 4 (L = 200 m, 0.45 % off) and N = 3, P = 4 (L = 1730 m, 0.52 %), MoorDyn N = 40
(0.71 % / 1730 m: 0.6 % against its own finest rung). The DG results are bit-identical to that
session's (benchmarks/dg_regression.py), so its accuracy figures hold. Cost: thread CPU per simulated
second, best of --repeat runs of --duration s, DG and MoorDyn interleaved:

- DG: a node tick = set_end_motion + advance_to(t + 0.02) + drain_end_tensions + end_forces();
- MoorDyn: moordyn.Step over 0.02 s with its largest stable internal step dividing 0.02 s
  (bench_moordyn.best_wall with NODE_STEP), the fairlead fed the same orbit.

MoorDyn has no bending stiffness: the alpha = 1 rows compare DG with bending against the same
MoorDyn runs. ``--baseline DIR`` adds another checkout's DG (bench_tick.load_baseline).

Usage: PYTHONPATH=. python benchmarks/bench_vs_moordyn.py [--duration 20] [--repeat 3] [--baseline DIR]
"""

import argparse
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks import bench_moordyn  # noqa: E402
from benchmarks import ropos_case as rc  # noqa: E402
from benchmarks.bench_tick import load_baseline  # noqa: E402

RUNGS = {200.0: 2, 1730.0: 3}  # DG elements of the 1 % rung (P = 4)
MOORDYN_SEGMENTS = 40


def dg_cost(factory, mod, length, n, alpha, duration):
    """Thread CPU per simulated s of 50 Hz node ticks (construction and static solve excluded)."""
    sol = factory.build_solver(mod.ropos_config(length, alpha=alpha, n_elements=n, order=4))
    sol.drain_end_tensions()
    ticks = int(round(duration * 50))
    cpu = 0.0
    for k in range(ticks):
        t1 = (k + 1) / 50.0
        c = time.thread_time()
        sol.set_end_motion("ship", *mod.fairlead_motion(t1))
        sol.advance_to(t1)
        sol.drain_end_tensions()
        sol.end_forces()
        cpu += time.thread_time() - c
    return cpu / duration


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=20.0)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--lengths", type=float, nargs="+", default=[200.0, 1730.0])
    ap.add_argument("--baseline")
    ap.add_argument("--workdir", default="out/moordyn")
    args = ap.parse_args(argv)
    from tether_sim.solvers import factory
    trees = [("dg", factory, rc)]
    if args.baseline:
        trees.append(("dg_base",) + load_baseline(args.baseline))
    Path(args.workdir).mkdir(parents=True, exist_ok=True)
    print(f"bench_vs_moordyn {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load {os.getloadavg()[0]:.1f}; "
          f"thread CPU ms per simulated s, best of {args.repeat} x {args.duration:g} s, 50 Hz coupling", flush=True)
    for length in args.lengths:
        n = RUNGS[length]
        for _, fac, mod in trees:  # warm the JIT caches, untimed
            for alpha in (0.0, 1.0):
                dg_cost(fac, mod, length, n, alpha, 0.1)
        best = {}
        dt_md = rc.moordyn_time_step(length, MOORDYN_SEGMENTS, bench_moordyn.NODE_STEP)
        for _ in range(args.repeat):
            for name, fac, mod in trees:
                for alpha in (0.0, 1.0):
                    c = dg_cost(fac, mod, length, n, alpha, args.duration)
                    best[(name, alpha)] = min(best.get((name, alpha), c), c)
            _, cpu = bench_moordyn.best_wall(length, MOORDYN_SEGMENTS, args.duration, bench_moordyn.NODE_STEP, dt_md,
                                             args.workdir, 1)
            best["md"] = min(best.get("md", cpu / args.duration), cpu / args.duration)
        md = best["md"]
        for alpha in (0.0, 1.0):
            line = f"  L={length:6.0f} alpha={alpha:g}: MoorDyn N={MOORDYN_SEGMENTS} {1e3 * md:7.2f} ms/s"
            for name, _, _ in trees:
                c = best[(name, alpha)]
                line += f" | {name} N={n} P=4 {1e3 * c:7.2f} ms/s, {name}/MoorDyn {c / md:.3f}"
            print(line, flush=True)


if __name__ == "__main__":
    main()
