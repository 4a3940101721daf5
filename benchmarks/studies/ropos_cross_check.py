"""ROPOS cross-check hybrid vs DG (acceptance): ship-tension amplitude, L = 1730 m, circular
fairlead a = 2 m, f = 0.1 Hz (no slack). Both solvers through the TetherSolver interface only.

    PYTHONPATH=. python benchmarks/studies/ropos_cross_check.py config/ropos_L1730_paper.yaml --frequency 0.1
"""

import argparse
from dataclasses import replace

import numpy as np

from benchmarks import drive
from tether_sim.io.params import load_config
from tether_sim.physics.motion import build_motion


def run(cfg, duration, command_dt):
    """Ship-end tensions at every substep and the CPU time, commands every ``command_dt`` (benchmarks/drive.py)."""
    motion = build_motion(cfg.motion, np.asarray(cfg.ship_end.position, dtype=float))
    res = drive.run(cfg, duration, rate=1.0 / command_dt, motion=lambda t: motion.at(t)[:2])
    return res["t"], res["ship"], res["cpu"]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("config")
    ap.add_argument("--frequency", type=float, default=0.1)
    ap.add_argument("--periods", type=float, default=6.0)
    ap.add_argument("--hybrid-dt", type=float, default=0.05)
    ap.add_argument("--solvers", nargs="+", default=["hybrid", "dg"])
    ap.add_argument("--cage-as-force", action="store_true",
                    help="replace the cage body by its submerged weight as a point force (when a solver lacks bodies)")
    args = ap.parse_args()
    base = load_config(args.config)
    if args.cage_as_force:
        from tether_sim.physics.bodies import submerged_weight

        weight = submerged_weight(base.body, base.environment)
        base = replace(base, vehicle_end=replace(base.vehicle_end, kind="force", force=(0.0, 0.0, -weight)))
    base = replace(base, motion=replace(base.motion, frequency=args.frequency))
    period = 1.0 / args.frequency
    amps = {}
    for name in args.solvers:
        cfg = replace(base, solver=name, hybrid=replace(base.hybrid, time_step=args.hybrid_dt, n_segments=40,
                                                          zoning="all_catenary" if base.cable.EI == 0 else "adaptive"))
        t, T, cpu = run(cfg, args.periods * period, 0.05)
        last = t > t[-1] - 2 * period
        amps[name] = 0.5 * (T[last].max() - T[last].min())
        print(f"{name}: ship tension mean {T[last].mean():.1f} N, amplitude {amps[name]:.1f} N "
              f"(max {T[last].max():.1f}, min {T[last].min():.1f}); cpu {cpu:.1f} s for {t[-1]:.0f} s", flush=True)
        np.savez(f"/tmp/ropos_{name}_{args.frequency:g}.npz", t=t, T=T)
    if len(amps) == 2:
        a, b = amps["hybrid"], amps["dg"]
        print(f"amplitude hybrid/dg - 1 = {100 * (a / b - 1):+.2f} %")


if __name__ == "__main__":
    main()
