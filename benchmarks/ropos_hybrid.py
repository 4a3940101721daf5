"""ROPOS tether with the hybrid solver: ship-tension amplitude vs the implicit time step.

    PYTHONPATH=. python benchmarks/ropos_hybrid.py config/ropos_L1730.yaml --frequency 0.1 --steps 0.05 0.1 0.2

Fairlead on the circular orbit of the config (a = 2 m) at the given frequency, one command per
implicit step through set_end_motion (as the node does when it ticks at 1/dt), static start, the last two periods evaluated.
"""

import argparse
from dataclasses import replace

import numpy as np

from benchmarks import drive
from tether_sim.io.params import load_config
from tether_sim.physics.motion import build_motion


def run(cfg, duration, command_dt=0.05):
    """Hybrid solver driven with one command per implicit step (benchmarks/drive.py)."""
    motion = build_motion(cfg.motion, np.asarray(cfg.ship_end.position, dtype=float))
    res = drive.run(replace(cfg, solver="hybrid"), duration, rate=1.0 / command_dt,
                    motion=lambda t: motion.at(t)[:2])
    return res["t"], res["ship"], res["cpu"], res["solver"]


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
