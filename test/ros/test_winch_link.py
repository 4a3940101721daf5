"""The winch between the driver and a solver (tether_sim/ros/winch_link.py), the offline runner's
winch topics, and the solvers that refuse a winch. Against the quasi-static hanging cable of
winch_fake.py (T_top = W + w L exactly), so every length and tension below is a closed form."""

from dataclasses import replace

import numpy as np
import pytest

from tether_sim.config import SimConfig
from tether_sim.errors import ConfigError
from tether_sim.physics.boundary import EndCondition
from tether_sim.physics.winch import WinchConfig
from tether_sim.ros.driver import SimulationDriver
from tether_sim.ros.winch_link import WinchedSolver, link_of
from winch_fake import W, HangingCable, w


def descent_config(**winch):
    """200 m hanging cable, winch at the ship: 1 m/s down from t = 1 s, hold at 230 m (length mode)
    from t = 20 s, haul in at 0.5 m/s from t = 60 s."""
    kw = dict(enabled=True, mode="speed", setpoint=0.0, max_speed=1.5, max_acceleration=0.5, min_length=10.0,
              max_length=2000.0, schedule_times=(1.0, 20.0, 60.0), schedule_modes=("speed", "length", "speed"),
              schedule_setpoints=(1.0, 230.0, -0.5))
    kw.update(winch)
    cfg = SimConfig(ship_end=EndCondition(kind="fixed", position=(0.0, 0.0, 0.0)),
                    vehicle_end=EndCondition(kind="fixed", position=(0.0, 0.0, -200.0)), winch=WinchConfig(**kw))
    cfg = replace(cfg, cable=replace(cfg.cable, length=200.0))
    return replace(cfg, node=replace(cfg.node, input_delay=0.0))


def run(driver, t_end, rate=50.0, t0=0.0):
    lengths = []
    for k in range(1, int(round((t_end - t0) * rate)) + 1):
        driver.tick(t0 + k / rate)
        lengths.append((driver.stamp, driver.solver.unstretched_length, link_of(driver).winch.speed))
    return np.array(lengths)


def test_the_schedule_drives_the_solver_length_through_the_pay_out_api():
    """Speed 1 m/s from 1 s at 0.5 m/s^2: L = 200 + 0.25 (t-1)^2 to 3 s, then 201 + (t - 3). At 20 s
    the length mode takes over (from 218 m, moving at 1 m/s) and settles on 230 m; the solver's
    length is the winch's at every tick (the ramp rule is shared, round-off only)."""
    driver = SimulationDriver(descent_config(), solver_factory=HangingCable)
    driver.start(0.0)
    assert isinstance(driver.solver, WinchedSolver)
    hist = run(driver, 19.0)
    t, L = hist[:, 0], hist[:, 1]
    exact = np.where(t < 1.0, 200.0, np.where(t < 3.0, 200.0 + 0.25 * (t - 1.0) ** 2, 201.0 + (t - 3.0)))
    assert np.max(np.abs(L - exact)) < 1e-9
    hist = run(driver, 59.0, t0=19.0)
    assert abs(hist[-1, 1] - 230.0) < 1e-3 and abs(hist[-1, 2]) < 1e-3
    assert hist[:, 1].max() <= 230.0 + 1e-9  # no overshoot (stopping from 1 m/s needs 1 m < 11 m left)
    link = link_of(driver)
    assert link.winch.length == driver.solver.unstretched_length
    assert [(round(t, 6), m, s) for t, m, s, _ in link.drain_applied()] == [(1.0, "speed", 1.0), (20.0, "length", 230.0)]
    run(driver, 70.0, t0=59.0)
    assert link.winch.speed == pytest.approx(-0.5) and link.winch.tension == pytest.approx(W + w * link.winch.length, rel=1e-3)


def test_the_node_tick_call_runs_the_winch_like_advance_to():
    """WinchedSolver.tick (the interface's one-call tick) applies the schedule before the interval
    exactly as advance_to does: the same lengths, speeds and drained tensions, tick by tick."""
    a = SimulationDriver(descent_config(), solver_factory=HangingCable)
    b = SimulationDriver(descent_config(), solver_factory=HangingCable)
    a.start(0.0)
    b.start(0.0)
    sa, sb = a.solver, b.solver
    for k in range(1, 400):  # 8 s: the 1 m/s pay-out ramps up from t = 1 s
        t = k / 50.0
        out = sa.tick(t)
        sb.advance_to(t)
        times, ship, _ = sb.drain_end_tensions()
        assert sa.unstretched_length == sb.unstretched_length
        np.testing.assert_array_equal(out.ship_tension, ship)
        assert out.loads[0, 3] == sb.end_forces().ship_tension
    assert sa.unstretched_length == pytest.approx(200.0 + 0.25 * 2.0 ** 2 + (7.98 - 3.0), abs=1e-9)


def test_a_topic_command_takes_over_and_a_bad_one_changes_nothing():
    driver = SimulationDriver(descent_config(), solver_factory=HangingCable)
    driver.start(0.0)
    link = link_of(driver)
    assert "max_speed" in link.request("speed", 5.0)
    assert link.request("length", 210.0) is None  # ends the schedule
    run(driver, 40.0)
    assert abs(driver.solver.unstretched_length - 210.0) < 1e-3 and link.winch.mode == "length"


def test_recovery_from_a_snapshot_restores_the_winch_with_the_cable_and_a_rebuild_keeps_the_length():
    """A divergence restores the last snapshot: solver length and winch state go back together. A
    second one before a new snapshot rebuilds from a static equilibrium: at the current length."""
    cfg = descent_config()
    cfg = replace(cfg, node=replace(cfg.node, snapshot_interval=1.0))
    built = []
    driver = SimulationDriver(cfg, solver_factory=lambda c: built.append(HangingCable(c)) or built[-1])
    driver.start(0.0)
    run(driver, 10.0)
    built[-1].fail_next = 1
    report = driver.tick(10.02)
    assert report.recovery == "snapshot"
    assert link_of(driver).winch.length == driver.solver.unstretched_length
    assert link_of(driver).winch.speed == pytest.approx(1.0)  # the snapshot was taken while paying out
    built[-1].fail_next = 1
    report = driver.tick(10.04)
    assert report.recovery == "static" and len(built) == 2
    assert built[-1].built_length == pytest.approx(link_of(driver).winch.length, abs=0.05) and built[-1].built_length > 205.0


class NoWinch(HangingCable):
    def __getattribute__(self, name):
        if name in ("set_pay_out_rate", "unstretched_length"):
            raise AttributeError(name)
        return super().__getattribute__(name)


def test_solvers_without_a_winch_refuse_winch_enabled():
    driver = SimulationDriver(descent_config(), solver_factory=NoWinch)
    with pytest.raises(ConfigError, match="cannot change its length"):
        driver.start(0.0)


def test_the_link_drives_the_hybrid_solver():
    """The descent schedule on the hybrid solver (segments added at the winch end, its own test file
    test/solvers/hybrid/test_hybrid_winch.py): a 200 m cable hanging in water with a 500 N load, 1 m/s
    from t = 1 s at 0.5 m/s^2, h0 = 5 m. The solver's length is the winch's at every tick (round-off), the
    winch element split as L grew, and the drum-side tension the winch saw is the quasi-static
    w L + F less the tangential drag 0.5 rho d Cdt V^2 L (62 N) within the ringing the ramp's end at
    3 s excites (at most the inertia gamma0 L a = 305 N): measured 207 N below w L + F at 5 s."""
    from tether_sim.physics.hydrodynamics import net_weight_per_length
    from tether_sim.solvers.config import HybridOptions

    cfg = replace(descent_config(), solver="hybrid", hybrid=HybridOptions(n_segments=40, time_step=0.02),
                  vehicle_end=EndCondition(kind="force", position=(0.0, 0.0, -200.0), force=(0.0, 0.0, -500.0)))
    driver = SimulationDriver(cfg)
    driver.start(0.0)
    assert isinstance(driver.solver, WinchedSolver) and driver.solver.inner.name == "hybrid"
    hist = run(driver, 5.0)
    t, L = hist[:, 0], hist[:, 1]
    exact = np.where(t < 1.0, 200.0, np.where(t < 3.0, 200.0 + 0.25 * (t - 1.0) ** 2, 201.0 + (t - 3.0)))
    assert np.max(np.abs(L - exact)) < 1e-9
    link = link_of(driver)
    assert link.winch.length == driver.solver.unstretched_length and driver.solver.pay_out_rate == pytest.approx(1.0)
    assert driver.solver.stats["winch_splits"] >= 1
    wl = net_weight_per_length(cfg.cable, cfg.environment)
    print(f"hybrid under the link: L {link.winch.length:.3f} m, drum tension {link.winch.tension:.1f} N, "
          f"w L + F {wl * link.winch.length + 500.0:.1f} N")
    cab, env = cfg.cable, cfg.environment
    drag = 0.5 * env.fluid_density * cab.diameter * cab.Cdt * link.winch.length
    assert abs(link.winch.tension - (wl * link.winch.length + 500.0 - drag)) < cab.gamma0 * link.winch.length * 0.5


def test_offline_run_records_winch_state_and_the_scheduled_commands(tmp_path):
    pytest.importorskip("rclpy")
    pytest.importorskip("tether_sim_msgs")
    from tether_sim.io.mcap_log import read_messages
    from tether_sim.ros.offline import run_offline

    out = tmp_path / "winch.mcap"
    run_offline(descent_config(), out, duration=25.0, progress=False, solver_factory=HangingCable)
    states, commands, tether = [], [], []
    for topic, _, _, msg in read_messages(str(out), ["/winch/state", "/winch/command", "/tether/state"]):
        {"/winch/state": states, "/winch/command": commands, "/tether/state": tether}[topic].append(msg)
    assert len(states) == len(tether) == 25 * 50 + 1
    assert [(c.mode, c.setpoint, c.header.stamp.sec) for c in commands] == [("speed", 1.0, 1), ("length", 230.0, 20)]
    last = states[-1]
    assert last.end == "ship" and last.mode == "length" and 225.0 < last.length <= 230.0
    assert last.tension == pytest.approx(W + w * last.length)
    for s, st in zip(states[::50], tether[::50]):
        assert st.arc_length[-1] == pytest.approx(s.length) and st.ship_end_tension == pytest.approx(s.tension)
    assert any(s.acceleration_limited for s in states)
    from tether_sim.report import make_report

    result = make_report(out, tmp_path / "figures")
    md = result["markdown"]
    assert "## Winch" in md and "| 1.00 | speed | 1 m/s | 200.0 |" in md and "| 20.00 | length | 230 m | 218.0 |" in md
    assert {"winch: tension and length against time", "winch: tension against length"} <= set(result["figures"])
    assert all(p.is_file() for p in result["figures"].values())
    run = result["run"]
    assert run.arc_history is not None and run.arc_history[-1, -1] == pytest.approx(last.length)
