"""Fixed per-tick work of the DG solver's node tick: what a tick costs beyond its substeps, and its parts.

One solver of a live file (default config/ropos_L1730.yaml), ticked at 50 Hz to t = --warm s with the
fairlead on a 0.5 m circle, then, interleaved block by block in one process (thread CPU, min over
--repeat blocks of --calls calls each):

- ``solver.tick`` over intervals of k = 1..4 substeps of the rule's step: a least-squares line through
  the four costs per call; its intercept is the fixed per-tick work (Python, the call, the kernel's own
  set-up, the output evaluation beyond the first stage it saves, the drain), its slope one substep;
- the kernel solver.tick calls, called directly with the same arguments (intercept and slope likewise):
  ``tick.ship_tick`` where the tree has it (the ship end's position and velocity as two arrays, the
  substeps from the rule), else ``tick.node_tick``; solver.tick's Python is the difference of the intercepts;
- ``node_tick`` with 0 substeps (t1 = t0: targets, checks, output evaluation, drain, no substep);
- an empty compiled function with node_tick's signature: the cost of the call itself (dispatch).

Usage: PYTHONPATH=. python benchmarks/probes/tick_fixed_work.py [--params config/ropos_L1730.yaml]
       [--ei 2620] [--calls 200] [--repeat 15] [--baseline /path/to/other/checkout]
"""

import argparse
import math
import os
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from tether_sim.numerics.jit import jit  # noqa: E402


@jit
def _empty(F, I, S, tin, ends_set, t0, t1, nsteps, dt, drain):
    return 0


def motion(t):
    """The fairlead's small circle (0.5 m, 1 rad/s) the tick probes drive their solvers with: (p, v)."""
    p = 0.5 * np.array((math.cos(t) - 1.0, math.sin(t), 0.0))
    v = 0.5 * np.array((-math.sin(t), math.cos(t), 0.0))
    return p, v


def tick_parser(description):
    """The options every tick probe takes (tick_fixed_work, tick_stages, substep_parts)."""
    ap = argparse.ArgumentParser(description=description)
    ap.add_argument("--params", default=str(ROOT / "config" / "ropos_L1730.yaml"))
    ap.add_argument("--ei", type=float, default=None, help="cable.EI override (N m^2)")
    ap.add_argument("--warm", type=float, default=2.0)
    ap.add_argument("--calls", type=int, default=200)
    ap.add_argument("--repeat", type=int, default=15)
    return ap


def warmed_solver(params, ei, warm, pkg="tether_sim"):
    """(config, solver) of the file ``params`` (cable.EI overridden by ``ei`` unless None), ticked at 50 Hz with
    :func:`motion` up to ``warm`` s (compiles and settles the paths the probes time)."""
    import importlib

    load_config = importlib.import_module(f"{pkg}.io.params").load_config
    build_solver = importlib.import_module(f"{pkg}.solvers.factory").build_solver
    cfg = load_config(Path(params), overrides={"cable.EI": ei} if ei is not None else None)
    s = build_solver(cfg)
    t = s.time
    while t < warm - 1e-9:
        t += 0.02
        s.tick(t, ship=motion(t))
    return cfg, s


def _tree(pkg, params, ei, warm):
    """A warmed solver of the package pkg (tether_sim or a baseline's tether_sim_base) and its block timers."""
    import importlib

    tick_mod = importlib.import_module(f"{pkg}.solvers.dg.tick")
    node_tick = tick_mod.node_tick
    ship_tick = getattr(tick_mod, "ship_tick", None)  # the kernel solver.tick calls, where the tree has it
    cfg, s = warmed_solver(params, ei, warm, pkg)
    dt = s._substep()
    F, I, S = s.ws.F, s.ws.I, s.ws.spec

    def tick(k, calls):
        t, span = s.time, k * dt * (1.0 - 1e-9)
        ts = [t + (i + 1) * span for i in range(calls)]
        motions = [motion(x) for x in ts]  # (made before the clock starts)
        c = time.thread_time()
        for x, m in zip(ts, motions):
            s.tick(x, ship=m)
        return (time.thread_time() - c) / calls

    def kernel(k, calls):
        tin = s._tick.tin if hasattr(s, "_tick") else s._tick_in
        t, span = s.time, k * dt * (1.0 - 1e-9)
        tins = []
        for i in range(calls):  # (made before the clock starts)
            p, v = motion(t + (i + 1) * span)
            tins.append(np.concatenate((p, v)).reshape(1, 6).repeat(2, axis=0))
        pvs = [(x[0, 0:3].copy(), x[0, 3:6].copy()) for x in tins]
        c = time.thread_time()
        if ship_tick is not None:  # k substeps: the rule's n over span = k dt (1 - 1e-9) with step dt
            for p, v in pvs:
                ship_tick(F, I, S, p, v, t, t + span, dt, True)
                t += span
        else:
            for x in tins:
                node_tick(F, I, S, x, 1, t, t + span, k, span / k, True)
                t += span
        el = (time.thread_time() - c) / calls
        s.time = t
        tin[:] = tins[-1]
        return el

    def zero(_, calls):
        tin = s._tick.tin if hasattr(s, "_tick") else s._tick_in
        t = s.time
        c = time.thread_time()
        for _ in range(calls):
            node_tick(F, I, S, tin, 1, t, t, 0, 0.0, True)
        return (time.thread_time() - c) / calls

    def empty(_, calls):
        tin = s._tick.tin if hasattr(s, "_tick") else s._tick_in
        t = s.time
        c = time.thread_time()
        for _ in range(calls):
            _empty(F, I, S, tin, 1, t, t, 0, 0.0, True)
        return (time.thread_time() - c) / calls

    return s, cfg, dt, dict(tick=tick, kernel=kernel, zero=zero, empty=empty)


def main(argv=None):
    ap = tick_parser(__doc__.split("\n")[0])
    ap.add_argument("--baseline", default=None, help="another checkout, timed interleaved (bench_tick.load_baseline)")
    args = ap.parse_args(argv)

    trees = [("new", "tether_sim")]
    if args.baseline:
        from benchmarks.bench_tick import load_baseline

        load_baseline(args.baseline)
        trees.insert(0, ("base", "tether_sim_base"))
    ks = (1, 2, 3, 4)
    built = {label: _tree(pkg, args.params, args.ei, args.warm) for label, pkg in trees}
    parts = [(label, name, k) for label, _ in trees for name in ("tick", "kernel") for k in ks]
    parts += [(label, name, 0) for label, _ in trees for name in ("zero", "empty")]
    best = {p: np.inf for p in parts}
    for r in range(args.repeat + 2):  # two rounds to warm every path, then timed; trees alternate
        order = parts if r % 2 == 0 else parts[::-1]
        for label, name, k in order:
            v = built[label][3][name](k, args.calls)
            if r >= 2:
                best[label, name, k] = min(best[label, name, k], v)
    s, cfg, dt, _ = built["new"]
    print(f"{args.params}: N = {s.N}, P = {s.P}, EI = {cfg.cable.EI:g}, substep {dt * 1e6:.2f} us, "
          f"{math.ceil(0.02 / dt * (1 - 1e-12))} substeps per 50 Hz tick; us per call, min of {args.repeat} x {args.calls}"
          f", load {os.getloadavg()[0]:.1f}")
    for label, _ in trees:
        us = {key[1:]: 1e6 * v for key, v in best.items() if key[0] == label}
        fits = {}
        for name in ("tick", "kernel"):
            y = np.array([us[name, k] for k in ks])
            slope, icpt = np.polyfit(np.array(ks, float), y, 1)
            fits[name] = icpt
            print(f"  {label:4s} {name:7s} k = 1..4: " + " ".join(f"{v:7.3f}" for v in y) +
                  f"   fixed (intercept) {icpt:6.3f}, per substep {slope:6.3f}")
        print(f"  {label:4s} solver.tick's Python (tick - kernel intercepts)  {fits['tick'] - fits['kernel']:6.3f}")
        print(f"  {label:4s} node_tick with 0 substeps                        {us['zero', 0]:6.3f}")
        print(f"  {label:4s} empty kernel, same signature (the call)          {us['empty', 0]:6.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
