"""The network node's output messages, built once for the node (published) and the offline runner
(written to MCAP): the line-network counterpart of :func:`tether_sim.ros.convert.tick_outputs`.

Topics (resolved names in the root namespace; docs/network.md "The node on a network"): per line
``/tether/<line>/state|path|marker|snap_events|slack_warnings|description``; per point and per
body ``/tether/<name>_wrench``; per body ``/<body>/sim_pose`` and its transform on /tf,
``/<body>/sim_twist`` and ``/<body>/sim_accel`` (its centre of gravity's velocity and acceleration
and its angular velocity and acceleration, world frame), ``/<body>/hydro_wrench`` (the water's
drag on it and its rotational damping moment, world frame) and ``/<body>/wet_weight`` (latched:
weight minus buoyancy, world frame); per winch ``/winch/<line>/state``; ``/diagnostics``.

The periodic outputs (winch states included) are CDR bytes (:mod:`tether_sim.ros.cdr`), events and
the description are message objects; a publisher takes either.
"""

import threading
from dataclasses import replace

import numpy as np
from diagnostic_msgs.msg import KeyValue

from tether_sim.numerics.rotations import quaternion_rotation
from tether_sim.physics.snap import NumericalSnapWarning, SnapEvent
from tether_sim.ros import cdr, convert
from tether_sim.physics.boundary import END_NAMES
from tether_sim.solvers.base import LOAD_F, LOAD_M

_plain_rotation = getattr(quaternion_rotation, "py_func", quaternion_rotation)  # no compiled call from Python


def line_topics(line: str) -> dict:
    """Output topics of one line: {resolved name: (type name, qos kind)}."""
    return {f"/tether/{line}/state": ("tether_sim_msgs/msg/TetherState", "reliable"),
            f"/tether/{line}/path": ("nav_msgs/msg/Path", "reliable"),
            f"/tether/{line}/marker": ("visualization_msgs/msg/Marker", "reliable"),
            f"/tether/{line}/snap_events": ("tether_sim_msgs/msg/SnapLoadEvent", "events"),
            f"/tether/{line}/slack_warnings": ("tether_sim_msgs/msg/SlackWarning", "events"),
            f"/tether/{line}/description": ("tether_sim_msgs/msg/TetherDescription", "latched")}


def output_topics(spec, winch_lines=()) -> dict:
    """Every output topic of a network (except /tf): {resolved name: (type name, qos kind)}."""
    out = {}
    for line in spec.lines:
        out.update(line_topics(line))
    for name in [*spec.points, *spec.bodies]:
        out[f"/tether/{name}_wrench"] = ("geometry_msgs/msg/WrenchStamped", "reliable")
    for name in spec.bodies:
        out[f"/{name}/sim_pose"] = ("geometry_msgs/msg/PoseStamped", "reliable")
        out[f"/{name}/sim_twist"] = ("geometry_msgs/msg/TwistStamped", "reliable")
        out[f"/{name}/sim_accel"] = ("geometry_msgs/msg/AccelStamped", "reliable")
        out[f"/{name}/hydro_wrench"] = ("geometry_msgs/msg/WrenchStamped", "reliable")
        out[f"/{name}/wet_weight"] = ("geometry_msgs/msg/WrenchStamped", "latched")
    for line in winch_lines:
        out[f"/winch/{line}/state"] = ("tether_sim_msgs/msg/WinchState", "reliable")
    out["/diagnostics"] = ("diagnostic_msgs/msg/DiagnosticArray", "reliable")
    return out


def attachment(node, name):
    """Attachment of a driven point's frame (``node.<point>_attachment`` for ship / vehicle)."""
    return getattr(node, f"{name}_attachment") if name in END_NAMES else (0.0, 0.0, 0.0)


def frame(node, name):
    """Body frame of a point or body: node.ship_frame / node.vehicle_frame, else <prefix><name>/base_link."""
    return node.body_frame(name) if name in END_NAMES else f"{node.frame_prefix}{name}/base_link"


def point_wrench(driver, node, name, orientation=None):
    """Force and torque by the lines on point ``name`` in its body frame (``orientation``: its pose
    input's quaternion x, y, z, w; None: world-aligned, as a fixed point or before the first pose),
    torque about the frame origin."""
    f, t = _point_wrench_floats(driver.net, name, [float(c) for c in attachment(node, name)], orientation)
    return np.array(f), np.array(t)


def _point_wrench_floats(net, name, r, orientation):
    """:func:`point_wrench` as two lists of 3 floats, ``r`` the attachment as floats."""
    F, M = [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]  # plain floats: numpy costs ~1 us per operation on 3-vectors
    for row in net.load_rows(name):
        for c in range(3):
            F[c] += row[LOAD_F + c]
            M[c] += row[LOAD_M + c]
    q = (0.0, 0.0, 0.0, 1.0) if orientation is None else orientation
    R = _rotation(q)
    f, m = _world_to_body(R, F), _world_to_body(R, M)
    t = [r[1] * f[2] - r[2] * f[1] + m[0], r[2] * f[0] - r[0] * f[2] + m[1], r[0] * f[1] - r[1] * f[0] + m[2]]
    return f, t


def body_wrench(net, name):
    """Force and moment about the CoG by the lines on body ``name``, in its body frame."""
    f, m = _body_wrench_floats(net, name)
    return np.array(f), np.array(m)


def _body_wrench_floats(net, name):
    """:func:`body_wrench` as two lists of 3 floats."""
    b = net.bodies[name]
    rows = net.load_rows(name)
    R = _rotation(b.state[3:7])
    force, moment = [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]
    for a, row in zip(b.attachments.tolist(), rows):
        f, m = row[LOAD_F:LOAD_F + 3], row[LOAD_M:LOAD_M + 3]
        lever = [R[3 * i] * a[0] + R[3 * i + 1] * a[1] + R[3 * i + 2] * a[2] for i in range(3)]  # R @ a
        force = [force[c] + f[c] for c in range(3)]
        cross = (lever[1] * f[2] - lever[2] * f[1], lever[2] * f[0] - lever[0] * f[2], lever[0] * f[1] - lever[1] * f[0])
        moment = [moment[c] + cross[c] + m[c] for c in range(3)]
    return _world_to_body(R, force), _world_to_body(R, moment)


def wet_weight(driver, node, name):
    """The latched ``/<body>/wet_weight`` of body ``name``: (0, 0, -(weight - buoyancy)) at its
    centre of gravity, world frame (CDR bytes)."""
    w = float(driver.net.bodies[name].wet_weight)
    return cdr.wrench_stamped(cdr.stamp_parts(driver.stamp), node.world_frame, (0.0, 0.0, -w), (0.0, 0.0, 0.0))


def _rotation(q):
    """R (body -> world) of the quaternion (x, y, z, w) as 9 floats, row major."""
    x, y, z, w = (float(c) for c in q)
    return _plain_rotation(x, y, z, w)


def _world_to_body(R, v):
    """R.T @ v on floats."""
    return [R[0] * v[0] + R[3] * v[1] + R[6] * v[2], R[1] * v[0] + R[4] * v[1] + R[7] * v[2],
            R[2] * v[0] + R[5] * v[1] + R[8] * v[2]]


class _Layout:
    """What the periodic outputs of a network read that holds while its network, node options and
    thread do: topic names, frames, attachments and the fixed-layout encoders (cdr.encoder's, per
    thread), so that a tick formats no topic name and looks up no encoder for them."""

    def __init__(self, driver, node):
        net = self.net = driver.net
        self.node, self.thread = node, threading.get_ident()
        world = node.world_frame
        self.lines = [(line, solver, f"/tether/{line}/state", f"/tether/{line}/path", f"/tether/{line}/marker",
                       f"tether/{line}") for line, solver in net.lines.items()]
        wrench = lambda frame_id: cdr.encoder(cdr.StampedDoublesEncoder, frame_id, 6)  # noqa: E731
        self.points = [(name, f"/tether/{name}_wrench", wrench(frame(node, name)),
                        [float(c) for c in attachment(node, name)]) for name in driver.spec.points]
        self.bodies = [(name, b, frame(node, name), f"/tether/{name}_wrench", wrench(frame(node, name)),
                        f"/{name}/sim_pose", cdr.encoder(cdr.StampedDoublesEncoder, world, 7),
                        (f"/{name}/sim_twist", f"/{name}/sim_accel", f"/{name}/hydro_wrench"), wrench(world))
                       for name, b in net.bodies.items()]
        self.winches = [(f"/winch/{line}/state", line, link, END_NAMES.index(link.config.winch.end))
                        for line, link in net.winches.items()]

    def valid(self, driver, node) -> bool:
        return driver.net is self.net and node is self.node and threading.get_ident() == self.thread


def _layout(driver, node) -> _Layout:
    layout = driver.output_layout
    if layout is None or not layout.valid(driver, node):
        layout = driver.output_layout = _Layout(driver, node)
    return layout


class _Everything:
    """A ``wanted`` that holds every topic."""

    def __contains__(self, topic) -> bool:
        return True


_ALL = _Everything()


def tick_outputs(driver, node, orientation_of=lambda name: None, wanted=None, shapes=True, visuals=True) -> list:
    """(topic, payload) of every periodic output of the driver's current state, stamped with its
    clock time; ``orientation_of(point)``: a driven point's quaternion (None: world-aligned);
    ``wanted``: only these topics (a container; None: all; the winch states go out regardless). Returns
    also the body transforms for /tf as the last item ``("/tf", [(frame, position, quaternion), ...])``
    (an empty list without bodies). ``shapes``: False leaves out the lines' state, path and marker
    (``node.shape_rate``, convert.ShapeGate); ``visuals``: False leaves out their path and marker
    (``node.visual_rate``)."""
    net = driver.net
    layout = _layout(driver, node)
    want = _ALL if wanted is None else wanted
    stamp = cdr.stamp_parts(driver.stamp)
    world = node.world_frame
    out = []
    if shapes:
        for line, solver, state_topic, path_topic, marker_topic, ns in layout.lines:
            state, path, marker = state_topic in want, visuals and path_topic in want, visuals and marker_topic in want
            if not (state or path or marker):
                continue
            st = driver.line_state(line, node.output_points)
            pts = np.asarray(st.position, float)
            if state:
                t0, t1 = net.end_tensions(line)
                out.append((state_topic, cdr.tether_state(
                    stamp, world, solver.name, st.arc_length, pts, st.velocity, st.tension, st.curvature,
                    st.bending_moment, t0, t1, float(st.time_step), float(driver.real_time_factor), float(driver.lag),
                    bool(driver.degraded))))
            if path:
                out.append((path_topic, cdr.path(stamp, world, pts)))
            if marker:
                scale = 2.0 * max(max(driver.static_tensions[line]), 1.0)
                out.append((marker_topic, cdr.marker_line_strip(
                    stamp, world, ns, 0, convert.MARKER_WIDTH, convert.MARKER_COLOUR, pts,
                    convert.tension_colours(st.tension, scale))))
    for name, topic, enc, r in layout.points:
        if topic in want:
            force, torque = _point_wrench_floats(net, name, r, orientation_of(name))
            out.append((topic, enc.encode(stamp, *force, *torque)))
    transforms = []
    for name, b, frame_id, wrench_topic, wrench_enc, pose_topic, pose_enc, kinds, world_enc in layout.bodies:
        if wrench_topic in want:
            force, moment = _body_wrench_floats(net, name)
            out.append((wrench_topic, wrench_enc.encode(stamp, *force, *moment)))
        pose = b.state[0:7]
        if pose_topic in want:
            out.append((pose_topic, pose_enc.encode(stamp, *pose.tolist())))
        twist, accel, hydro = (t in want for t in kinds)
        if twist or accel or hydro:
            m = net.body_motion(name)
            if twist:
                out.append((kinds[0], world_enc.encode(stamp, *m["velocity"], *m["omega"])))
            if accel:
                out.append((kinds[1], world_enc.encode(stamp, *m["acceleration"], *m["angular_acceleration"])))
            if hydro:
                out.append((kinds[2], world_enc.encode(stamp, *m["drag"], *m["damping_moment"])))
        transforms.append((frame_id, b.state[0:3], b.state[3:7]))
    for topic, line, link, end in layout.winches:
        w = link.winch
        out.append((topic, cdr.winch_state(
            stamp, world, link.config.winch.end, w.mode, w.setpoint, w.length, w.speed, w.commanded_speed,
            net.end_tensions(line)[end], **w.flags)))
    out.append(("/tf", transforms))
    return out


def event_outputs(driver, node, line, events) -> list:
    """(topic, message) of one line's detector events; the snap guard's NumericalSnapWarning items
    have no topic (never published as snaps: the caller logs and counts them). The event's ``end``
    is ship / vehicle, the line's s = 0 / s = L end."""
    out = []
    for ev in events:
        if isinstance(ev, NumericalSnapWarning):
            continue
        end = ev.location.rsplit("/", 1)[-1]
        ev = replace(ev, location=end)
        if isinstance(ev, SnapEvent):
            degraded = driver.degraded or driver.bridged(ev)  # (its slack ran across a re-synchronisation)
            out.append((f"/tether/{line}/snap_events", convert.snap_event(ev, node.world_frame, degraded, driver.lag)))
        else:
            static = driver.static_tensions[line][END_NAMES.index(end)]
            out.append((f"/tether/{line}/slack_warnings", convert.slack_warning(ev, node.world_frame, static)))
    return out


def description(spec, node, line, t):
    """TetherDescription of one line (its cable and every key), stamped ``t``."""
    cfg = replace(spec.lines[line].config, node=node)
    L = float(cfg.cable.length)
    msg = convert.description(cfg, np.linspace(0.0, L, node.output_points), t)
    # where the line's ends are in the network (the report finds a body's lines by them)
    for end in spec.lines[line].ends:
        key = "from" if end.end == END_NAMES[0] else "to"
        msg.parameters.append(KeyValue(key=f"network.lines.{line}.{key}", value=end.target))
    return msg
