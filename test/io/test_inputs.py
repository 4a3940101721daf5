"""Pose input validation, interpolation and velocity estimation (tether_sim.io.inputs), no ROS."""

import math

import numpy as np
import pytest

from tether_sim.io.inputs import EndPoseInput, rotation_matrix, slerp

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


def test_slerp_and_rotation_matrix():
    q = slerp(IDENTITY, yaw_quaternion(math.pi / 2), 0.5)
    np.testing.assert_allclose(q, yaw_quaternion(math.pi / 4), atol=1e-12)
    R = rotation_matrix(yaw_quaternion(math.pi / 2))
    np.testing.assert_allclose(R @ np.array([1.0, 0.0, 0.0]), (0.0, 1.0, 0.0), atol=1e-12)
    np.testing.assert_allclose(R.T @ R, np.eye(3), atol=1e-12)
