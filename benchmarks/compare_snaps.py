"""Snap events of a live file's offline run, this tree against another checkout or against this tree with other
parameters: a change that is not bit-identical (e.g. a solver's convergence path) must not move the physics.

Runs ``tether_sim.ros.offline.run_offline`` (no MCAP file) on each parameter file twice: with this tree's solver and
with ``--baseline``'s (a renamed copy, as bench_tick.load_baseline; the driver and snap detector are this tree's), or
with this tree's solver under ``--set key=value`` overrides. Prints every slack warning and snap event of both runs
side by side, the largest difference of snap time (s) and of peak tension (relative), and the largest difference
of the end tensions at every tick (N and relative to the largest). Exit code 1 when the events differ in number or
location, or a snap time differs by more than ``--time-tol`` or a peak by more than ``--peak-tol`` (relative).

Usage: PYTHONPATH=. .venv/bin/python benchmarks/compare_snaps.py --params config/ropos_L200_hybrid.yaml
           [--duration 60] [--baseline /path/to/checkout] [--first key=value ...] [--set key=value ...]
           [--time-tol 0.001] [--peak-tol 0.001]
"""

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


def _value(text):
    for cast in (int, float):
        try:
            return cast(text)
        except ValueError:
            pass
    return {"true": True, "false": False}.get(text.lower(), text)


def _run(params, duration, factory, overrides):
    from tether_sim.io.params import load_config
    from tether_sim.physics.snap import SnapEvent
    from tether_sim.ros import offline

    config = load_config(ROOT / params, overrides)
    tensions = []
    Driver = offline.SimulationDriver

    class Recording(Driver):  # the end tensions of every tick, as the node publishes them
        def tick(self, now):
            report = super().tick(now)
            f = self.solver.end_forces()
            tensions.append((now, f.ship_tension, f.vehicle_tension))
            return report

    offline.SimulationDriver = Recording
    try:
        cpu = time.process_time()
        out = offline.run_offline(config, None, duration=duration, progress=False, solver_factory=factory)
        cpu = time.process_time() - cpu
    finally:
        offline.SimulationDriver = Driver
    snaps = [e for e in out["events"] if isinstance(e, SnapEvent)]
    return snaps, out["slack_warnings"], np.array(tensions), cpu


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--params", nargs="+", default=["config/ropos_L200_hybrid.yaml", "config/ropos_L1730_hybrid.yaml"])
    ap.add_argument("--duration", type=float, default=60.0)
    ap.add_argument("--baseline", default=None)
    ap.add_argument("--set", nargs="*", default=[], help="key=value overrides of the second run")
    ap.add_argument("--first", nargs="*", default=[], help="key=value overrides of the first run (this tree)")
    ap.add_argument("--time-tol", type=float, default=1e-3)
    ap.add_argument("--peak-tol", type=float, default=1e-3)
    args = ap.parse_args(argv)
    from tether_sim.solvers.factory import build_solver

    if args.baseline:
        from benchmarks.bench_tick import load_baseline

        other, label = load_baseline(args.baseline)[0].build_solver, "baseline " + " ".join(args.set)
    else:
        other, label = build_solver, " ".join(args.set) or "the same"
    overrides, first = ({k: _value(v) for k, v in (item.split("=", 1) for item in items)}
                        for items in (args.set, args.first))
    print(f"compare_snaps {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, {args.duration:g} s, load "
          f"{os.getloadavg()[0]:.2f}; first run: this tree {' '.join(args.first)}; second run: {label}", flush=True)
    bad = False
    for params in args.params:
        a = _run(params, args.duration, build_solver, first)
        b = _run(params, args.duration, other, overrides)
        (sa, wa, ta, ca), (sb, wb, tb, cb) = a, b
        print(f"{Path(params).name}: this tree {len(sa)} snaps, {wa} slack warnings, CPU {ca:.1f} s; {label} "
              f"{len(sb)} snaps, {wb} slack warnings, CPU {cb:.1f} s")
        for x, y in zip(sa, sb):
            print(f"  {x.location:8s} t {x.time:9.4f} / {y.time:9.4f} s  peak {x.peak_tension:10.2f} / "
                  f"{y.peak_tension:10.2f} N  slack from {x.slack_start:8.4f} / {y.slack_start:8.4f} s")
        same = len(sa) == len(sb) and all(x.location == y.location for x, y in zip(sa, sb)) and wa == wb
        dt = max((abs(x.time - y.time) for x, y in zip(sa, sb)), default=0.0)
        dp = max((abs(x.peak_tension - y.peak_tension) / abs(y.peak_tension) for x, y in zip(sa, sb)), default=0.0)
        n = min(len(ta), len(tb))
        dT = float(np.abs(ta[:n, 1:] - tb[:n, 1:]).max()) if n else 0.0
        scale = float(np.abs(tb[:n, 1:]).max()) if n else 1.0
        print(f"  largest difference: snap time {dt:.3g} s, peak {dp:.3g} (relative); end tension at a tick "
              f"{dT:.3g} N ({dT / scale:.3g} of the largest, {scale:.6g} N) over {n} ticks")
        if not same or dt > args.time_tol or dp > args.peak_tol:
            bad = True
            print("  DIFFERENT: " + ("events differ in number or location" if not same else
                                     f"beyond {args.time_tol:g} s / {args.peak_tol:g}"))
    print(f"load {os.getloadavg()[0]:.2f}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
