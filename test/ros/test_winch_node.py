"""The node's winch topics (tether_sim/ros/winch_io.py): winch/state at the output rate, winch/command
accepted or rejected with a logged reason, tether/state points following L(t). Quasi-static fake
solver (winch_fake.py), so the numbers are closed forms."""

import pytest

pytest.importorskip("rclpy")
pytest.importorskip("tether_sim_msgs")
from tether_sim_msgs.msg import WinchCommand, WinchState  # noqa: E402

from sim_harness import SimHarness  # noqa: E402
from tether_sim.ros.convert import time_msg  # noqa: E402
from winch_fake import W, HangingCable, w  # noqa: E402

pytestmark = pytest.mark.ros

FLAT = {"ship_end.kind": "fixed", "ship_end.position": (0.0, 0.0, 0.0), "vehicle_end.kind": "fixed",
        "vehicle_end.position": (0.0, 0.0, -200.0), "cable.length": 200.0, "node.input_delay": 0.0,
        "winch.enabled": True, "winch.mode": "speed", "winch.setpoint": 0.5, "winch.max_speed": 1.0,
        "winch.max_acceleration": 1.0, "winch.min_length": 10.0, "winch.max_length": 1000.0,
        # a schedule (arrays whose default is empty): its first entry is the start's own command
        "winch.schedule_times": (0.0,), "winch.schedule_modes": ("speed",), "winch.schedule_setpoints": (0.5,)}


class Logger:
    """Records (level, text) instead of logging (rclpy refuses two severities from one call site)."""

    def __init__(self):
        self.lines = []

    def __getattr__(self, level):
        return lambda text, *args, **kwargs: self.lines.append((level, text))


def test_winch_state_commands_and_rejections():
    h = SimHarness(FLAT, solver_factory=HangingCable)
    try:
        assert h.node.config.winch.schedule_modes == ("speed",)  # arrays with an empty default, from parameters
        logger = Logger()
        h.node.get_logger = lambda: logger
        states, tether = [], h.received["/tether/state"]
        h.probe.create_subscription(WinchState, "/winch/state", states.append, 1000)
        commands = h.probe.create_publisher(WinchCommand, "/winch/command", 10)
        for _ in range(500):
            if commands.get_subscription_count() and h.node.winch_io.pub.get_subscription_count():
                break
            h.spin(1)
        h.run(2.0)
        # 0.5 m/s reached after 0.5 s at 1 m/s^2: L = 200 + 0.125 + 0.5 (t - 0.5), t from the node's start
        last = states[-1]
        t = last.header.stamp.sec + 1e-9 * last.header.stamp.nanosec - h.node.driver.anchor
        assert last.length == pytest.approx(200.0 + 0.125 + 0.5 * (t - 0.5), abs=1e-6)
        assert last.tension == pytest.approx(W + w * last.length) and last.mode == "speed" and last.end == "ship"
        same = [m for m in tether if m.header.stamp == last.header.stamp]
        assert same and same[0].arc_length[-1] == pytest.approx(last.length)
        for mode, setpoint, words in (("speed", 3.0, "max_speed"), ("length", 5.0, "outside"), ("reel", 1.0, "not one of"),
                                      ("tension", -10.0, "negative")):
            n = len(logger.lines)
            commands.publish(WinchCommand(header=h.pose_msg(h.time, (0, 0, 0)).header, mode=mode, setpoint=setpoint))
            for _ in range(200):
                if len(logger.lines) > n:
                    break
                h.spin(1)
            assert any(level == "warning" and "winch command rejected" in text and words in text
                       for level, text in logger.lines), (mode, logger.lines)
        h.run(2.5)
        assert states[-1].mode == "speed" and states[-1].setpoint == 0.5
        msg = WinchCommand(mode=WinchCommand.MODE_LENGTH, setpoint=201.5)
        msg.header.stamp = time_msg(h.time)
        commands.publish(msg)
        for _ in range(200):
            if any("accepted" in text for _, text in logger.lines):
                break
            h.spin(1)
        h.run(12.0)
        assert states[-1].mode == "length" and states[-1].length == pytest.approx(201.5, abs=1e-3)
        assert any("winch command accepted" in text for _, text in logger.lines)
    finally:
        h.close()
