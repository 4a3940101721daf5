"""The winch model (tether_sim/physics/winch.py) against closed forms: rate limits, length limits,
length setpoints without overshoot, the constant-tension loop on analysable quasi-static plants."""

import math

import numpy as np
import pytest
from scipy.linalg import expm

from tether_sim.errors import ConfigError
from tether_sim.io.params import from_flat
from tether_sim.physics.winch import Schedule, Winch, WinchConfig, braking_speed


def run(winch, plant, dt, n):
    """Tick the winch n times against a quasi-static plant T = plant(L); returns arrays t, L, v, T."""
    t, L, v, T = [0.0], [winch.length], [winch.speed], [plant(winch.length)]
    for _ in range(n):
        winch.step(dt, plant(winch.length))
        t.append(winch.time), L.append(winch.length), v.append(winch.speed), T.append(plant(winch.length))
    return np.array(t), np.array(L), np.array(v), np.array(T)


def no_load(_length):
    return 1000.0


def test_speed_mode_ramps_at_the_acceleration_limit_and_integrates_the_trapezoid():
    """From rest to 1 m/s at 0.5 m/s^2: v = a t until 2 s, then 1 m/s; L = L0 + a t^2 / 2, then
    L0 + v^2 / (2a) + v (t - v/a). The ramp ends on a tick (2 s = 100 ticks of 0.02 s), where the
    trapezoid rule is exact, so only round-off separates the two (1e-9 m over 1000 m)."""
    cfg = WinchConfig(enabled=True, mode="speed", setpoint=1.0, max_speed=2.0, max_acceleration=0.5)
    t, L, v, _ = run(Winch(cfg, 200.0), no_load, 0.02, 500)
    v_exact = np.minimum(0.5 * t, 1.0)
    L_exact = 200.0 + np.where(t < 2.0, 0.25 * t ** 2, 1.0 + (t - 2.0))
    assert np.allclose(v, v_exact, atol=1e-12)
    assert np.allclose(L, L_exact, atol=1e-9)
    assert np.all(np.abs(np.diff(v)) <= 0.5 * 0.02 * (1 + 1e-12))


@pytest.mark.parametrize("direction", [1.0, -1.0])
def test_length_limits_stop_the_drum_exactly_without_breaking_the_acceleration_limit(direction):
    """Paying out (hauling in) at full speed into max_length (min_length): the length never passes
    the limit, ends on it (within the 1 mm the linear approach leaves after 20 s), the rate
    returns to 0, and braking (profile at a/2) never needs more than the acceleration limit."""
    cfg = WinchConfig(enabled=True, mode="speed", setpoint=2.0 * direction, max_speed=2.0, max_acceleration=0.5,
                      min_length=100.0, max_length=300.0)
    winch = Winch(cfg, 200.0)
    _, hist_L, hist_v, _ = run(winch, no_load, 0.02, 6000)
    assert hist_L.min() >= 100.0 - 1e-12 and hist_L.max() <= 300.0 + 1e-12
    limit = 300.0 if direction > 0 else 100.0
    assert abs(hist_L[-1] - limit) < 1e-3
    assert abs(hist_v[-1]) < 1e-3
    assert np.all(np.abs(np.diff(hist_v)) <= 0.5 * 0.02 * (1 + 1e-9))
    assert np.abs(hist_v).max() <= 2.0
    assert winch.flags["at_max_length" if direction > 0 else "at_min_length"]
    assert not winch.flags["speed_limited"]  # the setpoint is the speed limit itself


@pytest.mark.parametrize("target", [200.01, 200.4, 205.0, 300.0, 150.0, 199.7])
@pytest.mark.parametrize("dt, a, gain", [(0.02, 0.5, 1.0), (0.005, 2.0, 5.0), (0.1, 0.1, 3.0)])
def test_length_setpoint_is_reached_from_rest_without_overshoot(target, dt, a, gain):
    """Module docstring: from rest, braking at a/2 then the linear approach of rate k (k dt <= 0.3
    here, below the 0.34 for real positive eigenvalues) reaches the setpoint monotonically. Stated
    bound: overshoot <= 1e-9 m (round-off of lengths ~300 m over a few thousand ticks is ~1e-11 m).
    Settling to 1 mm within the time-optimal profile (accelerate at a, cruise, brake at a/2: at most
    |e|/v_max + 1.5 v_max/a) plus the linear tail ln(max(d*, 1 mm)/1 mm)/k (d* = a/k^2, where the
    profile turns linear) plus 2 s."""
    cfg = WinchConfig(enabled=True, mode="length", setpoint=target, max_speed=1.5, max_acceleration=a,
                      length_gain=gain, min_length=10.0, max_length=1000.0)
    winch = Winch(cfg, 200.0)
    e0 = target - 200.0
    d_star = a / gain ** 2
    bound = abs(e0) / 1.5 + 1.5 * 1.5 / a + math.log(max(d_star, 1e-3) / 1e-3) / gain + 2.0
    t, L, v, _ = run(winch, no_load, dt, int(bound / dt) + 1)
    overshoot = np.max((L - target) * np.sign(e0))
    assert overshoot <= 1e-9
    assert abs(L[-1] - target) < 1e-3
    assert np.all(np.abs(v) <= 1.5) and np.all(np.abs(np.diff(v)) <= a * dt * (1 + 1e-9))
    assert np.all(np.diff(L) * np.sign(e0) >= -1e-12)  # monotone approach


def elastic_span(k_c, ell):
    """A taut span between fixed points, quasi-static: T = k_c (ell - L), dT/dL = -k_c (k_c = EA/L)."""
    return lambda L: k_c * (ell - L)


def test_constant_tension_loop_on_an_elastic_span_follows_the_closed_form():
    """PI on the elastic span: d/dt [e, I] = [[-k_c kp, -k_c], [ki, 0]] [e, I], e(0) = e0, I(0) = 0,
    closed form via the matrix exponential (limits set wide so they never bind). The discrete loop
    measures the tension at the start of a tick and ramps the rate over it: an effective delay of
    under one tick, so its deviation is O(k_c kp dt) of e0; with k_c kp = 1 1/s and dt = 1 ms the
    tolerance 0.5 % of e0 is 5 x that estimate."""
    k_c, kp, ki = 26300.0, 1.0 / 26300.0, 0.3 / 26300.0  # omega = 0.55 rad/s, zeta = 0.91
    plant = elastic_span(k_c, 1730.0 + 60000.0 / k_c)  # 60 kN at 1730 m; a 2 kN step: kp e0 = 0.076 m/s,
    L0, T_set = 1730.0, 58000.0  # reached in one tick at 100 m/s^2, so no limit binds
    cfg = WinchConfig(enabled=True, mode="tension", setpoint=T_set, max_speed=100.0, max_acceleration=100.0,
                      tension_kp=kp, tension_ki=ki, min_length=1.0, max_length=5000.0)
    dt = 1e-3
    t, L, v, T = run(Winch(cfg, L0), plant, dt, 20000)
    e0 = plant(L0) - T_set
    A = np.array([[-k_c * kp, -k_c], [ki, 0.0]])
    step, x, exact = expm(A * 500 * dt), np.array([e0, 0.0]), []
    for _ in t[::500]:
        exact.append(x[0])
        x = step @ x
    exact = np.array(exact)
    assert np.max(np.abs((T[::500] - T_set) - exact)) < 5e-3 * abs(e0)
    assert abs(T[-1] - T_set) < 1e-3 * abs(e0)  # 20 s = 11 time constants 1/(zeta omega)


def test_constant_tension_loop_is_stable_at_the_node_rate_with_the_default_gains():
    """Defaults (kp 1e-5 m/s/N, ki 1e-6 m/s^2/N) on the ROPOS span at 1730 m (k_c = EA/L = 26.3 kN/m):
    omega = 0.16 rad/s, zeta = 0.81, ticks of 0.02 s (50 Hz). Settles to 0.1 % of a 20 kN step in
    60 s (7.9 time constants 1/(zeta omega) = 7.6 s); its overshoot is that of the linear loop (from
    e(0) = e0, I(0) = 0, so e'(0) = -k_c kp e0: 17 % of the step, more than a plain second-order step
    response because of the PI zero) within 1 % of the step for the discrete delay and the 0.4 s the
    rate needs to reach kp e0 = 0.2 m/s at 0.5 m/s^2."""
    k_c = 45.5e6 / 1730.0
    plant = elastic_span(k_c, 1730.0 + 80000.0 / k_c)  # T = 80 kN at L = 1730 m
    cfg = WinchConfig(enabled=True, mode="tension", setpoint=60000.0, min_length=1.0, max_length=5000.0)
    t, L, v, T = run(Winch(cfg, 1730.0), plant, 0.02, 3000)
    A = np.array([[-k_c * cfg.tension_kp, -k_c], [cfg.tension_ki, 0.0]])
    step, x, linear_min = expm(A * 0.1), np.array([20000.0, 0.0]), 20000.0
    for _ in range(600):
        x = step @ x
        linear_min = min(linear_min, x[0])
    assert abs(T[-1] - 60000.0) < 20.0
    assert abs((T.min() - 60000.0) - linear_min) < 0.01 * 20000.0
    assert np.all(np.abs(np.diff(v)) <= 0.5 * 0.02 * (1 + 1e-9))


def test_anti_windup_keeps_the_saturated_step_from_overshooting():
    """A tension step too large for the speed limit (kp e0 = 5 m/s > 0.5 m/s): the rate sits on the
    limit for a while. With conditional integration the integral does not wind up, so after the
    saturation the loop behaves as the linear one: overshoot below 2 % of the step (linear: 0.03 %
    at zeta = 0.91). The same run integrating through the saturation overshoots by far more."""
    k_c = 26300.0
    plant = elastic_span(k_c, 1730.0 + 2e5 / k_c)  # 200 kN at 1730 m, setpoint 70 kN
    kw = dict(enabled=True, mode="tension", setpoint=70000.0, max_speed=0.5, max_acceleration=0.5,
              tension_kp=1.0 / k_c, tension_ki=0.3 / k_c, min_length=1.0, max_length=5000.0)
    step = 130000.0
    _, _, _, T = run(Winch(WinchConfig(**kw), 1730.0), plant, 0.02, 4000)
    assert T.min() > 70000.0 - 0.02 * step and abs(T[-1] - 70000.0) < 1e-3 * step

    class WindingWinch(Winch):
        def _integrate(self, dt, v_des, v):
            self.integral += self.cfg.tension_ki * (self.filtered - self.setpoint) * dt

    _, _, _, T_wound = run(WindingWinch(WinchConfig(**kw), 1730.0), plant, 0.02, 4000)
    assert T_wound.min() < 70000.0 - 0.1 * step


def test_constant_tension_cannot_hold_a_hanging_load_it_lowers_it_to_the_limit():
    """Hanging load: T = W + w L (dT/dL = +w). P control, v = kp (T - T_set): the first-order loop
    e' = w kp e has its pole at +w kp, so e(t) = e0 exp(w kp t) (checked over 40 s, 2 % for the one-tick
    delay: w kp dt = 5e-4 per tick, 2000 ticks -> ~1e-3 relative), then the winch pays out at full
    speed and stops on max_length: a constant-tension winch lowers a load heavier than its setpoint."""
    W, w, kp = 43000.0, 25.0, 1e-3
    plant = lambda L: W + w * L  # noqa: E731
    cfg = WinchConfig(enabled=True, mode="tension", setpoint=W + w * 200.0 - 50.0, max_speed=1.0,
                      max_acceleration=100.0, tension_kp=kp, tension_ki=0.0, min_length=1.0, max_length=400.0)
    winch = Winch(cfg, 200.0)
    t, L, v, T = run(winch, plant, 0.02, 2000)
    e = T - cfg.setpoint
    assert np.allclose(e, 50.0 * np.exp(w * kp * t), rtol=0.02)
    t2, L2, v2, _ = run(winch, plant, 0.02, 30000)
    assert v2.max() == pytest.approx(1.0)  # kp e reaches the 1 m/s speed limit on the way down
    assert L2.max() <= 400.0 + 1e-12 and abs(L2[-1] - 400.0) < 1e-3 and winch.flags["at_max_length"]


def test_commands_are_checked_and_the_schedule_fires_in_order():
    cfg = WinchConfig(enabled=True, max_speed=1.5, min_length=10.0, max_length=2000.0,
                      schedule_times=(0.0, 10.0, 10.0, 50.0), schedule_modes=("speed", "length", "speed", "tension"),
                      schedule_setpoints=(1.0, 500.0, 0.0, 3e4))
    winch = Winch(cfg, 200.0)
    assert "max_speed" in winch.command("speed", 2.0)
    assert "outside" in winch.command("length", 5.0)
    assert "negative" in winch.command("tension", -1.0)
    assert "not one of" in winch.command("brake", 0.0)
    assert "finite" in winch.command("speed", float("nan"))
    assert winch.command("length", 300.0) is None and winch.mode == "length"
    schedule = Schedule(cfg)
    assert [e[1] for e in schedule.due(0.0)] == ["speed"]
    assert [e[1] for e in schedule.due(20.0)] == ["length", "speed"]
    assert schedule.due(20.0) == [] and [e[2] for e in schedule.due(60.0)] == [3e4]


@pytest.mark.parametrize("flat, words", [
    ({"winch.schedule_times": [0.0, 5.0], "winch.schedule_modes": ["speed"], "winch.schedule_setpoints": [1.0, 0.0]},
     "parallel arrays"),
    ({"winch.schedule_times": [5.0, 1.0], "winch.schedule_modes": ["speed", "speed"], "winch.schedule_setpoints": [1.0, 0.0]},
     "non-decreasing"),
    ({"winch.schedule_times": [0.0], "winch.schedule_modes": ["hover"], "winch.schedule_setpoints": [1.0]},
     "not one of"),
    ({"winch.min_length": 500.0, "winch.max_length": 100.0}, "below winch.max_length"),
    ({"winch.mode": "speed", "winch.setpoint": 9.0}, "max_speed"),
])
def test_bad_winch_sections_are_refused_naming_the_key(flat, words):
    with pytest.raises(ConfigError, match=words):
        from_flat(flat)


def test_schedule_modes_is_a_string_array_and_the_start_length_must_be_in_the_limits():
    cfg = from_flat({"winch.enabled": True, "winch.schedule_times": [0.0], "winch.schedule_modes": ["length"],
                     "winch.schedule_setpoints": [1730.0]})
    assert cfg.winch.schedule_modes == ("length",)
    with pytest.raises(ConfigError, match="cable.length 5 m"):
        Winch(WinchConfig(min_length=10.0), 5.0)


def test_braking_speed_profile():
    """min(v_max, sqrt(a d), k d): the sqrt branch brakes at a/2 (v^2 = 2 (a/2) d)."""
    assert braking_speed(100.0, 1.0, 0.5, 1.0) == 1.0
    assert braking_speed(0.64, 5.0, 0.5, 1.0) == pytest.approx(math.sqrt(0.32))
    assert braking_speed(0.1, 5.0, 0.5, 1.0) == pytest.approx(0.1)
    assert braking_speed(-1.0, 5.0, 0.5, 1.0) == 0.0


def test_ropos_descent_schedule_reaches_its_lengths_within_the_run():
    """config/ropos_descent.yaml: the winch alone (speed 1 m/s, 0.2 m/s^2) lowers 200 -> 1730 m from
    t = 20 s: 1530 m at 1 m/s plus the ramps and the linear tail, ~1560 s, so it holds at 1730 m
    (within 1 mm) before the recovery command at 1650 s, and is back at 200 m before the end."""
    from pathlib import Path

    from tether_sim.io.params import load_config

    cfg = load_config(Path(__file__).resolve().parents[2] / "config" / "ropos_descent.yaml")
    winch, schedule = Winch(cfg.winch, cfg.cable.length), Schedule(cfg.winch)
    dt, lengths = 0.2, {}  # ticks of 0.2 s (k_L dt = 0.1 < 0.34) keep this test cheap
    for k in range(int(round(cfg.duration / dt))):
        for _, mode, setpoint in schedule.due(k * dt):
            assert winch.command(mode, setpoint) is None
        winch.step(dt, 50000.0)
        lengths[round(winch.time, 6)] = winch.length
    assert abs(lengths[1649.0] - 1730.0) < 1e-3 and abs(lengths[round(cfg.duration - 20.0, 6)] - 200.0) < 1e-3
    assert max(lengths.values()) <= 1730.0 + 1e-9 and min(lengths.values()) >= 200.0 - 1e-9
