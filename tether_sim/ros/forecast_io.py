"""The snap forecast's topics (docs/forecast.md): ``tether/snap_forecast`` out (SnapForecast, one
message per end per forecast), ``tether/ship_motion_forecast`` in (nav_msgs/Path: an external
forecast of the ship pose), and a ``snap forecast`` status on /diagnostics.

Used by the node (:class:`NodeForecast`: a few-line hook in ``sim_node``, the look-aheads in a worker
thread so the tick never waits) and the offline runner (:func:`forecast_message`, the forecasts run
inline), so both write the same messages. Without ``forecast.enabled`` nothing here is created.
"""

import math
import time

from diagnostic_msgs.msg import DiagnosticStatus, KeyValue
from nav_msgs.msg import Path
from rclpy.qos import QoSProfile, ReliabilityPolicy
from tether_sim_msgs.msg import SnapForecast

from tether_sim.forecast.service import ForecastService
from tether_sim.ros import convert

TOPICS = {"/tether/snap_forecast": ("tether_sim_msgs/msg/SnapForecast", "reliable")}
INPUT_TOPIC = "/tether/ship_motion_forecast"


def forecast_message(f, frame_id: str) -> SnapForecast:
    """SnapForecast of one :class:`~tether_sim.forecast.lookahead.EndForecast`."""
    return SnapForecast(header=convert.header(f.stamp, frame_id), end=f.end, horizon=float(f.horizon),
                        probability=float(f.probability), time_to_snap=float(f.time_to_snap),
                        time_to_snap_std=float(f.time_to_snap_std), predicted_peak=float(f.predicted_peak),
                        members=int(f.members), source=f.source, degraded=bool(f.degraded), reason=f.reason)


def path_arrays(msg: Path):
    """(header stamp s, frame, pose stamps (k,), positions (k, 3), quaternions (k, 4)) of a Path
    (a pose without a stamp takes the header's)."""
    stamp = convert.to_seconds(msg.header.stamp)
    times, pos, quat = [], [], []
    for p in msg.poses:
        times.append(convert.to_seconds(p.header.stamp) or stamp)
        q, o = p.pose.position, p.pose.orientation
        pos.append((q.x, q.y, q.z))
        quat.append((o.x, o.y, o.z, o.w))
    return stamp, msg.header.frame_id, times, pos, quat


def status(service, name: str) -> DiagnosticStatus:
    """The ``snap forecast`` diagnostics status: WARN when a snap is likely within the horizon (probability
    at least ``forecast.warn_probability``, the alarm), when the forecast is degraded, or external
    forecasts were rejected; the values of the service."""
    problems, level = [], DiagnosticStatus.OK
    warn = service.config.forecast.warn_probability
    for f in service.last:
        if f.probability >= warn:
            problems.append(f"snap at {f.end} likely (p = {f.probability:.2f} >= {warn:g}) in {f.time_to_snap:.1f} s, "
                            f"peak {f.predicted_peak:.0f} N")
    if service.last and service.last[0].degraded:
        problems.append(f"degraded: {service.last[0].reason}")
    if service.external.rejected:
        problems.append(f"external forecast rejected: {service.external.last_reason}")
    if problems:
        level = DiagnosticStatus.WARN
    values = [KeyValue(key=k, value=(f"{v:.6g}" if isinstance(v, float) else str(v)))
              for k, v in service.diagnostics().items()]
    return DiagnosticStatus(level=level, name=f"{name}: snap forecast", hardware_id="tether_sim",
                            message="; ".join(problems) or service.last_status, values=values)


class NodeForecast:
    """The node's snap forecast (inactive without ``forecast.enabled``)."""

    def __init__(self, node, solver_factory):
        self.node = node
        self.service = None
        fc = node.config.forecast
        if not fc.enabled:
            return
        self.service = ForecastService(node.config, solver_factory=solver_factory, threaded=True)
        reliable = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
        self.pub = node.create_publisher(SnapForecast, convert.ros_name("/tether/snap_forecast"), reliable)
        node.create_subscription(Path, convert.ros_name(INPUT_TOPIC), self._on_external, reliable)
        self._last_warn = -math.inf
        node.get_logger().info(f"snap forecast: {fc.members} member(s) over {fc.horizon:g} s at {fc.rate:g} Hz, "
                               f"source {fc.source}; external forecasts on {INPUT_TOPIC.lstrip('/')}")

    def _on_external(self, msg: Path):
        stamp, frame, times, pos, quat = path_arrays(msg)
        reason = self.service.external.offer(stamp, frame, times, pos, quat, now=self.node._now())
        if reason is not None and time.monotonic() - self._last_warn > 2.0:
            self._last_warn = time.monotonic()
            self.node.get_logger().warning(f"ship motion forecast rejected: {reason}")

    def tick(self, now):
        """After a tick: hand a forecast to the worker when one is due; publish the finished ones."""
        if self.service is None or self.node.driver.solver is None:
            return
        self.service.observe(self.node.driver, now=now)
        frame = self.node.config.node.world_frame
        for f in self.service.poll():
            self.pub.publish(forecast_message(f, frame))

    def add_status(self, array):
        """Append the forecast's status to a DiagnosticArray."""
        if self.service is not None:
            array.status.append(status(self.service, self.node.get_fully_qualified_name()))
        return array

    def close(self):
        if self.service is not None:
            self.service.close()


__all__ = ["TOPICS", "INPUT_TOPIC", "NodeForecast", "forecast_message", "path_arrays", "status"]
