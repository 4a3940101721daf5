"""Kirchhoff rod elements against closed forms [GP Eq. 6-11] (all-rod zoning, no gravity/fluid).

Cantilever (clamped at s = 0, tip load P): tip deflection P L^3/(3 EI), root moment P L, shear P.
Small deflection delta/L = 1e-3 keeps the geometric nonlinearity at ~1e-6; the box scheme's error
with 20 elements is ~(ds/L)^2/12 ~ 2e-4, so 0.5 % is a safe tolerance.
End torque M about the tangent: kappa_1 = M/GJ uniform and the tip section turns by M L / GJ.
"""

from dataclasses import replace

import numpy as np

from tether_sim.config import SimConfig
from tether_sim.numerics.rotations import rotation_vector
from tether_sim.physics.boundary import EndCondition
from tether_sim.physics.cable import CableProperties
from tether_sim.physics.environment import Environment
from tether_sim.solvers.config import HybridOptions, InitialState
from tether_sim.solvers.hybrid.solver import HybridRodCatenarySolver

EI, GJ, L = 1.0, 0.8, 1.0


def rod_config(force=(0.0, 0.0, 0.0), moment=(0.0, 0.0, 0.0)):
    cable = CableProperties(length=L, EA=0.0, gamma0=1.0, density=1000.0, diameter=0.01, EI=EI, GIp=GJ)
    return replace(SimConfig(), solver="hybrid", cable=cable, environment=Environment(g=0.0, fluid_density=0.0),
                   ship_end=EndCondition(kind="clamped", position=(0.0, 0.0, 0.0), direction=(1.0, 0.0, 0.0)),
                   vehicle_end=EndCondition(kind="force", position=(L, 0.0, 0.0), force=force, moment=moment),
                   hybrid=HybridOptions(n_segments=20, time_step=0.5, rho_inf=0.0, zoning="all_rod"),
                   initial=InitialState(kind="relax", relax_time=25.0))


def test_cantilever_tip_deflection_root_moment_and_shear():
    P = 3.0e-3 * EI / L**3  # delta = 1e-3 L
    solver = HybridRodCatenarySolver(rod_config(force=(0.0, 0.0, -P)))
    assert solver.stats["relax_final_speed"] < 1e-6  # at rest: m/s vs a 1e-3 m tip deflection
    st = solver.state(np.array([0.0, 0.5 * L, L]))
    delta = P * L**3 / (3.0 * EI)
    assert abs(-st.position[-1, 2] - delta) / delta < 5e-3
    # deflection at mid-span: P s^2 (3L - s)/(6 EI)
    mid = P * (0.5 * L) ** 2 * (3 * L - 0.5 * L) / (6 * EI)
    assert abs(-st.position[1, 2] - mid) / mid < 5e-3
    assert abs(st.bending_moment[0] - P * L) / (P * L) < 5e-3
    assert np.allclose(st.extra["shear"], P, rtol=5e-3)
    ef = solver.end_forces()
    assert np.allclose(ef.vehicle_force, [0.0, 0.0, P], atol=1e-6 * P)  # the cable pushes the load back
    assert np.all(st.extra["zone"] == 1)


def test_end_torque_twists_uniformly():
    M = 1.0e-2
    solver = HybridRodCatenarySolver(rod_config(moment=(M, 0.0, 0.0)))
    kappa_twist = solver.Y[:, 6]
    assert np.allclose(kappa_twist, M / GJ, rtol=1e-6)
    st = solver.state()
    assert np.allclose(st.extra["torsion_moment"], M, rtol=1e-6)
    assert np.allclose(st.bending_moment, 0.0, atol=1e-9)
    turn = rotation_vector(solver.Lf[-1] @ solver.Lf[0].T)
    assert abs(np.linalg.norm(turn) - M * L / GJ) < 1e-6 * M * L / GJ + 1e-12
    assert np.allclose(st.position[:, 1:], 0.0, atol=1e-12)  # the axis stays straight
