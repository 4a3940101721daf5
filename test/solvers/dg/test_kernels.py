"""DG right-hand side on states with known exact derivatives (compiled kernels, small meshes; the
ones marked jit_off also run with NUMBA_DISABLE_JIT=1 in `make test`)."""

import numpy as np
import pytest

from tether_sim.config import SimConfig
from tether_sim.physics.boundary import EndCondition
from tether_sim.physics.cable import CableProperties
from tether_sim.physics.environment import Environment
from tether_sim.solvers.config import DGOptions, InitialState
from tether_sim.solvers.dg import layout as Y
from tether_sim.solvers.dg.solver import DGCableSolver


def straight(EI=0.0, zeta=0.0, g=0.0, rho=0.0, N=3, P=4, kinds=("fixed", "fixed"), stretch=1.02):
    cab = CableProperties(length=10.0, EA=1e4, gamma0=2.0, diameter=0.05, density=2000.0, EI=EI, damping=zeta,
                          material="linear", Cdn=1.0, Cdt=0.1, Cmn=1.0, Cmt=0.5)
    cfg = SimConfig(cable=cab, environment=Environment(g=g, fluid_density=rho),
                    ship_end=EndCondition(kind=kinds[0], position=(0, 0, 0)),
                    vehicle_end=EndCondition(kind=kinds[1], position=(6.0 * stretch, 0, -8.0 * stretch)),
                    dg=DGOptions(n_elements=N, order=P, element_lengths=(1.0, 2.0, 1.5)),
                    initial=InitialState(kind="straight"))
    return DGCableSolver(cfg)


@pytest.mark.jit_off
def test_uniformly_stretched_cable_is_at_rest():
    s = straight(zeta=50.0)
    s._evaluate()
    assert np.max(np.abs(s.ws.dU)) < 1e-9
    # end forces: T = EA eps along the chord, pulling each end toward the other
    f = s.end_forces()
    T = 1e4 * 0.02
    i = np.array([0.6, 0.0, -0.8])
    assert np.allclose(f.ship_force, T * i) and np.allclose(f.vehicle_force, -T * i)
    assert abs(f.ship_tension - T) < 1e-9


@pytest.mark.jit_off
def test_bending_of_a_straight_cable_adds_nothing():
    a, b = straight(), straight(EI=5.0)
    assert a.ws.iprm[Y.I_BENDING] == 0 and b.ws.iprm[Y.I_BENDING] == 1
    a._evaluate()
    b._evaluate()
    assert np.allclose(a.ws.dU, b.ws.dU, atol=1e-9)


@pytest.mark.jit_off
def test_rigid_translation_has_no_internal_force():
    s = straight(kinds=("free", "free"))
    v = np.array([0.3, -0.2, 0.1])
    s.set_shape(lambda x: np.repeat(np.array([[0.6, 0.0, -0.8]]) * 1.02, np.size(x), axis=0),
                lambda x: np.repeat(v[None, :], np.size(x), axis=0))
    s.ws.prm[Y.P_HALF_RHO_D] = 0.0  # no drag: a translating cable keeps its momentum
    s._evaluate()
    # the free ends carry T_hat = 0 while the interior is stretched: only the end modes accelerate
    assert np.max(np.abs(s.ws.dU[:, :, 0:3])) < 1e-12  # uniform velocity: q does not change


@pytest.mark.jit_off
def test_weight_and_added_mass_give_the_sinking_acceleration():
    """Slack free-free cable in water: a = f_b / (gamma0 + m_n) for a horizontal cable (normal sinking)."""
    cab = CableProperties(length=10.0, EA=1e4, gamma0=2.0, diameter=0.05, density=2000.0, Cdn=0.0, Cdt=0.0,
                          Cmn=1.0, Cmt=0.0)
    env = Environment(g=9.81, fluid_density=1000.0)
    cfg = SimConfig(cable=cab, environment=env, ship_end=EndCondition(kind="free", position=(0, 0, 0)),
                    vehicle_end=EndCondition(kind="free", position=(10.0, 0, 0)),
                    dg=DGOptions(n_elements=2, order=3), initial=InitialState(kind="straight"))
    s = DGCableSolver(cfg)
    s._evaluate()
    mn = 1000.0 * np.pi * 0.05**2 / 4
    a = -9.81 * (2.0 - 1000.0 * cab.area) / (2.0 + mn)
    assert np.allclose(s.ws.dU[:, 0, 5] / 2.0, a, rtol=1e-12)
    assert np.allclose(s.ws.dU[:, 1:, 3:6], 0.0, atol=1e-9)  # round-off of EA-sized terms (1e4)


def test_central_q_flux_keeps_a_low_tension_curved_catenary_static():
    """dg.q_penalty = 0 removes the LF-q-penalty instability of curved cables with EA/T ~ 2e4
    (docs/dg_solver.md, known limitations): the static catenary stays static."""
    from tether_sim.solvers.config import DGOptions as Opt

    cfg = SimConfig(cable=CableProperties(length=100.0),
                    ship_end=EndCondition(kind="fixed", position=(0, 0, 0)),
                    vehicle_end=EndCondition(kind="fixed", position=(60.0, 0, -75.0)),
                    dg=Opt(n_elements=10, order=4, q_penalty=0.0), initial=InitialState(kind="static"))
    s = DGCableSolver(cfg)
    f0 = s.end_forces().vehicle_force
    s.advance_to(0.5)  # with q_penalty = 1 this case has grown by orders of magnitude by now
    # static start: only the O(h^5) projection residual rings (well below 1 % of the ~1 kN end force)
    assert np.allclose(s.end_forces().vehicle_force, f0, atol=10.0)
