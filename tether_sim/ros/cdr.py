"""Serialized (CDR) bytes of the per-tick output messages, built straight from numpy arrays.

The node publishes these bytes with ``Publisher.publish(bytes)`` (rmw publishes them as they are)
and the offline runner writes them into MCAP, so no Python message object is built per tick:
building a TetherState/Marker/Path as rclpy objects (one ``Point`` per output point, one
``PoseStamped`` per Path pose, each field type-checked on assignment) and converting them to C
for serialization cost ~2 ms per 50 Hz tick (docs/node.md). Each layout (message type, frame and
names, point count) is encoded once into a buffer (:class:`Template`); a tick writes the stamp and
the values in place and copies the bytes out (``benchmarks/bench_node_tick.py`` times the tick).

Encoding: the ROS 2 default, plain CDR little endian (XCDR1) with the 4-byte encapsulation header
``00 01 00 00``; every primitive is aligned to its size (8 for float64) counted from the end of
that header; strings are uint32 length (incl. the NUL) + bytes + NUL; sequences are a uint32 count
followed by the elements. test/ros/test_cdr.py checks every encoder against rclpy: the bytes
deserialize to the expected message and re-serialize to the same bytes.

No rclpy import here (plain numpy/struct); the field order follows the Jazzy message definitions.
"""

import struct
import threading

import numpy as np

ENCAPSULATION = b"\x00\x01\x00\x00"  # CDR, little endian
_ZEROS = bytes(8)
_U32 = struct.Struct("<I")
TIME = struct.Struct("<iI")  # builtin_interfaces/Time
_3I = struct.Struct("<iii")


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
        self.packed(TIME, 4, *stamp)
        self.string(frame)

    def float64s(self, values) -> None:
        """Fixed-size float64 fields (a nested message of doubles, or several in a row)."""
        self.align(8)
        self.raw(np.ascontiguousarray(values, dtype="<f8").tobytes())

    def tobytes(self) -> bytes:
        return b"".join(self.parts)


def _text(s: str) -> bytes:
    return s.encode("utf-8")


class Template:
    """The bytes of one message layout, written once with zero values on a CdrBuffer by the
    subclass's constructor, which records the offsets of the changing fields; each encoding writes
    those in place (numpy views, ``struct.pack_into``) and copies the bytes out. Not shared between
    threads (:func:`encoder` keeps one per thread). The buffer holds 4 bytes of lead before the
    encapsulation header, so a payload offset that is 8-aligned is 8-aligned in the buffer too."""

    LEAD = 4

    def _finish(self, b: CdrBuffer) -> None:
        data = b.tobytes()
        self.buf = bytearray(self.LEAD) + bytearray(data)
        self._out = memoryview(self.buf)[self.LEAD:]

    def _at(self, offset: int) -> int:
        """Buffer index of a payload offset."""
        return self.LEAD + len(ENCAPSULATION) + offset

    def _f8(self, offset: int, shape, strides=None) -> np.ndarray:
        return np.ndarray(shape, dtype="<f8", buffer=self.buf, offset=self._at(offset), strides=strides)

    def tobytes(self) -> bytes:
        return self._out.tobytes()


def header_at(b: CdrBuffer, frame: bytes) -> int:
    """Writes a std_msgs/Header with a zero stamp; returns the stamp's payload offset."""
    b.align(4)
    at = b.offset
    b.header((0, 0), frame)
    return at


def _sequence_at(b: CdrBuffer, n: int, width: int) -> int:
    """Writes sequence<float64> (width 1) or a sequence of a message of ``width`` doubles, n zero
    elements; returns the payload offset of the first double."""
    b.u32(n)
    if n:
        b.align(8)
    at = b.offset
    if n:
        b.raw(bytes(8 * n * width))
    return at


class TetherStateEncoder(Template):
    """tether_sim_msgs/TetherState of ``n`` points in one frame from one solver (a fixed layout)."""

    def __init__(self, frame: str, solver_name: str, n: int):
        b = CdrBuffer()
        self._stamp = header_at(b, _text(frame))
        b.string(_text(solver_name))
        offsets = [_sequence_at(b, n, width) for width in (1, 3, 3, 1, 1, 1)]
        b.align(8)
        scalars = b.offset
        b.raw(bytes(5 * 8 + 1))  # ship/vehicle tension, time step, real-time factor, lag; the bool degraded
        self._finish(b)
        self.n = n
        self.arrays = [self._f8(at, (n, 3) if width == 3 else (n,)) for at, width in zip(offsets, (1, 3, 3, 1, 1, 1))]
        self._scalars = self._at(scalars)

    def encode(self, stamp: tuple, arc_length, position, velocity, tension, curvature, bending_moment,
               ship_tension: float, vehicle_tension: float, time_step: float, real_time_factor: float,
               lag: float = 0.0, degraded: bool = False) -> bytes:
        TIME.pack_into(self.buf, self._at(self._stamp), *stamp)
        for view, values in zip(self.arrays, (arc_length, position, velocity, tension, curvature, bending_moment)):
            view[...] = values
        _5D_BOOL.pack_into(self.buf, self._scalars, ship_tension, vehicle_tension, time_step, real_time_factor, lag,
                           1 if degraded else 0)
        return self.tobytes()


_5D_BOOL = struct.Struct("<5dB")


def tether_state(stamp: tuple, frame: str, solver_name: str, arc_length, position, velocity, tension, curvature,
                 bending_moment, ship_tension: float, vehicle_tension: float, time_step: float,
                 real_time_factor: float, lag: float = 0.0, degraded: bool = False) -> bytes:
    """tether_sim_msgs/TetherState (msg_defs/msg/TetherState.msg); arrays (n,) or (n, 3), world frame."""
    enc = encoder(TetherStateEncoder, frame, solver_name, len(arc_length))
    return enc.encode(stamp, arc_length, position, velocity, tension, curvature, bending_moment, float(ship_tension),
                      float(vehicle_tension), float(time_step), float(real_time_factor), float(lag), bool(degraded))


_IDENTITY_POSE = np.array([0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0])  # Point position, Quaternion x, y, z, w
LINE_STRIP, ADD = 4, 0  # visualization_msgs/Marker constants


class MarkerLineStripEncoder(Template):
    """visualization_msgs/Marker LINE_STRIP (action ADD, identity pose, lifetime 0, not frame-locked)
    of ``n`` points with per-vertex colours, one frame, namespace, id, width and colour."""

    def __init__(self, frame: str, ns: str, marker_id: int, width: float, colour, n: int):
        b = CdrBuffer()
        self._stamp = header_at(b, _text(frame))
        b.string(_text(ns))
        b.packed(_3I, 4, int(marker_id), LINE_STRIP, ADD)
        b.float64s(_IDENTITY_POSE)
        b.float64s((float(width), 0.0, 0.0))  # scale
        b.align(4)
        b.raw(np.asarray(colour, dtype="<f4").tobytes())
        b.packed(TIME, 4, 0, 0)  # lifetime (Duration): forever
        b.raw(b"\x00")  # frame_locked = False
        points = _sequence_at(b, n, 3)
        b.u32(n)
        colours = b.offset
        b.raw(bytes(16 * n))  # ColorRGBA: 4 float32, 4-aligned
        b.string(b"")  # texture_resource
        b.header((0, 0), b"")  # texture (sensor_msgs/CompressedImage): header,
        b.string(b"")  # format,
        b.u32(0)  # data (uint8[])
        b.u32(0)  # uv_coordinates
        b.string(b"")  # text
        b.string(b"")  # mesh_resource
        b.string(b"")  # mesh_file (visualization_msgs/MeshFile): filename,
        b.u32(0)  # data (uint8[])
        b.raw(b"\x00")  # mesh_use_embedded_materials = False
        self._finish(b)
        self.n = n
        self.points = self._f8(points, (n, 3))
        self.colours = np.ndarray((n, 4), dtype="<f4", buffer=self.buf, offset=self._at(colours))

    def encode(self, stamp: tuple, points, colours) -> bytes:
        TIME.pack_into(self.buf, self._at(self._stamp), *stamp)
        self.points[...] = points
        self.colours[...] = colours  # float64 -> float32: rounded as astype rounds
        return self.tobytes()


def marker_line_strip(stamp: tuple, frame: str, ns: str, marker_id: int, width: float, colour, points,
                      colours) -> bytes:
    """visualization_msgs/Marker LINE_STRIP (action ADD, identity pose, lifetime 0, not frame-locked)
    with per-vertex colours: ``colour`` (4,) RGBA, ``points`` (n, 3), ``colours`` (n, 4) RGBA."""
    enc = encoder(MarkerLineStripEncoder, frame, ns, int(marker_id), float(width), tuple(float(c) for c in colour),
                  len(points))
    return enc.encode(stamp, points, colours)


class PathEncoder(Template):
    """nav_msgs/Path of ``n`` poses, each a PoseStamped with the path's header and identity orientation."""

    def __init__(self, frame: str, n: int):
        b = CdrBuffer()
        frame_b = _text(frame)
        stamps = [header_at(b, frame_b)]
        b.u32(n)
        positions = []
        for _ in range(n):
            stamps.append(header_at(b, frame_b))
            b.align(8)
            positions.append(b.offset)
            b.float64s(_IDENTITY_POSE)
        self._finish(b)
        self.n = n
        self._stamps = [self._at(at) for at in stamps]
        # every pose after the first starts 8-aligned, so they share one layout: a strided view
        self.first = self._f8(positions[0], (1, 3)) if n else None
        stride = positions[2] - positions[1] if n > 2 else 0
        self.rest = self._f8(positions[1], (n - 1, 3), (stride, 8)) if n > 1 else None
        if n > 1:
            self.sec = np.ndarray((n - 1,), "<i4", self.buf, self._stamps[2], (stride,))
            self.nanosec = np.ndarray((n - 1,), "<u4", self.buf, self._stamps[2] + 4, (stride,))

    def encode(self, stamp: tuple, points) -> bytes:
        n = self.n
        for at in self._stamps[:2]:
            TIME.pack_into(self.buf, at, *stamp)
        if n:
            points = np.asarray(points, float)
            self.first[0] = points[0]
        if n > 1:
            self.rest[...] = points[1:]
            self.sec[...] = stamp[0]
            self.nanosec[...] = stamp[1]
        return self.tobytes()


def path(stamp: tuple, frame: str, points) -> bytes:
    """nav_msgs/Path of ``points`` (n, 3), each a PoseStamped with the path's header and identity
    orientation."""
    return encoder(PathEncoder, frame, len(points)).encode(stamp, points)


class StampedDoublesEncoder(Template):
    """A header followed by ``count`` float64 (8-aligned): WrenchStamped (6), PoseStamped (7)."""

    def __init__(self, frame: str, count: int):
        b = CdrBuffer()
        self._stamp = header_at(b, _text(frame))
        b.align(8)
        at = b.offset
        b.raw(bytes(8 * count))
        self._finish(b)
        self._values = self._at(at)
        self._fmt = struct.Struct(f"<{count}d")

    def encode(self, stamp: tuple, *values) -> bytes:
        TIME.pack_into(self.buf, self._at(self._stamp), *stamp)
        self._fmt.pack_into(self.buf, self._values, *values)
        return self.tobytes()


def wrench_stamped(stamp: tuple, frame: str, force, torque) -> bytes:
    """geometry_msgs/WrenchStamped."""
    return encoder(StampedDoublesEncoder, frame, 6).encode(stamp, *(float(x) for x in force),
                                                            *(float(x) for x in torque))


def twist_stamped(stamp: tuple, frame: str, linear, angular) -> bytes:
    """geometry_msgs/TwistStamped (the same layout as WrenchStamped: a header and two Vector3)."""
    return wrench_stamped(stamp, frame, linear, angular)


def accel_stamped(stamp: tuple, frame: str, linear, angular) -> bytes:
    """geometry_msgs/AccelStamped (the same layout as WrenchStamped: a header and two Vector3)."""
    return wrench_stamped(stamp, frame, linear, angular)


def pose_stamped(stamp: tuple, frame: str, position, orientation) -> bytes:
    """geometry_msgs/PoseStamped (orientation quaternion x, y, z, w)."""
    return encoder(StampedDoublesEncoder, frame, 7).encode(stamp, *(float(x) for x in position),
                                                            *(float(x) for x in orientation))


class WinchStateEncoder(Template):
    """tether_sim_msgs/WinchState (msg_defs/msg/WinchState.msg) of one frame, winch end and mode."""

    _VALUES = struct.Struct("<5d4B")

    def __init__(self, frame: str, end: str, mode: str):
        b = CdrBuffer()
        self._stamp = header_at(b, _text(frame))
        b.string(_text(end))
        b.string(_text(mode))
        b.align(8)
        at = b.offset
        b.raw(bytes(self._VALUES.size))  # setpoint, length, speed, commanded_speed, tension; the four flags
        self._finish(b)
        self._values = self._at(at)

    def encode(self, stamp: tuple, setpoint, length, speed, commanded_speed, tension, speed_limited,
               acceleration_limited, at_min_length, at_max_length) -> bytes:
        TIME.pack_into(self.buf, self._at(self._stamp), *stamp)
        self._VALUES.pack_into(self.buf, self._values, setpoint, length, speed, commanded_speed, tension,
                               1 if speed_limited else 0, 1 if acceleration_limited else 0,
                               1 if at_min_length else 0, 1 if at_max_length else 0)
        return self.tobytes()


def winch_state(stamp: tuple, frame: str, end: str, mode: str, setpoint: float, length: float, speed: float,
                commanded_speed: float, tension: float, speed_limited: bool = False, acceleration_limited: bool = False,
                at_min_length: bool = False, at_max_length: bool = False) -> bytes:
    """tether_sim_msgs/WinchState: the winch at ``end`` in ``mode`` (the flags: which limit cut the rate)."""
    return encoder(WinchStateEncoder, frame, end, mode).encode(
        stamp, float(setpoint), float(length), float(speed), float(commanded_speed), float(tension),
        bool(speed_limited), bool(acceleration_limited), bool(at_min_length), bool(at_max_length))


_LOCAL = threading.local()  # each thread its own encoders: their buffers are written in place
MAX_ENCODERS = 64


def encoder(kind, *layout):
    """The encoder of a message layout (``kind(*layout)``), built on first use and kept (per thread)."""
    cache = getattr(_LOCAL, "encoders", None)
    if cache is None:
        cache = _LOCAL.encoders = {}
    key = (kind, *layout)
    enc = cache.get(key)
    if enc is None:
        if len(cache) >= MAX_ENCODERS:  # e.g. a winch changing the point count: rebuilt as needed
            cache.clear()
        enc = cache[key] = kind(*layout)
    return enc
