"""The vehicle and the tether in one process, in simulated time (tests and the loop-delay study).

``ClosedLoop`` runs tether-sim's node and the MuJoCo vehicle node in one executor: the vehicle owns
/clock and is ticked by the caller; each tick waits for the tether node's state of that tick, so a run
is deterministic and does not depend on the machine's speed. ``trace`` keeps, per tick, the time, the
vehicle's position, the tether wrench it applied and the stamp of the message it came from.
"""

from __future__ import annotations

import rclpy
from geometry_msgs.msg import WrenchStamped
from rclpy.executors import SingleThreadedExecutor
from rclpy.parameter import Parameter
from tether_sim_msgs.msg import TetherState

from tether_sim.io.params import read_param_file
from tether_sim.network.params import file_is_network
from tether_sim.ros.network_node import NetworkSimNode
from tether_sim.ros.sim_node import TetherSimNode
from tether_sim.ros.vehicle_node import VehicleNode
from tether_sim.vehicle.model import BLUEROV2_HEAVY
from tether_sim.vehicle.sim import StationKeeper, VehicleSim


def tether_parameters(path, **extra) -> list:
    """rclpy Parameters of a parameter file (plus ``extra`` flat keys), in sim time and never capped on
    the wall clock (node.tick_budget: a deterministic run)."""
    flat = {**read_param_file(path), "node.tick_budget": 1.0e6, **extra}
    return [Parameter("use_sim_time", Parameter.Type.BOOL, True)] + [
        Parameter(k, value=list(v) if isinstance(v, tuple) else v) for k, v in flat.items()]


class ClosedLoop:
    """The two nodes in one executor (module docstring); ``tether=False``: the vehicle alone; ``keeper``: a
    StationKeeper other than the default one."""

    def __init__(self, start, setpoint, params_file=None, current=(0.0, 0.0, 0.0), tether=True, model=BLUEROV2_HEAVY,
                 keeper=None, **extra):
        self.context = rclpy.Context()
        rclpy.init(context=self.context)
        self.sim = VehicleSim(model, position=start, dt=0.005, current=current)
        self.vehicle = VehicleNode(self.sim, keeper or StationKeeper(model), setpoint, rate=50.0, clock=True, timer=False,
                                   context=self.context)
        self.vehicle.publish()  # the first pose and /clock before the tether node starts
        self.tether = self._tether_node(params_file, extra) if tether else None
        self.probe = rclpy.create_node("probe", context=self.context)
        self.states, self.wrenches = [], []
        # the tick is done when its state arrives: a network publishes one per line (the first line's is waited for)
        state_topic = (f"/tether/{next(iter(self.tether.spec.lines))}/state" if isinstance(self.tether, NetworkSimNode)
                       else "/tether/state")
        self.probe.create_subscription(TetherState, state_topic, self.states.append, 1000)
        self.probe.create_subscription(WrenchStamped, "/tether/vehicle_wrench", self.wrenches.append, 1000)
        self.executor = SingleThreadedExecutor(context=self.context)
        for n in (self.vehicle, self.tether, self.probe):
            if n is not None:
                self.executor.add_node(n)
        self.trace = []  # (t, position, applied tether wrench (6,), stamp of the wrench message it came from)

    def _tether_node(self, params_file, extra):
        """tether-sim's node for the file: a line network's node for a network file (docs/network.md), else
        the single-line node; in sim time, never capped on the wall clock."""
        if params_file is not None and file_is_network(params_file):
            return NetworkSimNode(files=[str(params_file)], overrides={"node.tick_budget": 1.0e6, **extra},
                                  context=self.context,
                                  parameter_overrides=[Parameter("use_sim_time", Parameter.Type.BOOL, True)])
        return TetherSimNode(context=self.context, parameter_overrides=tether_parameters(params_file, **extra))

    def run(self, seconds):
        for _ in range(int(round(seconds * 50))):
            n = len(self.states)
            used = None if self.vehicle.wrench is None else self.vehicle.wrench[0]  # the wrench this tick applies
            self.vehicle.tick()
            for _ in range(40):
                self.executor.spin_once(timeout_sec=0.002)
                if len(self.states) > n and self.vehicle.wrench is not None and len(self.wrenches) >= len(self.states):
                    break
            self.executor.spin_once(timeout_sec=0.0)
            self.trace.append((self.sim.time, self.sim.position, self.vehicle.applied.copy(), used))
            if self.vehicle.failed:
                break

    def close(self):
        self.executor.shutdown()
        for n in (self.vehicle, self.tether, self.probe):
            if n is not None:
                n.destroy_node()
        rclpy.shutdown(context=self.context)
