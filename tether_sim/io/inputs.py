"""Pose inputs of the cable ends, without ROS: validation, interpolation, velocity estimation.

A driven end (kind ``prescribed``) follows the pose of a body frame (ship or vehicle) given as
time-stamped samples (position of the frame origin in the world ENU frame, orientation quaternion
x, y, z, w body FLU -> world). The cable is attached at a fixed offset ``r`` in the body frame, so the
attachment point is ``p_att = p + R(q) r`` and moves with ``v_att = v + w x (R(q) r)``.

Rejected samples (the reason string is returned, the stored history is unchanged):

- ``non-finite``: NaN or infinite position, orientation or stamp;
- ``bad quaternion``: a quaternion whose norm is not within 10 % of 1 (it is normalised otherwise);
- ``stamp not increasing``: a stamp at or before the last accepted one;
- ``jump``: the attachment point moved faster than ``max_end_speed`` since the last accepted sample.

Between samples the attachment point follows a cubic Hermite curve through the samples; the knot
velocities come from the twist topic when one was received for that instant, and otherwise from
finite differences of the samples (central inside, one-sided at the ends). After the last sample
the motion is extrapolated with the last velocity for at most ``max_extrapolation`` seconds and
then held (velocity zero). Orientation is interpolated by spherical linear interpolation.
"""

from collections import Counter, deque
from dataclasses import dataclass

import numpy as np

QUATERNION_NORM_TOLERANCE = 0.1  # |norm - 1| beyond this is not a rotation with rounding errors


def rotation_matrix(q) -> np.ndarray:
    """Rotation matrix (3, 3) of a unit quaternion (x, y, z, w), body -> world."""
    x, y, z, w = q
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def slerp(q0, q1, u: float) -> np.ndarray:
    """Spherical linear interpolation between unit quaternions, u in [0, 1] (shortest arc)."""
    q0 = np.asarray(q0, float)
    q1 = np.asarray(q1, float)
    dot = float(np.dot(q0, q1))
    if dot < 0.0:
        q1, dot = -q1, -dot
    if dot > 0.9995:  # nearly parallel: normalised lerp is exact to rounding
        q = q0 + u * (q1 - q0)
        return q / np.linalg.norm(q)
    theta = np.arccos(min(dot, 1.0))
    s = np.sin(theta)
    return (np.sin((1 - u) * theta) * q0 + np.sin(u * theta) * q1) / s


@dataclass
class _Sample:
    stamp: float
    origin: np.ndarray  # (3,) body frame origin, world
    orientation: np.ndarray  # (4,) unit quaternion x, y, z, w
    attachment: np.ndarray  # (3,) attachment point, world
    twist_velocity: np.ndarray | None = None  # (3,) attachment velocity from a twist, world


class EndPoseInput:
    """Validated history of one end's body pose, queried for the attachment point at any time."""

    def __init__(self, name: str, attachment=(0.0, 0.0, 0.0), *, max_end_speed: float = 20.0,
                 input_timeout: float = 1.0, max_extrapolation: float = 0.2, history: int = 64):
        self.name = name
        self.offset = np.asarray(attachment, dtype=float).reshape(3)
        self.max_end_speed = float(max_end_speed)
        self.input_timeout = float(input_timeout)
        self.max_extrapolation = float(max_extrapolation)
        self._samples: deque[_Sample] = deque(maxlen=max(history, 2))
        self._twists: deque = deque(maxlen=max(history, 2))  # (stamp, linear_world, angular_world)
        self.accepted = 0
        self.rejected: Counter = Counter()

    # ------------------------------------------------------------------ feeding
    def reset(self) -> None:
        """Forget the history (e.g. after the clock jumped back); counters are kept."""
        self._samples.clear()
        self._twists.clear()

    def add_pose(self, stamp: float, position, orientation) -> str | None:
        """Offer one pose sample; return None if accepted, else the reason it was rejected."""
        p = np.asarray(position, dtype=float).reshape(3)
        q = np.asarray(orientation, dtype=float).reshape(4)
        reason = self._check_pose(stamp, p, q)
        if reason is not None:
            self.rejected[reason] += 1
            return reason
        q = q / np.linalg.norm(q)
        att = p + rotation_matrix(q) @ self.offset
        if self._samples:
            last = self._samples[-1]
            dt = stamp - last.stamp
            if np.linalg.norm(att - last.attachment) > self.max_end_speed * dt + 1e-9:
                self.rejected["jump"] += 1
                return "jump"
        self._samples.append(_Sample(float(stamp), p, q, att, self._twist_velocity_at(stamp, q)))
        self.accepted += 1
        return None

    def add_twist(self, stamp: float, linear, angular, *, body_frame: bool = False) -> str | None:
        """Offer a twist of the body frame origin (linear m/s, angular rad/s).

        ``body_frame``: the vectors are expressed in the body frame (rotated to the world with the
        pose at that time); otherwise they are world-frame vectors. Returns None or the reason.
        """
        v = np.asarray(linear, dtype=float).reshape(3)
        w = np.asarray(angular, dtype=float).reshape(3)
        if not (np.isfinite(stamp) and np.all(np.isfinite(v)) and np.all(np.isfinite(w))):
            self.rejected["non-finite twist"] += 1
            return "non-finite twist"
        if self._twists and stamp <= self._twists[-1][0]:
            self.rejected["twist stamp not increasing"] += 1
            return "twist stamp not increasing"
        if body_frame:
            if not self._samples:
                self.rejected["twist before any pose"] += 1
                return "twist before any pose"
            R = rotation_matrix(self.orientation_at(stamp))
            v, w = R @ v, R @ w
        if np.linalg.norm(v) > self.max_end_speed:
            self.rejected["twist too fast"] += 1
            return "twist too fast"
        self._twists.append((float(stamp), v, w))
        for s in self._samples:  # a twist may arrive just after its pose
            if s.twist_velocity is None and abs(s.stamp - stamp) < 1e-6:
                s.twist_velocity = self._attachment_velocity(v, w, s.orientation)
        return None

    def _check_pose(self, stamp, p, q) -> str | None:
        if not (np.isfinite(stamp) and np.all(np.isfinite(p)) and np.all(np.isfinite(q))):
            return "non-finite"
        if abs(np.linalg.norm(q) - 1.0) > QUATERNION_NORM_TOLERANCE:
            return "bad quaternion"
        if self._samples and stamp <= self._samples[-1].stamp:
            return "stamp not increasing"
        return None

    def _attachment_velocity(self, v, w, q) -> np.ndarray:
        return v + np.cross(w, rotation_matrix(q) @ self.offset)

    def _twist_velocity_at(self, stamp, q):
        for t, v, w in reversed(self._twists):
            if abs(t - stamp) < 1e-6:
                return self._attachment_velocity(v, w, q)
        return None

    # ------------------------------------------------------------------ queries
    @property
    def has_data(self) -> bool:
        return bool(self._samples)

    @property
    def last_stamp(self) -> float | None:
        return self._samples[-1].stamp if self._samples else None

    def age(self, now: float) -> float:
        """Seconds since the last accepted sample (inf when none)."""
        return float("inf") if not self._samples else now - self._samples[-1].stamp

    def is_stale(self, now: float) -> bool:
        """True when no sample was accepted within ``input_timeout``."""
        return self.age(now) > self.input_timeout

    def _knot_velocity(self, i: int) -> np.ndarray:
        s = self._samples
        if s[i].twist_velocity is not None:
            return s[i].twist_velocity
        if len(s) == 1:
            return np.zeros(3)
        lo, hi = max(i - 1, 0), min(i + 1, len(s) - 1)
        return (s[hi].attachment - s[lo].attachment) / (s[hi].stamp - s[lo].stamp)

    def _bracket(self, t: float) -> int:
        """Index i with stamp[i] <= t < stamp[i+1] (samples must cover t)."""
        lo, hi = 0, len(self._samples) - 1
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if self._samples[mid].stamp <= t:
                lo = mid
            else:
                hi = mid
        return lo

    def attachment_at(self, t: float):
        """Attachment point position (3,) and velocity (3,) at time t (world frame).

        Raises LookupError when no sample was ever accepted.
        """
        s = self._samples
        if not s:
            raise LookupError(f"{self.name}: no pose received yet")
        if t <= s[0].stamp:
            return s[0].attachment.copy(), (self._knot_velocity(0) if t == s[0].stamp else np.zeros(3))
        if t >= s[-1].stamp:
            v = self._knot_velocity(len(s) - 1)
            dt = t - s[-1].stamp
            if dt <= self.max_extrapolation:
                return s[-1].attachment + v * dt, v
            return s[-1].attachment + v * self.max_extrapolation, np.zeros(3)
        i = self._bracket(t)
        a, b = s[i], s[i + 1]
        h = b.stamp - a.stamp
        u = (t - a.stamp) / h
        m0, m1 = self._knot_velocity(i) * h, self._knot_velocity(i + 1) * h
        # cubic Hermite basis and its derivative
        h00, h10, h01, h11 = 2 * u**3 - 3 * u**2 + 1, u**3 - 2 * u**2 + u, -2 * u**3 + 3 * u**2, u**3 - u**2
        d00, d10, d01, d11 = 6 * u**2 - 6 * u, 3 * u**2 - 4 * u + 1, -6 * u**2 + 6 * u, 3 * u**2 - 2 * u
        pos = h00 * a.attachment + h10 * m0 + h01 * b.attachment + h11 * m1
        vel = (d00 * a.attachment + d10 * m0 + d01 * b.attachment + d11 * m1) / h
        return pos, vel

    def orientation_at(self, t: float) -> np.ndarray:
        """Body orientation quaternion (x, y, z, w) at t: slerp inside, held outside the samples."""
        s = self._samples
        if not s:
            raise LookupError(f"{self.name}: no pose received yet")
        if t <= s[0].stamp:
            return s[0].orientation.copy()
        if t >= s[-1].stamp:
            return s[-1].orientation.copy()
        i = self._bracket(t)
        a, b = s[i], s[i + 1]
        return slerp(a.orientation, b.orientation, (t - a.stamp) / (b.stamp - a.stamp))

    def health(self, now: float) -> dict:
        """Counters for diagnostics: accepted, rejected by reason, age of the last sample."""
        return {"accepted": self.accepted, "rejected": dict(self.rejected), "age": self.age(now),
                "stale": self.is_stale(now)}
