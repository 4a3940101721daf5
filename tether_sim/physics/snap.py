"""Streaming slack and snap-load detection (constant work per sample). See class docs."""

from dataclasses import dataclass

from tether_sim.spec import param


@dataclass(frozen=True)
class SnapConfig:
    """Thresholds of the slack/snap detector (DNV-RP-H103 style: slack below 10% of static)."""

    slack_fraction: float = param(0.1, doc="slack begins when tension < slack_fraction * static tension", min=0.0, max=1.0, live=True)
    slack_threshold: float = param(0.0, unit="N", doc="absolute slack threshold; > 0 overrides slack_fraction", min=0.0, max=1e9, live=True)
    retension_fraction: float = param(0.2, doc="slack ends when tension rises above retension_fraction * static (hysteresis)", min=0.0, max=10.0, live=True)
    min_slack_duration: float = param(0.0, unit="s", doc="ignore slack periods shorter than this", min=0.0, max=1e4, live=True)
    monitor_arc_lengths: tuple = param((), unit="m", doc="extra arc lengths (span points) monitored besides both ends")
