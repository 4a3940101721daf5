"""The numpy CDR encoders of the per-tick outputs against rclpy (Fast CDR): for random values, point
counts and frame-name lengths (every padding case of the 8-byte alignment), the bytes must
deserialize to exactly the message built as rclpy objects, and have the length of rclpy's own
serialization (which leaves padding bytes uninitialised and may append a few bytes of slack, so
the bytes themselves are not compared). A misplaced field or padding would shift every later
value, and random values make an accidental match impossible."""

import numpy as np
import pytest

pytest.importorskip("rclpy")
pytest.importorskip("tether_sim_msgs")
from builtin_interfaces.msg import Time  # noqa: E402
from geometry_msgs.msg import AccelStamped, Point, PoseStamped, TwistStamped, Vector3, WrenchStamped  # noqa: E402
from nav_msgs.msg import Path  # noqa: E402
from rclpy.serialization import deserialize_message, serialize_message  # noqa: E402
from std_msgs.msg import ColorRGBA, Header  # noqa: E402
from tether_sim_msgs.msg import TetherState, WinchState  # noqa: E402
from visualization_msgs.msg import Marker  # noqa: E402

from tether_sim.ros import cdr  # noqa: E402
from tether_sim.ros.convert import tension_colours  # noqa: E402

pytestmark = pytest.mark.ros

# frame names of length 0..4 and 9 move the following doubles through every padding (0..7 bytes)
FRAMES = ["", "a", "ma", "map", "odom", "base_link"]
COUNTS = [1, 2, 5, 41]


def _header(stamp, frame):
    return Header(stamp=Time(sec=stamp[0], nanosec=stamp[1]), frame_id=frame)


def _points(a, kind=Point):
    return [kind(x=x, y=y, z=z) for x, y, z in a.tolist()]


def _check(data, expected):
    assert isinstance(data, bytes) and data[:4] == b"\x00\x01\x00\x00"  # CDR little endian
    assert deserialize_message(data, type(expected)) == expected  # every field, floats exactly
    reference = serialize_message(expected)
    assert len(reference) - 8 <= len(data) <= len(reference)
    with pytest.raises(Exception, match="deserializ"):  # no slack of ours: the last byte is a field's
        deserialize_message(data[:-1], type(expected))


@pytest.mark.parametrize("frame", FRAMES)
@pytest.mark.parametrize("n", COUNTS)
def test_tether_state(frame, n):
    rng = np.random.default_rng(n + len(frame))
    s, p, v, T, k, m = (rng.normal(size=shape) * 1e3 for shape in ((n,), (n, 3), (n, 3), (n,), (n,), (n,)))
    stamp = cdr.stamp_parts(1234.5678901234)
    for solver in ("dg", "hybrid"):
        data = cdr.tether_state(stamp, frame, solver, s, p, v, T, k, m, 86819.1, 43055.6, 2.5e-4, 7.3)
        expected = TetherState(header=_header(stamp, frame), solver=solver, arc_length=s.tolist(),
                               position=_points(p), velocity=_points(v, Vector3), tension=T.tolist(),
                               curvature=k.tolist(), bending_moment=m.tolist(), ship_end_tension=86819.1,
                               vehicle_end_tension=43055.6, time_step=2.5e-4, real_time_factor=7.3)
        _check(data, expected)


@pytest.mark.parametrize("frame", FRAMES)
@pytest.mark.parametrize("n", COUNTS)
def test_marker_line_strip(frame, n):
    rng = np.random.default_rng(n)
    p = rng.normal(size=(n, 3)) * 100
    tension = rng.normal(size=n) * 5e4  # includes slack (T < 0) and over-scale values
    colours = tension_colours(tension, 6e4)
    stamp = (17, 999_999_999)
    for ns in ("", "tether", "tether5"):
        data = cdr.marker_line_strip(stamp, frame, ns, 3, 0.2, (1.0, 1.0, 0.0, 1.0), p, colours)
        expected = Marker(header=_header(stamp, frame), ns=ns, id=3, type=Marker.LINE_STRIP, action=Marker.ADD)
        expected.pose.orientation.w = 1.0
        expected.scale.x = 0.2
        expected.color = ColorRGBA(r=1.0, g=1.0, b=0.0, a=1.0)
        expected.points = _points(p)
        wire = colours.astype(np.float32).astype(float).tolist()  # ColorRGBA is float32 on the wire
        expected.colors = [ColorRGBA(r=r, g=g, b=b, a=a) for r, g, b, a in wire]
        _check(data, expected)


def test_tension_colours_blue_green_red():
    """Slack (T <= 0) blue, half the scale green, at or above the scale red, linear in between; alpha 1."""
    c = tension_colours([-5.0, 0.0, 25.0, 50.0, 75.0, 100.0, 500.0], 100.0)
    np.testing.assert_array_equal(c, [[0, 0, 1, 1], [0, 0, 1, 1], [0, 0.5, 0.5, 1], [0, 1, 0, 1], [0.5, 0.5, 0, 1],
                                      [1, 0, 0, 1], [1, 0, 0, 1]])


@pytest.mark.parametrize("frame", FRAMES)
@pytest.mark.parametrize("n", COUNTS)
def test_path(frame, n):
    p = np.random.default_rng(n).normal(size=(n, 3))
    stamp = (5, 250_000_000)
    expected = Path(header=_header(stamp, frame))
    for x, y, z in p.tolist():
        pose = PoseStamped(header=_header(stamp, frame))
        pose.pose.position = Point(x=x, y=y, z=z)
        pose.pose.orientation.w = 1.0
        expected.poses.append(pose)
    _check(cdr.path(stamp, frame, p), expected)


@pytest.mark.parametrize("frame", FRAMES)
def test_wrench_and_pose(frame):
    stamp = (0, 1)
    f, t, q = np.array([1.5, -2.0, 3e4]), np.array([0.1, 0.2, -0.3]), np.array([0.1, 0.2, 0.3, 0.9])
    w = WrenchStamped(header=_header(stamp, frame))
    w.wrench.force, w.wrench.torque = Vector3(x=1.5, y=-2.0, z=3e4), Vector3(x=0.1, y=0.2, z=-0.3)
    _check(cdr.wrench_stamped(stamp, frame, f, t), w)
    pose = PoseStamped(header=_header(stamp, frame))
    pose.pose.position = Point(x=1.5, y=-2.0, z=3e4)
    pose.pose.orientation.x, pose.pose.orientation.y, pose.pose.orientation.z, pose.pose.orientation.w = q.tolist()
    _check(cdr.pose_stamped(stamp, frame, f, q), pose)


@pytest.mark.parametrize("frame", FRAMES)
def test_twist_and_accel(frame):
    """A network body's velocity and acceleration (network_outputs: <body>/sim_twist, <body>/sim_accel)."""
    stamp = (12, 345)
    lin, ang = np.array([0.25, -1.5, 7e-3]), np.array([-0.01, 0.02, 3.5])
    for encode, kind, fields in ((cdr.twist_stamped, TwistStamped, "twist"), (cdr.accel_stamped, AccelStamped, "accel")):
        msg = kind(header=_header(stamp, frame))
        inner = getattr(msg, fields)
        inner.linear, inner.angular = Vector3(x=0.25, y=-1.5, z=7e-3), Vector3(x=-0.01, y=0.02, z=3.5)
        _check(encode(stamp, frame, lin, ang), msg)


@pytest.mark.parametrize("frame", FRAMES)
@pytest.mark.parametrize("end, mode", [("ship", "speed"), ("vehicle", "length"), ("ship", "tension"), ("a", "")])
def test_winch_state(frame, end, mode):
    """Strings of every length before the 8-aligned doubles; every flag pattern; the layout kept per
    (frame, end, mode) carries each call's own values."""
    rng = np.random.default_rng(len(frame) + 7 * len(end) + 13 * len(mode))
    for flags in range(16):
        stamp = (int(rng.integers(0, 2**31 - 1)), int(rng.integers(0, 10**9)))
        values = rng.normal(size=5) * 1e3
        bits = [bool(flags >> k & 1) for k in range(4)]
        expected = WinchState(header=_header(stamp, frame), end=end, mode=mode, setpoint=values[0], length=values[1],
                              speed=values[2], commanded_speed=values[3], tension=values[4], speed_limited=bits[0],
                              acceleration_limited=bits[1], at_min_length=bits[2], at_max_length=bits[3])
        _check(cdr.winch_state(stamp, frame, end, mode, *values, *bits), expected)


def test_stamp_parts_rounds_to_nanoseconds_and_clamps_at_zero():
    assert cdr.stamp_parts(1.9999999996) == (2, 0)
    assert cdr.stamp_parts(3.25) == (3, 250_000_000)
    assert cdr.stamp_parts(-1.0) == (0, 0)


def test_a_reused_layout_carries_only_the_new_values():
    """The encoders keep one buffer per layout and rewrite its fields: a second message of the same
    layout must decode to its own values (no field left from the first), and a new point count (a
    winch) gets its own layout."""
    rng = np.random.default_rng(7)
    for n in (41, 41, 12, 41):
        p, v = rng.normal(size=(n, 3)), rng.normal(size=(n, 3))
        s, T, k, m = (rng.normal(size=n) for _ in range(4))
        stamp = (int(rng.integers(0, 2**31 - 1)), int(rng.integers(0, 10**9)))
        degraded = bool(rng.integers(0, 2))
        data = cdr.tether_state(stamp, "map", "dg", s, p, v, T, k, m, 1.0, 2.0, 3.0, 4.0, 0.5, degraded)
        _check(data, TetherState(header=_header(stamp, "map"), solver="dg", arc_length=s.tolist(), position=_points(p),
                                 velocity=_points(v, Vector3), tension=T.tolist(), curvature=k.tolist(),
                                 bending_moment=m.tolist(), ship_end_tension=1.0, vehicle_end_tension=2.0, time_step=3.0,
                                 real_time_factor=4.0, lag=0.5, degraded=degraded))
        expected = Path(header=_header(stamp, "map"))
        for x, y, z in p.tolist():
            pose = PoseStamped(header=_header(stamp, "map"))
            pose.pose.position = Point(x=x, y=y, z=z)
            pose.pose.orientation.w = 1.0
            expected.poses.append(pose)
        _check(cdr.path(stamp, "map", p), expected)
        w = WrenchStamped(header=_header(stamp, "ship/base_link"))
        w.wrench.force, w.wrench.torque = Vector3(x=p[0, 0], y=p[0, 1], z=p[0, 2]), Vector3(x=v[0, 0], y=v[0, 1], z=v[0, 2])
        _check(cdr.wrench_stamped(stamp, "ship/base_link", p[0], v[0]), w)
