"""The hybrid solver on a fixed-fixed, low-tension, stiff arc with bending.

Case: ROPOS tether properties with EA = 455 MN (10x ROPOS) and EI = 2620 N m^2, L = 325 m between a
ship end at (0, 0, -50) and a fixed end at (300, 0, -150) (chord 316.2 m): end tensions ~11 and ~9 kN,
EA/T ~ 4e4. The ship end then moves gently (circle of radius 0.5 m in the x-z plane, period 20 s,
ramped in over one period). Prints the static end tensions of the hybrid solver (adaptive and
all-catenary zoning), of the elastic catenary (physics/statics.py) and of the DG solver (N = 20, P = 4,
its static initial state through the public interface), then runs the hybrid for --duration s.

    PYTHONPATH=. python benchmarks/studies/hybrid_held_arc.py [--duration 600] [--no-dg] [--plot docs/figures/hybrid_held_arc.png]
"""

import argparse
import math
import time
from dataclasses import replace

import numpy as np

from tether_sim.config import SimConfig
from tether_sim.physics.boundary import EndCondition
from tether_sim.physics.cable import CableProperties
from tether_sim.physics.environment import Environment
from tether_sim.physics.statics import solve_static
from tether_sim.solvers.config import DGOptions, HybridOptions, InitialState
from tether_sim.solvers.factory import build_solver

SHIP = np.array([0.0, 0.0, -50.0])
RADIUS, PERIOD = 0.5, 20.0


def held_arc_config(solver="hybrid", zoning="adaptive", segments=60, dt=0.01, ship_kind="prescribed"):
    """The stiff held arc (module docstring)."""
    cable = CableProperties(length=325.0, EA=4.55e8, gamma0=3.01, density=7153.0, diameter=0.03, EI=2620.0)
    return SimConfig(solver=solver, cable=cable, environment=Environment(),
                     ship_end=EndCondition(kind=ship_kind, position=tuple(SHIP)),
                     vehicle_end=EndCondition(kind="fixed", position=(300.0, 0.0, -150.0)),
                     dg=DGOptions(n_elements=20, order=4),
                     hybrid=HybridOptions(n_segments=segments, time_step=dt, zoning=zoning),
                     initial=InitialState(kind="static"))


def ship_motion(t):
    """Gentle circle in the x-z plane, ramped in smoothly over one period: (position, velocity)."""
    w = 2.0 * math.pi / PERIOD
    ramp = min(t / PERIOD, 1.0)
    dramp = 1.0 / PERIOD if t < PERIOD else 0.0
    r = ramp * ramp * (3.0 - 2.0 * ramp)
    dr = 6.0 * ramp * (1.0 - ramp) * dramp
    off = RADIUS * np.array([math.sin(w * t), 0.0, 1.0 - math.cos(w * t)])
    doff = RADIUS * w * np.array([math.cos(w * t), 0.0, math.sin(w * t)])
    return SHIP + r * off, r * doff + dr * off


def run(solver, duration, rate=50.0):
    """Drive the ship end for duration s; (t, ship tension, vehicle tension, vertical force sum, cpu)."""
    out = []
    c0 = time.thread_time()
    for k in range(1, int(round(duration * rate)) + 1):
        t = k / rate
        p, v = ship_motion(t)
        solver.set_end_motion("ship", p, v)
        solver.advance_to(t)
        F = solver.end_forces()
        out.append((t, F.ship_tension, F.vehicle_tension, F.ship_force[2] + F.vehicle_force[2]))
    return np.array(out), time.thread_time() - c0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--duration", type=float, default=600.0)
    ap.add_argument("--no-dg", action="store_true")
    ap.add_argument("--plot", default="")
    args = ap.parse_args()
    sol = solve_static(held_arc_config())
    ref = (float(np.linalg.norm(sol.force_at(np.array([0.0]))[0])), float(np.linalg.norm(sol.force_at(np.array([325.0]))[0])))
    print(f"elastic catenary: ship {ref[0]:.2f} N, fixed end {ref[1]:.2f} N", flush=True)
    if not args.no_dg:
        c0 = time.process_time()
        F = build_solver(held_arc_config(solver="dg")).end_forces()
        print(f"DG N=20 P=4 static: ship {F.ship_tension:.2f} N, fixed end {F.vehicle_tension:.2f} N "
              f"({time.process_time() - c0:.0f} s CPU)", flush=True)
    solvers = {}
    for zoning in ("adaptive", "all_catenary"):
        s = build_solver(held_arc_config(zoning=zoning))
        F = s.end_forces()
        print(f"hybrid {zoning} static: ship {F.ship_tension:.2f} N ({100 * (F.ship_tension / ref[0] - 1):+.3f} %), "
              f"fixed end {F.vehicle_tension:.2f} N ({100 * (F.vehicle_tension / ref[1] - 1):+.3f} %), "
              f"relaxation final speed {s.stats['relax_final_speed']:.2g} m/s", flush=True)
        solvers[zoning] = s
    s = solvers["adaptive"]
    rec, cpu = run(s, args.duration)
    weight = 325.0 * s.net_weight
    last = rec[:, 0] > args.duration - 5 * PERIOD
    print(f"hybrid adaptive, {args.duration:g} s of end motion: ship tension {rec[:, 1].min():.1f}..{rec[:, 1].max():.1f} N, "
          f"fixed end {rec[:, 2].min():.1f}..{rec[:, 2].max():.1f} N; vertical end forces + weight "
          f"{np.abs(rec[:, 3] + weight).max():.2f} N max; mean ship tension over the last 5 periods "
          f"{rec[last, 1].mean():.2f} N; Newton {s.stats}; {cpu:.1f} s CPU", flush=True)
    if args.plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(9, 3.5))
        ax.plot(rec[:, 0], rec[:, 1] / 1e3, lw=0.6, label="ship end")
        ax.plot(rec[:, 0], rec[:, 2] / 1e3, lw=0.6, label="fixed end")
        ax.axhline(ref[0] / 1e3, color="k", lw=0.5, ls="--", label="static (elastic catenary)")
        ax.axhline(ref[1] / 1e3, color="k", lw=0.5, ls="--")
        ax.set_xlabel("t (s)")
        ax.set_ylabel("tension (kN)")
        ax.set_title("hybrid solver, held arc L = 325 m, EA = 455 MN, EI = 2620 N m$^2$, ship circle r = 0.5 m, T = 20 s")
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(args.plot, dpi=120)
        print("wrote", args.plot)


if __name__ == "__main__":
    main()
