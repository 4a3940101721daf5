"""ROPOS tether with the hybrid solver: ship-tension amplitude vs the implicit time step.

    PYTHONPATH=. python benchmarks/ropos_hybrid.py config/ropos_L1730.yaml --frequency 0.1 --steps 0.05 0.1 0.2

Fairlead on the circular orbit of the config (a = 2 m) at the given frequency, one command per
implicit step through set_end_motion (as the node does when it ticks at 1/dt), static start, the last two periods evaluated.
"""

import argparse
import time
from dataclasses import replace

import numpy as np

from tether_sim.io.params import load_config
from tether_sim.physics.motion import build_motion
from tether_sim.solvers.hybrid.solver import HybridRodCatenarySolver


def run(cfg, duration, command_dt=0.05):
    solver = HybridRodCatenarySolver(cfg)
    motion = build_motion(cfg.motion, np.asarray(cfg.ship_end.position, dtype=float))
    t = 0.0
    times, tension = [], []
    c0 = time.process_time()
    while t < duration - 1e-9:
        t += command_dt
        p, v, _ = motion.at(t)
        solver.set_end_motion("ship", p, v)
        solver.advance_to(t)
        tt, a, _ = solver.drain_end_tensions()
        times.extend(tt)
        tension.extend(a)
    return np.array(times), np.array(tension), time.process_time() - c0, solver


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("config")
    ap.add_argument("--frequency", type=float, default=0.1)
    ap.add_argument("--segments", type=int, default=40)
    ap.add_argument("--periods", type=float, default=6.0)
    ap.add_argument("--zoning", default="adaptive")
    ap.add_argument("--steps", type=float, nargs="+", default=[0.05])
    args = ap.parse_args()
    base = load_config(args.config)
    period = 1.0 / args.frequency
    for dt in args.steps:
        cfg = replace(base, solver="hybrid", motion=replace(base.motion, frequency=args.frequency),
                      hybrid=replace(base.hybrid, time_step=dt, n_segments=args.segments, zoning=args.zoning,
                                     static_relax_time=20.0),
                      initial=replace(base.initial, kind="static"))
        t, T, cpu, solver = run(cfg, args.periods * period, command_dt=dt)  # one implicit step per command
        last = t > t[-1] - 2 * period
        amp = 0.5 * (T[last].max() - T[last].min())
        print(f"dt {dt:g} s: ship tension mean {T[last].mean():.1f} N, amplitude {amp:.1f} N, max {T.max():.1f} N, "
              f"min {T.min():.1f} N; cpu {cpu:.1f} s for {t[-1]:.0f} s; Newton {solver.stats}", flush=True)


if __name__ == "__main__":
    main()
