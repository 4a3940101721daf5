"""Stepping policy of the node/offline driver (tether_sim.ros.driver): lag, substep cap, clock jumps,
divergence recovery, end motion from pose inputs, wrench frames and snap detection.

The policy is tested against a massless elastic string between the two ends (quasi-static: tension
T = EA * max(0, |r_v - r_s| / L - 1), the same at every point) that honours the solver interface,
so every number below is exact; the real solvers are exercised in test_sim_node / test_offline.
"""

import math
from dataclasses import replace

import numpy as np
import pytest

from tether_sim.config import SimConfig
from tether_sim.errors import SolverDivergedError
from tether_sim.io.inputs import EndPoseInput
from tether_sim.physics.boundary import EndCondition
from tether_sim.ros.driver import SimulationDriver
from tether_sim.solvers.base import EndForces, SolverState

DT = 0.01


class ElasticString:
    """Massless taut-or-slack string between two pinned ends, substeps of DT (solver interface)."""

    name = "string"

    def __init__(self, config):
        self.L, self.EA = config.cable.length, config.cable.EA
        self.ends = {"ship": np.array(config.ship_end.position, float), "vehicle": np.array(config.vehicle_end.position, float)}
        self.targets = {}
        self.time = 0.0
        self.fail_next = 0
        self.calls = []
        self._log = []

    def set_end_motion(self, end, position, velocity):
        self.targets[end] = (np.array(position, float), np.array(velocity, float))
        self.calls.append((end, self.time, np.array(position, float)))

    def set_end_load(self, end, force, moment=(0.0, 0.0, 0.0)):
        raise NotImplementedError

    def stable_time_step(self):
        return DT

    def tension(self):
        return self.EA * max(0.0, np.linalg.norm(self.ends["vehicle"] - self.ends["ship"]) / self.L - 1.0)

    def advance_to(self, t):
        if self.fail_next:
            self.fail_next -= 1
            self.ends["vehicle"][:] = np.nan
            raise SolverDivergedError("state became non-finite")
        n = max(1, math.ceil((t - self.time) / DT - 1e-9))
        start = {e: p.copy() for e, p in self.ends.items()}
        t0 = self.time
        for k in range(1, n + 1):  # linear motion of the ends towards their targets
            u = k / n
            for e, (p, _) in self.targets.items():
                self.ends[e] = start[e] + u * (p - start[e])
            self._log.append((t0 + u * (t - t0), self.tension()))
        self.time = t
        return n

    def state(self, arc_lengths=None):
        s = np.linspace(0, self.L, 5) if arc_lengths is None else np.asarray(arc_lengths, float)
        pos = self.ends["ship"] + np.outer(s / self.L, self.ends["vehicle"] - self.ends["ship"])
        z = np.zeros(len(s))
        return SolverState(self.time, s, pos, np.zeros_like(pos), z + self.tension(), z, z, z, DT)

    def end_forces(self):
        d = self.ends["vehicle"] - self.ends["ship"]
        u = d / np.linalg.norm(d)
        T = self.tension()
        return EndForces(ship_force=T * u, vehicle_force=-T * u, ship_tension=T, vehicle_tension=T)

    def body_state(self, end):
        return None

    def drain_end_tensions(self):
        log, self._log = self._log, []
        t = np.array([x[0] for x in log])
        T = np.array([x[1] for x in log])
        return t, T, T.copy()

    def snapshot(self):
        return (self.time, {e: p.copy() for e, p in self.ends.items()})

    def restore(self, snap):
        self.time = snap[0]
        self.ends = {e: p.copy() for e, p in snap[1].items()}


def make_config(**node):
    node.setdefault("input_delay", 0.0)
    cfg = SimConfig(ship_end=EndCondition(kind="prescribed", position=(0.0, 0.0, 0.0)),
                    vehicle_end=EndCondition(kind="fixed", position=(101.0, 0.0, 0.0)))
    cfg = replace(cfg, cable=replace(cfg.cable, length=100.0, EA=1.0e6))
    return replace(cfg, node=replace(cfg.node, **node))


def test_lag_is_carried_then_beyond_max_lag_the_driver_resynchronises_keeping_the_state():
    built = []
    driver = SimulationDriver(make_config(max_lag=1.0, max_substeps_per_tick=10),
                              solver_factory=lambda c: built.append(ElasticString(c)) or built[-1])
    driver.start(100.0)
    r = driver.tick(100.05)
    assert r.substeps == 5 and not r.capped and r.dropped == 0.0 and r.stamp == pytest.approx(100.05)
    assert not r.degraded and r.lag == pytest.approx(0.0, abs=1e-9)
    r = driver.tick(100.5)  # 0.45 s to do, at most 10 substeps of 0.01 s: capped, lag carried, honest stamp
    assert r.capped and r.substeps == 10 and r.dropped == 0.0
    assert r.stamp == pytest.approx(100.15) and r.lag == pytest.approx(0.35) and r.degraded
    t_sim = driver.solver.time
    r = driver.tick(105.0)  # 4.85 s behind > max_lag: re-synchronised, cable state kept (no rebuild)
    assert r.dropped == pytest.approx(4.85) and len(built) == 1 and driver.solver.time == pytest.approx(t_sim)
    assert r.stamp == pytest.approx(105.0) and r.degraded and driver.resyncs == 1
    r = driver.tick(105.05)
    assert r.substeps == 5 and r.dropped == 0.0 and r.stamp == pytest.approx(105.05)
    assert driver.dropped_total == pytest.approx(4.85) and driver.capped_ticks == 1


def test_clock_jump_back_resets_inputs_and_keeps_the_state():
    inp = EndPoseInput("ship")
    driver = SimulationDriver(make_config(), {"ship": inp}, solver_factory=ElasticString)
    inp.add_pose(9.9, (0.0, 0.0, 0.0), (0, 0, 0, 1))
    driver.start(10.0)
    driver.tick(10.5)
    t_sim = driver.solver.time
    r = driver.tick(2.0)
    assert r.clock_jump and not inp.has_data
    assert driver.solver.time == t_sim and driver.stamp == pytest.approx(2.0)


def test_divergence_restores_the_snapshot_then_rebuilds_from_static():
    built = []

    def factory(c):
        built.append(ElasticString(c))
        return built[-1]

    driver = SimulationDriver(make_config(snapshot_interval=0.5), solver_factory=factory)
    driver.start(0.0)
    for k in range(1, 8):
        driver.tick(k * 0.1)  # a snapshot at t = 0.5
    built[-1].fail_next = 1
    r = driver.tick(0.8)
    assert r.error and r.recovery == "snapshot" and driver.solver.time == pytest.approx(0.5)
    assert np.all(np.isfinite(driver.solver.ends["vehicle"]))
    assert driver.stamp == pytest.approx(0.8)  # lost time skipped, outputs stay monotonic
    driver.solver.fail_next = 1
    r = driver.tick(0.9)
    assert r.recovery == "static" and len(built) == 2 and driver.divergences == 2
    assert driver.tick(1.0).error is None  # running again


def test_prescribed_end_follows_the_attachment_point_of_its_pose_input():
    inp = EndPoseInput("ship", attachment=(0.0, 0.0, -5.0))
    for k in range(51):
        inp.add_pose(k * 0.1, (k * 0.02, 0.0, 0.0), (0, 0, 0, 1))  # 0.2 m/s east
    driver = SimulationDriver(make_config(ship_attachment=(0.0, 0.0, -5.0)), {"ship": inp}, solver_factory=ElasticString)
    driver.start(0.0)
    np.testing.assert_allclose(driver.solver.ends["ship"], (0.0, 0.0, -5.0))  # started at the input
    # the cable starts at rest: the end is blended from rest onto the 0.2 m/s stream over
    # 7.5 dv / BLEND_ACCELERATION = 3 s (degraded meanwhile), then follows the input exactly
    r = driver.tick(0.5)
    assert r.degraded and r.blending and r.blends[0][1] == pytest.approx(3.0)
    assert driver.solver.calls[-1][2][0] < 0.1
    for k in range(2, 8):
        r = driver.tick(0.5 * k)
    driver.tick(4.05)
    end, _, p = driver.solver.calls[-1]
    assert end == "ship" and not driver.degraded
    np.testing.assert_allclose(p, (0.81, 0.0, -5.0), atol=1e-12)  # Hermite with exact slopes on a line
    np.testing.assert_allclose(driver.solver.targets["ship"][1], (0.2, 0.0, 0.0), atol=1e-12)


def test_missing_input_holds_the_configured_position():
    driver = SimulationDriver(make_config(), {"ship": EndPoseInput("ship")}, solver_factory=ElasticString)
    driver.start(0.0)
    driver.tick(0.1)
    np.testing.assert_array_equal(driver.solver.targets["ship"][0], 0.0)
    np.testing.assert_array_equal(driver.solver.targets["ship"][1], 0.0)


def test_wrench_is_the_force_on_the_body_in_the_body_frame():
    # ship yawed 90 deg (body x = world north), fairlead 2 m ahead; the string pulls towards +x (east)
    # with T = EA * 1/100 = 1e4 N, i.e. along body -y; torque = r x F = (2,0,0) x (0,-1e4,0) = (0,0,-2e4)
    q = (0.0, 0.0, math.sin(math.pi / 4), math.cos(math.pi / 4))
    inp = EndPoseInput("ship", attachment=(2.0, 0.0, 0.0))
    inp.add_pose(0.0, (0.0, -2.0, 0.0), q)
    driver = SimulationDriver(make_config(ship_attachment=(2.0, 0.0, 0.0)), {"ship": inp}, solver_factory=ElasticString)
    driver.start(0.0)
    force, torque = driver.body_wrench("ship", driver.solver.end_forces())
    np.testing.assert_allclose(force, (0.0, -1.0e4, 0.0), atol=1e-6)
    np.testing.assert_allclose(torque, (0.0, 0.0, -2.0e4), atol=1e-6)
    # fixed vehicle end: world-aligned frame at the end; force points back to the ship (-x)
    force, torque = driver.body_wrench("vehicle", driver.solver.end_forces())
    np.testing.assert_allclose(force, (-1.0e4, 0.0, 0.0), atol=1e-6)
    np.testing.assert_allclose(torque, 0.0, atol=1e-6)


def test_slack_then_retension_gives_a_slack_warning_and_a_snap_event():
    # static T = 1e4 N (1 % stretch). The ship moves 2 m towards the vehicle (slack) and back 3 m beyond:
    # peak T = EA * (103/100 - 1)... = 3e4 N, amplification 3.
    inp = EndPoseInput("ship", max_end_speed=100.0)
    path = [(0.0, 0.0), (1.0, 0.0), (1.2, 2.0), (2.0, 2.0), (2.2, -2.0), (4.0, -2.0)]
    t_samples = np.arange(0.0, 4.001, 0.05)
    xs = np.interp(t_samples, [p[0] for p in path], [p[1] for p in path])
    for t, x in zip(t_samples, xs):
        assert inp.add_pose(t, (x, 0.0, 0.0), (0, 0, 0, 1)) is None
    cfg = make_config()
    cfg = replace(cfg, snap=replace(cfg.snap, monitor_arc_lengths=(50.0,)))
    driver = SimulationDriver(cfg, {"ship": inp}, solver_factory=ElasticString)
    driver.start(0.0)
    assert driver.static_tensions == pytest.approx((1.0e4, 1.0e4))
    events = []
    for k in range(1, 81):
        events += driver.tick(k * 0.05).events
    kinds = [(type(e).__name__, e.location) for e in events]
    assert ("SlackStarted", "ship") in kinds and ("SnapEvent", "ship") in kinds
    snap = next(e for e in events if type(e).__name__ == "SnapEvent" and e.location == "ship")
    # Hermite overshoot between samples is nil (flat segments, piecewise-linear knots) -> 1 %
    assert snap.peak_tension == pytest.approx(3.0e4, rel=0.01)
    assert snap.amplification == pytest.approx(3.0, rel=0.01)
    assert 1.0 < snap.slack_start < 1.2 and snap.time > 2.0
    # the span point (same uniform tension) is sampled once per tick: its peak is the tick maximum
    span = [e for e in events if e.location == "span s=50 m"]
    assert [type(e).__name__ for e in span] == ["SlackStarted", "SnapEvent"]
    assert span[1].arc_length == 50.0 and span[1].peak_tension == pytest.approx(3.0e4, rel=0.01)
    assert driver.static_by_location["span s=50 m"] == pytest.approx(1.0e4)


def test_wall_budget_limits_the_substeps_of_one_tick(monkeypatch):
    # substeps that cost 2 ms each on a fake wall clock; a 10 ms budget allows 5 substeps per tick
    import tether_sim.ros.driver as driver_module

    clock = {"t": 0.0}

    class FakeWall:
        @staticmethod
        def perf_counter():
            return clock["t"]

    class SlowString(ElasticString):
        def advance_to(self, t):
            n = super().advance_to(t)
            clock["t"] += 0.002 * n
            return n

    monkeypatch.setattr(driver_module, "wallclock", FakeWall)
    driver = SimulationDriver(make_config(max_lag=10.0), solver_factory=SlowString, wall_budget=0.01)
    driver.start(0.0)
    # the first tick already respects the budget: one substep is timed (2 ms), then 4 more fit
    r = driver.tick(1.0)
    assert r.capped and r.substeps == 5 and r.lag == pytest.approx(0.95)
    r = driver.tick(1.0)
    assert r.capped and r.substeps == 5 and r.lag == pytest.approx(0.90)
    assert driver.real_time_factor == pytest.approx(0.05 / 0.01)  # 5 substeps of 0.01 s in 10 ms


def test_an_input_appearing_far_from_the_held_end_restarts_the_solver_there():
    built = []

    def factory(c):
        built.append(ElasticString(c))
        return built[-1]

    inp = EndPoseInput("ship")
    driver = SimulationDriver(make_config(), {"ship": inp}, solver_factory=factory)
    driver.start(0.0)
    driver.tick(0.1)  # held at the configured (0, 0, 0)
    inp.add_pose(0.15, (-50.0, 0.0, 0.0), (0, 0, 0, 1))  # first pose, 50 m away
    r = driver.tick(0.2)
    assert r.restart and "ship" in r.restart and len(built) == 2
    np.testing.assert_allclose(built[-1].ends["ship"], (-50.0, 0.0, 0.0))
    assert driver.stamp == pytest.approx(0.2) and driver.tick(0.3).restart is None


def test_input_delay_makes_the_solver_interpolate_instead_of_extrapolate():
    # 10 Hz samples of x = t^2 up to t = 2.0; at clock 2.0 with a 0.2 s delay the end is at
    # x(1.8) from the Hermite curve (exact slopes of a parabola by central differences: error 0)
    inp = EndPoseInput("ship")
    for k in range(21):
        inp.add_pose(0.1 * k, ((0.1 * k) ** 2, 0.0, 0.0), (0, 0, 0, 1))
    driver = SimulationDriver(make_config(input_delay=0.2), {"ship": inp}, solver_factory=ElasticString)
    driver.start(0.2)  # (at rest: the start blend, from the 0.1 m/s one-sided slope, is over in 1.5 s)
    assert driver.stamp == pytest.approx(0.0)
    for now in (0.5, 1.0, 1.5, 2.0):
        driver.tick(now)
    assert driver.stamp == pytest.approx(1.8)
    np.testing.assert_allclose(driver.solver.targets["ship"][0], (3.24, 0.0, 0.0), atol=1e-12)
    np.testing.assert_allclose(driver.solver.targets["ship"][1], (3.6, 0.0, 0.0), atol=1e-12)


def test_a_substep_dearer_than_the_whole_budget_still_makes_progress(monkeypatch):
    import tether_sim.ros.driver as driver_module

    clock = {"t": 0.0}

    class FakeWall:
        @staticmethod
        def perf_counter():
            return clock["t"]

    class VerySlowString(ElasticString):
        def advance_to(self, t):
            n = super().advance_to(t)
            clock["t"] += 0.05 * n  # 50 ms a substep, budget 10 ms
            return n

    monkeypatch.setattr(driver_module, "wallclock", FakeWall)
    driver = SimulationDriver(make_config(max_lag=10.0), solver_factory=VerySlowString, wall_budget=0.01)
    driver.start(0.0)
    stamps = [driver.tick(0.02 * k).stamp for k in range(1, 6)]
    assert stamps == pytest.approx([0.01, 0.02, 0.03, 0.04, 0.05])  # one substep per tick, late but moving


def test_an_input_lost_blend_starts_where_the_end_is():
    # a ship end moving at 0.1 m/s whose input falls silent: after max_extrapolation (0.2 s) the
    # source holds it and the end is blended to rest. The blend is sized by the offset at the end of
    # the chunk (the probe) but starts at the chunk's start from the end's state there: the commanded
    # speed never exceeds the stream's 0.1 m/s (before 2026-11-27 the blend started from the
    # position extrapolated to the probe, one chunk's travel ahead: 0.2 m/s over that chunk)
    inp = EndPoseInput("ship", max_extrapolation=0.2)
    for k in range(21):
        inp.add_pose(0.05 * k, (0.1 * 0.05 * k, 0.0, 0.0), (0, 0, 0, 1))
    driver = SimulationDriver(make_config(), {"ship": inp}, solver_factory=ElasticString, start_blend=False)
    driver.start(0.5)
    reports = [driver.tick(0.5 + 0.02 * k) for k in range(1, 101)]
    assert any(reason == "input lost" for r in reports for *_, reason in r.blends)
    calls = [(t, p) for end, t, p in driver.solver.calls if end == "ship"]
    times = np.array([t for t, _ in calls]) + 0.02  # (a command is set at the chunk's start for its end)
    x = np.array([p[0] for _, p in calls])
    speed = np.diff(x) / np.diff(times)
    assert speed.max() <= 0.1 * (1.0 + 1e-9) and speed.min() > -0.1


def test_an_analytic_motion_is_commanded_without_its_acceleration():
    """MotionSource (the RAO ship of the node, the offline runner's motions) commands position and velocity:
    it takes them from the generator's position_velocity, at()'s first two numbers bit for bit, and does not
    compute the acceleration no end is told (the RAO response's rotations cost the node's tick ~30 us)."""
    from tether_sim.physics.motion import MotionConfig, build_motion
    from tether_sim.ros.end_commands import MotionSource

    class Counted:
        def __init__(self, motion):
            self.motion, self.full = motion, 0

        def at(self, t):
            self.full += 1
            return self.motion.at(t)

        def position_velocity(self, t):
            return self.motion.position_velocity(t)

    motion = build_motion(MotionConfig(kind="circle", amplitude=2.0, frequency=0.2, ramp_time=5.0), (0.0, 0.0, -5.0))
    counted = Counted(motion)
    source = MotionSource(counted)
    for t in (0.0, 1.3, 4.99, 7.25):
        p, v = source.attachment_at(t)
        ref = motion.at(t)
        assert p.tobytes() == np.asarray(ref[0], float).tobytes() and v.tobytes() == np.asarray(ref[1], float).tobytes()
    assert counted.full == 0

    class AtOnly:  # a motion with at() alone is still followed
        def at(self, t):
            return np.array([t, 0.0, 0.0]), np.array([1.0, 0.0, 0.0]), np.zeros(3)

    p, v = MotionSource(AtOnly()).attachment_at(2.0)
    assert p.tolist() == [2.0, 0.0, 0.0] and v.tolist() == [1.0, 0.0, 0.0]
