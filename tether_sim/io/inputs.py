"""Pose inputs of the cable ends, without ROS: validation, interpolation, velocity estimation.

A driven end (kind ``prescribed``) follows the pose of a body frame (ship or vehicle) given as
time-stamped samples (position of the frame origin in the world ENU frame, orientation quaternion
x, y, z, w body FLU -> world). The cable is attached at a fixed offset ``r`` in the body frame, so the
attachment point is ``p_att = p + R(q) r`` and moves with ``v_att = v + w x (R(q) r)``.

Rejected samples (the reason string is returned, the stored history is unchanged):

- ``non-finite``: NaN or infinite position, orientation or stamp;
- ``bad quaternion``: a quaternion whose norm is not within 10 % of 1 (it is normalised otherwise);
- ``stamp in the future``: later than the node's clock + ``future_tolerance`` (a single such pose
  is dropped; it does not block the valid poses after it);
- ``stamp too old``: earlier than the node's clock - ``max_age``;
- ``stamp not increasing``: a stamp at or before the last accepted one (but within those bounds);
- ``jump``: the attachment point moved faster than ``max_end_speed`` since the last accepted sample.

Samples closer together than ``min_spacing`` are not all kept as knots: a new sample replaces the
newest knot while that knot lies less than ``min_spacing`` after the one before it, so every knot
interval but the newest is at least ``min_spacing`` long. A pose source stamps its samples with some
jitter (the stamp and the measured position are not taken at the same instant); across samples
a fraction of a millisecond apart (a publisher catching up after a stall) finite differences turn
a millimetre of that jitter into metres per second of end velocity, which the solver, commanded
at the output rate, would carry into the cable as a tension wave that did not happen (a false
snap of 3.3 x static in a one-hour soak, docs/node.md). The node passes half an output period:
the commands sample the stream once per period, so detail finer than that lies beyond their
Nyquist frequency anyway; the velocity error from a stamp jitter ``d`` is then at most about
``|v| d / min_spacing`` instead of ``|v| d / (sample interval)``. The one-sided differences at
the oldest and the newest knot (the newest one's is the extrapolation's velocity) span at least
``4 min_spacing`` (two output periods at the node's spacing).

The history is sized by time (``history_span`` s behind the newest sample), not by a sample
count, so it is correct at any input rate (tested at 1 kHz). An input is stale when no pose was
accepted for ``input_timeout`` s of the node's clock, or when the newest accepted stamp is older
than that.

Between samples the attachment point follows a cubic Hermite curve through the samples; the knot
velocities come from the twist topic when one was received for that instant, and otherwise from
finite differences of the samples (central inside, one-sided at the ends). After the last sample
the motion is extrapolated with the last velocity for at most ``max_extrapolation`` seconds and
then held (velocity zero). Orientation is interpolated by spherical linear interpolation.
"""

import bisect
import math
from collections import Counter
from dataclasses import dataclass

import numpy as np

from tether_sim.numerics.rotations import quaternion_matrix

QUATERNION_NORM_TOLERANCE = 0.1  # |norm - 1| beyond this is not a rotation with rounding errors
FUTURE_TOLERANCE = 0.25  # s a stamp may lie ahead of the node's clock (clock skew, replay timing)
MAX_AGE = 2.0  # s a stamp may lie behind the node's clock (transport latency)
MAX_SAMPLES = 20000  # hard cap of the pose history (1 kHz for 20 s)


def knot_spacing(output_rate: float) -> float:
    """The shortest knot interval of a pose input commanded at ``output_rate`` Hz: half an output
    period (module docstring), s."""
    return 0.5 / max(float(output_rate), 1e-9)


def slerp(q0, q1, u: float) -> np.ndarray:
    """Spherical linear interpolation between unit quaternions, u in [0, 1] (shortest arc)."""
    q0 = np.asarray(q0, float)
    q1 = np.asarray(q1, float)
    dot = float(np.dot(q0, q1))
    if dot < 0.0:
        q1, dot = -q1, -dot
    if dot > 0.9995:  # nearly parallel: normalised lerp is exact to rounding
        q = q0 + u * (q1 - q0)
        return q / math.sqrt(q.dot(q))  # (np.linalg.norm's own sqrt(q.dot(q)), without its wrapper)
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
    """Validated history of one end's body pose, queried for the attachment point at any time.

    ``min_spacing``: shortest interval between interpolation knots, s (module docstring; 0 keeps
    every sample). ``history_span``: seconds of samples kept behind the newest one (the node passes
    ``input_delay + max_lag`` plus a margin, so a simulation running late still interpolates);
    at most ``max_samples`` (+63, pruned in batches) are kept (a flood beyond that shortens the
    span, shown in ``health()['history_span']``). ``future_tolerance`` / ``max_age``: with the node's clock
    ``now`` given to :meth:`add_pose`, a stamp later than ``now + future_tolerance`` or earlier
    than ``now - max_age`` is rejected (without ``now``, e.g. offline, stamps are only checked
    against each other).
    """

    def __init__(self, name: str, attachment=(0.0, 0.0, 0.0), *, max_end_speed: float = 20.0,
                 input_timeout: float = 1.0, max_extrapolation: float = 0.2, history_span: float = 3.0,
                 max_samples: int = MAX_SAMPLES, future_tolerance: float = FUTURE_TOLERANCE,
                 max_age: float = MAX_AGE, min_spacing: float = 0.0):
        self.name = name
        self.offset = np.asarray(attachment, dtype=float).reshape(3)
        self.max_end_speed = float(max_end_speed)
        self.input_timeout = float(input_timeout)
        self.max_extrapolation = float(max_extrapolation)
        self.history_span = float(history_span)
        self.max_samples = max(int(max_samples), 4)
        self.future_tolerance = float(future_tolerance)
        self.max_age = float(max_age)
        self.min_spacing = max(float(min_spacing), 0.0)  # s, shortest knot interval (module docstring)
        self._samples: list[_Sample] = []
        self._stamps: list[float] = []  # the samples' stamps (bisect)
        self._twists: list = []  # (stamp, linear_world, angular_world)
        self._accepted_at = -math.inf  # clock time of the last accepted pose
        self.accepted = 0
        self.rejected: Counter = Counter()

    @classmethod
    def for_node(cls, name: str, node, attachment=(0.0, 0.0, 0.0)) -> "EndPoseInput":
        """The input of a driven end or point as the live node builds it from its ``node`` section
        (io.params' NodeConfig): every limit from the section, knots at most every half output period,
        and a history of ``input_delay + max_lag`` (``max_lag`` counted up to 60 s) plus 1 s of margin,
        so a node running late still interpolates before it re-synchronises."""
        return cls(name, attachment, max_end_speed=node.max_end_speed, input_timeout=node.input_timeout,
                   max_extrapolation=node.max_extrapolation,
                   history_span=node.input_delay + min(node.max_lag, 60.0) + 1.0,
                   future_tolerance=node.future_stamp_tolerance, max_age=node.max_input_age,
                   min_spacing=knot_spacing(node.output_rate))

    # ------------------------------------------------------------------ feeding
    def reset(self) -> None:
        """Forget the history (e.g. after the clock jumped back); counters are kept."""
        self._samples.clear()
        self._stamps.clear()
        self._twists.clear()
        self._accepted_at = -math.inf

    def _reject(self, reason: str) -> str:
        self.rejected[reason] += 1
        return reason

    def add_pose(self, stamp: float, position, orientation, now: float | None = None) -> str | None:
        """Offer one pose sample; return None if accepted, else the reason it was rejected.

        ``now``: the node's clock (checks future / too old stamps and times staleness)."""
        p = np.asarray(position, dtype=float).reshape(3)
        q = np.asarray(orientation, dtype=float).reshape(4)
        reason = self._check_pose(stamp, p, q, now)
        if reason is not None:
            return self._reject(reason)
        q = q / np.linalg.norm(q)
        att = p + quaternion_matrix(q) @ self.offset
        if self._samples:
            last = self._samples[-1]
            dt = stamp - last.stamp
            if np.linalg.norm(att - last.attachment) > self.max_end_speed * dt + 1e-9:
                return self._reject("jump")
        sample = _Sample(float(stamp), p, q, att, self._twist_velocity_at(stamp, q))
        s = self._samples
        if len(s) >= 2 and s[-1].stamp - s[-2].stamp < self.min_spacing:
            s[-1], self._stamps[-1] = sample, float(stamp)  # the newest knot was too close: replaced
        else:
            s.append(sample)
            self._stamps.append(float(stamp))
        self._prune()
        self._accepted_at = float(stamp) if now is None else float(now)
        self.accepted += 1
        return None

    def _prune(self) -> None:
        """Drop samples older than ``history_span`` behind the newest (keeping the one that
        brackets the edge of the span) and beyond ``max_samples``; in batches (amortised O(1))."""
        cutoff = self._stamps[-1] - self.history_span
        k = max(bisect.bisect_right(self._stamps, cutoff) - 1, len(self._stamps) - self.max_samples)
        if k >= 64:  # (so at most max_samples + 63 are held)
            del self._samples[:k]
            del self._stamps[:k]
        if len(self._twists) > 128 and self._twists[0][0] < cutoff - 1.0:
            j = next((i for i, tw in enumerate(self._twists) if tw[0] >= cutoff), len(self._twists))
            del self._twists[:j]

    def add_twist(self, stamp: float, linear, angular, *, body_frame: bool = False,
                  now: float | None = None) -> str | None:
        """Offer a twist of the body frame origin (linear m/s, angular rad/s).

        ``body_frame``: the vectors are expressed in the body frame (rotated to the world with the
        pose at that time); otherwise they are world-frame vectors. Returns None or the reason.
        """
        v = np.asarray(linear, dtype=float).reshape(3)
        w = np.asarray(angular, dtype=float).reshape(3)
        if not (np.isfinite(stamp) and np.all(np.isfinite(v)) and np.all(np.isfinite(w))):
            return self._reject("non-finite twist")
        timing = self._check_clock(stamp, now)
        if timing is not None:
            return self._reject(f"twist {timing}")
        if self._twists and stamp <= self._twists[-1][0]:
            return self._reject("twist stamp not increasing")
        if body_frame:
            if not self._samples:
                return self._reject("twist before any pose")
            R = quaternion_matrix(self.orientation_at(stamp))
            v, w = R @ v, R @ w
        if np.linalg.norm(v) > self.max_end_speed:
            return self._reject("twist too fast")
        self._twists.append((float(stamp), v, w))
        i = bisect.bisect_left(self._stamps, stamp - 1e-6)
        for s in self._samples[i:i + 2]:  # a twist may arrive just after its pose
            if s.twist_velocity is None and abs(s.stamp - stamp) < 1e-6:
                s.twist_velocity = self._attachment_velocity(v, w, s.orientation)
        return None

    def _check_clock(self, stamp, now) -> str | None:
        if now is None:
            return None
        if stamp > now + self.future_tolerance:
            return "stamp in the future"
        if stamp < now - self.max_age:
            return "stamp too old"
        return None

    def _check_pose(self, stamp, p, q, now) -> str | None:
        if not (np.isfinite(stamp) and np.all(np.isfinite(p)) and np.all(np.isfinite(q))):
            return "non-finite"
        if abs(np.linalg.norm(q) - 1.0) > QUATERNION_NORM_TOLERANCE:
            return "bad quaternion"
        timing = self._check_clock(stamp, now)
        if timing is not None:
            return timing
        if self._samples and stamp <= self._samples[-1].stamp:
            return "stamp not increasing"
        return None

    def _attachment_velocity(self, v, w, q) -> np.ndarray:
        return v + np.cross(w, quaternion_matrix(q) @ self.offset)

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

    def covers(self, t: float) -> bool:
        """True when the history reaches back to ``t`` (its oldest sample is at or before it)."""
        return bool(self._samples) and self._samples[0].stamp <= t

    def age(self, now: float) -> float:
        """Seconds from the newest accepted stamp to ``now`` (inf when none)."""
        return float("inf") if not self._samples else now - self._samples[-1].stamp

    def is_stale(self, now: float) -> bool:
        """True when no sample was accepted within ``input_timeout`` of clock time, or the newest
        accepted stamp is older than that (whatever the stamps say, silence is stale)."""
        return (not self._samples or now - self._accepted_at > self.input_timeout
                or self.age(now) > self.input_timeout)

    def span(self) -> float:
        """Seconds of history held (newest minus oldest stamp)."""
        return self._stamps[-1] - self._stamps[0] if self._stamps else 0.0

    def _knot_velocity(self, i: int) -> np.ndarray:
        """Knot ``i``'s velocity as a (3,) array (:meth:`_knot_velocity_floats`, the same numbers)."""
        return np.array(self._knot_velocity_floats(i))

    def _knot_velocity_floats(self, i: int) -> list:
        """Knot ``i``'s velocity as a list of 3 floats (the interpolation's inner loop, without numpy's
        small-array overheads): its twist when the pose came with one, else the difference quotient of
        the samples around it (:meth:`_knot_span`)."""
        s = self._samples
        if s[i].twist_velocity is not None:
            return s[i].twist_velocity.tolist()
        if len(s) == 1:
            return [0.0, 0.0, 0.0]
        lo, hi = self._knot_span(i)
        (a0, a1, a2), (b0, b1, b2), dt = s[hi].attachment.tolist(), s[lo].attachment.tolist(), s[hi].stamp - s[lo].stamp
        return [(a0 - b0) / dt, (a1 - b1) / dt, (a2 - b2) / dt]

    def _knot_span(self, i: int) -> tuple:
        """(lo, hi): the samples whose difference quotient is knot ``i``'s velocity."""
        s = self._samples
        lo, hi = max(i - 1, 0), min(i + 1, len(s) - 1)
        if self.min_spacing > 0.0 and (lo == i or hi == i):  # one-sided: over at least 4 min_spacing
            if hi == i:  # the newest knot (its velocity is the extrapolation's)
                lo = max(bisect.bisect_right(self._stamps, s[i].stamp - 4.0 * self.min_spacing) - 1, 0)
            else:
                hi = min(bisect.bisect_left(self._stamps, s[i].stamp + 4.0 * self.min_spacing), len(s) - 1)
        return lo, hi

    def _bracket(self, t: float) -> int:
        """Index i with stamp[i] <= t < stamp[i+1] (samples must cover t)."""
        return min(max(bisect.bisect_right(self._stamps, t) - 1, 0), len(self._stamps) - 2)

    def is_held(self, t: float) -> bool:
        """True when ``t`` lies beyond the newest sample plus ``max_extrapolation`` (the end is
        held at rest there) or no sample exists: the pose stream gives no motion at ``t``."""
        return not self._samples or t - self._samples[-1].stamp > self.max_extrapolation  # (as attachment_at)

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
        # cubic Hermite basis and its derivative
        h00, h10, h01, h11 = 2 * u**3 - 3 * u**2 + 1, u**3 - 2 * u**2 + u, -2 * u**3 + 3 * u**2, u**3 - u**2
        d00, d10, d01, d11 = 6 * u**2 - 6 * u, 3 * u**2 - 4 * u + 1, -6 * u**2 + 6 * u, 3 * u**2 - 2 * u
        # per component in plain floats: the same operations in the same order as on the 3-vectors
        # (tens of microseconds less per call than numpy's small-array overheads)
        pos, vel = [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]
        for c, (pa, pb, v0, v1) in enumerate(zip(a.attachment.tolist(), b.attachment.tolist(),
                                                 self._knot_velocity_floats(i), self._knot_velocity_floats(i + 1))):
            m0, m1 = v0 * h, v1 * h
            pos[c] = h00 * pa + h10 * m0 + h01 * pb + h11 * m1
            vel[c] = (d00 * pa + d10 * m0 + d01 * pb + d11 * m1) / h
        return np.array(pos), np.array(vel)

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
                "stale": self.is_stale(now), "history_span": self.span(), "history_samples": len(self._samples),
                "since_accepted": now - self._accepted_at}
