"""Fixed per-tick work of the DG solver's node tick: what a tick costs beyond its substeps, and its parts.

One solver of a live file (default config/ropos_L1730.yaml), ticked at 50 Hz to t = --warm s with the
fairlead on a 0.5 m circle, then, interleaved block by block in one process (thread CPU, min over
--repeat blocks of --calls calls each):

- ``solver.tick`` over intervals of k = 1..4 substeps of the rule's step: a least-squares line through
  the four costs per call; its intercept is the fixed per-tick work (Python, the call, the kernel's own
  set-up, the output evaluation beyond the first stage it saves, the drain), its slope one substep;
- the kernel ``tick.node_tick`` called directly with the same arguments (intercept and slope likewise):
  solver.tick's Python is the difference of the intercepts;
- ``node_tick`` with 0 substeps (t1 = t0: targets, checks, output evaluation, drain, no substep);
- an empty compiled function with node_tick's signature: the cost of the call itself (dispatch).

Usage: PYTHONPATH=. python benchmarks/probes/tick_fixed_work.py [--params config/ropos_L1730.yaml]
       [--ei 2620] [--calls 200] [--repeat 15]
"""

import argparse
import math
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


def _motion(t):
    p = 0.5 * np.array((math.cos(t) - 1.0, math.sin(t), 0.0))
    v = 0.5 * np.array((-math.sin(t), math.cos(t), 0.0))
    return p, v


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--params", default=str(ROOT / "config" / "ropos_L1730.yaml"))
    ap.add_argument("--ei", type=float, default=None, help="cable.EI override (N m^2)")
    ap.add_argument("--warm", type=float, default=2.0)
    ap.add_argument("--calls", type=int, default=200)
    ap.add_argument("--repeat", type=int, default=15)
    args = ap.parse_args(argv)

    from tether_sim.io.params import load_config
    from tether_sim.solvers.dg import stepping
    from tether_sim.solvers.dg.tick import node_tick
    from tether_sim.solvers.factory import build_solver

    overrides = {"cable.EI": args.ei} if args.ei is not None else None
    cfg = load_config(Path(args.params), overrides=overrides)
    s = build_solver(cfg)
    t = s.time
    while t < args.warm - 1e-9:
        t += 0.02
        s.tick(t, ship=_motion(t))
    dt = s._substep()
    ws, tin = s.ws, s._tick_in
    F, I, S = ws.F, ws.I, ws.spec
    ks = (1, 2, 3, 4)

    def block_tick(k):
        t = s.time
        span = k * dt * (1.0 - 1e-9)
        motion = _motion(t)
        c = time.thread_time()
        for _ in range(args.calls):
            t += span
            s.tick(t, ship=motion)
        return (time.thread_time() - c) / args.calls

    def block_kernel(k):
        t = s.time
        span = k * dt * (1.0 - 1e-9)
        stepping.tick_inputs(tin, _motion(t), None, s.ends, s.kinds)
        c = time.thread_time()
        for _ in range(args.calls):
            node_tick(F, I, S, tin, 1, t, t + span, k, span / k, True)
            t += span
        el = (time.thread_time() - c) / args.calls
        s.time = t
        return el

    def block_zero(_):
        t = s.time
        c = time.thread_time()
        for _ in range(args.calls):
            node_tick(F, I, S, tin, 1, t, t, 0, 0.0, True)
        return (time.thread_time() - c) / args.calls

    def block_empty(_):
        t = s.time
        c = time.thread_time()
        for _ in range(args.calls):
            _empty(F, I, S, tin, 1, t, t, 0, 0.0, True)
        return (time.thread_time() - c) / args.calls

    parts = [("tick", k, block_tick) for k in ks] + [("kernel", k, block_kernel) for k in ks]
    parts += [("zero", 0, block_zero), ("empty", 0, block_empty)]
    best = {(n, k): np.inf for n, k, _ in parts}
    for _ in range(2):  # warm every path
        for n, k, f in parts:
            f(k)
    for _ in range(args.repeat):
        for n, k, f in parts:
            best[n, k] = min(best[n, k], f(k))
    us = {key: 1e6 * v for key, v in best.items()}
    print(f"{args.params}: N = {s.N}, P = {s.P}, EI = {cfg.cable.EI:g}, substep {dt * 1e6:.2f} us, "
          f"{round(0.02 / dt * (1 - 1e-12) + 0.5)} substeps per 50 Hz tick (ceil); us per call, min of {args.repeat} x {args.calls}")
    fits = {}
    for name in ("tick", "kernel"):
        y = np.array([us[name, k] for k in ks])
        slope, icpt = np.polyfit(np.array(ks, float), y, 1)
        fits[name] = (icpt, slope)
        print(f"  {name:7s} k = 1..4: " + " ".join(f"{v:7.3f}" for v in y) +
              f"   fixed (intercept) {icpt:6.3f}, per substep {slope:6.3f}")
    print(f"  solver.tick's Python (tick - kernel intercepts)  {fits['tick'][0] - fits['kernel'][0]:6.3f}")
    print(f"  node_tick with 0 substeps                        {us['zero', 0]:6.3f}")
    print(f"  empty kernel, same signature (the call)          {us['empty', 0]:6.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
