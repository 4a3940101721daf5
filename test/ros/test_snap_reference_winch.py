"""The snap detector's reference tensions follow the winch's length (physics.winch.static_end_tensions,
ros/winch_link.LengthReference, driver._detect).

Against the quasi-static hanging cable of winch_fake.py (T_top = W + w L exactly), with a cable whose
submerged weight per metre is the fake's w, so the reference must equal W + w L(t) to round-off."""

from dataclasses import replace

import numpy as np
import pytest

from tether_sim.physics.hydrodynamics import net_weight_per_length
from tether_sim.physics.snap import SlackStarted, SnapEvent
from tether_sim.physics.winch import static_end_tensions
from tether_sim.ros.driver import SimulationDriver
from test_winch_link import descent_config
from winch_fake import W, HangingCable, w


def test_static_end_tensions_closed_forms():
    """Vertical hang: the top carries W + w L, the bottom W. Inclined: the added weight goes into the
    upper end's vertical component, its horizontal force and the lower end are kept."""
    hang = [[0.0, 0.0, -(W + w * 200.0)], [0.0, 0.0, W]]
    top, bottom = static_end_tensions(hang, 0, w, 1530.0)
    assert top == pytest.approx(W + w * 1730.0, rel=1e-15) and bottom == W
    top, bottom = static_end_tensions(hang, 0, w, -150.0)  # hauled in to 50 m
    assert top == pytest.approx(W + w * 50.0, rel=1e-15)
    inclined = [[3e3, 4e3, -2e4], [-3e3, -4e3, 5e3]]  # H = 5 kN at both ends
    top, bottom = static_end_tensions(inclined, 0, 20.0, 100.0)
    assert top == pytest.approx(np.hypot(5e3, 2e4 + 2e3), rel=1e-15)
    assert bottom == pytest.approx(np.linalg.norm([-3e3, -4e3, 5e3]), rel=1e-15)
    # a vehicle-end winch below the ship: the ship (upper end) carries the cable added at the bottom
    top, bottom = static_end_tensions(hang, 0, w, 100.0)
    assert top == pytest.approx(W + w * 300.0, rel=1e-15)


def fake_weight_config(**winch):
    """descent_config with a cable whose net weight in water is the fake's w (N/m)."""
    cfg = descent_config(**winch)
    env, cab = cfg.environment, cfg.cable
    gamma0 = w / (env.g * (1.0 - env.fluid_density / cab.density))  # w = g gamma0 (1 - rho_f / rho_c)
    cfg = replace(cfg, cable=replace(cab, gamma0=gamma0))
    assert net_weight_per_length(cfg.cable, cfg.environment) == pytest.approx(w, rel=1e-12)
    return cfg


class DippingCable(HangingCable):
    """The fake, with the top tension dropped to ``dip`` N over [t0, t1] (a slack spell)."""

    window = (40.0, 40.5)
    dip = 6000.0

    def drain_end_tensions(self):
        t, top, bottom = super().drain_end_tensions()
        inside = (t >= self.window[0]) & (t <= self.window[1])
        top[inside] = self.dip
        return t, top, bottom


def run_events(driver, t_end, rate=50.0):
    events, refs = [], []
    for k in range(1, int(round(t_end * rate)) + 1):
        report = driver.tick(k / rate)
        events += report.events
        refs.append((driver.solver.unstretched_length, driver.detector.static_tensions.copy()))
    return events, refs


def test_slow_pay_out_keeps_the_reference_on_the_static_tension_and_raises_nothing():
    """1 m/s pay-out from 200 m for 60 s (then held): the reference at the ship is W + w L(t) at
    every tick (round-off: one subtraction and one hypot), the vehicle's stays W, and the
    quasi-static tensions raise no slack warning and no snap."""
    cfg = fake_weight_config(schedule_times=(1.0,), schedule_modes=("speed",), schedule_setpoints=(1.0,),
                             max_length=260.0)
    driver = SimulationDriver(cfg, solver_factory=HangingCable)
    driver.start(0.0)
    events, refs = run_events(driver, 70.0)
    assert events == []
    lengths = np.array([r[0] for r in refs])
    ship = np.array([r[1][0] for r in refs])
    assert lengths[-1] == pytest.approx(260.0, abs=1e-3)  # braking onto max_length
    np.testing.assert_allclose(ship, W + w * lengths, rtol=1e-12)
    assert all(r[1][1] == W for r in refs)
    assert driver.static_by_location["ship"] == pytest.approx(W + w * lengths[-1], rel=1e-12)


def test_a_slack_spell_at_a_long_length_is_judged_against_that_length():
    """At L = 238 m (the dip at t = 40 s) the static top tension is W + w L = 48.95 kN: a dip to
    4.85 kN lies between 10 % of it (4.895 kN: slack) and 10 % of the starting 200 m static tension
    (4.8 kN). With the reference following L the warning comes, at the threshold of that length;
    the tension then returns to the static one, which is not a snap (no event). With the reference
    frozen at the start (until 2026-11-24) the slack spell went unreported."""
    cfg = fake_weight_config(schedule_times=(1.0,), schedule_modes=("speed",), schedule_setpoints=(1.0,),
                             max_length=2000.0)
    DippingCable.dip = 4850.0
    L_dip = 200.0 + 0.5 * 1.0 * 2.0 + (40.0 - 3.0)  # ramp 1 -> 3 s at 0.5 m/s^2 (1 m), then 1 m/s
    for follow in (True, False):
        driver = SimulationDriver(cfg, solver_factory=DippingCable)
        driver.start(0.0)
        if not follow:
            driver._reference = None
        events, _ = run_events(driver, 44.0)
        slack = [e for e in events if isinstance(e, SlackStarted)]
        assert not [e for e in events if isinstance(e, SnapEvent)]
        if follow:
            assert len(slack) == 1 and slack[0].location == "ship"
            assert slack[0].time == pytest.approx(40.0, abs=0.011)
            assert slack[0].threshold == pytest.approx(0.1 * (W + w * L_dip), rel=1e-4)
        else:
            assert slack == []
