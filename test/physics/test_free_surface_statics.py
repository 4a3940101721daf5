"""Static shape of a cable hanging from a point above the free surface.

Above z = 0 the cable weighs w_air = g (gamma0 - rho_air A) per metre, below it w = g (gamma0 - rho_w A).
Closed forms: along the cable d|T|/ds = w_local (dz/ds) / (1 + eps) (tangential equilibrium of the
elastic catenary), so for a vertical cable T_top = T_waterline + w_air * s_c and the waterline tension
is the submerged weight below it, T_waterline = W_end + w (L - s_c); the height of the top above the
water is h = s_c + int_0^{s_c} eps ds. Both are exact identities of the model: tolerances are round-off.
"""

import dataclasses as dc
import math

import numpy as np
import pytest

from tether_sim.physics.cable import CableProperties
from tether_sim.physics.constitutive import TensionLaw
from tether_sim.physics.environment import Environment
from tether_sim.physics.hydrodynamics import air_weight_per_length, net_weight_per_length
from tether_sim.physics.statics import catenary_between, hanging_from, solve_static, surface_crossing
from tether_sim.scenarios import harness

CAB = CableProperties(length=100.0, EA=2.0e5, gamma0=2.0, density=2000.0, diameter=0.03)
ENV = Environment(free_surface=True)
W = net_weight_per_length(CAB, ENV)  # 9.56 N/m
WA = air_weight_per_length(CAB, ENV)  # 19.61 N/m: twice the submerged weight (a buoyant cable)


def test_vertical_cable_from_above_the_surface_closed_form():
    h, load = 5.0, 300.0  # top 5 m above the water, 300 N hanging at the bottom
    law = TensionLaw(CAB)
    sol = hanging_from((0.0, 0.0, h), CAB.length, W, law, (0.0, 0.0, -load), at_start=True, w_air=WA)
    sc = sol.crossing
    # height of the air part: h = int_0^sc (1 + T(s)/EA) ds with T(s) = T_top - WA s
    T_top = load + W * (CAB.length - sc) + WA * sc
    assert sc + (T_top * sc - 0.5 * WA * sc**2) / CAB.EA == pytest.approx(h, rel=1e-12)
    T = sol.tension([0.0, sc, CAB.length])
    assert T[0] == pytest.approx(T_top, rel=1e-12)
    assert T[1] == pytest.approx(load + W * (CAB.length - sc), rel=1e-12)  # waterline: weight in water below
    assert T[2] == pytest.approx(load, rel=1e-12)
    assert sol.position([sc])[0, 2] == pytest.approx(0.0, abs=1e-10)
    # below the waterline the submerged elastic hanging cable: z(L) = -(L - sc) - stretch
    Tw = T[1]
    stretch = (Tw * (CAB.length - sc) - 0.5 * W * (CAB.length - sc) ** 2) / CAB.EA
    assert sol.position([CAB.length])[0, 2] == pytest.approx(-(CAB.length - sc) - stretch, rel=1e-12)


def test_inclined_catenary_through_the_surface_is_two_catenaries_joined():
    """Both ends held, the top 5 m above water: T is continuous at the crossing, each part is an elastic
    catenary of its own weight, and |T| drops by w_air * int dz / (1 + eps) over the air part."""
    law = TensionLaw(CAB)
    A, B = np.array([0.0, 0.0, 5.0]), np.array([60.0, 0.0, -60.0])
    sol = catenary_between(A, B, CAB.length, W, law, w_air=WA)
    sc = sol.crossing
    assert 0.0 < sc < CAB.length
    np.testing.assert_allclose(sol.position([CAB.length])[0], B, atol=1e-9 * CAB.length)
    assert sol.position([sc])[0, 2] == pytest.approx(0.0, abs=1e-9)
    s = np.linspace(0.0, sc, 4001)
    T = sol.tension(s)
    dz = np.diff(sol.position(s)[:, 2])
    drop = np.sum(-WA * dz / (1.0 + 0.5 * (T[1:] + T[:-1]) / CAB.EA))  # trapezoid, O(ds^2) ~ 1e-9 relative
    assert T[0] - T[-1] == pytest.approx(drop, rel=1e-6)
    # the horizontal tension is the same in both parts; the vertical force jumps by the weights
    assert sol.force_at([0.0])[0, 2] + WA * sc + W * (CAB.length - sc) == pytest.approx(sol.force_at([CAB.length])[0, 2])
    # the same geometry fully submerged (free surface off) has a different (lower) top tension
    sub = catenary_between(A, B, CAB.length, W, law)
    assert sol.tension([0.0])[0] > sub.tension([0.0])[0] + 0.5 * (WA - W) * 5.0


def test_crossing_is_zero_below_the_surface_and_whole_length_in_air():
    law = TensionLaw(CAB)
    T0 = np.array([0.0, 0.0, -1000.0])
    assert surface_crossing(T0, WA, law, CAB.length, -1.0) == 0.0
    assert surface_crossing(T0, WA, law, CAB.length, 500.0) == CAB.length


def test_solve_static_uses_the_surface_only_when_on():
    flat = {"cable.length": 100.0, "cable.EA": 2.0e5, "cable.gamma0": 2.0, "cable.density": 2000.0,
            "environment.free_surface": True,
            "ship_end.kind": "prescribed", "ship_end.position": [0.0, 0.0, 5.0],
            "vehicle_end.kind": "free", "vehicle_end.position": [0.0, 0.0, -95.0]}
    cfg = harness.make_config(flat)
    on = solve_static(cfg)
    off = solve_static(dc.replace(cfg, environment=dc.replace(cfg.environment, free_surface=False)))
    assert on.crossing == pytest.approx(5.0 / (1.0 + on.tension([0.0])[0] / CAB.EA), rel=1e-3)
    assert off.crossing == 0.0
    assert on.tension([0.0])[0] - off.tension([0.0])[0] == pytest.approx((WA - W) * on.crossing, rel=1e-9)
    # a vehicle end above a ship end in the water is refused with a clear message
    bad = harness.make_config({**flat, "ship_end.position": [0.0, 0.0, -5.0], "vehicle_end.kind": "fixed",
                               "vehicle_end.position": [50.0, 0.0, 20.0]})
    with pytest.raises(RuntimeError, match="free surface"):
        solve_static(bad)
    assert math.isfinite(on.T0[2])
