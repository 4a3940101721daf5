"""The compiled loop's stepper rows (dg.stepper) against their plain form on the solver's own right-hand side.

One substep of the compiled loop (stepper.dg_advance via solver.step) must equal numerics.integrators'
stepper_step driven by the compiled right-hand side (solver._evaluate) to round-off, for every stepper:
this checks the stage table's a, b, d, c and the keep register (ssprk93) in the loop, on a hanging cable
in water with gravity and drag (a non-linear right-hand side). Marked ``jit_off``: also run as Python.
"""

import numpy as np
import pytest

from tether_sim.config import SimConfig
from tether_sim.numerics.integrators import STEPPER_NAMES, stepper_step
from tether_sim.physics.boundary import EndCondition
from tether_sim.physics.cable import CableProperties
from tether_sim.physics.environment import Environment
from tether_sim.solvers.config import DGOptions, InitialState
from tether_sim.solvers.dg.solver import DGCableSolver

pytestmark = pytest.mark.jit_off


def solver(stepper):
    cab = CableProperties(length=60.0, EA=2e5, gamma0=3.0, diameter=0.03, density=7000.0, damping=300.0,
                          Cdn=1.2, Cdt=0.05, Cmn=1.0, Cmt=0.3)
    cfg = SimConfig(cable=cab, environment=Environment(g=9.81, fluid_density=1025.0),
                    ship_end=EndCondition(kind="fixed", position=(0, 0, 0)),
                    vehicle_end=EndCondition(kind="fixed", position=(20.0, 0, -55.0)),
                    dg=DGOptions(n_elements=3, order=3, stepper=stepper), initial=InitialState(kind="straight"))
    return DGCableSolver(cfg)


@pytest.mark.parametrize("stepper", STEPPER_NAMES)
def test_compiled_substep_equals_the_plain_rows(stepper):
    s = solver(stepper)
    s.advance_to(0.05)  # a moving, non-trivial state
    u0 = s.ws.U.copy()
    dt = s.stable_time_step()

    def rhs(u, t):
        s.ws.U[...] = u
        s._evaluate()
        return s.ws.dU.copy()

    want = stepper_step(stepper, rhs, u0, s.time, dt)
    s.ws.U[...] = u0
    s.step(dt)
    scale = np.max(np.abs(u0))
    assert np.max(np.abs(want - u0)) > 1e-6 * scale  # the step moved the state
    assert np.max(np.abs(s.ws.U - want)) <= 1e-12 * scale


def test_larger_steppers_take_larger_substeps_on_the_same_case():
    dts = {name: solver(name).stable_time_step() for name in STEPPER_NAMES}
    assert dts["ssprk3"] < dts["ssprk43"] < dts["ssprk93"]
