"""Seabed contact in the hybrid solver: the DG solver's law [PE2020 Eq. 15-16, physics/seabed.py].

A taut cable (T ~ 47 kN) between two supports 0.1 m above the seabed sags onto it: free spans of
sqrt(2 T 0.1 / w) ~ 19 m, resting on the seabed over the middle ~60 m. Along the resting part, at rest:
* the seabed carries the submerged weight: f_z = sqrt(1+eps) K_g d delta = w per unstretched metre,
  i.e. the penetration delta = w / (sqrt(1+eps) K_g d);
* nothing acts along the cable (no friction at rest, gravity normal to it): dT/ds = 0.
Both hold exactly for the discrete equations of a flat run of cells (the box-scheme mean of F over a
cell vanishes), so the tolerances are the relaxation's residual motion: 1e-3 of w and 1e-5 of T.
"""

from dataclasses import replace

import numpy as np

from tether_sim.config import SimConfig
from tether_sim.physics.boundary import EndCondition
from tether_sim.physics.cable import CableProperties
from tether_sim.physics.environment import Environment
from tether_sim.solvers.config import HybridOptions, InitialState
from tether_sim.solvers.hybrid.solver import HybridRodCatenarySolver

L, ZG, EA = 100.0, -50.0, 45.5e6


def test_cable_resting_on_seabed():
    cable = CableProperties(length=L, EA=EA, gamma0=3.01, density=7153.0, diameter=0.03, EI=0.0, damping=45.5e3)
    env = Environment(seabed=True, seabed_z=ZG, seabed_stiffness=3.0e6, seabed_damping=1.0, seabed_friction=0.5)
    z_end = ZG + 0.1
    cfg = replace(SimConfig(), solver="hybrid", cable=cable, environment=env,
                  ship_end=EndCondition(kind="fixed", position=(0.0, 0.0, z_end)),
                  vehicle_end=EndCondition(kind="fixed", position=(L * 1.001, 0.0, z_end)),
                  hybrid=HybridOptions(n_segments=50, time_step=0.5, rho_inf=0.0, zoning="all_catenary"),
                  initial=InitialState(kind="relax", relax_time=120.0))
    solver = HybridRodCatenarySolver(cfg)
    assert solver.stats["relax_final_speed"] < 1e-6  # at rest (m/s)
    w = (cable.gamma0 - env.fluid_density * cable.area) * env.g
    kd = env.seabed_stiffness * cable.diameter
    st = solver.state(solver.s_grid)
    delta = ZG - st.position[:, 2]
    resting = delta > 0.5 * w / kd
    # interior of the resting part (two cells away from the touch-down points)
    idx = np.nonzero(resting)[0]
    inner = idx[2:-2]
    assert inner.size > 20  # ~30 of the 51 nodes rest on the seabed
    reaction = np.sqrt(1.0 + st.strain[inner]) * kd * delta[inner]
    assert np.max(np.abs(reaction / w - 1.0)) < 1e-3
    T = st.tension[inner]
    assert np.ptp(T) / T.mean() < 1e-5
    # the supports carry the free spans only (their tangent is flat at touch-down): about w x free length
    F = solver.end_forces()
    free_len = solver.s_grid[idx[0]] + (L - solver.s_grid[idx[-1]])
    carried = abs(F.ship_force[2]) + abs(F.vehicle_force[2])
    assert 0.5 * w * free_len < carried < 1.5 * w * free_len  # without the seabed: w L, 4x more
