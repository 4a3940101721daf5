"""``tether/snap_markers``: each SnapLoadEvent also as a visualization_msgs/Marker, for RViz.

RViz cannot display tether_sim_msgs/SnapLoadEvent; this text marker (TEXT_VIEW_FACING, red, in the
world frame) stands at the snapping point (the event's arc length on the cable at the time it is
published) and reads ``snap <end>: <peak> kN (x<amplification>)`` for ``LIFETIME_S``. Foxglove
reads the events themselves (foxglove/tether_sim.json). Published reliable, depth 50, like the events.
"""

from __future__ import annotations

import numpy as np
from rclpy.qos import QoSProfile, ReliabilityPolicy
from visualization_msgs.msg import Marker

from tether_sim.ros import convert

TOPIC = "tether/snap_markers"
LIFETIME_S = 30
QOS = QoSProfile(depth=50, reliability=ReliabilityPolicy.RELIABLE)


def snap_marker(event, position, marker_id: int, frame: str, text_height: float) -> Marker:
    """The text marker of a SnapLoadEvent ``event`` at ``position`` (world frame, m)."""
    m = Marker()
    m.header = convert.header(convert.to_seconds(event.header.stamp), frame)
    m.ns, m.id, m.type, m.action = "snap_events", int(marker_id), Marker.TEXT_VIEW_FACING, Marker.ADD
    m.pose.position.x, m.pose.position.y, m.pose.position.z = (float(c) for c in position)
    m.pose.orientation.w = 1.0
    m.scale.z = float(text_height)
    m.color.r, m.color.g, m.color.b, m.color.a = 1.0, 0.2, 0.2, 1.0
    m.lifetime.sec = LIFETIME_S
    amp = f" (x{event.amplification:.2f})" if event.amplification > 0 else ""
    m.text = f"snap {event.end}: {event.peak_tension / 1e3:.1f} kN{amp}"
    return m


class SnapMarkerPublisher:
    def __init__(self, node):
        self.pub = node.create_publisher(Marker, TOPIC, QOS)
        self.count = 0

    def publish(self, event, driver) -> None:
        cfg = driver.config
        s = min(max(float(event.arc_length), 0.0), cfg.cable.length)
        position = np.asarray(driver.solver.state(np.array([s])).position, float)[0]
        height = min(max(0.03 * cfg.cable.length, 0.5), 20.0)  # m: readable next to the cable
        self.pub.publish(snap_marker(event, position, self.count, cfg.node.world_frame, height))
        self.count += 1
