"""Thread-CPU cost of one DG substep (compiled dg_advance), of state() and end_forces().

ROPOS case (cage body, L = 1730 m by default, N = 20, P = 4), warmed to t = 6 s (taut/slack mix),
then the compiled tick (``tick.dg_tick``, via ``_run``) runs blocks of substeps from the same snapshot; best of
``--repeat`` blocks (the machine is shared: the minimum is the robust figure).

The outputs are timed as right after an advance (their shared evaluation not cached yet).

Usage: PYTHONPATH=. python benchmarks/bench_dg_kernel.py [--length 1730] [--alpha 0 1] [--steps 500]
"""

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks import ropos_case as rc  # noqa: E402
from tether_sim.solvers.factory import build_solver  # noqa: E402


def warmed_solver(length, alpha, t_warm=6.0):
    sol = build_solver(rc.ropos_config(length, alpha=alpha))
    for k in range(int(t_warm * 50)):
        t1 = (k + 1) / 50.0
        sol.set_end_motion("ship", *rc.fairlead_motion(t1))
        sol.advance_to(t1)
    return sol


def best_of(fn, repeat):
    best = np.inf
    for _ in range(repeat):
        c = time.thread_time()
        fn()
        best = min(best, time.thread_time() - c)
    return best


def substep_cost(sol, steps, repeat):
    """us per substep of the compiled loop (no Python per substep)."""
    snap = sol.snapshot()
    dt = sol._substep()
    t1 = sol.time + steps * dt
    target = rc.fairlead_motion(t1)

    def block():  # one compiled call (tick.dg_tick) of `steps` substeps
        sol.restore(snap)
        sol.set_end_motion("ship", *target)
        sol._run(steps, dt, t1)

    cost = best_of(block, repeat) / steps
    sol.restore(snap)
    return 1e6 * cost


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--length", type=float, default=1730.0)
    ap.add_argument("--alpha", type=float, nargs="+", default=[0.0, 1.0])
    ap.add_argument("--steps", type=int, default=500)
    ap.add_argument("--repeat", type=int, default=15)
    args = ap.parse_args(argv)
    print(f"bench_dg_kernel L={args.length:.0f} m N=20 P=4 cage=body, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, "
          f"load {os.getloadavg()[0]:.1f}")
    for alpha in args.alpha:
        sol = warmed_solver(args.length, alpha)
        us = substep_cost(sol, args.steps, args.repeat)
        def fresh(fn):  # as after an advance: the output evaluation is not cached yet
            def run():
                for _ in range(20):
                    sol._outputs_valid = False
                    fn()
            return 1e6 * best_of(run, args.repeat) / 20
        st = fresh(sol.state)
        ef = fresh(sol.end_forces)
        outs = fresh(lambda: (sol.state(), sol.end_forces(), sol.body_state("vehicle")))

        half = 0.5 * sol._substep()

        def tick():  # one substep per advance_to, as a node at a tick rate above 1 / dt
            for k in range(20):
                t1 = sol.time + half
                sol.set_end_motion("ship", *rc.fairlead_motion(t1))
                sol.advance_to(t1)
                sol.drain_end_tensions()
        snap = sol.snapshot()
        tk = 1e6 * best_of(tick, args.repeat) / 20
        sol.restore(snap)
        mo = 1e6 * best_of(lambda: [rc.fairlead_motion(sol.time) for _ in range(20)], args.repeat) / 20
        print(f"  alpha={alpha:g}: substep {us:6.1f} us | state() {st:6.1f} us | end_forces() {ef:6.1f} us | "
              f"state+end_forces+body_state {outs:6.1f} us | Python per advance_to (set_end_motion + "
              f"advance_to of one substep + drain, minus the substep) {tk - mo - us:6.1f} us | dt {sol._substep():.3g} s",
              flush=True)


if __name__ == "__main__":
    main()
