"""The coupling of a line network against the monolithic body: the ROPOS tether (200 m) and cage as the
single-line DG solver (cage integrated inside its Runge-Kutta stages, ``vehicle_end.kind: body``) and
as a one-line network (cage stepped by the network's kick-drift-kick at the coupling step), on the
ROPOS fairlead orbit; prints the first snap peak at the ship and at the cage of each.

Usage: PYTHONPATH=. python benchmarks/studies/network_vs_single_line.py [--couplings 0.02 0.005 0.00125]
       [--mesh 2 4] [--cfl 0.8] [--duration 10]
"""

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from benchmarks import ropos_case as rc  # noqa: E402
from benchmarks.studies.network_vs_moordyn import network_tree  # noqa: E402
from tether_sim.network.solver import NetworkSolver  # noqa: E402
from tether_sim.network.spec import parse_network  # noqa: E402
from tether_sim.solvers.factory import build_solver  # noqa: E402


def peaks(ts, Ts, Tc):
    ts, Ts, Tc = map(np.concatenate, (ts, Ts, Tc))
    return rc.snap_metrics(ts, Ts)["first_peak"], rc.snap_metrics(ts, Tc)["first_peak"]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--couplings", type=float, nargs="+", default=[0.02, 0.005, 0.00125])
    ap.add_argument("--mesh", type=int, nargs=2, default=[2, 4])
    ap.add_argument("--cfl", type=float, default=0.8)
    ap.add_argument("--duration", type=float, default=10.0)
    args = ap.parse_args(argv)
    (N, P), dur = args.mesh, args.duration
    print(f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load {os.getloadavg()[0]:.1f}; "
          f"L = 200 m, DG N = {N}, P = {P}, cfl {args.cfl}, {dur} s")
    s = build_solver(rc.ropos_config(200.0, n_elements=N, order=P, cfl=args.cfl))
    ts, Ts, Tc = [], [], []
    for k in range(1, int(round(dur / 0.005)) + 1):
        t = 0.005 * k
        o = s.tick(t, ship=rc.fairlead_motion(t))
        ts.append(o.times.copy())
        Ts.append(o.ship_tension.copy())
        Tc.append(o.vehicle_tension.copy())
    ref = peaks(ts, Ts, Tc)
    print(f"single line (body in the RK stages): ship {ref[0] / 1e3:.3f} kN, cage {ref[1] / 1e3:.3f} kN", flush=True)
    for coupling in args.couplings:
        tree = network_tree("dg", coupling, tether_mesh=(N, P))
        tree["lines"]["tether"]["dg"]["cfl"] = args.cfl
        del tree["lines"]["excursion"], tree["points"]["vehicle"]
        net = NetworkSolver(parse_network(tree))
        tick = max(coupling, 0.005)
        ts, Ts, Tc = [], [], []
        for k in range(1, int(round(dur / tick)) + 1):
            t = tick * k
            net.set_point_motion("ship", *rc.fairlead_motion(t))
            o = net.tick(t)["tether"]["samples"]
            ts.append(o[0])
            Ts.append(o[1])
            Tc.append(o[2])
        got = peaks(ts, Ts, Tc)
        print(f"network, coupling step {coupling:g} s: ship {got[0] / 1e3:.3f} kN ({100 * (got[0] / ref[0] - 1):+.3f} %), "
              f"cage {got[1] / 1e3:.3f} kN ({100 * (got[1] / ref[1] - 1):+.3f} %)", flush=True)


if __name__ == "__main__":
    main()
