"""Cost of the TMS network file (config/ropos_tms.yaml) at rest, driven as the node drives it.

The network driver (tether_sim/ros/network_driver.py, no ROS) ticks at ``node.output_rate`` with
the ship and vehicle held; prints the start-up time (statics of both lines, settling), the CPU and
wall seconds per simulated second and the end tensions.

Usage: PYTHONPATH=. python benchmarks/bench_tms.py [--duration 10] [--params config/ropos_tms.yaml]
"""

import argparse
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from tether_sim.network.params import load_network_files  # noqa: E402
from tether_sim.ros.network_driver import NetworkDriver  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=10.0)
    ap.add_argument("--params", default=str(Path(__file__).resolve().parents[1] / "config" / "ropos_tms.yaml"))
    args = ap.parse_args(argv)
    spec, cfg = load_network_files([args.params])
    t0 = time.perf_counter()
    d = NetworkDriver(spec, cfg.node)
    d.start(0.0)
    start = time.perf_counter() - t0
    now, period = 0.0, 1.0 / cfg.node.output_rate
    d.tick(now + period)  # first tick outside the timing
    now += period
    c0, w0 = time.process_time(), time.perf_counter()
    while now < args.duration:
        now += period
        r = d.tick(now)
        if r.error:
            print("failed:", r.error)
            return 1
    cpu, wall = time.process_time() - c0, time.perf_counter() - w0
    sim = now - period
    print(f"start-up {start:.1f} s (settled lines: {', '.join(d.settled) or 'none'})")
    print(f"{sim:.2f} s simulated: {cpu / sim:.3f} CPU s and {wall / sim:.3f} wall s per simulated s "
          f"(x{sim / cpu:.2f} real time per CPU s); load {os.getloadavg()[0]:.1f}")
    for line in d.net.lines:
        t = [d.net.end_load(line, e)[1] for e in ("ship", "vehicle")]
        print(f"{line}: end tensions {t[0]:.1f} / {t[1]:.1f} N")
    return 0


if __name__ == "__main__":
    sys.exit(main())
