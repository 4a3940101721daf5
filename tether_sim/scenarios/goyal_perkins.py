"""Goyal & Perkins benchmark [GP Sec. 4, Table 1, Fig. 5-8]: a 2 m cable sagging between a pinned
left end and a tension-free right end whose tangent is held 30 deg from horizontal under a 0.01 N
force normal to it. Relaxed from straight to rest with dt = 1 s, ds = 5 mm.

Interpretation (the paper gives no figure data): the x-z plane, z up; the right-end tangent points
30 deg *below* horizontal, t_L = (cos 30, 0, -sin 30), and the force is the upward normal
(sin 30, 0, cos 30) * 0.01 N, so the cable hangs as a suspension with positive tension (a horizontal
force component of 0.005 N). The initial straight line runs from (0, 0, 0) along t_L.
GP's tangential drag pi*C_t (Eq. 19) is C_dt = 0.1*pi in the PE2020 form used here; rho_c = 1000
kg/m^3 makes A = gamma0/rho_c = pi D^2/4 as in GP Eq. 21.
"""

import math
from dataclasses import replace

from tether_sim.config import SimConfig
from tether_sim.physics.boundary import EndCondition
from tether_sim.physics.cable import CableProperties
from tether_sim.physics.environment import Environment
from tether_sim.solvers.config import HybridOptions, InitialState

LENGTH = 2.0
ANGLE = math.radians(30.0)
END_FORCE = 0.01
JOINT = 1.5


def goyal_perkins_config(zoning="fixed", n_segments=400, time_step=1.0, rho_inf=0.0, duration=60.0):
    """SimConfig of the GP benchmark (Table 1); zoning 'fixed' (joint at 1.5 m) or 'all_rod'/'adaptive'."""
    tangent = (math.cos(ANGLE), 0.0, -math.sin(ANGLE))
    normal = (math.sin(ANGLE), 0.0, math.cos(ANGLE))
    cable = CableProperties(length=LENGTH, EA=0.0, gamma0=math.pi / 4 * 1e-3, diameter=1e-3, density=1000.0,
                            EI=5 * math.pi / 64 * 1e-3, GIp=math.pi / 16 * 1e-3, Cdn=1.0, Cdt=0.1 * math.pi,
                            Cmn=0.0, Cmt=0.0, material="linear")
    env = Environment(g=9.8, fluid_density=1.0)
    ship = EndCondition(kind="fixed", position=(0.0, 0.0, 0.0))
    vehicle = EndCondition(kind="force", position=tuple(LENGTH * c for c in tangent), direction=tangent,
                           force=tuple(END_FORCE * c for c in normal))
    hybrid = HybridOptions(n_segments=n_segments, time_step=time_step, rho_inf=rho_inf, zoning=zoning,
                           joint_arc_length=JOINT, hold_direction_vehicle=True, end_rod_length=0.1,
                           rotary_inertia_bend=math.pi / 64 * 1e-9, rotary_inertia_torsion=math.pi / 32 * 1e-9)
    return replace(SimConfig(), solver="hybrid", duration=duration, cable=cable, environment=env, ship_end=ship,
                   vehicle_end=vehicle, hybrid=hybrid, initial=InitialState(kind="straight"))


def run_to_rest(solver, t_max=200.0, tol=1e-7, chunk=5.0):
    """Advance until the largest node speed is below tol (m/s) or t_max; returns the final time."""
    import numpy as np

    while solver.time < t_max:
        solver.advance_to(solver.time + chunk)
        if float(np.abs(solver.state().velocity).max()) < tol:
            break
    return solver.time
