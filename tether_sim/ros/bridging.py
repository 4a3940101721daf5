"""Re-synchronisation bookkeeping shared by the single-line driver (tether_sim/ros/driver.py) and the
network driver (tether_sim/ros/network_driver.py); no rclpy.

A re-synchronisation keeps the cable state and its simulated time and moves only the clock mapping
(the anchor) by the skipped clock time. Two things follow, the same for every driver:

- **The ends catch up without coasting** (:class:`CatchUp`). The end's commanded motion at the
  skip is kept (position and velocity continuous) and the jump of its input across the skip is
  added as a decaying offset ``(1 - w(u)) (dp + dv tau)`` on top of what the end follows (its
  input, or a blend already running, which keeps its own progress: its clock start moves with the
  anchor). ``dp``, ``dv`` are the command's position and velocity before the skip minus after it,
  ``w`` the quintic of :class:`~tether_sim.ros.end_commands.Blend`, the duration
  :func:`~tether_sim.ros.end_commands.blend_time` of ``(|dp|, |dv|)``. Each offset ends on its own
  after its duration, whatever comes after it: however often the driver re-synchronises, the end
  converges onto its input once the offsets of the last skips have run out, and while they run it
  stays within their sum of the input. (Before, every re-synchronisation restarted one blend from
  the end's current position and velocity; its held trajectory carried that velocity on until the
  weight grew, and a node re-synchronising faster than its blends finished let the end coast away
  from its input without bound.)
- **Snap detection goes on across the skip** (:class:`Bridges`, :func:`shift_detectors`). The
  detectors' clock skips with the anchor (``SnapDetector.shift_time``: a slack period open across
  the skip keeps its simulated duration) and the skip and the offsets after it are recorded as
  clock spans; an event whose slack period or re-tensioning overlaps one is published as degraded.
  Input blends (an input lost, resumed or revised) are recorded the same way: they move an end
  while the cable state and its clock run on, so detection goes on across them too (a slack period
  is never dropped by them).
"""

from dataclasses import dataclass

import numpy as np

from tether_sim.ros.end_commands import blend_time, quintic

MAX_BRIDGES = 16  # spans remembered for marking the events that overlap them (bridged)


@dataclass
class Offset:
    """``(1 - w(u)) (dp + dv tau)``, ``tau = t - t0``, ``u = tau / duration``: the part of an end's
    command that a re-synchronisation added (module doc)."""

    t0: float  # clock time of the skip (after it)
    duration: float  # s
    dp: np.ndarray
    dv: np.ndarray

    def at(self, t):
        """(position offset, velocity offset, finished) at clock time ``t``."""
        tau = max(t - self.t0, 0.0)
        w, dw, finished = quintic(tau, self.duration)
        held = self.dp + self.dv * tau
        return (1.0 - w) * held, (1.0 - w) * self.dv - dw * held, finished


class CatchUp:
    """The offsets of one driver, per end (or point) name (module doc)."""

    def __init__(self):
        self.offsets = {}  # name -> [Offset]

    def __bool__(self):
        return any(self.offsets.values())

    def active(self, name) -> bool:
        return bool(self.offsets.get(name))

    def clear(self, name=None):
        if name is None:
            self.offsets.clear()
        else:
            self.offsets.pop(name, None)

    def shift(self, dt):
        """The clock skipped ``dt`` s: every running offset keeps its progress."""
        for offsets in self.offsets.values():
            for o in offsets:
                o.t0 += dt

    def add(self, name, t, dp, dv, max_end_speed) -> float:
        """A new offset of ``name`` from clock time ``t``; returns its duration (0: none needed)."""
        dp, dv = np.asarray(dp, float).copy(), np.asarray(dv, float).copy()
        distance, speed = float(np.linalg.norm(dp)), float(np.linalg.norm(dv))
        if distance < 1e-9 and speed < 1e-9:
            return 0.0
        duration = blend_time(distance, speed, max_end_speed)
        self.offsets.setdefault(name, []).append(Offset(float(t), duration, dp, dv))
        return duration

    def apply(self, name, t, position, velocity, drop=True):
        """``(position, velocity)`` of ``name`` at clock time ``t`` with its offsets added; ``drop``:
        finished offsets are removed."""
        offsets = self.offsets.get(name)
        if not offsets:
            return position, velocity
        p, v = np.array(position, float), np.array(velocity, float)
        keep = []
        for o in offsets:
            dp, dv, finished = o.at(t)
            p += dp
            v += dv
            if not finished:
                keep.append(o)
        if drop:
            self.offsets[name] = keep
        return p, v


class Bridges:
    """Clock spans over which an end was bridged (a re-synchronisation's skip and catch-up, an input
    blend): a snap event overlapping one is published as degraded (module doc)."""

    def __init__(self):
        self.spans = []

    def add(self, start, end):
        self.spans = self.spans[-(MAX_BRIDGES - 1):] + [(float(start), float(end))]

    def shift(self, dt):
        """The detectors' clock skipped ``dt`` s (a re-synchronisation): the recorded spans move with it."""
        self.spans = [(a + dt, b + dt) for a, b in self.spans]

    def clear(self):
        self.spans = []

    def covers(self, event) -> bool:
        """True when a detector event's slack period or re-tensioning (``slack_start`` .. ``time``)
        overlaps a recorded span."""
        start = getattr(event, "slack_start", event.time)
        return any(start - 1e-9 <= b and a <= event.time + 1e-9 for a, b in self.spans)


def shift_detectors(detectors, dt) -> None:
    """Move the time axis of every detector (None skipped) ``dt`` s later (``SnapDetector.shift_time``)."""
    for detector in detectors:
        if detector is not None:
            detector.shift_time(dt)
