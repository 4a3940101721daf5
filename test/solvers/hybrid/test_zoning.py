"""Adaptive zoning: criterion chi = sqrt(EI w^2 / T^3) with hysteresis (docs/hybrid_solver.md)."""

import numpy as np

from tether_sim.scenarios.goyal_perkins import goyal_perkins_config, run_to_rest
from tether_sim.solvers.hybrid import zoning
from tether_sim.solvers.hybrid.solver import HybridRodCatenarySolver

EI, W = 2620.0, 25.3  # ROPOS tether with EI*: T_on = (EI w^2 / 0.3^2)^(1/3) = 188.6 N, T_off = 299.4 N


def test_switching_tensions_and_hysteresis():
    T_on = (EI * W**2 / 0.3**2) ** (1 / 3)
    T_off = (EI * W**2 / 0.15**2) ** (1 / 3)
    T = np.array([1e4, 1.01 * T_on, 0.99 * T_on, 0.0, -5.0, 0.5 * (T_on + T_off), 1.01 * T_off, 1e4])
    cat = np.zeros(T.size, dtype=int)
    z1 = zoning.classify(T, cat, EI, W, 0.3, 0.15, min_zone=1)
    assert z1.tolist() == [0, 0, 1, 1, 1, 0, 0, 0]  # from catenary: rod below T_on (and at T <= 0)
    rod = np.ones(T.size, dtype=int)
    z2 = zoning.classify(T, rod, EI, W, 0.3, 0.15, min_zone=1)
    assert z2.tolist() == [0, 1, 1, 1, 1, 1, 0, 0]  # from rod: back to catenary only above T_off


def test_short_zones_are_absorbed_and_held_ends_stay_rod():
    T = np.full(20, 1e4)
    T[8:10] = 0.0  # a 2-element rod island
    z = zoning.classify(T, np.zeros(20, dtype=int), EI, W, 0.3, 0.15, min_zone=4, end_rod=(0, 3))
    assert z[:17].sum() == 0 and np.all(z[17:] == 1)
    T = np.zeros(20)
    T[8:10] = 1e4  # a 2-element catenary gap inside rod
    z = zoning.classify(T, np.ones(20, dtype=int), EI, W, 0.3, 0.15, min_zone=4)
    assert np.all(z == 1)


def test_gp_benchmark_adaptive_zones_settle_without_chatter():
    solver = HybridRodCatenarySolver(goyal_perkins_config(zoning="adaptive", n_segments=50))
    run_to_rest(solver, t_max=100.0)
    zones = solver.zones
    # bending matters along the whole GP cable (docs/hybrid_solver.md "Zoning"): at rest even beside the
    # pinned end the rod's shear force is 14 % of its 8 mN tension (chi = sqrt(|f_shear|/T) = 0.37 > chi_on;
    # the weight alone gives 0.17), so a joint there would kink the catenary by 8 degrees: all rod
    assert np.all(zones == 1)
    count = solver.stats["rezonings"]
    solver.advance_to(solver.time + 10.0)
    assert solver.stats["rezonings"] == count  # at rest the zones do not chatter


# A slack excursion tether with bending (the TMS file's line: 30 m, EA 2 MN, 1.59 kg/m, 1000 kg/m^3, 45 mm,
# buoyant; EI = EA d^2 / 16 = 253 N m^2, PE2020's solid-section rule), from a driven end to a fixed end
# 20 m off and 15 m below, 30 segments, dt 5 ms, adaptive zoning (docs/hybrid_solver.md "Zoning").
EXC_EI = 253.125


def _excursion(zoning_kind="adaptive"):
    from tether_sim.config import SimConfig
    from tether_sim.physics.boundary import EndCondition
    from tether_sim.physics.cable import CableProperties
    from tether_sim.physics.environment import Environment
    from tether_sim.solvers.config import HybridOptions, InitialState
    cab = CableProperties(length=30.0, EA=2e6, gamma0=1.59, density=1000.0, diameter=0.045, EI=EXC_EI,
                          damping=2000.0, material="bilinear", Cdn=1.2, Cdt=0.02, Cmn=1.0, Cmt=0.0)
    cfg = SimConfig(solver="hybrid", cable=cab, environment=Environment(g=9.81, fluid_density=1025.0),
                    ship_end=EndCondition(kind="prescribed", position=(0.0, 0.0, 0.0)),
                    vehicle_end=EndCondition(kind="fixed", position=(20.0, 0.0, -15.0)),
                    hybrid=HybridOptions(n_segments=30, time_step=0.005, zoning=zoning_kind),
                    initial=InitialState(kind="static"))
    return HybridRodCatenarySolver(cfg)


def test_a_sheared_or_bent_rod_element_stays_rod():
    # at T = 50 N the weight alone gives chi = 0.016 (catenary); a rod element carrying a shear force of
    # 30 N (chi = sqrt(30/50) = 0.77) or a curvature of 0.5 1/m (chi = sqrt(EI/T) 0.5 = 1.1) keeps it
    T = np.full(6, 50.0)
    rod = np.ones(6, dtype=int)
    w = 0.39
    plain = zoning.classify(T, rod, EXC_EI, w, 0.3, 0.15, min_zone=1)
    assert np.all(plain == 0)
    shear = np.array([0.0, 0.0, 30.0, 0.0, 0.0, 0.0])
    kappa = np.array([0.0, 0.0, 0.0, 0.0, 0.5, 0.0])
    z = zoning.classify(T, rod, EXC_EI, w, 0.3, 0.15, min_zone=1, kappa_elem=kappa, shear_elem=shear)
    assert z.tolist() == [0, 0, 1, 0, 1, 0]
    # the static catenary's own curvature and shear (w/T, EI w^2/T^2) give back the weight criterion
    chi = zoning.tension_ratio(T, EXC_EI, w, kappa_elem=w / T, shear_elem=EXC_EI * w**2 / T**2)
    assert np.allclose(chi, np.sqrt(EXC_EI * w**2 / T**3), rtol=1e-12)


def test_new_catenary_cells_close_on_the_held_end():
    """A rod zone's shape integrated from its tangents misses the fixed end (rate-form compatibility);
    the catenary taking over the last elements starts with its position-form cell equation closed."""
    from tether_sim.solvers.hybrid.layout import CAT_EPS, CAT_TAN
    from tether_sim.solvers.hybrid.state_io import convert_state
    s = _excursion("all_rod")
    fixed = np.array([20.0, 0.0, -15.0])
    assert np.linalg.norm(s.positions[-1] - fixed) > 1e-3  # the rod's own shape misses by millimetres
    new = s.zones.copy()
    new[-5:] = zoning.CATENARY
    Y, _, _, pos, _ = convert_state(s, new)
    assert np.allclose(pos[-1], fixed, atol=1e-12)
    K = len(pos)
    for c in range(K - 6, K - 1):  # the five catenary cells: (r_b - r_a) = ds mean((1 + eps) t)
        ta, tb = (Y[k, CAT_TAN:CAT_TAN + 3] / np.linalg.norm(Y[k, CAT_TAN:CAT_TAN + 3]) for k in (c, c + 1))
        chord = 0.5 * s.ds * ((1 + Y[c, CAT_EPS]) * ta + (1 + Y[c + 1, CAT_EPS]) * tb)
        assert np.allclose(pos[c + 1] - pos[c], chord, atol=1e-12)


def test_adaptive_zoning_with_bending_runs_through_a_jerk():
    """The driven end heaves 1 m at 2 rad/s: the slack line is jerked taut twice in 3 s. Before the
    zoning took the rod's own shear and curvature and anchored new catenary cells, the rod-to-catenary
    switch at the jerk put the rod shape's miss into one catenary cell (0.5 MN) and Newton failed at
    2.18 s. Bound: an end moving at v jerks a line taut with at most its axial impedance force
    sqrt(EA gamma0) v, doubled at a fixed end's reflection: 2 x 1783 N s/m x 2 m/s = 7.1 kN."""
    s = _excursion()
    for k in range(1, 151):
        t = 0.02 * k
        s.set_end_motion("ship", np.array([0.0, 0.0, np.sin(2.0 * t)]), np.array([0.0, 0.0, 2.0 * np.cos(2.0 * t)]))
        s.advance_to(t)
    _, ship, vehicle = s.drain_end_tensions()
    bound = 2.0 * np.sqrt(2e6 * 1.59) * 2.0
    assert max(ship.max(), vehicle.max()) < bound, (ship.max(), vehicle.max())
    assert s.stats["rezonings"] > 2  # the zoning did switch (rod while slack, catenary taut)
