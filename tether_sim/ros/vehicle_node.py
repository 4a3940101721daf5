"""A vehicle simulated in MuJoCo on the far end of the tether (console script ``tether-sim-vehicle``).

    tether-sim-vehicle [--model bluerov2_heavy] [--position X Y Z] [--yaw RAD] [--setpoint X Y Z]
                       [--setpoint-yaw RAD] [--current UX UY UZ] [--rate HZ] [--dt S] [--clock]
                       [--transit X Y Z [--transit-after S] [--transit-speed V]] [--hold-until-tether]
                       [--stop-after S] [--duration S] [--ros-args -r __ns:=/rov1]

The vehicle (``tether_sim.vehicle``: rigid body in MuJoCo, hydrodynamics of the model's table,
thrusters, a station-keeping controller) flies with the tether's force on it: each MuJoCo step
applies the latest ``tether/vehicle_wrench`` (geometry_msgs/WrenchStamped, the force BY the tether ON
the vehicle in the vehicle frame about its origin, as tether-sim publishes it) rotated to the world.
It publishes ``vehicle/pose`` (PoseStamped, world frame) at ``--rate`` (default 50 Hz), the
thrusters' body wrench on ``vehicle/thrust`` and, with ``--clock``, ``/clock`` (the simulation's
time: then tether-sim runs with ``use_sim_time:=true`` and follows it).

A wrench in another frame than the vehicle frame, or with non-finite values, is rejected with a log
line; a wrench older than ``WRENCH_TIMEOUT`` of simulated time is not applied any more (the vehicle
then flies without the tether's force, and the log says so once per such gap). With
``--hold-until-tether`` the vehicle is held still (its time running, /clock published) until the
tether's first wrench, so a tether node's start-up does not leave it flying alone; the mission (hold
the set point, then ``--transit``) counts from that release. Exit code 0, or 1 when the simulation
went unstable (it then stops publishing), 2 for a bad argument.
"""

from __future__ import annotations

import argparse
import math
import sys
import time

import numpy as np
import rclpy
from geometry_msgs.msg import PoseStamped, WrenchStamped
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy
from rosgraph_msgs.msg import Clock

from tether_sim.ros.convert import time_msg
from tether_sim.ros.node_cli import ignore_further_signals, stop_flag
from tether_sim.vehicle.model import MODELS
from tether_sim.vehicle.sim import Mission, StationKeeper, VehicleDiverged, VehicleSim

WRENCH_TIMEOUT = 0.5  # s of simulated time a tether wrench stays applied without a newer one


def stamp_seconds(stamp) -> float:
    return stamp.sec + stamp.nanosec * 1e-9


class VehicleNode(Node):
    """The vehicle simulator (module docstring). ``tick()`` advances the simulation by one output
    period and publishes; with ``clock`` the node owns the time (``/clock``), else it follows the
    wall clock (the MuJoCo time catches up with the elapsed wall time, at most 5 periods per tick)."""

    def __init__(self, sim: VehicleSim, keeper: StationKeeper, setpoint, setpoint_yaw=0.0, rate=50.0,
                 clock=False, world_frame="map", vehicle_frame="rov/base_link", timer=True,
                 hold_until_tether=False, **kwargs):
        super().__init__("tether_sim_vehicle", **kwargs)
        self.sim, self.keeper = sim, keeper
        self.mission = setpoint if isinstance(setpoint, Mission) else Mission(setpoint)
        self.setpoint_yaw = float(setpoint_yaw)
        # held still at its start (time running) until the tether's first wrench: the tether node's
        # start-up then costs the vehicle nothing; the mission's clock starts at the release
        self.released_at = None if hold_until_tether else sim.time
        self.period, self.own_clock = 1.0 / rate, bool(clock)
        self.world_frame, self.vehicle_frame = world_frame, vehicle_frame
        self.substeps = max(1, int(round(self.period / sim.dt)))
        self.wrench = None  # (stamp s, force (3,), torque (3,)) of the latest accepted tether wrench
        self.stale = False
        self.rejected = 0
        self.failed = False  # the simulation went unstable: nothing more is published
        self.thrust = np.zeros(len(sim.model.thruster_positions))
        self.applied = np.zeros(6)  # the tether wrench applied in the last step (body frame)
        self.pose_pub = self.create_publisher(PoseStamped, "vehicle/pose", 10)
        self.thrust_pub = self.create_publisher(WrenchStamped, "vehicle/thrust", 10)
        self.clock_pub = (self.create_publisher(Clock, "/clock", QoSProfile(depth=1, reliability=ReliabilityPolicy.BEST_EFFORT))
                          if clock else None)
        self.create_subscription(WrenchStamped, "tether/vehicle_wrench", self._on_wrench, 10)
        self.t_wall0 = None
        if timer:
            self.create_timer(self.period, self.tick)

    def now(self) -> float:
        """The stamp of what is published: the simulation's time with ``clock``, else this node's clock."""
        return self.sim.time if self.own_clock else self.get_clock().now().nanoseconds * 1e-9

    def _on_wrench(self, msg: WrenchStamped):
        f = np.array([msg.wrench.force.x, msg.wrench.force.y, msg.wrench.force.z], float)
        m = np.array([msg.wrench.torque.x, msg.wrench.torque.y, msg.wrench.torque.z], float)
        why = None
        if msg.header.frame_id != self.vehicle_frame:
            why = f"frame '{msg.header.frame_id}', expected the vehicle frame '{self.vehicle_frame}'"
        elif not (np.all(np.isfinite(f)) and np.all(np.isfinite(m))):
            why = "non-finite force or torque"
        if why is not None:
            self.rejected += 1
            self.get_logger().warning(f"tether/vehicle_wrench rejected: {why}", throttle_duration_sec=5.0)
            return
        self.wrench = (stamp_seconds(msg.header.stamp), f, m)

    def _tether_wrench(self, t: float):
        if self.wrench is None:
            return np.zeros(3), np.zeros(3)
        stamp, f, m = self.wrench
        if t - stamp > WRENCH_TIMEOUT:
            if not self.stale:
                self.get_logger().warning(f"tether/vehicle_wrench stale ({t - stamp:.2f} s old at t = {t:.2f} s): "
                                          "flying without the tether's force until a new one arrives")
            self.stale = True
            return np.zeros(3), np.zeros(3)
        self.stale = False
        return f, m

    def tick(self):
        """One output period: MuJoCo steps (each with the controller's thrust and the tether wrench),
        then vehicle/pose, vehicle/thrust and /clock. A simulation that went unstable publishes nothing
        more (its state is not the vehicle's motion)."""
        if self.failed:
            return
        try:
            self._advance()
        except VehicleDiverged as exc:
            self.failed = True
            self.get_logger().error(f"{exc}: stopped publishing vehicle/pose")
            return
        self.publish()

    def _advance(self):
        steps = self.substeps
        if not self.own_clock:  # follow the wall clock
            now = self.get_clock().now().nanoseconds * 1e-9
            if self.t_wall0 is None:
                self.t_wall0 = now - self.sim.time
            steps = int(min(5 * self.substeps, max(0, round((now - self.t_wall0 - self.sim.time) / self.sim.dt))))
        if self.released_at is None:
            if self.wrench is None:  # held: the time runs, the vehicle does not move
                self.sim.data.time += steps * self.sim.dt
                return
            self.released_at = self.sim.time
            self.get_logger().info(f"the tether's first wrench: vehicle released at t = {self.sim.time:.2f} s")
        for _ in range(steps):
            setpoint = self.mission.setpoint(self.sim.time - self.released_at)
            self.thrust = self.keeper.thrust(self.sim, setpoint, self.setpoint_yaw, self.sim.dt)
            f, m = self._tether_wrench(self.sim.time if self.own_clock else self.now())
            self.applied = np.concatenate([f, m])
            self.sim.step(self.thrust, f, m)

    def publish(self):
        t = self.now()
        if self.clock_pub is not None:
            self.clock_pub.publish(Clock(clock=time_msg(t)))
        pose = PoseStamped()
        pose.header.stamp, pose.header.frame_id = time_msg(t), self.world_frame
        p, q = self.sim.position, self.sim.orientation
        pose.pose.position.x, pose.pose.position.y, pose.pose.position.z = (float(c) for c in p)
        o = pose.pose.orientation
        o.x, o.y, o.z, o.w = (float(c) for c in q)
        self.pose_pub.publish(pose)
        w = WrenchStamped()
        w.header.stamp, w.header.frame_id = time_msg(t), self.vehicle_frame
        tau = self.sim.B @ self.thrust
        w.wrench.force.x, w.wrench.force.y, w.wrench.force.z = (float(c) for c in tau[:3])
        w.wrench.torque.x, w.wrench.torque.y, w.wrench.torque.z = (float(c) for c in tau[3:])
        self.thrust_pub.publish(w)


def _vec3(text_values, name):
    v = [float(x) for x in text_values]
    if not all(math.isfinite(x) for x in v):
        raise ValueError(f"{name}: expected 3 finite numbers, got {text_values}")
    return v


def main(argv=None) -> int:
    argv = list(sys.argv if argv is None else argv)
    ap = argparse.ArgumentParser(prog="tether-sim-vehicle", description=__doc__.split("\n\n")[0])
    ap.add_argument("--model", default="bluerov2_heavy", choices=sorted(MODELS), help="vehicle model")
    ap.add_argument("--position", nargs=3, default=[0.0, 0.0, -10.0], metavar=("X", "Y", "Z"), help="start, m (world ENU)")
    ap.add_argument("--yaw", type=float, default=0.0, help="start heading, rad (ENU: 0 = east)")
    ap.add_argument("--setpoint", nargs=3, default=None, metavar=("X", "Y", "Z"), help="station to hold, m (default: the start)")
    ap.add_argument("--setpoint-yaw", type=float, default=None, help="heading to hold, rad (default: the start)")
    ap.add_argument("--current", nargs=3, default=[0.0, 0.0, 0.0], metavar=("UX", "UY", "UZ"), help="current, m/s (world)")
    ap.add_argument("--rate", type=float, default=50.0, help="pose rate, Hz (default 50)")
    ap.add_argument("--dt", type=float, default=0.005, help="MuJoCo time step, s (default 0.005)")
    ap.add_argument("--clock", action="store_true", help="publish /clock: the simulation owns the time")
    ap.add_argument("--world-frame", default="map")
    ap.add_argument("--vehicle-frame", default="rov/base_link")
    ap.add_argument("--duration", type=float, default=0.0, help="stop after this many seconds of wall time (0: never)")
    ap.add_argument("--transit", nargs=3, default=None, metavar=("X", "Y", "Z"), help="then fly to this point, m")
    ap.add_argument("--transit-after", type=float, default=30.0, help="start the transit this long after the release, s")
    ap.add_argument("--transit-speed", type=float, default=0.3, help="set point speed of the transit, m/s")
    ap.add_argument("--hold-until-tether", action="store_true",
                    help="hold the vehicle still (time running) until the tether's first wrench arrives")
    ap.add_argument("--stop-after", type=float, default=0.0,
                    help="stop this many simulated seconds after the release (0: never)")
    args = ap.parse_args(rclpy.utilities.remove_ros_args(argv)[1:])
    try:
        position = _vec3(args.position, "--position")
        setpoint = _vec3(args.setpoint, "--setpoint") if args.setpoint is not None else position
        current = _vec3(args.current, "--current")
        if not (math.isfinite(args.rate) and 1.0 <= args.rate <= 1000.0):
            raise ValueError(f"--rate {args.rate}: between 1 and 1000 Hz")
        if not (math.isfinite(args.dt) and 1e-4 <= args.dt <= 0.5 / args.rate):
            raise ValueError(f"--dt {args.dt}: between 1e-4 s and half the output period")
        for name, v in (("--yaw", args.yaw), ("--setpoint-yaw", args.setpoint_yaw)):
            if v is not None and not math.isfinite(v):
                raise ValueError(f"{name} {v}: a finite angle in rad")
        target = _vec3(args.transit, "--transit") if args.transit is not None else None
        for name, v, lo in (("--transit-after", args.transit_after, 0.0), ("--transit-speed", args.transit_speed, 1e-3),
                            ("--stop-after", args.stop_after, 0.0)):
            if not (math.isfinite(v) and v >= lo):
                raise ValueError(f"{name} {v}: a finite number >= {lo:g}")
    except ValueError as exc:
        print(f"tether-sim-vehicle: {exc}", file=sys.stderr)
        return 2
    model = MODELS[args.model]
    sim = VehicleSim(model, position=position, yaw=args.yaw, dt=args.dt, current=current)
    rclpy.init(args=argv)
    mission = Mission(setpoint, target, args.transit_after, args.transit_speed)
    node = VehicleNode(sim, StationKeeper(model), mission, args.yaw if args.setpoint_yaw is None else args.setpoint_yaw,
                       rate=args.rate, clock=args.clock, world_frame=args.world_frame, vehicle_frame=args.vehicle_frame,
                       hold_until_tether=args.hold_until_tether)
    node.get_logger().info(f"{model.name} ({model.source}) at {position}, holding {list(setpoint)}"
                           + (f", then to {target} at {args.transit_speed:g} m/s after {args.transit_after:g} s" if target else "")
                           + f"; current {current} m/s; pose at {args.rate:g} Hz{', publishing /clock' if args.clock else ''}")
    stopped = stop_flag()  # a signal ends the loop between callbacks, never inside rclpy
    t_end = time.monotonic() + args.duration if args.duration > 0 else math.inf
    try:
        while not stopped and rclpy.ok() and time.monotonic() < t_end and not node.failed:
            rclpy.spin_once(node, timeout_sec=0.1)
            if args.stop_after > 0 and node.released_at is not None and node.sim.time - node.released_at >= args.stop_after:
                node.get_logger().info(f"mission done: {args.stop_after:g} s after the release")
                break
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        ignore_further_signals()  # more Ctrl-C / SIGTERM must not cut the clean-up short (exit 0, no traceback)
        node.destroy_node()
        rclpy.try_shutdown()
        ignore_further_signals()  # rclpy's shutdown puts back the handlers it found at init
    return 1 if node.failed else 0


if __name__ == "__main__":
    sys.exit(main())
