"""Section ``forecast``: the snap forecast (look-ahead ensemble runs of the solver, docs/forecast.md)."""

from dataclasses import dataclass

from tether_sim.spec import param

FORECAST_SOURCES = ("auto", "known_sea", "poses", "external")


@dataclass(frozen=True)
class ForecastConfig:
    """Look-ahead runs of copies of the solver from the current state over ``horizon`` seconds."""

    enabled: bool = param(False, doc="publish tether/snap_forecast (look-ahead runs from the current state)")
    horizon: float = param(20.0, unit="s", doc="look-ahead horizon of each forecast", min=1.0, max=120.0)
    rate: float = param(1.0, unit="Hz", doc="forecasts started per second (the node skips one while the previous is still running)", min=0.01, max=10.0)
    members: int = param(8, doc="ensemble members per forecast (1: the nominal forecast only)", min=1, max=256)
    source: str = param("auto", doc="ship-motion forecast: known_sea (the run's own analytic sea/motion, perturbed), poses (autoregressive predictor on the ship pose history), external (tether/ship_motion_forecast, nav_msgs/Path), auto (known_sea for an analytic motion, else external while one is valid, else poses)", choices=FORECAST_SOURCES)
    command_rate: float = param(0.0, unit="Hz", doc="rate at which the look-ahead runs command the ship end (Hermite interpolation by the solver in between, as in the node); 0 = node.output_rate (then an exact forecast repeats the run bit for bit)", min=0.0, max=1000.0)
    sea_error: float = param(0.1, doc="known_sea: forecast error of the wave elevation as a fraction of Hs (rms; 0.1 = 10 % of Hs); sets the spread of the members' amplitude and phase perturbations (energy-preserving, so below Hs / sqrt(8): the error of an unrelated sea of the same spectrum)", min=0.0, max=0.35)
    condition_time: float = param(2.0, unit="s", doc="known_sea: the perturbed members start from the ship's commanded position and velocity, their difference to the member's own forecast continued by its conditional mean under the sea's covariance; what the sea's components do not carry fades as (dp + (dv + dp/T) tau) exp(-tau/T) with T this time (0: members start where their forecast says)", min=0.0, max=60.0)
    ar_order: int = param(24, doc="poses: order p of the autoregressive ship-motion model", min=1, max=200)
    ar_sample_period: float = param(0.5, unit="s", doc="poses: sampling period of the autoregressive model (the pose history is resampled to it)", min=0.02, max=5.0)
    ar_window: float = param(300.0, unit="s", doc="poses: length of pose history the model is fitted on (at least 4 x order x sample period needed)", min=5.0, max=7200.0)
    external_max_age: float = param(2.0, unit="s", doc="external: a forecast whose header stamp is older than this at the time of use is stale (rejected)", min=0.0, max=600.0)
    warn_probability: float = param(0.75, doc="the alarm: /diagnostics warns of a snap, and the report and the skill benchmark count a warning, when a forecast's probability is at least this (the message carries the probability itself); 0.75 was chosen on the skill benchmark's tuning seeds, where p 0.5-0.625 forecasts verified 38 % and most false alarms were of them (docs/forecast.md)", min=0.05, max=1.0)
    lagged: int = param(1, doc="forecasts pooled into each published one (a lagged ensemble: the newest forecast's members with those of the forecasts issued one and more periods before it, each member's snap on the common clock, over the newest one's horizon; 1: each forecast as it is run); 2 halves the chance that a marginal wave group crosses a probability threshold by sampling alone, at no extra look-ahead (docs/forecast.md)", min=1, max=4)
    slack_margin: float = param(0.0, doc="a member's snap counts only when its least end tension before the snap lay below (1 - slack_margin) x the slack level (snap.slack_fraction): the members' slack corrected for a measured bias against the run, whose least tension near the slack level was 0.29 slack levels above the members' on the tuning seeds; 0: every member snap counts (docs/forecast.md, \"Calibration of the members' slack\")", min=0.0, max=1.0)
    seed: int = param(0, doc="seed of the ensemble perturbations (forecast k uses seed + k)", min=0, max=2**31 - 1)
