"""tether_sim_msgs through rclpy: each custom message is published and received in-process.

Also checks the message definitions themselves: every field carries a comment (unit and frame).
"""

import re
import time
from pathlib import Path

import pytest

MSG_DIR = Path(__file__).resolve().parents[2] / "msg_defs" / "msg"
MESSAGES = ("TetherState", "SnapLoadEvent", "SlackWarning", "TetherDescription", "WinchCommand", "WinchState",
            "SnapForecast")
# units a numeric field comment must name (dimensionless quantities say "dimensionless")
UNIT = re.compile(r"(?<![\w/])(m|m/s|N|N m|N m\^2|1/m|kg/m|s|dimensionless|SI units)(?![\w/^])")


def _fields(name):
    """(type, field name, comment) of every field line of msg_defs/msg/<name>.msg."""
    rows = []
    for line in (MSG_DIR / f"{name}.msg").read_text().splitlines():
        code, _, comment = line.partition("#")
        parts = code.split()
        if len(parts) >= 2 and "=" not in code:
            rows.append((parts[0], parts[1], comment.strip()))
    return rows


@pytest.mark.parametrize("name", MESSAGES)
def test_every_field_is_documented_with_unit_or_frame(name):
    """Headers name their stamp and frame, times say so, strings say what they hold, numbers their unit."""
    rows = _fields(name)
    assert rows, f"{name}.msg has no fields"
    for kind, field, comment in rows:
        where = f"{name}.{field}: {comment!r}"
        assert comment, f"{name}.{field} has no comment"
        if kind == "std_msgs/Header":
            assert "stamp" in comment and "frame_id" in comment, where
        elif kind == "builtin_interfaces/Time":
            assert "time" in comment, where
        elif kind.startswith("string"):
            assert len(comment.split()) >= 3, where
        else:
            assert UNIT.search(comment), f"numeric field names no unit: {where}"
        if kind.startswith("geometry_msgs/"):
            assert "frame" in comment or "ENU" in comment, f"vector field names no frame: {where}"


def _filled(name):
    """A message of each type with every field set to a non-default value."""
    from builtin_interfaces.msg import Time
    from diagnostic_msgs.msg import KeyValue
    from geometry_msgs.msg import Point, Vector3
    from std_msgs.msg import Header

    import tether_sim_msgs.msg as m

    header = Header(stamp=Time(sec=12, nanosec=345), frame_id="map")
    if name == "TetherState":
        return m.TetherState(
            header=header, solver="dg", arc_length=[0.0, 100.0, 200.0],
            position=[Point(x=0.0, y=0.0, z=-1.0), Point(x=5.0, y=0.0, z=-100.0), Point(x=9.0, y=1.0, z=-199.5)],
            velocity=[Vector3(x=0.1, y=0.0, z=0.5), Vector3(x=0.0, y=0.2, z=0.0), Vector3(x=0.0, y=0.0, z=-0.3)],
            tension=[5100.0, 2500.0, 900.5], curvature=[0.0, 0.01, 0.02], bending_moment=[0.0, 1.5, 3.0],
            ship_end_tension=5100.0, vehicle_end_tension=900.5, time_step=2.5e-4, real_time_factor=1.7)
    if name == "SnapLoadEvent":
        return m.SnapLoadEvent(
            header=header, end=m.SnapLoadEvent.END_VEHICLE, arc_length=200.0, peak_tension=48000.0,
            min_tension=0.0, slack_start=Time(sec=11, nanosec=5), slack_duration=0.8, rise_time=0.05,
            static_tension=9000.0, amplification=48000.0 / 9000.0, criterion="slack_fraction")
    if name == "SlackWarning":
        return m.SlackWarning(header=header, end=m.SlackWarning.END_SHIP, arc_length=0.0, tension=420.0,
                              threshold=900.0, static_tension=9000.0)
    if name == "SnapForecast":
        return m.SnapForecast(header=header, end=m.SnapForecast.END_VEHICLE, horizon=20.0, probability=0.75,
                              time_to_snap=6.25, time_to_snap_std=0.4, predicted_peak=137000.0, members=8,
                              source=m.SnapForecast.SOURCE_KNOWN_SEA, degraded=True, reason="1 of 8 members diverged")
    if name == "WinchCommand":
        return m.WinchCommand(header=header, mode=m.WinchCommand.MODE_LENGTH, setpoint=1730.0)
    if name == "WinchState":
        return m.WinchState(header=header, end="ship", mode="tension", setpoint=60000.0, length=812.5, speed=-0.75,
                            commanded_speed=-1.2, tension=61234.5, speed_limited=True, acceleration_limited=True,
                            at_min_length=False, at_max_length=True)
    return m.TetherDescription(
        header=header, solver="hybrid", length=200.0, axial_stiffness=45.5e6, bending_stiffness=120.0,
        mass_per_length=3.01, diameter=0.03, wave_speed=(45.5e6 / 3.01) ** 0.5,
        ship_end_kind="prescribed", vehicle_end_kind="body", ship_frame="ship/base_link",
        vehicle_frame="rov/base_link", ship_attachment=Point(x=1.0, y=0.0, z=-2.0),
        vehicle_attachment=Point(x=0.0, y=0.0, z=0.5), output_arc_length=[0.0, 100.0, 200.0],
        parameters=[KeyValue(key="cable.EA", value="45500000.0"), KeyValue(key="solver", value="hybrid")])


def _spin_until(executor, done, timeout=5.0):
    deadline = time.monotonic() + timeout
    while not done() and time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.05)
    return done()


@pytest.mark.ros
@pytest.mark.parametrize("name", MESSAGES)
def test_publish_and_receive(ros_context, name):
    """Publish one filled message on a reliable topic and receive an identical one."""
    import rclpy
    from rclpy.executors import SingleThreadedExecutor

    sent = _filled(name)
    node = rclpy.create_node(f"test_{name.lower()}", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    received = []
    try:
        pub = node.create_publisher(type(sent), f"/test/{name}", 10)
        node.create_subscription(type(sent), f"/test/{name}", received.append, 10)
        assert _spin_until(executor, lambda: pub.get_subscription_count() == 1), "subscription never matched"
        pub.publish(sent)
        assert _spin_until(executor, lambda: bool(received)), f"{name} was not received within 5 s"
    finally:
        executor.shutdown()
        node.destroy_node()
    got = received[0]
    assert got == sent  # generated __eq__ compares every field, nested messages and arrays included
    assert got is not sent
    assert got.header.stamp.sec == 12 and got.header.frame_id == "map"


@pytest.mark.ros
def test_description_is_latched_for_a_late_subscriber(ros_context):
    """TetherDescription on a TRANSIENT_LOCAL topic reaches a subscriber created after publishing."""
    import rclpy
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

    latched = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL)
    sent = _filled("TetherDescription")
    talker = rclpy.create_node("test_description_talker", context=ros_context)
    listener = rclpy.create_node("test_description_listener", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(talker)
    executor.add_node(listener)
    received = []
    try:
        talker.create_publisher(type(sent), "/test/description", latched).publish(sent)
        executor.spin_once(timeout_sec=0.1)
        listener.create_subscription(type(sent), "/test/description", received.append, latched)
        assert _spin_until(executor, lambda: bool(received)), "late subscriber did not get the latched message"
    finally:
        executor.shutdown()
        talker.destroy_node()
        listener.destroy_node()
    assert received[0] == sent
