"""Speed of a line network: the ship, 200 m ROPOS tether, cage, 30 m excursion tether, vehicle case of
``network_vs_moordyn.py`` at the node's 50 Hz tick (coupling step = tick), CPU seconds per simulated
second, split into the lines' ticks and the rest (bodies, points, Python).

Usage: PYTHONPATH=. python benchmarks/bench_network.py [--duration 3] [--excursion 10:4 6:3]
       [--damping explicit implicit]
"""

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks import ropos_case as rc  # noqa: E402
from benchmarks.studies.network_vs_moordyn import network_tree, vehicle_position  # noqa: E402
from tether_sim.network.solver import NetworkSolver  # noqa: E402
from tether_sim.network.spec import parse_network  # noqa: E402

TICK = 0.02


def measure(exc, damping, duration):
    tree = network_tree("dg", TICK, exc_dg=exc)
    tree["lines"]["excursion"]["dg"]["damping"] = damping
    net = NetworkSolver(parse_network(tree))
    cost = {n: 0.0 for n in net.lines}
    for n, s in net.lines.items():
        inner = s.tick

        def timed(*a, _f=inner, _n=n, **k):
            c = time.process_time()
            out = _f(*a, **k)
            cost[_n] += time.process_time() - c
            return out

        s.tick = timed
    net.tick(TICK)  # first tick outside the timing (first calls of the kernels)
    veh = vehicle_position()
    cost = {n: 0.0 for n in net.lines}
    c0 = time.process_time()
    n = int(round(duration / TICK))
    for k in range(2, n + 2):
        t = TICK * k
        net.set_point_motion("ship", *rc.fairlead_motion(t))
        net.set_point_motion("vehicle", veh, np.zeros(3))
        net.tick(t)
    cpu = time.process_time() - c0
    dg = net.line("tether").config.dg
    print(f"excursion DG N={exc[0]} P={exc[1]} damping {damping}: x{duration / cpu:.2f} real time per CPU s; "
          f"CPU s per simulated s: " + ", ".join(f"{k} {c / duration:.3f}" for k, c in cost.items())
          + f", rest {(cpu - sum(cost.values())) / duration:.3f} (tether N={dg.n_elements} P={dg.order} cfl {dg.cfl})",
          flush=True)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=3.0)
    ap.add_argument("--excursion", nargs="+", default=["10:4", "6:3"])
    ap.add_argument("--damping", nargs="+", default=["explicit", "implicit"])
    args = ap.parse_args(argv)
    print(f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load {os.getloadavg()[0]:.1f}, tick {TICK} s, "
          f"{args.duration} s from t = {TICK} s of the ROPOS orbit")
    for e in args.excursion:
        for d in args.damping:
            measure(tuple(int(x) for x in e.split(":")), d, args.duration)


if __name__ == "__main__":
    main()
