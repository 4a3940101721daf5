"""Analytic and recorded fairlead motion generators [PE2020 Sec. 6.2]."""

from dataclasses import dataclass

from tether_sim.spec import param

MOTION_KINDS = ("none", "circle", "heave", "sines", "record")


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
