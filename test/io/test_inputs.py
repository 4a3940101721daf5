"""Pose input validation, interpolation and velocity estimation (tether_sim.io.inputs), no ROS."""

import math

import numpy as np
import pytest

from tether_sim.io.inputs import EndPoseInput, slerp
from tether_sim.numerics.rotations import quaternion_matrix

IDENTITY = (0.0, 0.0, 0.0, 1.0)


def yaw_quaternion(psi):
    return (0.0, 0.0, math.sin(psi / 2), math.cos(psi / 2))


def circle(t, a=2.0, f=0.2):
    """Vertical circular orbit of radius a in the x-z plane [PE2020 Sec. 6.2]."""
    w = 2 * math.pi * f
    return (np.array([a * math.cos(w * t), 0.0, a * math.sin(w * t)]),
            np.array([-a * w * math.sin(w * t), 0.0, a * w * math.cos(w * t)]))


def test_hermite_interpolation_of_sampled_circle_without_twist():
    # 20 Hz samples of a 2 m, 0.2 Hz orbit. Central differences err by a*w^3*h^2/6 = 1.7e-3 m/s
    # (h = 0.05 s); a cubic Hermite with such slopes errs by at most ~h/4 * that = 2e-5 m in position
    # plus the exact-slope remainder a*w^4*h^4/384 ~ 1e-8 m. Tolerances: 1e-4 m and 1e-2 m/s.
    inp = EndPoseInput("ship")
    for k in range(41):
        assert inp.add_pose(k * 0.05, circle(k * 0.05)[0], IDENTITY) is None
    for t in np.linspace(0.1, 1.9, 37) + 0.013:
        p, v = inp.attachment_at(t)
        p_ref, v_ref = circle(t)
        assert np.linalg.norm(p - p_ref) < 1e-4
        assert np.linalg.norm(v - v_ref) < 1e-2


def test_twist_velocities_are_used_at_the_knots():
    inp = EndPoseInput("ship")
    for k in range(5):
        t = k * 0.1
        p, v = circle(t)
        assert inp.add_pose(t, p, IDENTITY) is None
        assert inp.add_twist(t, v, (0.0, 0.0, 0.0)) is None
    for k in range(1, 4):
        _, v = inp.attachment_at(k * 0.1)
        np.testing.assert_allclose(v, circle(k * 0.1)[1], atol=1e-12)


def test_attachment_offset_rotates_with_the_body_and_moves_with_its_spin():
    # yaw 90 deg maps body x onto world y; spin w_z = 0.5 rad/s gives v = w x (R r) = (-0.5*1, 0, 0)
    inp = EndPoseInput("ship", attachment=(1.0, 0.0, -2.0))
    assert inp.add_pose(0.0, (10.0, 0.0, 0.0), yaw_quaternion(math.pi / 2)) is None
    assert inp.add_twist(0.0, (0.0, 0.0, 0.0), (0.0, 0.0, 0.5)) is None
    p, v = inp.attachment_at(0.0)
    np.testing.assert_allclose(p, (10.0, 1.0, -2.0), atol=1e-12)
    np.testing.assert_allclose(v, (-0.5, 0.0, 0.0), atol=1e-12)


def test_body_frame_twist_is_rotated_to_the_world():
    inp = EndPoseInput("vehicle")
    inp.add_pose(0.0, (0.0, 0.0, 0.0), yaw_quaternion(math.pi / 2))
    assert inp.add_twist(0.0, (1.0, 0.0, 0.0), (0.0, 0.0, 0.0), body_frame=True) is None
    _, v = inp.attachment_at(0.0)
    np.testing.assert_allclose(v, (0.0, 1.0, 0.0), atol=1e-12)  # surge along world north


@pytest.mark.parametrize("stamp, position, orientation, reason", [
    (1.0, (math.nan, 0.0, 0.0), IDENTITY, "non-finite"),
    (1.0, (0.0, math.inf, 0.0), IDENTITY, "non-finite"),
    (1.0, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, math.nan), "non-finite"),
    (math.nan, (0.0, 0.0, 0.0), IDENTITY, "non-finite"),
    (1.0, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 0.0), "bad quaternion"),
    (0.4, (0.0, 0.0, 0.0), IDENTITY, "stamp not increasing"),
    (0.5, (0.1, 0.0, 0.0), IDENTITY, "stamp not increasing"),  # duplicate stamp
    (0.6, (5.0, 0.0, 0.0), IDENTITY, "jump"),  # 5 m in 0.1 s = 50 m/s > 20 m/s
])
def test_bad_samples_are_rejected_and_leave_the_history_unchanged(stamp, position, orientation, reason):
    inp = EndPoseInput("ship", max_end_speed=20.0)
    inp.add_pose(0.0, (0.0, 0.0, 0.0), IDENTITY)
    inp.add_pose(0.5, (0.0, 0.0, 0.0), IDENTITY)
    assert inp.add_pose(stamp, position, orientation) == reason
    assert inp.rejected[reason] == 1 and inp.accepted == 2
    assert inp.last_stamp == 0.5
    p, v = inp.attachment_at(0.5)
    np.testing.assert_array_equal(p, 0.0)


def test_a_displacement_becomes_acceptable_once_enough_time_has_passed():
    # 5 m at 20 m/s needs 0.25 s: rejected at dt = 0.1 s, accepted at dt = 0.3 s
    inp = EndPoseInput("ship", max_end_speed=20.0)
    inp.add_pose(0.0, (0.0, 0.0, 0.0), IDENTITY)
    assert inp.add_pose(0.1, (5.0, 0.0, 0.0), IDENTITY) == "jump"
    assert inp.add_pose(0.3, (5.0, 0.0, 0.0), IDENTITY) is None


def test_jump_is_judged_at_the_attachment_point():
    # a 180 deg yaw in 0.1 s swings a 10 m offset by 20 m (200 m/s) although the origin stays put
    inp = EndPoseInput("ship", attachment=(10.0, 0.0, 0.0), max_end_speed=20.0)
    inp.add_pose(0.0, (0.0, 0.0, 0.0), IDENTITY)
    assert inp.add_pose(0.1, (0.0, 0.0, 0.0), yaw_quaternion(math.pi)) == "jump"


def test_non_unit_quaternion_within_tolerance_is_normalised():
    inp = EndPoseInput("ship", attachment=(1.0, 0.0, 0.0))
    assert inp.add_pose(0.0, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.05)) is None
    np.testing.assert_allclose(inp.orientation_at(0.0), IDENTITY)
    np.testing.assert_allclose(inp.attachment_at(0.0)[0], (1.0, 0.0, 0.0))


def test_extrapolation_is_bounded_then_held():
    inp = EndPoseInput("ship", max_extrapolation=0.2)
    inp.add_pose(0.0, (0.0, 0.0, 0.0), IDENTITY)
    inp.add_pose(1.0, (1.0, 0.0, 0.0), IDENTITY)  # 1 m/s east
    p, v = inp.attachment_at(1.1)
    np.testing.assert_allclose(p, (1.1, 0.0, 0.0))
    np.testing.assert_allclose(v, (1.0, 0.0, 0.0))
    p, v = inp.attachment_at(3.0)
    np.testing.assert_allclose(p, (1.2, 0.0, 0.0))
    np.testing.assert_array_equal(v, 0.0)


def test_staleness_and_missing_input():
    inp = EndPoseInput("vehicle", input_timeout=1.0)
    assert inp.is_stale(0.0) and not inp.has_data
    with pytest.raises(LookupError):
        inp.attachment_at(0.0)
    inp.add_pose(10.0, (0.0, 0.0, -100.0), IDENTITY)
    assert not inp.is_stale(10.5)
    assert inp.is_stale(11.5)
    assert inp.health(11.5)["age"] == pytest.approx(1.5)


def test_reset_accepts_earlier_stamps_again():
    inp = EndPoseInput("ship")
    inp.add_pose(10.0, (0.0, 0.0, 0.0), IDENTITY)
    inp.reset()
    assert inp.add_pose(1.0, (0.0, 0.0, 0.0), IDENTITY) is None


def test_slerp_and_quaternion_matrix():
    q = slerp(IDENTITY, yaw_quaternion(math.pi / 2), 0.5)
    np.testing.assert_allclose(q, yaw_quaternion(math.pi / 4), atol=1e-12)
    R = quaternion_matrix(yaw_quaternion(math.pi / 2))
    np.testing.assert_allclose(R @ np.array([1.0, 0.0, 0.0]), (0.0, 1.0, 0.0), atol=1e-12)
    np.testing.assert_allclose(R.T @ R, np.eye(3), atol=1e-12)


# ---------------------------------------------------------------- timing against the node's clock
def test_stamps_are_checked_against_the_clock_with_distinct_reasons():
    inp = EndPoseInput("ship", future_tolerance=0.25, max_age=2.0, input_timeout=1.0)
    assert inp.add_pose(100.0, (0.0, 0.0, 0.0), IDENTITY, now=100.0) is None
    assert inp.add_pose(3700.0, (0.0, 0.0, 0.0), IDENTITY, now=100.1) == "stamp in the future"
    assert inp.add_pose(97.0, (0.0, 0.0, 0.0), IDENTITY, now=100.1) == "stamp too old"
    assert inp.add_pose(99.9, (0.0, 0.0, 0.0), IDENTITY, now=100.1) == "stamp not increasing"
    assert inp.add_pose(100.2, (0.0, 0.0, 0.0), IDENTITY, now=100.05) is None  # within the tolerance
    # the single future pose did not block the input: later valid poses are accepted
    for k in range(1, 6):
        assert inp.add_pose(100.2 + 0.1 * k, (0.0, 0.0, 0.0), IDENTITY, now=100.2 + 0.1 * k) is None
    assert dict(inp.rejected) == {"stamp in the future": 1, "stamp too old": 1, "stamp not increasing": 1}
    assert not inp.is_stale(100.8)


def test_stale_when_nothing_valid_arrives_whatever_the_stamps_say():
    # a pose accepted slightly in the future makes age() negative; silence still makes it stale
    inp = EndPoseInput("ship", future_tolerance=0.25, input_timeout=1.0)
    assert inp.add_pose(10.2, (0.0, 0.0, 0.0), IDENTITY, now=10.0) is None
    assert inp.age(10.1) < 0 and not inp.is_stale(10.1)
    for k in range(1, 30):  # only future-stamped poses from now on: all rejected
        assert inp.add_pose(20.0 + k, (0.0, 0.0, 0.0), IDENTITY, now=10.0 + 0.1 * k) == "stamp in the future"
    assert inp.is_stale(11.1) and inp.health(11.1)["since_accepted"] == pytest.approx(1.1)


# ---------------------------------------------------------------- history sized by time
def test_history_is_sized_by_time_and_correct_at_1_khz():
    # 1 kHz samples of a 2 m, 0.2 Hz orbit for 4 s; the node looks back input_delay + lag, here up
    # to 1.2 s. The buffer of 2026-11-21 kept 64 samples (0.064 s at 1 kHz): a query 0.2 s back returned the oldest
    # sample with zero velocity. Tolerances: h = 1 ms central differences err by a w^3 h^2 / 6 ~ 4e-7
    # m/s; Hermite position error ~ h * that ~ 1e-9 m -> 1e-6 m and 1e-4 m/s
    inp = EndPoseInput("ship", history_span=1.5)
    for k in range(4001):
        assert inp.add_pose(k * 1e-3, circle(k * 1e-3)[0], IDENTITY) is None
    assert 1.5 <= inp.span() < 1.5 + 0.065 and inp.health(4.0)["history_samples"] <= 1566
    for back in (0.0025, 0.2, 0.7, 1.2, 1.45):  # (the newest interval has a one-sided slope)
        t = 4.0 - back
        p, v = inp.attachment_at(t)
        p_ref, v_ref = circle(t)
        assert np.linalg.norm(p - p_ref) < 1e-6 and np.linalg.norm(v - v_ref) < 1e-4, back


def test_a_flood_is_capped_in_samples():
    inp = EndPoseInput("ship", history_span=10.0, max_samples=1000)
    for k in range(5000):  # 100 kHz flood
        inp.add_pose(k * 1e-5, (0.0, 0.0, 0.0), IDENTITY)
    assert len(inp._samples) <= 1000 + 63 and inp.accepted == 5000


def test_is_held_beyond_the_extrapolation():
    inp = EndPoseInput("ship", max_extrapolation=0.2)
    assert inp.is_held(0.0)
    inp.add_pose(1.0, (0.0, 0.0, 0.0), IDENTITY)
    assert not inp.is_held(1.1) and inp.is_held(1.3)


# ---------------------------------------------------------------- knots at least min_spacing apart
def test_a_catch_up_burst_with_stamp_jitter_gives_no_velocity_spike():
    # 20 Hz samples of a 0.5 m, 0.1 Hz heave (peak speed 0.314 m/s); at 2 s the publisher catches up
    # after a stall: poses 1 ms apart, the middle one's position read 30 ms before its stamp (9.4 mm).
    # Every sample a knot: a finite difference over 1 ms makes metres per second of it (the false snap
    # of the one-hour soak, docs/node.md). Knots at least 10 ms apart: the burst is one knot and the
    # velocity stays the heave's (central differences over 0.1 s err by a w^3 h^2 / 6 = 2e-4 m/s).
    w = 2 * math.pi * 0.1

    def heave(t):
        return (0.0, 0.0, 0.5 * math.sin(w * t))

    stamps = [0.05 * k for k in range(41)] + [2.001, 2.002, 2.003] + [2.05 + 0.05 * k for k in range(10)]
    speeds = {}
    for min_spacing in (0.0, 0.01):
        inp = EndPoseInput("ship", min_spacing=min_spacing)
        for s in stamps:
            assert inp.add_pose(s, heave(s - 0.03 if s == 2.002 else s), IDENTITY) is None
        speeds[min_spacing] = max(np.linalg.norm(inp.attachment_at(t)[1]) for t in np.linspace(1.9, 2.4, 2001))
        if min_spacing:
            gaps = np.diff(inp._stamps)
            assert gaps[:-1].min() >= min_spacing and inp.last_stamp == pytest.approx(2.5)
            for t in np.linspace(1.9, 2.4, 51):
                assert inp.attachment_at(t)[0][2] == pytest.approx(heave(t)[2], abs=1e-5)
    assert speeds[0.0] > 4.0 and speeds[0.01] < 0.315  # (measured 4.56 and 0.314 m/s)


def test_knots_of_a_fast_stream_are_min_spacing_apart_and_the_newest_sample_is_always_kept():
    inp = EndPoseInput("ship", min_spacing=0.01)
    for k in range(1001):  # 1 kHz for 1 s
        assert inp.add_pose(k * 1e-3, circle(k * 1e-3)[0], IDENTITY) is None
    gaps = np.diff(inp._stamps)
    assert gaps[:-1].min() >= 0.01 - 1e-12 and inp.last_stamp == pytest.approx(1.0) and inp.accepted == 1001
    for t in np.linspace(0.1, 0.95, 18):  # 10 ms knots: central differences err by a w^3 h^2 / 6 ~ 3e-4 m/s
        p, v = inp.attachment_at(t)
        assert np.linalg.norm(p - circle(t)[0]) < 1e-5 and np.linalg.norm(v - circle(t)[1]) < 2e-3
