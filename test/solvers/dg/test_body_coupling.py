"""Rigid body at a cable end (PE2020 Table 1, last row) coupled through the DG boundary flux."""

import math

import numpy as np
from scipy.optimize import brentq

from tether_sim.config import SimConfig
from tether_sim.physics.bodies import RigidBodyProperties
from tether_sim.physics.boundary import EndCondition
from tether_sim.physics.cable import CableProperties
from tether_sim.physics.environment import Environment
from tether_sim.solvers.config import DGOptions, InitialState
from tether_sim.solvers.dg.solver import DGCableSolver

L, EA, GAMMA0, M = 20.0, 2e6, 1.0, 1000.0


def hanging_body():
    cfg = SimConfig(cable=CableProperties(length=L, EA=EA, gamma0=GAMMA0, diameter=0.01, density=8000.0,
                                          Cdn=0.0, Cdt=0.0, Cmn=0.0, Cmt=0.0),
                    environment=Environment(g=9.81, fluid_density=0.0),
                    ship_end=EndCondition(kind="fixed", position=(0.0, 0.0, 0.0)),
                    vehicle_end=EndCondition(kind="body", position=(0.0, 0.0, -L)),
                    body=RigidBodyProperties(mass=M, density=8000.0, added_mass=(0.0, 0.0, 0.0),
                                             drag_coefficients=(0.0, 0.0, 0.0), attachment=(0.0, 0.0, 0.5),
                                             inertia=(100.0, 100.0, 100.0)),
                    dg=DGOptions(n_elements=4, order=4), initial=InitialState(kind="static"))
    return DGCableSolver(cfg)


def test_static_body_hangs_in_equilibrium():
    s = hanging_body()
    b = s.body_state("vehicle")
    W, w = M * 9.81, GAMMA0 * 9.81
    stretch = (W * L + 0.5 * w * L**2) / EA
    assert np.allclose(b.position, [0.0, 0.0, -L - stretch - 0.5], atol=1e-9)
    assert np.max(np.abs(b.acceleration)) < 1e-9  # static solve is the DG equilibrium here
    assert abs(s.end_forces().ship_tension - (W + w * L)) < 1e-6 * W
    assert s.body_state("ship") is None


def test_axial_oscillation_period_of_body_on_elastic_cable():
    """Mass M on an elastic rod: beta tan(beta) = gamma0 L / M, omega = beta c / L."""
    s = hanging_body()
    c = math.sqrt(EA / GAMMA0)
    beta = brentq(lambda b: b * math.tan(b) - GAMMA0 * L / M, 1e-6, 1.5)
    T = 2 * math.pi * L / (beta * c)
    s.ws.bs[1, 9] = 0.01  # 1 cm/s upward kick of the body
    ts, vz = [], []
    for i in range(1, 601):
        s.advance_to(i * 2.5 * T / 600)
        ts.append(s.time)
        vz.append(s.body_state("vehicle").velocity[2])
    ts, vz = np.array(ts), np.array(vz)
    down = [ts[i] + (ts[i + 1] - ts[i]) * vz[i] / (vz[i] - vz[i + 1]) for i in range(len(vz) - 1) if vz[i] > 0 >= vz[i + 1]]
    periods = np.diff(down)
    # 4 elements of order 4 resolve the fundamental to << 0.1 %; crossing interpolation ~1e-4 T
    assert len(periods) >= 1 and np.all(np.abs(periods / T - 1.0) < 2e-3), periods / T
