"""The node with forecast.enabled: tether/snap_forecast from look-ahead runs in a worker thread, the
forecast status on /diagnostics, and external ship-motion forecasts (nav_msgs/Path) validated."""

import math
import time

import numpy as np
import pytest

pytest.importorskip("rclpy")
pytest.importorskip("tether_sim_msgs")
from geometry_msgs.msg import PoseStamped  # noqa: E402
from nav_msgs.msg import Path  # noqa: E402
from sim_harness import SimHarness, status, values  # noqa: E402
from tether_sim_msgs.msg import SnapForecast  # noqa: E402
from test_sim_node import ATTACH, VEHICLE, base_params  # noqa: E402

from tether_sim.ros.convert import time_msg  # noqa: E402

pytestmark = pytest.mark.ros

SEA = {"motion.kind": "rao", "motion.rao_path": "config/rao_support_vessel_80m.txt",
       "motion.rao_lever_arm": (-35.0, 0.0, 5.0), "waves.kind": "regular", "waves.height": 2.0, "waves.period": 8.0,
       "waves.direction": 180.0, "forecast.enabled": True, "forecast.horizon": 2.0, "forecast.rate": 2.0,
       "forecast.members": 2, "forecast.command_rate": 10.0}


def run_until_forecasts(h, n, after=-1.0, wall=120.0, **poses):
    """Step sim time until ``n`` forecasts stamped after ``after`` arrived; returns those. The worker
    runs in wall time beside the ticks (a forecast falling due while it is busy is skipped), so sim
    time is stepped slowly and the wait is bounded in wall time, not sim time (a loaded machine)."""
    def got():
        return [f for f in h.forecasts if f.header.stamp.sec + 1e-9 * f.header.stamp.nanosec > after]
    deadline = time.monotonic() + wall
    while len(got()) < n and time.monotonic() < deadline:
        h.step(h.time + 0.02, **poses)
        time.sleep(0.01)
    return got()


def harness(flat):
    h = SimHarness(flat)
    h.forecasts = []
    h.probe.create_subscription(SnapForecast, "/tether/snap_forecast", h.forecasts.append, 100)
    h.path_pub = h.probe.create_publisher(Path, "/tether/ship_motion_forecast", 10)
    return h


def path(t_stamp, frame="map", n=30, dt=0.2, z=5.0):
    msg = Path()
    msg.header.stamp = time_msg(t_stamp)
    msg.header.frame_id = frame
    for k in range(n):
        p = PoseStamped()
        p.header.stamp = time_msg(t_stamp + k * dt)
        p.header.frame_id = frame
        p.pose.position.z = z + 0.2 * math.sin(0.8 * k * dt)
        p.pose.orientation.w = 1.0
        msg.poses.append(p)
    return msg


def test_node_publishes_known_sea_forecasts_and_their_status():
    h = harness(base_params(**SEA))
    try:
        vehicle = tuple(np.subtract(VEHICLE, ATTACH))
        got = run_until_forecasts(h, 4, vehicle=vehicle)
        assert len(got) >= 4
        assert {f.end for f in got} == {"ship", "vehicle"}
        for f in got:
            assert f.source == "known_sea" and f.members == 2 and f.horizon == 2.0 and not f.degraded
            assert 0.0 <= f.probability <= 1.0 and f.header.frame_id == "map"
        h.run(h.time + 1.1, vehicle=vehicle)  # a diagnostics period
        st = status(h.received["/diagnostics"][-1], ": snap forecast")
        assert st is not None
        v = values(st)
        assert int(v["forecast completed"]) >= 2 and v["forecast status"] in ("ok", "")
    finally:
        h.close()


def test_node_rejects_bad_external_forecasts_with_the_reason_and_degrades():
    h = harness(base_params(**{**SEA, "forecast.source": "external", "forecast.members": 1}))
    try:
        vehicle = tuple(np.subtract(VEHICLE, ATTACH))
        h.run(0.5, vehicle=vehicle)
        h.path_pub.publish(path(h.time, frame="ship/base_link"))
        h.run(h.time + 0.1, vehicle=vehicle)
        got = run_until_forecasts(h, 2, after=h.time, vehicle=vehicle)
        assert got
        f = got[-1]
        assert f.degraded and "wrong frame 'ship/base_link'" in f.reason and f.members == 0
        assert math.isnan(f.probability)  # no ship-motion forecast at all: pose history too short
        assert h.node.forecast_io.service.external.rejected == 1
        # a valid one is taken: not degraded, source external
        t_pub = h.time
        for _ in range(4):
            h.path_pub.publish(path(h.time))
            got = run_until_forecasts(h, 2, after=t_pub, wall=20.0, vehicle=vehicle)
            if any(f.source == "external" for f in got):
                break
        ext = [f for f in got if f.source == "external"]
        assert ext and not ext[-1].degraded and ext[-1].members == 1
        h.run(h.time + 1.1, vehicle=vehicle)
        st = status(h.received["/diagnostics"][-1], ": snap forecast")
        assert "wrong frame" in values(st)["external last rejection"]
    finally:
        h.close()


def test_status_warns_at_the_alarm_threshold_not_below():
    """/diagnostics warns of a snap only at forecast.warn_probability and above (a forecast at p 0.625
    with the default 0.75 is no alarm; at 0.75 it is, and a lowered threshold warns at 0.5)."""
    from dataclasses import replace
    from types import SimpleNamespace

    from diagnostic_msgs.msg import DiagnosticStatus

    from tether_sim.config import SimConfig
    from tether_sim.forecast.lookahead import EndForecast
    from tether_sim.ros.forecast_io import status as forecast_status

    def service(p, warn=None):
        cfg = SimConfig()
        if warn is not None:
            cfg = replace(cfg, forecast=replace(cfg.forecast, warn_probability=warn))
        f = EndForecast(stamp=10.0, end="vehicle", horizon=15.0, probability=p, time_to_snap=7.0,
                        time_to_snap_std=0.2, predicted_peak=9e4, members=8, source="known_sea")
        return SimpleNamespace(config=cfg, last=[f], last_status="ok", diagnostics=lambda: {},
                               external=SimpleNamespace(rejected=0, last_reason=""))

    assert forecast_status(service(0.625), "n").level == DiagnosticStatus.OK
    st = forecast_status(service(0.75), "n")
    assert st.level == DiagnosticStatus.WARN and "snap at vehicle likely (p = 0.75 >= 0.75) in 7.0 s" in st.message
    assert forecast_status(service(0.5, warn=0.5), "n").level == DiagnosticStatus.WARN
