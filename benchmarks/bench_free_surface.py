"""Thread-CPU cost of one DG substep with the free surface (and waves, when the wave module is there).

ROPOS case (cage body, N = 20 and the live N = 2, P = 4, implicit damping; the fairlead orbits 2 m around the still-water level, so with
the surface on the top of the cable goes in and out of the water), warmed to t = 6 s, then blocks of
compiled substeps from the same snapshot (bench_dg_kernel.substep_cost; best of ``--repeat``).
Variants, all in one process: the whole cable submerged (vectorised step 5, soa.py), a weak current
(the element-wise step 5 with positions, what the free surface also needs), the free surface.

Usage: PYTHONPATH=. python benchmarks/bench_free_surface.py [--length 200] [--steps 500] [--repeat 15]
"""

import argparse
import dataclasses as dc
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks import ropos_case as rc  # noqa: E402
from benchmarks.bench_dg_kernel import substep_cost  # noqa: E402
from tether_sim.solvers.factory import build_solver  # noqa: E402


def variants(length, n_elements):
    base = rc.ropos_config(length, alpha=0.0, damping="implicit", n_elements=n_elements)  # the live default (dg.damping)
    env = base.environment
    out = {
        "submerged (SoA step 5 if N >= 7)": base,
        "current 0.01 m/s (element-wise step 5)": dc.replace(base, environment=dc.replace(
            env, current_z=(-1000.0, 0.0), current_x=(0.01, 0.01), current_y=(0.0, 0.0))),
        "free surface": dc.replace(base, environment=dc.replace(env, free_surface=True)),
    }
    return out


def warmed(config, t_warm=6.0):
    sol = build_solver(config)
    for k in range(int(t_warm * 50)):
        t1 = (k + 1) / 50.0
        sol.set_end_motion("ship", *rc.fairlead_motion(t1))
        sol.advance_to(t1)
    return sol


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--length", type=float, default=200.0)
    ap.add_argument("--elements", type=int, nargs="+", default=[20, 2], help="N (2: the live L = 200 m mesh)")
    ap.add_argument("--steps", type=int, default=500)
    ap.add_argument("--repeat", type=int, default=15)
    args = ap.parse_args(argv)
    print(f"bench_free_surface L={args.length:.0f} m P=4 cage=body dg.damping=implicit, "
          f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load {os.getloadavg()[0]:.1f}")
    for n in args.elements:
        ref = None
        for name, cfg in variants(args.length, n).items():
            sol = warmed(cfg)
            us = substep_cost(sol, args.steps, args.repeat)
            ref = us if ref is None else ref
            print(f"  N={n:2d} {name:42s} substep {us:6.1f} us  ({us / ref:.2f} x submerged)  dt {sol._substep():.3g} s"
                  f" -> {us / sol._substep() * 1e-6:.3f} s CPU per s simulated", flush=True)


if __name__ == "__main__":
    main()
