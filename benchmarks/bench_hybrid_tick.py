"""The hybrid solver's share of a node tick, by part, on a live file's own orbit; optionally against another checkout
in the same process (interleaved tick by tick, so the ratios do not depend on the machine's load).

Per 50 Hz tick each tree's solver gets the calls the node makes (``bench_node_tick.py --profile``): ``tick`` with the
fairlead's commanded position and velocity from the file's ``motion`` (advance_to, drain_end_tensions, end_forces),
``state`` at the file's output points, ``state`` at the two ends and ``body_state`` of both ends twice (the outputs and
the snap detector's relative end speed). Parts, thread CPU per tick: ``newton`` (the compiled Newton iterations of
the steps), ``closing`` (the re-closing of rod shapes, ``close_rod_shapes``), ``rezone`` (zone evaluations and
conversions, the closing included), ``advance`` (advance_to, all of the above included), ``outputs`` (every call after
advance_to). Newton iterations and Jacobians per step are counted from the solver's ``stats``.

    PYTHONPATH=. nice -n 5 python benchmarks/bench_hybrid_tick.py [--params config/ropos_L200_hybrid.yaml ...]
        [--ticks 1500] [--warm 100] [--baseline /path/to/other/checkout]
"""

import argparse
import importlib
import os
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

PARTS = ("tick", "advance", "newton", "rezone", "closing", "outputs")


class _Tree:
    """One tree's solver of one file, its motion and its per-tick part times."""

    def __init__(self, pkg, params):
        load_config = importlib.import_module(f"{pkg}.io.params").load_config
        build_solver = importlib.import_module(f"{pkg}.solvers.factory").build_solver
        build_motion = importlib.import_module(f"{pkg}.physics.motion").build_motion
        self.cfg = load_config(ROOT / params)
        self.solver = build_solver(self.cfg)
        self.motion = build_motion(self.cfg.motion, self.cfg.ship_end.position)
        self.points = np.linspace(0.0, self.cfg.cable.length, self.cfg.node.output_points)
        self.ends = np.array([0.0, self.cfg.cable.length])
        self.acc = dict.fromkeys(PARTS, 0.0)
        self.rows = []
        acc = self.acc

        def timed(obj, name, key):
            fn = getattr(obj, name)

            def wrapper(*a, **k):
                c = time.thread_time()
                try:
                    return fn(*a, **k)
                finally:
                    acc[key] += time.thread_time() - c
            setattr(obj, name, wrapper)

        mod = importlib.import_module(f"{pkg}.solvers.hybrid.solver")
        timed(self.solver, "_newton_compiled", "newton")
        timed(self.solver, "_rezone", "rezone")
        timed(self.solver, "advance_to", "advance")
        timed(mod, "close_rod_shapes", "closing")
        self.t0 = self.solver.time

    def tick(self, k, keep):
        s = self.solver
        for key in self.acc:
            self.acc[key] = 0.0
        steps0, it0, jac0 = s.stats["steps"], s.stats["newton_iterations"], s.stats.get("jacobians", 0)
        t = self.t0 + 0.02 * (k + 1)
        p, v, _ = self.motion.at(t)
        c = time.thread_time()
        s.tick(t, ship=(p, v))
        c1 = time.thread_time()
        s.state(self.points)
        s.state(self.ends)
        for _ in range(2):
            s.body_state("ship")
            s.body_state("vehicle")
        c2 = time.thread_time()
        self.acc["tick"] = c2 - c
        self.acc["outputs"] = c2 - c1 + (c1 - c - self.acc["advance"])
        if keep:
            st = s.stats
            self.rows.append([self.acc[key] for key in PARTS] + [st["steps"] - steps0, st["newton_iterations"] - it0,
                                                                 st.get("jacobians", 0) - jac0])

    def summary(self):
        r = np.array(self.rows)
        out = {key: float(np.median(r[:, i]) * 1e3) for i, key in enumerate(PARTS)}
        out.update({key + "_mean": float(np.mean(r[:, i]) * 1e3) for i, key in enumerate(PARTS)})
        out["tick_p99"] = float(np.percentile(r[:, 0], 99) * 1e3)
        steps = r[:, len(PARTS)].sum()
        out["iterations_per_step"] = float(r[:, len(PARTS) + 1].sum() / steps)
        out["jacobians_per_step"] = float(r[:, len(PARTS) + 2].sum() / steps)
        out["steps_per_tick"] = float(steps / len(r))
        return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--params", nargs="+", default=["config/ropos_L200_hybrid.yaml", "config/ropos_L1730_hybrid.yaml"])
    ap.add_argument("--ticks", type=int, default=1500)
    ap.add_argument("--warm", type=int, default=100)
    ap.add_argument("--baseline", default=None, help="another checkout, ticked alternately with this one")
    args = ap.parse_args(argv)
    pkgs = ["tether_sim"]
    if args.baseline:
        from benchmarks.bench_tick import load_baseline
        load_baseline(args.baseline)
        pkgs.insert(0, "tether_sim_base")
    print(f"bench_hybrid_tick {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, {args.ticks} ticks after "
          f"{args.warm}, load {os.getloadavg()[0]:.2f}", flush=True)
    for params in args.params:
        trees = [_Tree(pkg, params) for pkg in pkgs]
        for k in range(args.warm + args.ticks):
            for tree in (trees if k % 2 == 0 else trees[::-1]):
                tree.tick(k, k >= args.warm)
        sums = [tree.summary() for tree in trees]
        for pkg, s in zip(pkgs, sums):
            name = "baseline" if pkg != "tether_sim" else "this tree"
            print(f"{Path(params).name} [{name}] median ms/tick: " + ", ".join(f"{key} {s[key]:.3f}" for key in PARTS)
                  + f" (tick p99 {s['tick_p99']:.3f}; means: " + ", ".join(f"{key} {s[key + '_mean']:.3f}" for key in PARTS)
                  + f"); {s['steps_per_tick']:.2f} steps/tick, {s['iterations_per_step']:.2f} Newton iterations and "
                  f"{s['jacobians_per_step']:.2f} Jacobians per step", flush=True)
        if args.baseline:
            b, w = sums
            print(f"{Path(params).name} baseline / this tree (medians): " + ", ".join(
                f"{key} {b[key] / w[key]:.2f}" if w[key] > 0 else f"{key} -" for key in PARTS)
                + "; means: " + ", ".join(f"{key} {b[key + '_mean'] / w[key + '_mean']:.2f}" if w[key + "_mean"] > 0
                                           else f"{key} -" for key in PARTS), flush=True)
    print(f"load {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
