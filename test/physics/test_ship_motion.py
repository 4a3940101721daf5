"""Ship motion from a sea state through an RAO table (physics/ship_motion.py, motion kind ``rao``).

Closed forms: a regular wave at a tabulated frequency gives each DOF a |RAO| cos(w t - psi + eps) exactly;
a unit heave RAO reproduces the wave elevation at the ship's reference point for any sea (the ship and the
cable see the same components); the lever arm adds w x (R r); headings interpolate periodically, phases
along the shorter arc. Tolerances: 1e-12 relative where the evaluation is the same sum of cosines in
another order (round-off); finite differences O(h^2) with h = 1e-3 s on motions of period >= 2 s.
"""

import math
from dataclasses import replace

import numpy as np
import pytest

from tether_sim.config import SimConfig
from tether_sim.physics.motion import MotionConfig, RaoMotion, build_motion
from tether_sim.physics.ship_motion import (fairlead_offset, fairlead_position_velocity_many, lever_arm_kinematics,
                                            parse_rao_table, rao_at, read_rao_table, ShipResponse)
from tether_sim.physics.waves import WaveConfig, wave_components, wave_elevation

SHIPPED = "config/rao_support_vessel_80m.txt"


def table_text(rows):
    return "\n".join(" ".join(f"{v:.10g}" for v in r) for r in rows)


def grid_table(headings, omegas, fun):
    """A table text whose (amp, phase_deg) per DOF is fun(heading, omega) -> (6,), (6,)."""
    rows = []
    for h in headings:
        for w in omegas:
            a, p = fun(h, w)
            rows.append([h, w] + [x for pair in zip(a, p) for x in pair])
    return table_text(rows)


AMPS = np.array([0.8, 0.3, 1.1, 2.0, 1.5, 0.4])  # m/m and deg/m
PHASES = np.array([-90.0, 30.0, 10.0, -120.0, 75.0, 160.0])  # deg


def regular_config(direction=30.0, period=8.0, height=2.0, phase=40.0, depth=0.0):
    return SimConfig(waves=WaveConfig(kind="regular", height=height, period=period, direction=direction,
                                      phase=phase, depth=depth))


def test_regular_wave_gives_the_rao_amplitude_and_phase_exactly():
    cfg = regular_config()
    waves = wave_components(cfg)
    w = float(waves.omega[0])
    # wave heading relative to a ship heading 100 deg: 30 - 100 = -70 = 290 deg, a tabulated heading
    table = parse_rao_table(grid_table([0.0, 290.0], [0.5 * w, w, 2.0 * w], lambda h, om: (AMPS * (h == 290.0) * (om == w), PHASES)))
    ref = np.array([120.0, -40.0, 0.0])
    resp = ShipResponse(table, waves, ref, heading_deg=100.0)
    a, k, b = 1.0, float(waves.k[0]), math.radians(30.0)
    psi = k * (ref[0] * math.cos(b) + ref[1] * math.sin(b)) + math.radians(40.0)
    amp = AMPS.copy()
    amp[3:] = np.radians(amp[3:])
    for t in (0.0, 1.3, 7.7, 55.0):
        eta_ref = wave_elevation(ref[0], ref[1], t, *waves.arrays())
        assert eta_ref == pytest.approx(a * math.cos(w * t - psi), abs=1e-12)
        q, qd, qdd = resp.dofs(t)
        expect = a * amp * np.cos(w * t - psi + np.radians(PHASES))
        np.testing.assert_allclose(q, expect, atol=1e-12)
        np.testing.assert_allclose(qd, -a * amp * w * np.sin(w * t - psi + np.radians(PHASES)), atol=1e-12)
        np.testing.assert_allclose(qdd, -w * w * expect, atol=1e-12)


@pytest.mark.parametrize("heading", [0.0, 137.0])
def test_unit_heave_rao_reproduces_the_cable_sea_at_the_reference_point(heading):
    cfg = SimConfig(waves=WaveConfig(kind="jonswap", Hs=3.0, Tp=9.0, n_frequencies=40, n_directions=5, spreading=4.0,
                                     direction=20.0, seed=7, depth=300.0))
    waves = wave_components(cfg)
    unit = lambda h, w: (np.array([0, 0, 1.0, 0, 0, 0]), np.zeros(6))  # noqa: E731
    table = parse_rao_table(grid_table([0.0, 180.0], [0.1, 5.0], unit))
    origin = np.array([35.0, 12.0, 0.0])
    motion = RaoMotion(origin, table, waves, (0.0, 0.0, 0.0), heading)
    for t in (0.0, 3.1, 47.9, 600.2):
        p, v, _ = motion.at(t)
        assert p[2] == pytest.approx(wave_elevation(origin[0], origin[1], t, *waves.arrays()), abs=1e-12)
        np.testing.assert_allclose(p[:2], origin[:2], atol=1e-15)


def test_lever_arm_adds_omega_cross_r():
    cfg = regular_config(direction=90.0, period=10.0)  # beam sea for a ship heading 0: waves toward port
    waves = wave_components(cfg)
    roll_only = lambda h, w: (np.array([0, 0, 0, 3.0, 0, 0]), np.array([0, 0, 0, -90.0, 0, 0]))  # noqa: E731
    table = parse_rao_table(grid_table([0.0, 90.0, 180.0, 270.0], [0.3, 0.9], roll_only))
    r = np.array([-30.0, 8.0, 12.0])
    resp = ShipResponse(table, waves, np.zeros(3), 0.0)
    for t in (0.4, 2.9, 6.1):
        q, qd, _ = resp.dofs(t)
        p, v, a = fairlead_offset(resp, r, t)
        phi = q[3]
        R = np.array([[1, 0, 0], [0, math.cos(phi), -math.sin(phi)], [0, math.sin(phi), math.cos(phi)]])
        np.testing.assert_allclose(p, R @ r - r, atol=1e-12)
        np.testing.assert_allclose(v, np.cross([qd[3], 0, 0], R @ r), atol=1e-12)
    # general 6-DOF composition: velocity and acceleration are the derivatives of the position
    full = parse_rao_table(grid_table([0.0, 120.0, 240.0], [0.3, 0.9], lambda h, w: (AMPS * (1 + h / 240.0), PHASES + h)))
    resp = ShipResponse(full, waves, np.array([5.0, -3.0, 0.0]), 33.0)
    h = 1e-3
    for t in (1.0, 4.2):
        p0, v0, a0 = fairlead_offset(resp, r, t)
        pp, vp, _ = fairlead_offset(resp, r, t + h)
        pm, vm, _ = fairlead_offset(resp, r, t - h)
        # O(h^2) central differences: |p'''| h^2 / 6 ~ 1e-6 of |v| at w = 0.63 rad/s
        np.testing.assert_allclose((pp - pm) / (2 * h), v0, rtol=0, atol=1e-6 * (1 + np.abs(v0).max()))
        np.testing.assert_allclose((vp - vm) / (2 * h), a0, rtol=0, atol=1e-6 * (1 + np.abs(a0).max()))
        Rr, w_vec, _ = lever_arm_kinematics(*resp.dofs(t), r)
        assert np.linalg.norm(Rr) == pytest.approx(np.linalg.norm(r), rel=1e-14)  # a rotation, not a stretch


def test_heading_and_frequency_interpolation():
    phases = {0.0: 170.0, 90.0: -170.0, 180.0: 0.0, 270.0: 40.0}
    amps = {0.0: 1.0, 90.0: 3.0, 180.0: 2.0, 270.0: 0.0}
    table = parse_rao_table(grid_table(list(phases), [0.5, 1.5],
                                       lambda h, w: (np.full(6, amps[h] * w), np.full(6, phases[h]))))
    a, p = rao_at(table, 1.0, 45.0)
    np.testing.assert_allclose(a[:3], 0.5 * (1.0 + 3.0) * 1.0, rtol=1e-14)  # bilinear in heading and omega
    np.testing.assert_allclose(np.cos(p), -1.0, atol=1e-14)  # 170 -> -170 by the shorter arc: 180, not 0
    a, p = rao_at(table, 0.5, 315.0)  # periodic: between 270 and 360 = 0
    np.testing.assert_allclose(a[:3], 0.5 * (0.0 + 1.0) * 0.5, rtol=1e-14)
    np.testing.assert_allclose(p, math.radians(105.0), rtol=1e-14)  # 40 -> 170
    a, _ = rao_at(table, 0.5, -45.0)
    np.testing.assert_allclose(a[:3], 0.25, rtol=1e-14)
    np.testing.assert_allclose(a[3:], math.radians(0.25), rtol=1e-14)  # rotations given in deg/m
    with pytest.raises(ValueError, match="rad/s"):
        rao_at(table, 2.0, 0.0)


def test_bad_tables_are_refused_with_a_reason():
    with pytest.raises(ValueError, match="14 columns"):
        parse_rao_table("0 0.5 1 2 3")
    with pytest.raises(ValueError, match="full grid"):
        parse_rao_table(table_text([[0, 0.5] + [1, 0] * 6, [0, 1.0] + [1, 0] * 6, [90, 0.5] + [1, 0] * 6]))
    with pytest.raises(ValueError, match="negative"):
        parse_rao_table(table_text([[0, 0.5, -1.0, 0] + [1, 0] * 5]))
    with pytest.raises(ValueError, match="no data"):
        parse_rao_table("# nothing\n")
    with pytest.raises(ValueError, match="rao_path"):
        build_motion(MotionConfig(kind="rao"), np.zeros(3), wave_components(regular_config()))
    with pytest.raises(ValueError, match="sea state"):
        build_motion(MotionConfig(kind="rao", rao_path=SHIPPED), np.zeros(3))


def test_shipped_table_through_the_motion_kind():
    """The illustrative table drives the fairlead: mean position = origin, ramp from rest, same sea."""
    table = read_rao_table(SHIPPED)
    assert table.headings.size == 12 and table.omegas[0] <= 0.2 and table.omegas[-1] >= 3.0
    cfg = SimConfig(waves=WaveConfig(kind="jonswap", Hs=3.0, Tp=9.0, direction=60.0))
    waves = wave_components(cfg)
    mc = MotionConfig(kind="rao", rao_path=SHIPPED, rao_lever_arm=(-35.0, 0.0, 5.0), ship_heading=0.0, ramp_time=20.0)
    origin = np.array([0.0, 0.0, 5.0])
    motion = build_motion(mc, origin, waves)
    p0, v0, a0 = motion.at(0.0)
    np.testing.assert_array_equal(p0, origin)
    np.testing.assert_array_equal(v0, 0.0)
    z = np.array([motion.at(t)[0][2] for t in np.arange(20.0, 1820.0, 0.5)]) - origin[2]
    # a stern A-frame in a Hs 3 m sea moves by metres, not centimetres nor tens of metres
    assert 0.3 < 4.0 * z.std() < 6.0
    # the same seed gives the same ship
    again = build_motion(replace(mc), origin, wave_components(cfg))
    np.testing.assert_array_equal(again.at(123.4)[0], motion.at(123.4)[0])


def test_position_velocity_paths_are_the_same_numbers_as_at():
    """The forecast members' paths (no acceleration; a whole horizon at once) give the numbers of
    ``at`` bit for bit: the slack-snap dynamics amplify round-off (docs/forecast.md), so an exact forecast
    must command exactly what the run commands. A short-crested JONSWAP sea through the shipped table,
    the benchmark's A-frame lever arm, with rotations large enough that every term counts."""
    cfg = SimConfig(waves=WaveConfig(kind="jonswap", Hs=6.0, Tp=9.0, n_frequencies=12, n_directions=3, spreading=6.0,
                                     direction=195.0, seed=4))
    motion = RaoMotion(np.array([3.0, -2.0, 5.0]), read_rao_table(SHIPPED), wave_components(cfg), (-35.0, 0.0, 5.0),
                       20.0, ramp_time=10.0)
    ts = np.concatenate([np.linspace(0.0, 12.0, 25), 40.0 + 0.1 * np.arange(1, 151) + 0.013])  # in and after the ramp
    ref = [motion.at(t) for t in ts]
    for t, (p, v, _) in zip(ts, ref):
        p2, v2 = motion.position_velocity(t)
        assert np.array_equal(p, p2) and np.array_equal(v, v2)
        d, dd, _ = fairlead_offset(motion.response, motion.lever, t)
        d2, dd2, none = fairlead_offset(motion.response, motion.lever, t, acceleration=False)
        assert none is None and np.array_equal(d, d2) and np.array_equal(dd, dd2)
    P, V = motion.position_velocity_many(ts)
    assert np.array_equal(P, np.array([r[0] for r in ref])) and np.array_equal(V, np.array([r[1] for r in ref]))
    D, DD = fairlead_position_velocity_many(motion.response, motion.lever, ts)
    assert np.array_equal(D, np.array([fairlead_offset(motion.response, motion.lever, t)[0] for t in ts]))
    assert np.abs(np.array([r[0] for r in ref]) - motion.origin).max() > 1.0  # the sea moves the fairlead by metres
