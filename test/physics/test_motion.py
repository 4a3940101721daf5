"""Fairlead motion generators: exact kinematics, smooth ramp, recorded series."""

import math
from pathlib import Path

import numpy as np
import pytest

from tether_sim.physics.motion import MotionConfig, RecordedMotion, build_motion, ramp

ORIGIN = np.array([1.0, -2.0, 0.0])
RECORD = Path(__file__).resolve().parents[2] / "data" / "ropos_ship_heave.mcap"


def numeric_derivatives(gen, t, h=1e-4):
    p0, _, _ = gen.at(t - h)
    p1, v1, a1 = gen.at(t)
    p2, _, _ = gen.at(t + h)
    return (p2 - p0) / (2 * h), (p2 - 2 * p1 + p0) / h**2, v1, a1


def test_circle_orbit_radius_speed_and_plane():
    cfg = MotionConfig(kind="circle", amplitude=2.0, frequency=0.2, plane_azimuth=math.pi / 2)
    gen = build_motion(cfg, ORIGIN)
    w = 2 * math.pi * 0.2
    for t in np.linspace(0.0, 5.0, 11):
        p, v, a = gen.at(t)
        assert np.linalg.norm(p - ORIGIN) == pytest.approx(2.0, rel=1e-12)
        assert np.linalg.norm(v) == pytest.approx(2.0 * w, rel=1e-12)
        assert a == pytest.approx(-w * w * (p - ORIGIN), abs=1e-12)
        assert p[0] == pytest.approx(ORIGIN[0], abs=1e-12)  # azimuth pi/2: the y-z plane
    assert gen.at(0.0)[0] == pytest.approx(ORIGIN + [0, 0, 2.0])  # orbit starts at its top


def test_ramp_is_c2_and_derivatives_consistent():
    assert ramp(0.0, 5.0) == (0.0, 0.0, 0.0) and ramp(5.0, 5.0) == (1.0, 0.0, 0.0)
    cfg = MotionConfig(kind="circle", amplitude=2.0, frequency=0.25, ramp_time=4.0)
    gen = build_motion(cfg, ORIGIN)
    p, v, a = gen.at(0.0)
    assert p == pytest.approx(ORIGIN) and v == pytest.approx(np.zeros(3)) and a == pytest.approx(np.zeros(3))
    for t in (0.7, 2.0, 3.9, 6.0):
        vn, an, v, a = numeric_derivatives(gen, t)
        # central differences, h = 1e-4 s: truncation ~1e-8 (v) and roundoff ~1e-8/h^2 ~ 1e-4 (a)
        assert v == pytest.approx(vn, abs=1e-6)
        assert a == pytest.approx(an, abs=1e-3)


def test_heave_and_sum_of_sines():
    gen = build_motion(MotionConfig(kind="heave", amplitude=1.5, frequency=0.1), ORIGIN)
    p, v, _ = gen.at(2.5)  # quarter period
    assert p == pytest.approx(ORIGIN + [0, 0, 1.5]) and v == pytest.approx(np.zeros(3), abs=1e-12)
    cfg = MotionConfig(kind="sines", sine_amplitudes=(1.0, 0.5), sine_frequencies=(0.1, 0.3), sine_phases=(0.0, 1.0))
    gen = build_motion(cfg, ORIGIN)
    t = 3.3
    z = math.sin(2 * math.pi * 0.1 * t) + 0.5 * math.sin(2 * math.pi * 0.3 * t + 1.0)
    assert gen.at(t)[0][2] == pytest.approx(z, rel=1e-12)
    vn, an, v, a = numeric_derivatives(gen, t)
    assert v == pytest.approx(vn, abs=1e-6) and a == pytest.approx(an, abs=1e-3)
    with pytest.raises(ValueError, match="equal lengths"):
        build_motion(MotionConfig(kind="sines", sine_amplitudes=(1.0,), sine_frequencies=(0.1, 0.2)), ORIGIN)


def test_recorded_series_interpolates_samples_and_scales():
    t = np.arange(0.0, 20.0, 0.1)
    pos = np.c_[np.zeros_like(t), np.zeros_like(t), 3.0 + np.sin(0.5 * t)]
    gen = RecordedMotion(ORIGIN, t + 100.0, pos, scale=1.2)
    # Knots are reproduced exactly (relative to the first sample, scaled); spline error between
    # knots for sin(0.5 t) at h = 0.1 s is ~ h^4 w^4 / 384 ~ 2e-8 (away from the natural ends).
    assert gen.at(5.0)[0][2] == pytest.approx(1.2 * math.sin(2.5), abs=1e-12)
    assert gen.at(7.05)[0][2] == pytest.approx(1.2 * math.sin(3.525), abs=1e-6)
    assert gen.at(7.05)[1][2] == pytest.approx(1.2 * 0.5 * math.cos(3.525), abs=1e-5)
    assert gen.at(-1.0)[0] == pytest.approx(ORIGIN)
    assert gen.at(100.0)[1] == pytest.approx(np.zeros(3))
    with pytest.raises(ValueError, match="increasing"):
        RecordedMotion(ORIGIN, t[::-1], pos)


def test_synthetic_ship_record_from_mcap():
    cfg = MotionConfig(kind="record", record_path=str(RECORD), record_topic="/ship/pose")
    gen = build_motion(cfg, ORIGIN)
    assert gen.duration == pytest.approx(599.9)
    z = np.array([gen.at(t)[0][2] for t in np.arange(0.0, 600.0, 0.1)]) - ORIGIN[2]
    # Documented properties of tools/make_ropos_record.py: starts at rest, largest wave 4 m.
    assert abs(z[0]) < 1e-9 and np.ptp(z) < 4.5
    up = np.where((z[:-1] < 0) & (z[1:] >= 0))[0]
    h = max(np.ptp(z[a:b + 1]) for a, b in zip(up[:-1], up[1:]))
    assert h == pytest.approx(4.0, abs=0.01)
    with pytest.raises(ValueError, match="no messages"):
        build_motion(MotionConfig(kind="record", record_path=str(RECORD), record_topic="/nope"), ORIGIN)
    with pytest.raises(FileNotFoundError, match="record_path"):
        build_motion(MotionConfig(kind="record", record_path="missing.mcap"), ORIGIN)
