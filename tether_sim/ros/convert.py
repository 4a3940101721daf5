"""Solver results -> ROS messages. The only place where output messages are built.

Shared by the simulation node (published) and the offline runner (serialized into MCAP), so both
produce identical topics. Frames: cable states in the world frame (ENU); wrenches in the body frames
(force BY the tether ON the body, torque about the body frame origin).
"""

import math

import numpy as np
from builtin_interfaces.msg import Time
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from geometry_msgs.msg import Point, Pose, PoseStamped, Vector3, WrenchStamped
from nav_msgs.msg import Path
from std_msgs.msg import ColorRGBA, Header
from tether_sim_msgs.msg import SlackWarning, SnapLoadEvent, TetherDescription, TetherState
from visualization_msgs.msg import Marker

from tether_sim.io.params import to_flat

# Output topics, their message types and QoS kind (the MCAP writer's names). Remappable in the node.
TOPICS = {
    "/tether/state": ("tether_sim_msgs/msg/TetherState", "reliable"),
    "/tether/marker": ("visualization_msgs/msg/Marker", "reliable"),
    "/tether/path": ("nav_msgs/msg/Path", "reliable"),
    "/tether/ship_wrench": ("geometry_msgs/msg/WrenchStamped", "reliable"),
    "/tether/vehicle_wrench": ("geometry_msgs/msg/WrenchStamped", "reliable"),
    "/tether/snap_events": ("tether_sim_msgs/msg/SnapLoadEvent", "reliable"),
    "/tether/slack_warnings": ("tether_sim_msgs/msg/SlackWarning", "reliable"),
    "/tether/description": ("tether_sim_msgs/msg/TetherDescription", "latched"),
    "/diagnostics": ("diagnostic_msgs/msg/DiagnosticArray", "reliable"),
    "/ship/sim_pose": ("geometry_msgs/msg/PoseStamped", "reliable"),
    "/vehicle/sim_pose": ("geometry_msgs/msg/PoseStamped", "reliable"),
}

LEVEL_OK, LEVEL_WARN, LEVEL_ERROR, LEVEL_STALE = (DiagnosticStatus.OK, DiagnosticStatus.WARN,
                                                  DiagnosticStatus.ERROR, DiagnosticStatus.STALE)


def time_msg(t: float) -> Time:
    """builtin_interfaces/Time of a clock time in seconds (clamped at 0)."""
    ns = max(0, int(round(t * 1e9)))
    return Time(sec=ns // 1_000_000_000, nanosec=ns % 1_000_000_000)


def to_seconds(stamp) -> float:
    return stamp.sec + stamp.nanosec * 1e-9


def header(t: float, frame_id: str) -> Header:
    return Header(stamp=time_msg(t), frame_id=frame_id)


def _point(p) -> Point:
    return Point(x=float(p[0]), y=float(p[1]), z=float(p[2]))


def _vector(v) -> Vector3:
    return Vector3(x=float(v[0]), y=float(v[1]), z=float(v[2]))


def tether_state(state, forces, solver_name: str, t: float, frame_id: str, real_time_factor: float) -> TetherState:
    """TetherState from a SolverState sampled at the output points and the EndForces."""
    msg = TetherState(header=header(t, frame_id), solver=solver_name)
    msg.arc_length = np.asarray(state.arc_length, float).tolist()
    msg.position = [Point(x=x, y=y, z=z) for x, y, z in np.asarray(state.position, float).tolist()]
    msg.velocity = [Vector3(x=x, y=y, z=z) for x, y, z in np.asarray(state.velocity, float).tolist()]
    msg.tension = np.asarray(state.tension, float).tolist()
    msg.curvature = np.asarray(state.curvature, float).tolist()
    msg.bending_moment = np.asarray(state.bending_moment, float).tolist()
    msg.ship_end_tension = float(forces.ship_tension)
    msg.vehicle_end_tension = float(forces.vehicle_tension)
    msg.time_step = float(state.time_step)
    msg.real_time_factor = float(real_time_factor)
    return msg


def tension_colour(tension: float, scale: float) -> ColorRGBA:
    """Blue (slack, T <= 0) through green to red (T >= scale)."""
    u = min(max(tension / scale, 0.0), 1.0) if scale > 0 else 0.0
    return ColorRGBA(r=float(min(1.0, 2 * u)), g=float(1.0 - abs(2 * u - 1.0)), b=float(max(0.0, 1 - 2 * u)), a=1.0)


def marker(state, t: float, frame_id: str, tension_scale: float, width: float = 0.2) -> Marker:
    """LINE_STRIP of the cable with per-vertex colours by tension (len(colors) == len(points))."""
    msg = Marker(header=header(t, frame_id), ns="tether", id=0, type=Marker.LINE_STRIP, action=Marker.ADD)
    msg.pose.orientation.w = 1.0
    msg.scale.x = float(width)
    msg.color = ColorRGBA(r=1.0, g=1.0, b=0.0, a=1.0)
    msg.points = [Point(x=x, y=y, z=z) for x, y, z in np.asarray(state.position, float).tolist()]
    msg.colors = [tension_colour(float(T), tension_scale) for T in state.tension]
    msg.frame_locked = False
    return msg


def path(state, t: float, frame_id: str) -> Path:
    """nav_msgs/Path of the output points (orientation identity)."""
    hdr = header(t, frame_id)
    msg = Path(header=hdr)
    for x, y, z in np.asarray(state.position, float).tolist():
        pose = PoseStamped()
        pose.header = hdr
        pos = pose.pose.position
        pos.x, pos.y, pos.z = x, y, z
        pose.pose.orientation.w = 1.0
        msg.poses.append(pose)
    return msg


def wrench(force, torque, t: float, frame_id: str) -> WrenchStamped:
    """WrenchStamped: force BY the tether ON the body, in ``frame_id``, about its origin."""
    msg = WrenchStamped(header=header(t, frame_id))
    msg.wrench.force = _vector(force)
    msg.wrench.torque = _vector(torque)
    return msg


def pose(position, orientation, t: float, frame_id: str) -> PoseStamped:
    """PoseStamped of a body (quaternion x, y, z, w)."""
    msg = PoseStamped(header=header(t, frame_id))
    msg.pose = Pose(position=_point(position))
    msg.pose.orientation.x, msg.pose.orientation.y, msg.pose.orientation.z, msg.pose.orientation.w = (
        float(x) for x in orientation)
    return msg


def _end_label(location: str) -> str:
    return location if location in ("ship", "vehicle") else "span"


def snap_event(ev, frame_id: str) -> SnapLoadEvent:
    """SnapLoadEvent from the detector's SnapEvent (times are clock times)."""
    return SnapLoadEvent(header=header(ev.time, frame_id), end=_end_label(ev.location), arc_length=float(ev.arc_length),
                         peak_tension=float(ev.peak_tension), min_tension=float(ev.min_tension),
                         slack_start=time_msg(ev.slack_start), slack_duration=float(ev.slack_duration),
                         rise_time=float(ev.rise_time), static_tension=float(ev.static_tension),
                         amplification=float(ev.amplification) if math.isfinite(ev.amplification) else 0.0,
                         criterion=str(ev.criterion))


def slack_warning(ev, frame_id: str, static_tension: float) -> SlackWarning:
    """SlackWarning from the detector's SlackStarted."""
    return SlackWarning(header=header(ev.time, frame_id), end=_end_label(ev.location), arc_length=float(ev.arc_length),
                        tension=float(ev.tension), threshold=float(ev.threshold), static_tension=float(static_tension))


def description(config, output_arc_length, t: float) -> TetherDescription:
    """The latched TetherDescription: cable, ends, frames and every configuration key."""
    node, cable = config.node, config.cable
    msg = TetherDescription(header=header(t, node.world_frame), solver=config.solver, length=float(cable.length),
                            axial_stiffness=float(cable.EA), bending_stiffness=float(cable.EI),
                            mass_per_length=float(cable.gamma0), diameter=float(cable.diameter),
                            wave_speed=float(cable.wave_speed), ship_end_kind=config.ship_end.kind,
                            vehicle_end_kind=config.vehicle_end.kind, ship_frame=node.ship_frame,
                            vehicle_frame=node.vehicle_frame, ship_attachment=_point(node.ship_attachment),
                            vehicle_attachment=_point(node.vehicle_attachment))
    msg.output_arc_length = np.asarray(output_arc_length, float).tolist()
    msg.parameters = [KeyValue(key=k, value=str(list(v) if isinstance(v, tuple) else v))
                      for k, v in to_flat(config).items()]
    return msg


def _status(name, level, message, values) -> DiagnosticStatus:
    return DiagnosticStatus(level=level, name=name, message=message, hardware_id="tether_sim",
                            values=[KeyValue(key=k, value=str(v)) for k, v in values.items()])


def diagnostics(t: float, node_name: str, sim: dict, inputs: dict) -> DiagnosticArray:
    """DiagnosticArray: one status for the simulation, one per pose input.

    ``sim`` has: real_time_factor, time_step, lag, dropped_total, capped, divergences, last_error,
    slack (dict end -> bool), snaps (count in the period), running (bool).
    ``inputs``: end -> EndPoseInput.health(now) dict plus ``rejected_recent`` (count in the period).
    """
    msg = DiagnosticArray(header=header(t, ""))
    if not sim.get("running", True):
        level, text = LEVEL_STALE, "waiting for inputs or clock"
    elif sim.get("error_recent"):
        level, text = LEVEL_ERROR, f"solver diverged and was recovered: {sim.get('last_error')}"
    elif sim.get("snaps"):
        level, text = LEVEL_ERROR, f"{sim['snaps']} snap load(s) in the last period"
    elif sim.get("behind"):
        level, text = LEVEL_WARN, "cannot keep up with the clock (lag dropped or substeps capped)"
    elif any(sim.get("slack", {}).values()):
        level, text = LEVEL_WARN, "tether slack at " + ", ".join(k for k, v in sim["slack"].items() if v)
    else:
        level, text = LEVEL_OK, "running"
    values = {k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in sim.items()
              if k not in ("slack",)}
    values.update({f"slack_{k}": v for k, v in sim.get("slack", {}).items()})
    msg.status.append(_status(f"{node_name}: simulation", level, text, values))
    for end, h in inputs.items():
        if h["stale"]:
            level, text = LEVEL_STALE, f"no valid {end} pose for {h['age']:.3g} s"
        elif h.get("rejected_recent"):
            level, text = LEVEL_WARN, f"{h['rejected_recent']} {end} pose(s) rejected in the last period"
        else:
            level, text = LEVEL_OK, "ok"
        values = {"accepted": h["accepted"], "age_s": f"{h['age']:.6g}", "rejected_recent": h.get("rejected_recent", 0)}
        values.update({f"rejected_{reason}": n for reason, n in h["rejected"].items()})
        msg.status.append(_status(f"{node_name}: {end} input", level, text, values))
    return msg


def tension_scale(driver) -> float:
    """Colour scale of the marker: twice the larger static end tension (red = 2x static)."""
    return 2.0 * max(abs(driver.static_tensions[0]), abs(driver.static_tensions[1]), 1.0)


def tick_outputs(driver, arc_lengths) -> list:
    """(topic, message) of every periodic output of the current driver state."""
    cfg, solver = driver.config, driver.solver
    node, t = cfg.node, driver.stamp
    state = solver.state(arc_lengths)
    forces = solver.end_forces()
    out = [("/tether/state", tether_state(state, forces, solver.name, t, node.world_frame, driver.real_time_factor)),
           ("/tether/marker", marker(state, t, node.world_frame, tension_scale(driver))),
           ("/tether/path", path(state, t, node.world_frame))]
    for end in ("ship", "vehicle"):
        force, torque = driver.body_wrench(end, forces)
        out.append((f"/tether/{end}_wrench", wrench(force, torque, t, getattr(node, f"{end}_frame"))))
        if getattr(cfg, f"{end}_end").kind == "body":
            body = solver.body_state(end)
            if body is not None:
                out.append((f"/{end}/sim_pose", pose(body.position, body.orientation, t, node.world_frame)))
    return out


def event_outputs(events, driver) -> list:
    """(topic, message) for the detector's SlackStarted / SnapEvent items."""
    frame = driver.config.node.world_frame
    out = []
    for ev in events:
        if hasattr(ev, "peak_tension"):
            out.append(("/tether/snap_events", snap_event(ev, frame)))
        else:
            static = driver.static_by_location.get(ev.location, 0.0)
            out.append(("/tether/slack_warnings", slack_warning(ev, frame, static)))
    return out
