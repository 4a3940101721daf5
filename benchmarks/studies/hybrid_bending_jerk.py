"""A slack line with bending jerked taut on the hybrid solver, per zoning (docs/hybrid_solver.md "Zoning").

The TMS file's excursion tether (30 m, EA 2 MN, 1.59 kg/m, 1000 kg/m^3, 45 mm: buoyant) with
EI = EA d^2 / 16 = 253 N m^2 (PE2020's solid-section rule), from a driven end heaving ``--heave`` m at
2 rad/s to a fixed end 20 m off and 15 m below; commands at 50 Hz. Prints per zoning the largest end
tensions, the Newton statistics and the largest miss of the line's integrated shape at the fixed end.

Usage: PYTHONPATH=. python benchmarks/studies/hybrid_bending_jerk.py [--zoning adaptive all_rod all_catenary]
       [--duration 3] [--segments 30] [--dt 0.005] [--EI 253.125] [--heave 1.0]
"""

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from tether_sim.config import SimConfig  # noqa: E402
from tether_sim.errors import SolverDivergedError  # noqa: E402
from tether_sim.physics.boundary import EndCondition  # noqa: E402
from tether_sim.physics.cable import CableProperties  # noqa: E402
from tether_sim.physics.environment import Environment  # noqa: E402
from tether_sim.solvers.config import HybridOptions, InitialState  # noqa: E402
from tether_sim.solvers.hybrid.solver import HybridRodCatenarySolver  # noqa: E402

FIXED = (20.0, 0.0, -15.0)


def run(zoning, duration, segments, dt, EI, heave):
    cab = CableProperties(length=30.0, EA=2e6, gamma0=1.59, density=1000.0, diameter=0.045, EI=EI, damping=2000.0,
                          material="bilinear", Cdn=1.2, Cdt=0.02, Cmn=1.0, Cmt=0.0)
    cfg = SimConfig(solver="hybrid", cable=cab, environment=Environment(g=9.81, fluid_density=1025.0),
                    ship_end=EndCondition(kind="prescribed", position=(0.0, 0.0, 0.0)),
                    vehicle_end=EndCondition(kind="fixed", position=FIXED),
                    hybrid=HybridOptions(n_segments=segments, time_step=dt, zoning=zoning),
                    initial=InitialState(kind="static"))
    c0 = time.process_time()
    miss, error, k = 0.0, "", 0
    try:
        s = HybridRodCatenarySolver(cfg)
    except SolverDivergedError as exc:  # in the static relaxation
        return dict(ship=np.nan, vehicle=np.nan, stats={"rezonings": 0, "halvings": 0, "newton_iterations": 0,
                                                        "steps": 0}, miss=np.nan, error=f"start: {exc}",
                    cpu=time.process_time() - c0, reached=0.0)
    try:
        while s.time < duration - 1e-9:
            k += 1
            t = 0.02 * k
            s.set_end_motion("ship", np.array([0.0, 0.0, heave * np.sin(2.0 * t)]),
                             np.array([0.0, 0.0, 2.0 * heave * np.cos(2.0 * t)]))
            s.advance_to(t)
            miss = max(miss, float(np.linalg.norm(s.positions[-1] - np.asarray(FIXED))))
    except SolverDivergedError as exc:
        error = str(exc)
    _, a, b = s.drain_end_tensions()
    return dict(ship=a.max(), vehicle=b.max(), stats=dict(s.stats), miss=miss, error=error,
                cpu=time.process_time() - c0, reached=s.time)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--zoning", nargs="+", default=["adaptive", "all_rod", "all_catenary"])
    ap.add_argument("--duration", type=float, default=3.0)
    ap.add_argument("--segments", type=int, default=30)
    ap.add_argument("--dt", type=float, default=0.005)
    ap.add_argument("--EI", type=float, default=253.125)
    ap.add_argument("--heave", type=float, default=1.0)
    a = ap.parse_args(argv)
    for z in a.zoning:
        r = run(z, a.duration, a.segments, a.dt, a.EI, a.heave)
        st = r["stats"]
        print(f"{z}: reached {r['reached']:.4g} s{' FAILED: ' + r['error'] if r['error'] else ''}; largest end tension "
              f"{r['ship']:.1f} / {r['vehicle']:.1f} N; shape miss at the fixed end up to {1e3 * r['miss']:.1f} mm; "
              f"re-zonings {st['rezonings']}, halvings {st['halvings']}, Newton {st['newton_iterations']} in "
              f"{st['steps']} steps; {r['cpu']:.1f} CPU s")


if __name__ == "__main__":
    main()
