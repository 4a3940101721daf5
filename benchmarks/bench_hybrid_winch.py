"""Cost of the hybrid solver's winch: segments added and removed at the winch end.

A cable hanging in water from a fixed sheave with a 500 N load at its lower end (the default cable
of tether_sim.physics.cable, L = 200 m, hybrid defaults: 100 segments, h0 = 2 m, dt = 0.01 s), fed
at 50 Hz (advance_to per tick). Four runs per repeat, interleaved, thread CPU time of the ticks
only (construction and the static relaxation excluded), best of --repeats:

- fixed: winch.enabled false (the solver's fixed-length path);
- idle: winch enabled, rate 0 (element lengths reset every step, no split or merge);
- pay out / haul in: +-V m/s (ramped over the first second at V m/s^2), splits or merges every
  h0 / V seconds.

Prints the cost per simulated second, its ratio to the fixed-length run, the splits/merges and the
Newton iterations per step (paying out changes the dynamics the Newton solves see), and the load.

Usage: PYTHONPATH=. python benchmarks/bench_hybrid_winch.py [--length 200] [--duration 20] [--speed 1]
       [--repeats 3]
"""

import argparse
import os
import sys
import time
from dataclasses import replace
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from tether_sim.config import SimConfig  # noqa: E402
from tether_sim.physics.boundary import EndCondition  # noqa: E402
from tether_sim.physics.winch import WinchConfig  # noqa: E402
from tether_sim.solvers.hybrid.solver import HybridRodCatenarySolver  # noqa: E402

RATE = 50.0  # ticks per second


def config(length, enabled):
    cfg = SimConfig(solver="hybrid", ship_end=EndCondition(kind="fixed", position=(0.0, 0.0, 0.0)),
                    vehicle_end=EndCondition(kind="force", position=(0.0, 0.0, -length), force=(0.0, 0.0, -500.0)),
                    winch=WinchConfig(enabled=enabled))
    return replace(cfg, cable=replace(cfg.cable, length=length))


def run(length, duration, speed):
    """Thread CPU seconds of the ticks, and the solver after them (speed None: no winch)."""
    s = HybridRodCatenarySolver(config(length, speed is not None))
    n = int(round(duration * RATE))
    t0 = time.thread_time()
    for k in range(1, n + 1):
        t = k / RATE
        if speed:
            s.set_pay_out_rate(speed * min(t, 1.0))
        s.advance_to(t)
        s.drain_end_tensions()
    return time.thread_time() - t0, s


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--length", type=float, default=200.0)
    ap.add_argument("--duration", type=float, default=20.0)
    ap.add_argument("--speed", type=float, default=1.0)
    ap.add_argument("--repeats", type=int, default=3)
    a = ap.parse_args(argv)
    cases = {"fixed": None, "idle": 0.0, "pay out": a.speed, "haul in": -a.speed}
    best, solvers = {}, {}
    run(a.length, 0.1, a.speed)  # warm-up: numba caches loaded, first calls made
    for _ in range(a.repeats):
        for name, speed in cases.items():
            cpu, s = run(a.length, a.duration, speed)
            best[name] = min(best.get(name, float("inf")), cpu)
            solvers[name] = s
    print(f"hybrid winch: L0 = {a.length:g} m, {a.duration:g} s simulated at {RATE:g} Hz ticks, speed {a.speed:g} m/s, "
          f"best of {a.repeats}; load {os.getloadavg()[0]:.2f}")
    print("| run | ms CPU per simulated s | x fixed | us per step | L end (m) | splits | merges | Newton it./step |")
    print("|---|---|---|---|---|---|---|---|")
    for name in cases:
        s = solvers[name]
        st = s.stats
        print(f"| {name} | {1e3 * best[name] / a.duration:.1f} | {best[name] / best['fixed']:.3f} | "
              f"{1e6 * best[name] / max(st['steps'], 1):.0f} | "
              f"{s.unstretched_length:.2f} | {st.get('winch_splits', 0)} | {st.get('winch_merges', 0)} | "
              f"{st['newton_iterations'] / max(st['steps'], 1):.2f} |")


if __name__ == "__main__":
    main()
