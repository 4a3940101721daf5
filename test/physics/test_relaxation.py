"""Lumped-mass dynamic relaxation (statics fallback) against closed forms and force balance."""

import numpy as np

from tether_sim.physics.cable import CableProperties
from tether_sim.physics.constitutive import TensionLaw
from tether_sim.physics.environment import Environment
from tether_sim.physics.relaxation import relax_cable
from tether_sim.physics.statics import catenary_between, hanging_from


def test_relaxed_shape_matches_the_elastic_catenary():
    law = TensionLaw(CableProperties(EA=2e5))
    B = (120.0, 60.0, -90.0)
    sh = relax_cable((0, 0, 0), B, 200.0, law, 30.0, held=(True, True), n_nodes=101, tol=1e-10)
    cat = catenary_between((0, 0, 0), B, 200.0, 30.0, law)
    s = np.linspace(0, 200, 21)
    assert sh.converged
    # lumped masses on 100 segments: O(ds^2) shape error, here < 4 mm on a 200 m cable (2e-5 L)
    assert np.max(np.abs(sh.position(s) - cat.position(s))) < 4e-3


def test_hanging_cable_with_end_load_is_exact():
    law = TensionLaw(CableProperties(EA=45.5e6))
    sh = relax_cable((0, 0, 0), (0, 0, -1730.0), 1730.0, law, 25.3, held=(True, False),
                     loads=[[0, 0, 0], [0, 0, -43e3]], n_nodes=51, tol=1e-10)
    ref = hanging_from((0, 0, 0), 1730.0, 25.3, law, (0, 0, -43e3))
    s = np.linspace(0, 1730.0, 51)  # at the nodes a vertical lumped cable is exact
    assert sh.converged and np.max(np.abs(sh.position(s) - ref.position(s))) < 1e-6


def test_current_drag_is_balanced_by_the_top_tension():
    cab = CableProperties(length=100.0, EA=1e6, gamma0=3.0, diameter=0.03, density=7000.0, Cdn=1.2, Cdt=0.0)
    env = Environment(current_z=(-200.0, 0.0), current_x=(0.5, 0.5), current_y=(0.0, 0.0))
    law = TensionLaw(cab)
    w = env.g * (cab.gamma0 - env.fluid_density * cab.area)
    W = 2000.0
    sh = relax_cable((0, 0, 0), (0, 0, -100.0), 100.0, law, w, held=(True, False), loads=[[0, 0, 0], [0, 0, -W]],
                     n_nodes=41, env=env, cable=cab, tol=1e-10)
    assert sh.converged
    r = sh.r
    # the cable leans downstream; the first segment's tension carries all the drag except the half
    # of the first segment's drag lumped on the held node (force balance of the free nodes)
    seg = np.diff(r, axis=0)
    d = seg[0]
    T0 = law.tension(np.linalg.norm(d) / (sh.s[1] - sh.s[0]) - 1.0)[0] * d / np.linalg.norm(d)
    t = seg / np.linalg.norm(seg, axis=1)[:, None]
    un = np.array([0.5, 0, 0]) - (t @ np.array([0.5, 0, 0]))[:, None] * t
    l = np.linalg.norm(seg, axis=1) / np.diff(sh.s)
    per_seg = 0.5 * 1025.0 * 0.03 * 1.2 * np.sqrt(l)[:, None] * np.linalg.norm(un, axis=1)[:, None] * un * np.diff(sh.s)[:, None]
    drag = per_seg.sum(0) - 0.5 * per_seg[0]
    assert r[-1, 0] > 0.5  # deflected downstream
    assert abs(T0[0] - drag[0]) < 1e-3 * drag[0]


def test_end_tensions_of_a_curved_relaxed_shape_are_the_catenary_s():
    """The end tensions of the relaxed shape (its segments' strain) against the elastic catenary's, at
    both ends of a sagging cable: the finite-difference gradient's length at a curved end is not the
    stretch (it read several times the tension on stiff cables)."""
    law = TensionLaw(CableProperties(EA=2e5))
    B = (50.0, 0.0, 0.0)
    sh = relax_cable((0, 0, 0), B, 60.0, law, 0.05, held=(True, True), n_nodes=101, tol=1e-10)
    cat = catenary_between((0, 0, 0), B, 60.0, 0.05, law)
    # lumped weights on 100 segments: the end tension within 1 % (the weight of a half segment is 0.5 %)
    assert np.allclose(sh.tension([0.0, 60.0]), cat.tension([0.0, 60.0]), rtol=0.01)
    t = sh.tangent([0.0, 30.0, 60.0])
    assert np.allclose(np.linalg.norm(t, axis=1), 1.0 + sh.strain([0.0, 30.0, 60.0]), rtol=1e-12)
