"""The closed forms of tether_sim.scenarios.references, each checked independently (no solver)."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from tether_sim.scenarios import references as ref


def test_weight_speeds_and_added_mass():
    # Neutrally buoyant cable (rho_c = rho_f) weighs nothing; in vacuum w = gamma0 g.
    assert ref.submerged_weight(2.0, 1025.0, 1025.0) == pytest.approx(0.0, abs=1e-12)
    assert ref.submerged_weight(2.0, 7000.0, 0.0, g=9.81) == pytest.approx(19.62)
    assert ref.axial_wave_speed(1541.0, 0.702) == pytest.approx(46.853, rel=1e-4)
    assert ref.longitudinal_return_period(2.022, 1541.0, 0.702) == pytest.approx(2 * 2.022 / 46.853, rel=1e-4)
    assert ref.normal_added_mass(1000.0, 0.1, 1.0) == pytest.approx(1000.0 * np.pi * 0.0025)


def test_taut_string_frequency_in_stretched_coordinates():
    # Same frequency computed in the stretched length L(1+e) with mass per stretched metre m/(1+e).
    L, T, m, e, ma = 10.0, 200.0, 1.5, 0.02, 0.3
    Ls = L * (1 + e)
    expected = np.pi / Ls * np.sqrt(T / ((m + ma) / (1 + e)))
    assert ref.taut_string_frequency(1, L, T, m, e, ma) == pytest.approx(expected, rel=1e-14)
    assert ref.taut_string_frequency(3, L, T, m) == pytest.approx(3 * np.pi / L * np.sqrt(T / m))


def test_terminal_velocity_balances_weight_and_seabed_balances():
    w, rho, d, cd, e = 12.0, 1025.0, 0.03, 1.2, 0.01
    v = ref.terminal_velocity(w, rho, d, cd, e)
    assert 0.5 * rho * d * np.sqrt(1 + e) * cd * v * v == pytest.approx(w, rel=1e-14)  # Eq. 17
    delta = ref.seabed_sink_depth(w, 3e6, d)
    assert 3e6 * d * delta == pytest.approx(w)  # Eq. 15 at rest


def test_seabed_friction_opposes_velocity_and_saturates():
    f = ref.seabed_friction_force([0.3, -0.4], weight=10.0, mu=0.5, v_mu=0.01)
    assert np.dot(f, [0.3, -0.4]) < 0 and f[0] * -0.4 - f[1] * 0.3 == pytest.approx(0.0, abs=1e-12)
    assert np.linalg.norm(f) == pytest.approx(5.0, rel=1e-12)  # fully developed: mu w
    slow = ref.seabed_friction_force([0.001, 0.0], weight=10.0, mu=0.5, v_mu=0.01)
    assert slow[0] == pytest.approx(-5.0 * np.tanh(np.pi * 0.1))
    assert np.all(ref.seabed_friction_force([0.0, 0.0], 10.0, 0.5, 0.01) == 0.0)


def test_snap_front_speed_jump_conditions():
    EA, g0, V = 1.0e5, 2.0, 3.0
    c = ref.axial_wave_speed(EA, g0)
    S, e1 = ref.snap_front_speed(EA, g0, V, 0.0)
    assert S == pytest.approx(c, rel=1e-12)  # a just-slack cable snaps at c
    a = 1e-3
    S, e1 = ref.snap_front_speed(EA, g0, V, -a)
    assert S * (e1 + a) == pytest.approx(V)  # S [q] = -[v/gamma0]
    assert S * g0 * V == pytest.approx(EA * e1)  # S gamma0 [nu] = -[T]
    assert S < c


@pytest.mark.parametrize("span,rise", [(80.0, 0.0), (80.0, 30.0), (60.0, -50.0)])
def test_elastic_catenary_matches_direct_integration(span, rise):
    L, EA, w = 100.0, 2.0e4, 19.62
    cat = ref.elastic_catenary(L, EA, w, span, rise)
    assert cat.shape([L])[0] == pytest.approx([span, rise], abs=1e-9)

    def rhs(s, r):  # dr/ds = T/|T| + T/EA with T = (H, V0 + w s): independent of the closed form
        T = np.array([cat.H, cat.V0 + w * s])
        return T / np.linalg.norm(T) + T / EA

    s = np.linspace(0, L, 11)
    sol = solve_ivp(rhs, (0, L), [0.0, 0.0], t_eval=s, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(cat.shape(s), sol.y.T, atol=1e-8)
    # Vertical equilibrium: the two end vertical components carry the whole weight.
    assert cat.tension_vector([L])[0, 1] - cat.tension_vector([0.0])[0, 1] == pytest.approx(w * L)


def test_level_catenary_inextensible_limit():
    L, w = 100.0, 10.0
    cat = ref.elastic_catenary(L, 1e13, w, 80.0, 0.0)
    assert cat.V0 == pytest.approx(-0.5 * w * L, rel=1e-9)  # symmetric: half the weight per end
    # Rigid catenary: L = (2H/w) sinh(w X / 2H), sag = (H/w)(cosh(w X / 2H) - 1)
    assert 2 * cat.H / w * np.sinh(w * 80.0 / (2 * cat.H)) == pytest.approx(L, rel=1e-9)
    assert cat.sag() == pytest.approx(cat.H / w * (np.cosh(w * 40.0 / cat.H) - 1.0), rel=1e-6)


def test_vertical_hanging_cable():
    L, EA, w, F = 50.0, 1e4, 20.0, 100.0
    s = np.linspace(0, L, 101)
    depth, T = ref.vertical_hanging_cable(s, L, EA, w, F)
    assert T[0] == pytest.approx(w * L + F) and T[-1] == pytest.approx(F)
    # Stretch of each piece: d(depth)/ds = 1 + T/EA (checked by finite differences)
    np.testing.assert_allclose(np.gradient(depth, s, edge_order=2), 1 + T / EA, rtol=1e-12)
    assert depth[-1] - L == pytest.approx((w * L * L / 2 + F * L) / EA)


def test_axial_pulse_solution_solves_the_wave_problem():
    L, c, a, t0, sig = 1.0, 2.0, 1e-3, 0.3, 0.06
    t = 0.9
    s = np.linspace(0, L, 2001)
    u, ut, us = ref.axial_pulse_solution(s, t, L, c, a, t0, sig)
    assert u[0] == pytest.approx(ref.gaussian_pulse(t, a, t0, sig)[0], abs=1e-15)
    assert u[-1] == pytest.approx(0.0, abs=1e-15)
    np.testing.assert_allclose(us, np.gradient(u, s, edge_order=2), atol=2e-4 * a / sig)
    dt = 1e-6
    up = ref.axial_pulse_solution(s, t + dt, L, c, a, t0, sig)[0]
    um = ref.axial_pulse_solution(s, t - dt, L, c, a, t0, sig)[0]
    np.testing.assert_allclose(ut, (up - um) / (2 * dt), atol=1e-7 * a / sig)
    # At rest initially (the pulse starts 5 widths after t = 0).
    u0, ut0, _ = ref.axial_pulse_solution(s, 0.0, L, c, a, t0, sig)
    assert np.max(np.abs(u0)) < 1e-10 * a and np.max(np.abs(ut0)) < 1e-8 * a / sig


def test_cantilever_roots_modes_and_boundary_conditions():
    known = [1.8751040687, 4.6940911330, 7.8547574382, 10.9955407349, 14.1371683910]
    L = 100.0
    for i, k in enumerate(known, start=1):
        x = ref.cantilever_root(i)
        assert x == pytest.approx(k, abs=1e-9)
        assert 1 + np.cos(x) * np.cosh(x) == pytest.approx(0.0, abs=1e-7)  # Eq. 44
        assert abs(ref.cantilever_mode(L, i, L)) == pytest.approx(1.0, abs=1e-9)  # tip amplitude A
        assert ref.cantilever_mode(0.0, i, L) == 0.0 and ref.cantilever_mode(0.0, i, L, 1) == 0.0
        scale2, scale3 = (x / L) ** 2, (x / L) ** 3  # free end: no moment, no shear (Eq. 40)
        assert abs(ref.cantilever_mode(L, i, L, 2)) < 1e-8 * scale2
        assert abs(ref.cantilever_mode(L, i, L, 3)) < 1e-8 * scale3
    s = np.linspace(0, L, 4001)
    for d in range(3):
        np.testing.assert_allclose(np.gradient(ref.cantilever_mode(s, 3, L, d), s, edge_order=2),
                                   ref.cantilever_mode(s, 3, L, d + 1),
                                   atol=1e-4 * (ref.cantilever_root(3) / L) ** (d + 1))
    # Eq. 45 for the paper's beam: sqrt(EI/(m L^4)) = 0.01 1/s, so T1 = 2 pi / (1.87510^2 * 0.01).
    assert 2 * np.pi / ref.cantilever_omega(1, 1e5, 10.0, 100.0) == pytest.approx(178.702, rel=1e-5)


def test_ring_beam_circle_and_error_norm():
    s = np.linspace(0, 2 * np.pi, 501)
    r = ref.ring_beam_shape(s)
    np.testing.assert_allclose(np.linalg.norm(r - [0, 0, -1], axis=1), 1.0, rtol=1e-14)
    np.testing.assert_allclose(r[-1], [0, 0, 0], atol=1e-14)  # closes into a full ring
    assert ref.relative_l2_error(s, r, r) == 0.0
    assert ref.relative_l2_error(s, 1.01 * r, r) == pytest.approx(0.01, rel=1e-12)  # Eq. 34 scaling
    np.testing.assert_allclose(ref.convergence_rates([1e-2, 2.5e-3, 6.25e-4]), [2.0, 2.0])  # Eq. 36


def test_gauss_points_integrate_polynomials_exactly():
    s, w = ref.gauss_points(5, 4, 3.0)
    assert np.sum(w * s**7) == pytest.approx(3.0**8 / 8, rel=1e-13)
