"""Cost of the TMS network file (config/ropos_tms.yaml), driven as the node drives it.

The network driver (tether_sim/ros/network_driver.py, no ROS) ticks at ``node.output_rate``; the
ship heaves as in the node soak (benchmarks/soak_node.py: 0.5 m at 0.1 Hz; ``--heave 0`` holds it)
and the vehicle is held at its configured position. Prints per file the start-up time (statics of
every line, settling), the CPU seconds per simulated second in all and per line (each line's own
tick: its compiled call, winch controller included) with its substeps per tick, the rest (bodies,
points, snap detection: the network's and the driver's Python) and the real time per CPU second.
Several files (``--params A.yaml B.yaml``) are measured one after the other in one process, each
after a warm-up of the same length, so their ratios are taken at one load.

Usage: PYTHONPATH=. python benchmarks/bench_tms.py [--duration 10] [--params config/ropos_tms.yaml ...]
"""

import argparse
import math
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from tether_sim.network.params import load_network_files  # noqa: E402
from tether_sim.ros.network_driver import NetworkDriver  # noqa: E402

HEAVE_FREQUENCY = 0.1  # Hz, as benchmarks/soak_node.heave


class Heave:
    """A driven point's source: its configured position plus a vertical heave a sin(2 pi f t)."""

    has_data = True

    def __init__(self, position, amplitude):
        self.p, self.a, self.w = np.asarray(position, float), float(amplitude), 2 * math.pi * HEAVE_FREQUENCY

    def attachment_at(self, t):
        return (self.p + np.array([0.0, 0.0, self.a * math.sin(self.w * t)]),
                np.array([0.0, 0.0, self.a * self.w * math.cos(self.w * t)]))


def measure(params, duration, heave):
    spec, cfg = load_network_files([params])
    sources = {n: Heave(p.position, heave if n == "ship" else 0.0)
               for n, p in spec.points.items() if p.kind == "prescribed"}
    t0 = time.perf_counter()
    d = NetworkDriver(spec, cfg.node, sources=sources)
    d.start(0.0)
    start = time.perf_counter() - t0
    cost = {n: [0.0, 0] for n in d.net.lines}
    for name, line in d.net.lines.items():
        inner_tick = line.tick

        def timed(*a, _tick=inner_tick, _acc=cost[name], **k):
            c = time.process_time()
            out = _tick(*a, **k)
            _acc[0] += time.process_time() - c
            _acc[1] += out.substeps
            return out
        line.tick = timed
    now, period = 0.0, 1.0 / cfg.node.output_rate
    ticks = int(round(duration / period))
    for _ in range(ticks):  # warm-up (the first ticks after the settling) outside the timing
        now += period
        d.tick(now)
    for acc in cost.values():
        acc[:] = [0.0, 0]
    c0, w0 = time.process_time(), time.perf_counter()
    for _ in range(ticks):
        now += period
        r = d.tick(now)
        if r.error:
            raise SystemExit(f"{params}: failed: {r.error}")
    cpu, wall = time.process_time() - c0, time.perf_counter() - w0
    sim = ticks * period
    lines = {n: (c / sim, k / ticks) for n, (c, k) in cost.items()}
    rest = (cpu - sum(c for c, _ in cost.values())) / sim
    return dict(start=start, cpu=cpu / sim, wall=wall / sim, lines=lines, rest=rest, settled=d.settled,
                tensions={n: [d.net.end_load(n, e)[1] for e in ("ship", "vehicle")] for n in d.net.lines})


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=10.0, help="simulated s timed (after as long a warm-up)")
    ap.add_argument("--heave", type=float, default=0.5, help="ship heave amplitude, m (0: held)")
    ap.add_argument("--params", nargs="+",
                    default=[str(Path(__file__).resolve().parents[1] / "config" / "ropos_tms.yaml")])
    args = ap.parse_args(argv)
    rows = [(p, measure(p, args.duration, args.heave)) for p in args.params]
    print(f"{args.duration:g} s simulated per file after a warm-up of as long, ship heave {args.heave:g} m at "
          f"{HEAVE_FREQUENCY:g} Hz; load {os.getloadavg()[0]:.1f}")
    first = rows[0][1]["cpu"]
    for p, r in rows:
        per_line = ", ".join(f"{n} {c:.4f} ({k:.0f} substeps/tick)" for n, (c, k) in r["lines"].items())
        print(f"{p}: start-up {r['start']:.1f} s; {r['cpu']:.4f} CPU s per simulated s (x{1 / r['cpu']:.2f} "
              f"real time per CPU s; {r['cpu'] / first:.3f} of the first file): {per_line}, rest {r['rest']:.4f}; "
              f"{r['wall']:.3f} wall s per simulated s")
        print("   end tensions: " + "; ".join(f"{n} {a:.1f} / {b:.1f} N" for n, (a, b) in r["tensions"].items()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
