"""Analytic and recorded fairlead motion generators [PE2020 Sec. 6.1-6.2].

``build_motion(config, origin)`` returns an object whose ``at(t)`` gives the world position,
velocity and acceleration (each (3,)) of a prescribed cable end:

- ``circle``: orbit of radius a at frequency f in the vertical plane of azimuth psi, centred on
  ``origin`` and starting at its top: d = a (sin wt e_h + cos wt e_z) (PE2020 Sec. 6.2).
- ``heave``: d = a sin(wt) e_z.
- ``sines``: d = sum_i a_i sin(w_i t + phi_i) e_z.
- ``record``: a recorded pose series (times, positions), taken relative to its first sample,
  scaled by ``record_scale`` (PE2020 Sec. 6.1 needed +20%) and interpolated by a C2 cubic spline.
- ``rao``: the ship's response to the sea state of the ``waves`` section through the RAO table
  ``rao_path`` (physics/ship_motion.py, docs/ship_motion.md), carried to the fairlead by the lever arm
  ``rao_lever_arm``; ``origin`` is the fairlead's mean position (ship reference point = origin minus
  the rotated lever arm), so the ship and the cable see the same waves.

All analytic offsets are multiplied by a C2 quintic ramp r(t) (0 -> 1 over ``ramp_time``), so a
run starting from a static shape at ``origin`` sees no jump in position, velocity or acceleration.
"""

import math
from dataclasses import dataclass

import numpy as np

from tether_sim.paths import resolve_data_path
from tether_sim.physics.ship_motion import ShipResponse, fairlead_offset, fairlead_position_velocity_many, read_rao_table
from tether_sim.spec import param

MOTION_KINDS = ("none", "circle", "heave", "sines", "record", "rao")


@dataclass(frozen=True)
class MotionConfig:
    """Motion of a prescribed end about its initial position (world frame)."""

    kind: str = param("none", doc="motion generator", choices=MOTION_KINDS)
    amplitude: float = param(2.0, unit="m", doc="orbit radius a (circle) or heave amplitude", min=0.0, max=100.0)
    frequency: float = param(0.2, unit="Hz", doc="orbit or heave frequency f", min=0.0, max=100.0)
    plane_azimuth: float = param(0.0, unit="rad", doc="azimuth of the vertical plane of the circular orbit (0 = x-z plane)", min=-7.0, max=7.0)
    sine_amplitudes: tuple = param((), unit="m", doc="heave amplitudes of a sum of sines")
    sine_frequencies: tuple = param((), unit="Hz", doc="frequencies of a sum of sines")
    sine_phases: tuple = param((), unit="rad", doc="phases of a sum of sines")
    ramp_time: float = param(0.0, unit="s", doc="smooth start: amplitude ramped over this time", min=0.0, max=1e5)
    record_path: str = param("", doc="MCAP file of geometry_msgs/PoseStamped (kind=record); relative to the package share")
    record_topic: str = param("/ship/pose", doc="topic of the recorded poses")
    record_scale: float = param(1.0, doc="amplitude factor applied to the recorded motion (PE2020 calibrated +20%)", min=0.0, max=10.0)
    rao_path: str = param("", doc="kind=rao: RAO table (plain text, docs/ship_motion.md); relative to the package share")
    rao_lever_arm: tuple = param((0.0, 0.0, 0.0), unit="m", doc="kind=rao: fairlead position relative to the ship reference point, ship axes (x bow, y port, z up)")
    ship_heading: float = param(0.0, unit="deg", doc="kind=rao: mean heading of the ship's bow, from +x (east) counter-clockwise", min=-360.0, max=360.0)


def ramp(t: float, duration: float):
    """C2 quintic ramp r = 10 s^3 - 15 s^4 + 6 s^5, s = t / duration; returns (r, r', r'')."""
    if duration <= 0.0 or t >= duration:
        return 1.0, 0.0, 0.0
    if t <= 0.0:
        return 0.0, 0.0, 0.0
    s = t / duration
    r = s**3 * (10.0 - 15.0 * s + 6.0 * s * s)
    dr = 30.0 * s * s * (1.0 - s) ** 2 / duration
    ddr = 60.0 * s * (1.0 - s) * (1.0 - 2.0 * s) / duration**2
    return r, dr, ddr


class _Offset:
    """Generator built from an offset d(t) (with d', d''), a ramp and an origin."""

    def __init__(self, origin, ramp_time):
        self.origin = np.asarray(origin, dtype=np.float64).reshape(3).copy()
        self.ramp_time = float(ramp_time)

    def at(self, t: float):
        """World (position, velocity, acceleration) at time t (s), each (3,)."""
        d, dd, ddd = self.offset(float(t))
        r, dr, ddr = ramp(float(t), self.ramp_time)
        return self.origin + r * d, r * dd + dr * d, r * ddd + 2.0 * dr * dd + ddr * d

    def position_velocity(self, t: float):
        """World (position, velocity) at time t: the first two of :meth:`at`, the same numbers, without
        computing the acceleration where the generator can skip it (a forecast's members command
        position and velocity only)."""
        d, dd = self.offset_pv(float(t))
        r, dr, _ = ramp(float(t), self.ramp_time)
        return self.origin + r * d, r * dd + dr * d

    def offset_pv(self, t):
        """(d, d') of :meth:`offset` (generators that can skip d'' override this)."""
        return self.offset(t)[:2]

    def position_velocity_many(self, ts):
        """(positions (k, 3), velocities (k, 3)) of :meth:`position_velocity` at the times ``ts`` (k,),
        the same numbers (generators that can evaluate many times at once override ``offset_pv_many``)."""
        ts = np.asarray(ts, float).reshape(-1)
        d, dd = self.offset_pv_many(ts)
        ramps = [ramp(float(t), self.ramp_time) for t in ts]
        r = np.array([x[0] for x in ramps])[:, None]
        dr = np.array([x[1] for x in ramps])[:, None]
        return self.origin + r * d, r * dd + dr * d

    def offset_pv_many(self, ts):
        out = [self.offset_pv(float(t)) for t in ts]
        return np.array([o[0] for o in out], float).reshape(-1, 3), np.array([o[1] for o in out], float).reshape(-1, 3)


class StillMotion(_Offset):
    """The end stays at its origin (kind ``none``)."""

    def offset(self, t):
        z = np.zeros(3)
        return z, z.copy(), z.copy()


class CircleMotion(_Offset):
    """Circular orbit of radius a in a vertical plane, starting at its top [PE2020 Sec. 6.2]."""

    def __init__(self, origin, radius, frequency, azimuth=0.0, ramp_time=0.0):
        super().__init__(origin, ramp_time)
        self.radius, self.omega = float(radius), 2.0 * math.pi * float(frequency)
        self.e_h = np.array([math.cos(azimuth), math.sin(azimuth), 0.0])
        self.e_z = np.array([0.0, 0.0, 1.0])

    def offset(self, t):
        a, w = self.radius, self.omega
        s, c = math.sin(w * t), math.cos(w * t)
        pos = a * (s * self.e_h + c * self.e_z)
        vel = a * w * (c * self.e_h - s * self.e_z)
        return pos, vel, -w * w * pos


class SinesMotion(_Offset):
    """Vertical sum of sines, d_z = sum a_i sin(w_i t + phi_i) (a heave sine is one term)."""

    def __init__(self, origin, amplitudes, frequencies, phases=None, ramp_time=0.0):
        super().__init__(origin, ramp_time)
        self.a = np.asarray(amplitudes, dtype=np.float64).reshape(-1)
        self.w = 2.0 * np.pi * np.asarray(frequencies, dtype=np.float64).reshape(-1)
        self.phi = np.zeros_like(self.a) if phases is None or len(phases) == 0 else np.asarray(phases, dtype=np.float64).reshape(-1)
        if not (self.a.shape == self.w.shape == self.phi.shape):
            raise ValueError(f"motion: sine_amplitudes, sine_frequencies and sine_phases need equal lengths, "
                             f"got {self.a.size}, {self.w.size}, {self.phi.size}")

    def offset(self, t):
        arg = self.w * t + self.phi
        z = np.zeros((3, 3))
        z[0, 2] = np.sum(self.a * np.sin(arg))
        z[1, 2] = np.sum(self.a * self.w * np.cos(arg))
        z[2, 2] = -np.sum(self.a * self.w**2 * np.sin(arg))
        return z[0], z[1], z[2]


class RecordedMotion(_Offset):
    """Recorded positions relative to the first sample, scaled, C2 cubic-spline interpolated.

    Before the first sample the end rests at ``origin``; after the last one it holds the last
    (scaled) offset at rest. Record time is counted from the first sample.
    """

    def __init__(self, origin, times, positions, scale=1.0, ramp_time=0.0):
        super().__init__(origin, ramp_time)
        from scipy.interpolate import CubicSpline

        times = np.asarray(times, dtype=np.float64).reshape(-1)
        positions = np.asarray(positions, dtype=np.float64)
        if positions.shape != (times.size, 3) or times.size < 4:
            raise ValueError(f"motion: a record needs >= 4 samples of (t, x, y, z), got times {times.shape}, positions {positions.shape}")
        if not (np.all(np.isfinite(times)) and np.all(np.isfinite(positions))):
            raise ValueError("motion: the record has non-finite samples")
        if np.any(np.diff(times) <= 0.0):
            raise ValueError("motion: record times must be strictly increasing")
        self.t0 = times[0]
        self.duration = times[-1] - times[0]
        self.spline = CubicSpline(times - self.t0, float(scale) * (positions - positions[0]), axis=0, bc_type="natural")

    def offset(self, t):
        if t <= 0.0:
            z = np.zeros(3)
            return z, z.copy(), z.copy()
        if t >= self.duration:
            return self.spline(self.duration), np.zeros(3), np.zeros(3)
        return self.spline(t), self.spline(t, 1), self.spline(t, 2)


class RaoMotion(_Offset):
    """The fairlead of a ship responding to the sea through its RAOs (kind ``rao``)."""

    def __init__(self, origin, table, waves, lever_arm, heading_deg, ramp_time=0.0):
        super().__init__(origin, ramp_time)
        self.lever = np.asarray(lever_arm, dtype=np.float64).reshape(3)
        c, s = math.cos(math.radians(heading_deg)), math.sin(math.radians(heading_deg))
        reference = self.origin - np.array([c * self.lever[0] - s * self.lever[1], s * self.lever[0] + c * self.lever[1], self.lever[2]])
        self.response = ShipResponse(table, waves, reference, heading_deg)

    def offset(self, t):
        return fairlead_offset(self.response, self.lever, t)

    def offset_pv(self, t):
        return fairlead_offset(self.response, self.lever, t, acceleration=False)[:2]

    def offset_pv_many(self, ts):
        return fairlead_position_velocity_many(self.response, self.lever, ts)


def read_pose_record(path, topic="/ship/pose"):
    """(times (n,), positions (n, 3)) of the geometry_msgs/PoseStamped messages on ``topic`` of an MCAP.

    Time is the header stamp (log time if the stamp is zero).
    """
    from mcap.reader import make_reader
    from mcap_ros2.decoder import DecoderFactory

    times, positions = [], []
    with open(resolve_data_path(path, "motion.record_path"), "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        for _, _, message, msg in reader.iter_decoded_messages(topics=[topic]):
            stamp = msg.header.stamp
            t = stamp.sec + 1e-9 * stamp.nanosec
            times.append(t if t > 0.0 else 1e-9 * message.log_time)
            p = msg.pose.position
            positions.append((p.x, p.y, p.z))
    if not times:
        raise ValueError(f"motion: no messages on topic {topic!r} in {path}")
    return np.asarray(times), np.asarray(positions)


def build_motion(config: MotionConfig, origin, waves=None):
    """The motion generator ``config`` describes, about ``origin`` (3,) (world frame); kind ``rao``
    needs the run's wave components ``waves`` (physics.waves.wave_components)."""
    ramp_time = config.ramp_time
    if config.kind == "none":
        return StillMotion(origin, 0.0)
    if config.kind == "circle":
        return CircleMotion(origin, config.amplitude, config.frequency, config.plane_azimuth, ramp_time)
    if config.kind == "heave":
        return SinesMotion(origin, [config.amplitude], [config.frequency], [0.0], ramp_time)
    if config.kind == "sines":
        return SinesMotion(origin, config.sine_amplitudes, config.sine_frequencies, config.sine_phases, ramp_time)
    if config.kind == "record":
        if not config.record_path:
            raise ValueError("motion.record_path: required for motion.kind = record")
        times, positions = read_pose_record(config.record_path, config.record_topic)
        return RecordedMotion(origin, times, positions, config.record_scale, ramp_time)
    if config.kind == "rao":
        if not config.rao_path:
            raise ValueError("motion.rao_path: required for motion.kind = rao")
        if waves is None:
            raise ValueError("motion.kind = rao: the sea state (waves section) was not passed to build_motion")
        return RaoMotion(origin, read_rao_table(config.rao_path), waves, config.rao_lever_arm, config.ship_heading, ramp_time)
    raise ValueError(f"motion.kind: unknown {config.kind!r}; choose one of {MOTION_KINDS}")
