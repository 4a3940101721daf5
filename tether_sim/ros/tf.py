"""/tf and /tf_static of the simulation node (docs/node.md, "Frames and TF").

- ``/tf_static`` (latched: reliable, transient local, depth 1; sent once, at the first output):
  each end's body frame -> its tether attachment frame, ``ship/base_link -> ship/tether_sheave``
  and ``rov/base_link -> rov/tether_attach`` (names from ``node.ship_frame`` /
  ``node.vehicle_frame`` with the last path element replaced, or ``node.*_attachment_frame``; all
  of them, and the tether frames, behind ``node.frame_prefix``), translated by the attachment offset
  (``node.*_attachment``, or ``body.attachment`` from the centre of gravity for a simulated body),
  no rotation.
- ``/tf`` (at ``node.visual_rate``, every fifth 50 Hz output by default, only while something
  subscribes): world (``node.world_frame``) -> each end's
  body frame: the simulated pose of a ``body`` end (cage or vehicle, origin at its centre of
  gravity), the interpolated input pose of a ``prescribed`` end (unless
  ``node.tf_prescribed_ends`` is false, for stacks that publish those transforms themselves), and a
  frame aligned with the world at the end's attachment point minus its offset for the other kinds;
  plus ``node.tf_tether_frames`` frames ``<tether_frame_prefix>/<k>`` equally spaced along the cable
  (x along the local tangent, pointing from the ship towards the vehicle).

The message type is ``tf2_msgs/msg/TFMessage``: the distribution's tf2_msgs where importable, else
the same interface built from its definition by tools/setup_env.sh (msg_defs/tf2_msgs). Without
either the node runs without TF and says so once.
"""

from __future__ import annotations

import math
import struct

import numpy as np
from geometry_msgs.msg import TransformStamped
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

from tether_sim.config import NodeOptions
from tether_sim.physics.boundary import END_NAMES
from tether_sim.ros import cdr, convert

try:
    from tf2_msgs.msg import TFMessage
except ImportError:  # no tf2_msgs: neither a ROS 2 install nor msg_defs/tf2_msgs built
    TFMessage = None

TF_QOS = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE)  # as tf2_ros' broadcaster
TF_STATIC_QOS = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                           durability=DurabilityPolicy.TRANSIENT_LOCAL)
_7D = struct.Struct("<7d")


def attachment_frame(body_frame: str, end: str) -> str:
    """``ship/base_link`` -> ``ship/tether_sheave``, ``rov/base_link`` -> ``rov/tether_attach``;
    a frame without a ``/`` gets a suffix (``boat`` -> ``boat_tether_sheave``)."""
    return NodeOptions(**{f"{end}_frame": body_frame}).attachment_frame(end)


def rotate(q, v) -> np.ndarray:
    """``R(q) v`` for a unit quaternion (x, y, z, w): v + 2 w (u x v) + 2 u x (u x v), u = (x, y, z)."""
    return np.array(_rotated(q, v))


def _rotated(q, v) -> tuple:
    """:func:`rotate` as a tuple of floats."""
    x, y, z, w = (float(c) for c in q)
    a, b, c = (float(e) for e in v)
    tx, ty, tz = y * c - z * b, z * a - x * c, x * b - y * a  # u x v
    return (a + 2.0 * (w * tx + y * tz - z * ty), b + 2.0 * (w * ty + z * tx - x * tz),
            c + 2.0 * (w * tz + x * ty - y * tx))


def tangent_quaternion(t) -> tuple:
    """Quaternion (x, y, z, w) of the shortest rotation taking the x axis onto the unit vector t."""
    t = np.asarray(t, float)
    n = float(np.linalg.norm(t))
    if n == 0.0 or not math.isfinite(n):
        return (0.0, 0.0, 0.0, 1.0)
    t = t / n
    c = float(t[0])  # cos of the angle between x and t
    if c < -1.0 + 1e-12:
        return (0.0, 0.0, 1.0, 0.0)  # half turn about z
    axis = np.array([0.0, -t[2], t[1]])  # x cross t
    s = math.sqrt(2.0 * (1.0 + c))
    return (float(axis[0] / s), float(axis[1] / s), float(axis[2] / s), 0.5 * s)


def transform(stamp: float, parent: str, child: str, position, quaternion=(0.0, 0.0, 0.0, 1.0)):
    msg = TransformStamped()
    msg.header = convert.header(stamp, parent)
    msg.child_frame_id = child
    tr, rq = msg.transform.translation, msg.transform.rotation
    tr.x, tr.y, tr.z = (float(c) for c in position)
    rq.x, rq.y, rq.z, rq.w = (float(c) for c in quaternion)
    return msg


def static_transforms(driver, stamp: float) -> list:
    """Body frame -> attachment frame of both ends."""
    node = driver.config.node
    return [transform(stamp, node.body_frame(end), node.attachment_frame(end), tuple(driver.offset(end)))
            for end in END_NAMES]


def body_poses(driver, include_prescribed: bool = True, frame=None) -> list:
    """(end, position, quaternion) of each end's body frame origin in the world frame, as tuples of
    floats (``frame``: the :class:`~tether_sim.ros.convert.OutputFrame` of this state, if the caller
    has one)."""
    cfg = driver.config
    frame = convert.OutputFrame(driver) if frame is None else frame
    out, attach = [], None
    for end, kind, offset in convert._layout(driver).offsets:
        if kind == "prescribed" and not include_prescribed:
            continue
        if kind == "body":
            body = frame.body(end)
            if body is not None:
                out.append((end, tuple(body.position.tolist()), tuple(body.orientation.tolist())))
                continue
        if attach is None:
            attach = frame.end_positions(cfg.cable.length).tolist()
        q = tuple(np.asarray(frame.orientation(end), float).tolist())
        (px, py, pz), (rx, ry, rz) = attach[0 if end == "ship" else 1], _rotated(q, offset)
        out.append((end, (px - rx, py - ry, pz - rz), q))
    return out


def tether_frames(solver, length: float, count: int) -> list:
    """(position, quaternion) of ``count`` equally spaced points along the cable, x along the tangent."""
    if count <= 0:
        return []
    s = np.linspace(0.0, length, count) if count > 1 else np.array([0.5 * length])
    ds = 1e-3 * length
    probe = np.concatenate([s, np.clip(s + ds, 0.0, length), np.clip(s - ds, 0.0, length)])
    pos = np.asarray(solver.state(probe).position, float)
    p, ahead, behind = pos[:count], pos[count:2 * count], pos[2 * count:]
    return [(p[k], tangent_quaternion(ahead[k] - behind[k])) for k in range(count)]


def dynamic_transforms(driver, frame=None) -> list:
    """(child frame, position, quaternion) of every /tf transform, all with the world frame as parent
    (``frame``: the :class:`~tether_sim.ros.convert.OutputFrame` of this state, if the caller has one)."""
    node = driver.config.node
    out = [(node.body_frame(end), p, q) for end, p, q in body_poses(driver, node.tf_prescribed_ends, frame)]
    for k, (p, q) in enumerate(tether_frames(driver.solver, driver.config.cable.length, node.tf_tether_frames)):
        out.append((node.tether_frame(k), p, q))
    return out


class TfMessageEncoder(cdr.Template):
    """tf2_msgs/TFMessage of a fixed list of child frames, all with one parent (a fixed layout:
    encoded once, each message writes the stamps and the 7 doubles of each transform in place)."""

    def __init__(self, parent: str, children: tuple):
        b = cdr.CdrBuffer()
        b.u32(len(children))
        stamps, values = [], []
        parent = parent.encode("utf-8")
        for child in children:
            stamps.append(cdr.header_at(b, parent))
            b.string(child.encode("utf-8"))
            b.align(8)
            values.append(b.offset)
            b.raw(bytes(_7D.size))
        self._finish(b)
        self._stamps = [self._at(at) for at in stamps]
        self._values = [self._at(at) for at in values]

    def encode(self, stamp: tuple, transforms) -> bytes:
        buf = self.buf
        for at in self._stamps:
            cdr.TIME.pack_into(buf, at, *stamp)
        for at, (_, p, q) in zip(self._values, transforms):  # ('d' packs what float() gives)
            _7D.pack_into(buf, at, *p, *q)
        return self.tobytes()


def tf_message_cdr(stamp: float, parent: str, transforms) -> bytes:
    """Serialized tf2_msgs/TFMessage (CDR, as :mod:`tether_sim.ros.cdr` writes the other periodic
    outputs; building TransformStamped objects cost ~1 ms per tick, measured with
    benchmarks/bench_tf.py): ``transforms`` = [(child frame, position, quaternion x y z w)]."""
    enc = cdr.encoder(TfMessageEncoder, parent, tuple(child for child, _, _ in transforms))
    return enc.encode(cdr.stamp_parts(stamp), transforms)


class TfPublisher:
    """The node's /tf and /tf_static publishers; :meth:`publish` once per output (docs above)."""

    def __init__(self, node):
        self.node = node
        self.enabled = TFMessage is not None and node.config.node.publish_tf
        self._static_sent = False
        if TFMessage is None:
            node.get_logger().warning("tf2_msgs is not importable (build msg_defs/tf2_msgs: tools/setup_env.sh): "
                                      "no /tf or /tf_static")
        if not self.enabled:
            return
        self.pub = node.create_publisher(TFMessage, "/tf", TF_QOS)
        self.static_pub = node.create_publisher(TFMessage, "/tf_static", TF_STATIC_QOS)

    def publish(self, driver, frame=None, due=True) -> None:
        """``frame``: the :class:`~tether_sim.ros.convert.OutputFrame` the tick's other outputs read;
        ``due``: False leaves /tf out of this output (``node.visual_rate``; /tf_static goes out regardless)."""
        if not self.enabled or driver.solver is None:
            return
        if not self._static_sent:
            self.static_pub.publish(TFMessage(transforms=static_transforms(driver, driver.stamp)))
            self._static_sent = True
        if due and self.pub.get_subscription_count() > 0:
            cfg = driver.config
            self.pub.publish(tf_message_cdr(driver.stamp, cfg.node.world_frame, dynamic_transforms(driver, frame)))
