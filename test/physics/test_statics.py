"""Static equilibrium shapes against closed-form catenaries."""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from tether_sim.physics.cable import CableProperties
from tether_sim.physics.constitutive import TensionLaw
from tether_sim.physics.statics import catenary_between, hanging_from


def test_nearly_inextensible_symmetric_catenary():
    w, L, a = 20.0, 100.0, 80.0
    law = TensionLaw(CableProperties(EA=1e12))
    sol = catenary_between((0, 0, 0), (a, 0, 0), L, w, law)
    H = brentq(lambda H: 2 * H / w * math.sinh(w * a / (2 * H)) - L, 50.0, 1e7)
    sag = H / w * (math.cosh(w * a / (2 * H)) - 1.0)
    assert sol.T0[0] == pytest.approx(H, rel=1e-8)
    assert sol.T0[2] == pytest.approx(-w * L / 2, rel=1e-10)
    assert sol.position([L / 2])[0, 2] == pytest.approx(-sag, rel=1e-8)
    assert np.allclose(sol.position([L])[0], [a, 0, 0], atol=1e-9)


def test_elastic_catenary_matches_irvine_closed_form():
    """Irvine's elastic catenary: span and drop as functions of H and V0, both satisfied."""
    w, L, EA = 30.0, 200.0, 2e5
    law = TensionLaw(CableProperties(EA=EA))
    B = np.array([120.0, 60.0, -90.0])
    sol = catenary_between((0, 0, 0), B, L, w, law)
    H = np.hypot(sol.T0[0], sol.T0[1])
    V0, VL = sol.T0[2], sol.T0[2] + w * L
    span = H * L / EA + H / w * (math.asinh(VL / H) - math.asinh(V0 / H))
    drop = (VL**2 - V0**2) / (2 * EA * w) + (math.hypot(H, VL) - math.hypot(H, V0)) / w
    assert span == pytest.approx(np.hypot(B[0], B[1]), rel=1e-9)
    assert drop == pytest.approx(B[2], rel=1e-9)
    assert sol.T0[1] / sol.T0[0] == pytest.approx(0.5)  # in the vertical plane through A and B


def test_taut_line_is_straight_with_uniform_strain_when_weightless():
    law = TensionLaw(CableProperties(EA=1e4))
    sol = catenary_between((0, 0, 0), (0, 0, -101.0), 100.0, 1e-9, law)
    assert sol.tension([0.0, 50.0, 100.0]) == pytest.approx([100.0] * 3, rel=1e-6)


def test_vertical_hanging_cable_with_cage_load():
    """T(s) = W + w (L - s); stretch = int T / EA ds."""
    w, L, EA, W = 25.0, 1730.0, 45.5e6, 43e3
    law = TensionLaw(CableProperties(EA=EA))
    sol = hanging_from((0, 0, 0), L, w, law, (0, 0, -W))
    assert sol.tension([0.0, L]) == pytest.approx([W + w * L, W], rel=1e-12)
    zL = sol.position([L])[0, 2]
    assert zL == pytest.approx(-(L + (W * L + w * L**2 / 2) / EA), rel=1e-12)


def test_touchdown_on_the_seabed():
    w, L, EA, zg = 20.0, 300.0, 1e9, -100.0
    law = TensionLaw(CableProperties(EA=EA))
    sol = catenary_between((0, 0, 0), (220.0, 0, zg), L, w, law, seabed_z=zg, sink=0.0)
    assert sol.touchdown > 0
    s = np.linspace(0, L, 301)
    r = sol.position(s)
    assert np.all(r[:, 2] >= zg - 1e-6)
    assert np.allclose(r[s > sol.touchdown + 1e-9, 2], zg, atol=1e-6)
    # at the touchdown the cable is horizontal, and the hanging part is an ordinary catenary
    assert abs(sol.force_at([sol.touchdown])[0, 2]) < 1e-6 * w * L
    H = sol.T0[0]
    assert sol.T0[2] == pytest.approx(-w * sol.touchdown)
    # inextensible closed form; EA = 1e9 stretches by ~1e-6, hence rel 1e-5
    assert -zg == pytest.approx((math.hypot(H, w * sol.touchdown) - H) / w, rel=1e-5)
    assert np.allclose(r[-1], [220.0, 0, zg], atol=1e-6)


def test_an_anchor_at_s0_is_the_mirror_of_an_anchor_at_sL():
    """The same line with its ends swapped: the s = 0 end the anchor on the seabed (a line described
    from its anchor) gives the mirrored shape and the same end tensions as the s = L end on it."""
    w, L, EA, zg = 1000.0, 450.0, 5e8, -50.0
    law = TensionLaw(CableProperties(EA=EA))
    top, anchor = np.array([420.0, 0.0, 0.0]), np.array([0.0, 0.0, zg])
    down = catenary_between(top, anchor, L, w, law, seabed_z=zg)
    up = catenary_between(anchor, top, L, w, law, seabed_z=zg)
    s = np.linspace(0.0, L, 91)
    assert np.allclose(up.position(s), down.position(L - s), rtol=0, atol=1e-9 * L)
    assert np.allclose(up.tension(s), down.tension(L - s), rtol=1e-10)
    assert np.allclose(up.force_at(s), -down.force_at(L - s), rtol=0, atol=1e-9 * w * L)
    assert up.touchdown == 0.0 and up.liftoff == pytest.approx(L - down.touchdown, rel=1e-12)


def test_both_ends_above_the_seabed_with_the_middle_lying_on_it():
    """A long tether from a ship to a vehicle both above the seabed, its middle on the seabed: two
    inextensible catenaries with horizontal touchdowns, s_h = sqrt(h^2 + 2 h H / w) and span
    x = (H / w) asinh(w s_h / H) each (Irvine), joined by a straight lying part with the same H."""
    w, L, zg = 50.0, 480.0, -100.0
    law = TensionLaw(CableProperties(EA=1e12))
    A, B = np.array([0.0, 0.0, 0.0]), np.array([0.0, 380.0, -70.0])
    sol = catenary_between(A, B, L, w, law, seabed_z=zg)

    def part(H, h):
        sh = math.sqrt(h * h + 2.0 * h * H / w)
        return sh, H / w * math.asinh(w * sh / H)

    def span(H):
        (sa, xa), (sb, xb) = part(H, 100.0), part(H, 30.0)
        return xa + xb + (L - sa - sb) - 380.0

    H = brentq(span, 1.0, 1e6, xtol=1e-12)
    assert np.linalg.norm(sol.T0[:2]) == pytest.approx(H, rel=1e-6)
    assert sol.touchdown == pytest.approx(part(H, 100.0)[0], rel=1e-6)
    assert L - sol.liftoff == pytest.approx(part(H, 30.0)[0], rel=1e-6)
    s = np.linspace(0.0, L, 601)
    r = sol.position(s)
    assert np.allclose(r[[0, -1]], [A, B], atol=1e-6)
    assert np.all(r[:, 2] >= zg - 1e-6)
    assert np.allclose(r[(s > sol.touchdown + 1e-6) & (s < sol.liftoff - 1e-6), 2], zg, atol=1e-6)
    T = sol.force_at([0.0, L])
    assert T[1, 2] - T[0, 2] == pytest.approx(w * (sol.touchdown + L - sol.liftoff), rel=1e-12)
    assert T[1, 2] == pytest.approx(w * part(H, 30.0)[0], rel=1e-6)  # the vehicle end carries its hanging part
