"""Real-time factor of the DG solver on the ROPOS tether [PE2020 Sec. 6, Table 3].

L = 1730 m, EA = 45.5 MN, gamma0 = 3.01 kg/m, d = 0.03 m, rho_c = 7153 kg/m^3, zeta = 45.5 kN s,
Cdn = 1, Cdt = 0.02, Cmn = 1, Cmt = 0; N = 20, P = 4; the cage hangs as a point load (its submerged
weight; or the 6-DOF cage body of Table 3) at s = L; the ship end follows a 2 m, 0.2 Hz circular orbit fed at 50 Hz like the ROS node.
Prints simulated seconds per wall-clock second, without and with bending (EI = 2.62 kN m^2).

    PYTHONPATH=. python benchmarks/bench_dg.py [sim_seconds]
"""

import math
import sys
import time

import numpy as np

from tether_sim.config import SimConfig
from tether_sim.physics.boundary import EndCondition
from tether_sim.physics.cable import CableProperties
from tether_sim.physics.environment import Environment
from tether_sim.solvers.config import DGOptions, InitialState
from tether_sim.solvers.dg.solver import DGCableSolver

CAGE_MASS, CAGE_DENSITY, RHO, G = 4995.0, 8448.0, 1025.0, 9.81


def ropos_config(EI=0.0, N=20, P=4, vehicle="force"):
    cab = CableProperties(length=1730.0, EA=45.5e6, gamma0=3.01, diameter=0.03, density=7153.0, damping=45.5e3,
                          Cdn=1.0, Cdt=0.02, Cmn=1.0, Cmt=0.0, EI=EI)
    w_cage = (CAGE_MASS - RHO * CAGE_MASS / CAGE_DENSITY) * G
    return SimConfig(cable=cab, environment=Environment(g=G, fluid_density=RHO),
                     ship_end=EndCondition(kind="prescribed", position=(0.0, 0.0, 0.0)),
                     vehicle_end=EndCondition(kind=vehicle, position=(0.0, 0.0, -1730.0), force=(0.0, 0.0, -w_cage)),
                     dg=DGOptions(n_elements=N, order=P), initial=InitialState(kind="static"))


def run(cfg, sim_seconds, rate=50.0, a=2.0, f=0.2):
    s = DGCableSolver(cfg)
    s.advance_to(1.0 / rate)  # compile / warm up outside the timing
    t0 = time.perf_counter()
    c0 = time.process_time()
    steps = 0
    n = int(sim_seconds * rate)
    w = 2 * math.pi * f
    for k in range(2, n + 2):
        t = k / rate
        s.set_end_motion("ship", (a * math.sin(w * t), 0.0, a * (1 - math.cos(w * t))),
                         (a * w * math.cos(w * t), 0.0, a * w * math.sin(w * t)))
        steps += s.advance_to(t)
        s.drain_end_tensions()
    wall = time.perf_counter() - t0
    cpu = time.process_time() - c0
    return sim_seconds / wall, sim_seconds / cpu, steps / sim_seconds, s


def main(sim_seconds=20.0):
    print("real-time factor = simulated s / wall s (and / CPU s of this process: robust on a loaded machine)")
    for vehicle in ("force", "body"):
        for label, EI in (("no bending", 0.0), ("EI = 2.62 kN m^2", 2.62e3)):
            rtf, rtf_cpu, per_s, s = run(ropos_config(EI, vehicle=vehicle), sim_seconds)
            T = s.end_forces().ship_tension
            print(f"ROPOS L=1730 N=20 P=4 cage={vehicle:5s} {label:17s}: RTF wall {rtf:7.2f}  cpu {rtf_cpu:7.2f}  "
                  f"substep {s._substep():.3e} s ({per_s:.0f}/s)  ship tension {T / 1e3:.1f} kN", flush=True)


if __name__ == "__main__":
    main(float(sys.argv[1]) if len(sys.argv) > 1 else 20.0)
