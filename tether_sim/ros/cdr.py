"""Serialized (CDR) bytes of the per-tick output messages, built straight from numpy arrays.

The node publishes these bytes with ``Publisher.publish(bytes)`` (rmw publishes them as they are)
and the offline runner writes them into MCAP, so no Python message object is built per tick:
building a TetherState/Marker/Path as rclpy objects (one ``Point`` per output point, one
``PoseStamped`` per Path pose, each field type-checked on assignment) and converting them to C
for serialization cost ~2 ms per 50 Hz tick; these encoders take ~0.1 ms (docs/node.md).

Encoding: the ROS 2 default, plain CDR little endian (XCDR1) with the 4-byte encapsulation header
``00 01 00 00``; every primitive is aligned to its size (8 for float64) counted from the end of
that header; strings are uint32 length (incl. the NUL) + bytes + NUL; sequences are a uint32 count
followed by the elements. test/ros/test_cdr.py checks every encoder against rclpy: the bytes
deserialize to the expected message and re-serialize to the same bytes.

No rclpy import here (plain numpy/struct); the field order follows the Jazzy message definitions.
"""

import struct

import numpy as np

ENCAPSULATION = b"\x00\x01\x00\x00"  # CDR, little endian
_ZEROS = bytes(8)
_U32 = struct.Struct("<I")
_TIME = struct.Struct("<iI")
_3I = struct.Struct("<iii")
_6D = struct.Struct("<6d")
_7D = struct.Struct("<7d")


def stamp_parts(t: float) -> tuple:
    """(sec, nanosec) of a clock time in seconds (clamped at 0), as builtin_interfaces/Time."""
    ns = max(0, int(round(t * 1e9)))
    return ns // 1_000_000_000, ns % 1_000_000_000


class CdrBuffer:
    """Append-only CDR writer; ``offset`` counts payload bytes after the encapsulation header."""

    __slots__ = ("parts", "offset")

    def __init__(self):
        self.parts = [ENCAPSULATION]
        self.offset = 0

    def align(self, size: int) -> None:
        pad = -self.offset % size
        if pad:
            self.parts.append(_ZEROS[:pad])
            self.offset += pad

    def raw(self, data: bytes) -> None:
        self.parts.append(data)
        self.offset += len(data)

    def packed(self, fmt: struct.Struct, align: int, *values) -> None:
        self.align(align)
        self.raw(fmt.pack(*values))

    def u32(self, value: int) -> None:
        self.packed(_U32, 4, value)

    def string(self, text: bytes) -> None:
        self.align(4)
        self.raw(_U32.pack(len(text) + 1) + text + b"\x00")

    def header(self, stamp: tuple, frame: bytes) -> None:
        """std_msgs/Header: builtin_interfaces/Time stamp, string frame_id."""
        self.packed(_TIME, 4, *stamp)
        self.string(frame)

    def float64s(self, values) -> None:
        """Fixed-size float64 fields (a nested message of doubles, or several in a row)."""
        self.align(8)
        self.raw(np.ascontiguousarray(values, dtype="<f8").tobytes())

    def float64_sequence(self, values) -> None:
        """sequence<float64>, or a sequence of a message of doubles (Point, Vector3) given as (n, k)."""
        values = np.ascontiguousarray(values, dtype="<f8")
        self.u32(values.shape[0] if values.ndim else 1)
        if values.size:
            self.float64s(values)

    def tobytes(self) -> bytes:
        return b"".join(self.parts)


def _text(s: str) -> bytes:
    return s.encode("utf-8")


def tether_state(stamp: tuple, frame: str, solver_name: str, arc_length, position, velocity, tension, curvature,
                 bending_moment, ship_tension: float, vehicle_tension: float, time_step: float,
                 real_time_factor: float, lag: float = 0.0, degraded: bool = False) -> bytes:
    """tether_sim_msgs/TetherState (msg_defs/msg/TetherState.msg); arrays (n,) or (n, 3), world frame."""
    b = CdrBuffer()
    b.header(stamp, _text(frame))
    b.string(_text(solver_name))
    b.float64_sequence(arc_length)
    b.float64_sequence(position)
    b.float64_sequence(velocity)
    b.float64_sequence(tension)
    b.float64_sequence(curvature)
    b.float64_sequence(bending_moment)
    b.float64s((ship_tension, vehicle_tension, time_step, real_time_factor, lag))
    b.raw(b"\x01" if degraded else b"\x00")  # bool (1 byte, no alignment)
    return b.tobytes()


_IDENTITY_POSE = np.array([0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0])  # Point position, Quaternion x, y, z, w
LINE_STRIP, ADD = 4, 0  # visualization_msgs/Marker constants


def _marker_constant_parts(frame: bytes, ns: str, marker_id: int, width: float, colour) -> tuple:
    """(bytes from the end of the header to the points count, bytes after the colours): constant
    for a frame name and marker style, so they are encoded once (their padding depends only on the
    frame name's length; the part after the 4-byte colours holds only 4-aligned and 1-byte items)."""
    key = (frame, ns, marker_id, width, tuple(colour))
    parts = _MARKER_PARTS.get(key)
    if parts is None:
        b = CdrBuffer()
        b.header((0, 0), frame)
        start = len(b.tobytes())
        b.string(_text(ns))
        b.packed(_3I, 4, marker_id, LINE_STRIP, ADD)
        b.float64s(_IDENTITY_POSE)
        b.float64s((width, 0.0, 0.0))  # scale
        b.align(4)
        b.raw(np.asarray(colour, dtype="<f4").tobytes())
        b.packed(_TIME, 4, 0, 0)  # lifetime (Duration): forever
        b.raw(b"\x00")  # frame_locked = False
        middle = b.tobytes()[start:]
        t = CdrBuffer()  # after the colours (offset 4-aligned):
        t.string(b"")  # texture_resource
        t.header((0, 0), b"")  # texture (sensor_msgs/CompressedImage): header,
        t.string(b"")  # format,
        t.u32(0)  # data (uint8[])
        t.u32(0)  # uv_coordinates
        t.string(b"")  # text
        t.string(b"")  # mesh_resource
        t.string(b"")  # mesh_file (visualization_msgs/MeshFile): filename,
        t.u32(0)  # data (uint8[])
        t.raw(b"\x00")  # mesh_use_embedded_materials = False
        parts = _MARKER_PARTS[key] = (middle, t.tobytes()[len(ENCAPSULATION):])
    return parts


_MARKER_PARTS = {}


def marker_line_strip(stamp: tuple, frame: str, ns: str, marker_id: int, width: float, colour, points,
                      colours) -> bytes:
    """visualization_msgs/Marker LINE_STRIP (action ADD, identity pose, lifetime 0, not frame-locked)
    with per-vertex colours: ``colour`` (4,) RGBA, ``points`` (n, 3), ``colours`` (n, 4) RGBA."""
    frame_b = _text(frame)
    middle, tail = _marker_constant_parts(frame_b, ns, int(marker_id), float(width), tuple(float(c) for c in colour))
    b = CdrBuffer()
    b.header(stamp, frame_b)
    b.raw(middle)
    b.float64_sequence(points)
    colours = np.ascontiguousarray(colours, dtype="<f4")
    b.u32(colours.shape[0])
    b.raw(colours.tobytes())
    b.raw(tail)
    return b.tobytes()


def path(stamp: tuple, frame: str, points) -> bytes:
    """nav_msgs/Path of ``points`` (n, 3), each a PoseStamped with the path's header and identity
    orientation."""
    b = CdrBuffer()
    frame_b = _text(frame)
    b.header(stamp, frame_b)
    n = len(points)
    b.u32(n)
    if n == 0:
        return b.tobytes()
    poses = np.zeros((n, 7), dtype="<f8")
    poses[:, 0:3] = points
    poses[:, 6] = 1.0
    head = np.frombuffer(_TIME.pack(*stamp) + _U32.pack(len(frame_b) + 1) + frame_b + b"\x00", np.uint8)
    b.raw(head.tobytes())  # the first PoseStamped: header (4-aligned), pose (8-aligned)
    b.align(8)
    b.raw(poses[0].tobytes())
    if n > 1:  # the others all start 8-aligned, so they share one layout: a (n - 1, stride) block
        gap = -head.size % 8
        rows = np.zeros((n - 1, head.size + gap + 56), np.uint8)
        rows[:, :head.size] = head
        rows[:, head.size + gap:] = poses[1:].view(np.uint8).reshape(n - 1, 56)
        b.raw(rows.tobytes())
    return b.tobytes()


def wrench_stamped(stamp: tuple, frame: str, force, torque) -> bytes:
    """geometry_msgs/WrenchStamped."""
    b = CdrBuffer()
    b.header(stamp, _text(frame))
    b.packed(_6D, 8, *(float(x) for x in force), *(float(x) for x in torque))
    return b.tobytes()


def pose_stamped(stamp: tuple, frame: str, position, orientation) -> bytes:
    """geometry_msgs/PoseStamped (orientation quaternion x, y, z, w)."""
    b = CdrBuffer()
    b.header(stamp, _text(frame))
    b.packed(_7D, 8, *(float(x) for x in position), *(float(x) for x in orientation))
    return b.tobytes()
