"""The winch's topics: ``winch/command`` in (WinchCommand), ``winch/state`` out (WinchState).

Used by the node (:class:`NodeWinch`: a few-line hook in ``sim_node``) and the offline runner
(:func:`offline_outputs`), so both write the same messages. Without ``winch.enabled`` nothing here
is created. The controller and its limits: :mod:`tether_sim.physics.winch`; how it reaches the
solver: :mod:`tether_sim.ros.winch_link`.

Each tick, after stepping: the output points follow the length (``linspace(0, L(t), n)``), the
vehicle-end location of the snap detector is moved to ``s = L(t)``, and the winch state is
published, stamped with the simulated instant. Commands received on the topic are applied at the
start of the next stepping interval; a bad one (unknown mode, non-finite setpoint, a speed above
``winch.max_speed``, a length outside the limits, a negative tension) is rejected with a logged
reason and changes nothing. Applied commands (topic or schedule) are logged; offline the schedule's
commands are written to ``/winch/command`` at the instant they took effect.
"""

import numpy as np
from rclpy.qos import QoSProfile, ReliabilityPolicy
from tether_sim_msgs.msg import WinchCommand, WinchState

from tether_sim.physics.winch import UNITS
from tether_sim.ros import convert
from tether_sim.ros.winch_link import END_TENSION, link_of

TOPICS = {"/winch/state": ("tether_sim_msgs/msg/WinchState", "reliable"),
          "/winch/command": ("tether_sim_msgs/msg/WinchCommand", "reliable")}


def state_message(driver, link) -> WinchState:
    """WinchState of the driver's current state (drum-side tension from the current end forces)."""
    w = link.winch
    tension = float(getattr(driver.solver.end_forces(), END_TENSION[link.config.winch.end]))
    return WinchState(header=convert.header(driver.stamp, driver.config.node.world_frame), end=link.config.winch.end,
                      mode=w.mode, setpoint=float(w.setpoint), length=float(w.length), speed=float(w.speed),
                      commanded_speed=float(w.commanded_speed), tension=tension, **w.flags)


def command_message(stamp: float, mode: str, setpoint: float) -> WinchCommand:
    return WinchCommand(header=convert.header(stamp, ""), mode=mode, setpoint=float(setpoint))


def follow_length(driver, link, arc_lengths):
    """Output points on [0, L(t)] and the vehicle-end snap location at L(t); returns the points."""
    length = float(link.winch.length)
    if driver.detector is not None:
        driver.detector.arc_lengths[-1] = length
    if arc_lengths[-1] == length:
        return arc_lengths
    return np.linspace(0.0, length, len(arc_lengths))


def applied_commands(driver, link) -> list:
    """(clock stamp, mode, setpoint, source) of the commands applied since the last call."""
    solver_time = driver.solver.time if driver.solver is not None else 0.0
    return [(driver.stamp - (solver_time + link.offset - t), mode, sp, src) for t, mode, sp, src in link.drain_applied()]


def offline_outputs(driver, arc_lengths):
    """Offline runner: (arc lengths, [(topic, message)]) for this tick; ([...], []) without a winch."""
    link = link_of(driver)
    if link is None:
        return arc_lengths, []
    out = [("/winch/command", command_message(t, mode, sp)) for t, mode, sp, src in applied_commands(driver, link)
           if src == "schedule"]
    out.append(("/winch/state", state_message(driver, link)))
    return follow_length(driver, link, arc_lengths), out


class NodeWinch:
    """The node's winch topics (inactive without ``winch.enabled``)."""

    def __init__(self, node):
        self.node = node
        self.link = link_of(node.driver)
        if self.link is None:
            return
        reliable = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
        self.pub = node.create_publisher(WinchState, convert.ros_name("/winch/state"), reliable)
        node.create_subscription(WinchCommand, convert.ros_name("/winch/command"), self._on_command, reliable)
        w = self.link.config.winch
        node.get_logger().info(f"winch at the {w.end} end: {w.mode} {w.setpoint:g} {UNITS.get(w.mode, '')}, "
                               f"{len(w.schedule_times)} scheduled command(s); commands on winch/command")

    def _on_command(self, msg: WinchCommand):
        problem = self.link.request(msg.mode, msg.setpoint, "topic")
        log = self.node.get_logger()
        if problem is not None:
            log.warning(f"winch command rejected: {problem}")
        else:
            log.info(f"winch command accepted: {msg.mode} {msg.setpoint:g} {UNITS.get(msg.mode, '')} (schedule, if any, ended)")

    def tick(self, arc_lengths):
        """After a tick with a new state: publish the winch state; returns the output points."""
        if self.link is None or self.node.driver.solver is None:
            return arc_lengths
        for _, mode, setpoint, source in applied_commands(self.node.driver, self.link):
            if source == "schedule":
                self.node.get_logger().info(f"winch schedule: {mode} {setpoint:g} {UNITS.get(mode, '')}")
        self.pub.publish(state_message(self.node.driver, self.link))
        return follow_length(self.node.driver, self.link, arc_lengths)


__all__ = ["TOPICS", "NodeWinch", "offline_outputs", "state_message", "command_message"]
