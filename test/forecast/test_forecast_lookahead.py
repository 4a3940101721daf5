"""Look-ahead snap forecast (tether_sim.forecast): a forecast from the exact future of the sea is the
run itself, so its predicted snaps are the snaps the run reports later.

The case: the 1730 m ROPOS tether on the live mesh, the ship on its A-frame responding through the RAO
table to a regular wave (H = 6 m, T = 9 s; config/ropos_aframe_jonswap.yaml with waves.kind regular),
which makes the cage end go slack and snap once per wave period. The driver runs as in the offline
runner; a forecast (horizon 10 s) is issued every second from the current state.
"""

import math
from dataclasses import replace

import numpy as np
import pytest

from tether_sim.forecast.lookahead import ensemble_median_time
from tether_sim.forecast.service import ForecastService
from tether_sim.io.params import load_config
from tether_sim.physics.motion import build_motion
from tether_sim.physics.snap import SnapEvent
from tether_sim.physics.waves import wave_components
from tether_sim.ros.driver import MotionSource, SimulationDriver

RATE = 10.0
DURATION = 40.0


def regular_wave_case(**forecast):
    over = {"waves.kind": "regular", "waves.height": 6.0, "waves.period": 9.0, "motion.ramp_time": 5.0,
            "forecast.members": 1, "forecast.sea_error": 0.0, "forecast.horizon": 10.0, "node.output_rate": RATE}
    over.update({f"forecast.{k}": v for k, v in forecast.items()})
    cfg = load_config("config/ropos_aframe_jonswap.yaml", over)
    return replace(cfg, node=replace(cfg.node, max_lag=math.inf, input_delay=0.0))


def run(cfg, duration=DURATION):
    """(snap events of the run, every EndForecast issued), driver and service as in the offline runner."""
    src = {"ship": MotionSource(build_motion(cfg.motion, np.asarray(cfg.ship_end.position, float), wave_components(cfg)))}
    driver = SimulationDriver(cfg, src, start_blend=False)
    service = ForecastService(cfg)
    driver.start(0.0)
    snaps, forecasts = [], []
    for k in range(1, int(duration * RATE) + 1):
        report = driver.tick(k / RATE)
        snaps += [e for e in report.events if isinstance(e, SnapEvent)]
        service.observe(driver, clock_origin=0.0, tick_index=k)
        forecasts += service.poll()
    return snaps, forecasts


def first_snap_after(snaps, end, t):
    return next((s for s in snaps if s.location == end and s.time >= t - 1e-9), None)


def check_against_run(snaps, forecasts, horizon, peak_rtol, time_tol):
    checked = 0
    for f in forecasts:
        if f.stamp + horizon + 2.0 > DURATION:  # the run ended before this forecast's horizon did
            continue
        actual = first_snap_after(snaps, f.end, f.stamp)
        expected = 1.0 if actual is not None and actual.time <= f.stamp + horizon else 0.0
        assert f.probability == expected, (f, actual)
        if expected:
            assert f.stamp + f.time_to_snap == pytest.approx(actual.time, abs=time_tol)
            assert f.predicted_peak == pytest.approx(actual.peak_tension, rel=peak_rtol)
            checked += 1
    return checked


def test_exact_forecast_of_a_regular_wave_predicts_the_snaps_that_happen():
    cfg = regular_wave_case()
    snaps, forecasts = run(cfg)
    assert len([s for s in snaps if s.location == "vehicle"]) >= 3  # the case does snap, once per period
    ramp = cfg.motion.ramp_time
    assert len(forecasts) == 2 * int(DURATION - ramp)  # one per end per second, after the ramp-in
    assert min(f.stamp for f in forecasts) >= ramp
    assert all(f.members == 1 and f.source == "known_sea" and not f.degraded for f in forecasts)
    # the acceptance bound is 1 % and one tick; an exact forecast on the run's own tick grid repeats
    # the run, so it meets it with round-off to spare
    checked = check_against_run(snaps, forecasts, cfg.forecast.horizon, peak_rtol=1e-9, time_tol=1e-9)
    assert checked >= 20  # of the 35 forecasts per end after the ramp-in


def test_exact_forecast_on_a_coarser_command_grid_is_within_one_percent_and_one_tick():
    """Commanding the ship every 0.2 s instead of every 0.1 s (Hermite in between) is another run of
    the same sea: the acceptance bound holds (1 % of the peak, one tick of the node)."""
    cfg = regular_wave_case(command_rate=5.0)
    snaps, forecasts = run(cfg)
    checked = check_against_run(snaps, forecasts, cfg.forecast.horizon, peak_rtol=0.01, time_tol=1.0 / RATE)
    assert checked >= 20  # of the 35 forecasts per end after the ramp-in


def test_a_forecast_issued_inside_a_slack_period_continues_the_detector_state():
    """A forecast issued after the slack began (the run's detector is slack) still predicts the snap:
    the members continue the run's detector rather than starting a fresh one."""
    cfg = regular_wave_case()
    snaps, forecasts = run(cfg, duration=12.0)
    snap = first_snap_after(snaps, "vehicle", 0.0)
    inside = [f for f in forecasts if f.end == "vehicle" and snap.time - snap.slack_duration - snap.rise_time < f.stamp < snap.time]
    assert inside, "no forecast was issued inside the slack period"
    for f in inside:
        assert f.probability == 1.0 and f.stamp + f.time_to_snap == pytest.approx(snap.time, abs=1e-9)


def test_ensemble_members_spread_and_the_probability_counts_them():
    # unconditioned members (condition_time 0): in a regular wave the measured ship state determines the
    # one component, and conditioned members are all the truth (test_ship_forecast.py)
    cfg = regular_wave_case(members=6, sea_error=0.1, condition_time=0.0)
    snaps, forecasts = run(cfg, duration=8.0)
    vehicle = [f for f in forecasts if f.end == "vehicle" and f.probability > 0]
    assert vehicle
    for f in vehicle:
        assert f.members == 6
        assert f.probability == pytest.approx(len(f.member_snaps) / 6)
        times = [t - f.stamp for t, _ in f.member_snaps]
        if f.probability >= 0.5:  # the median of all six, those without a snap counted after the horizon
            assert f.time_to_snap == pytest.approx(ensemble_median_time(times, 6))
        else:
            assert math.isnan(f.time_to_snap)
        assert f.predicted_peak == pytest.approx(np.median([p for _, p in f.member_snaps]))
    assert any(f.time_to_snap_std > 0.0 for f in vehicle if len(f.member_snaps) > 1)


@pytest.mark.parametrize("condition_time", [0.0, 2.0])
def test_members_evaluated_a_horizon_at_once_give_the_forecasts_of_tick_by_tick(monkeypatch, condition_time):
    """The look-ahead evaluates a member's ship motion over the horizon at once where the member can
    (``at_many``); the forecasts are those of the tick-by-tick ``at`` (the plain twin), bit for bit."""
    from tether_sim.forecast.ship_forecast import ConditionedMember, MotionMember

    cfg = regular_wave_case(members=4, sea_error=0.1, condition_time=condition_time)
    fast = run(cfg, duration=8.0)[1]
    monkeypatch.delattr(MotionMember, "at_many")
    monkeypatch.delattr(ConditionedMember, "at_many")
    plain = run(cfg, duration=8.0)[1]
    key = lambda f: (f.stamp, f.end, f.probability, f.time_to_snap, f.predicted_peak, f.member_snaps, f.member_troughs)  # noqa: E731
    assert len(fast) == len(plain) >= 4
    assert [repr(key(f)) for f in fast] == [repr(key(f)) for f in plain]
    assert any(f.member_snaps for f in fast)


def test_ensemble_time_to_snap_counts_the_members_that_do_not_snap():
    """Five of eight members snap at 10..12 s: the ensemble's median snap time is 11.75 s (the 4th and
    5th of all eight), not 11 s (the median of the five, which ignores the three that snap later);
    with fewer than half snapping the median lies beyond the horizon (NaN); with exactly half, the
    last of them; with all snapping, the ordinary median."""
    times = [12.0, 10.0, 11.5, 10.5, 11.0]
    assert ensemble_median_time(times, 8) == pytest.approx(11.75)
    assert math.isnan(ensemble_median_time(times[:3], 8))
    assert ensemble_median_time(times[:4], 8) == pytest.approx(12.0)
    assert ensemble_median_time(times[:4], 4) == pytest.approx(np.median(times[:4]))
    assert ensemble_median_time([3.0], 1) == 3.0 and math.isnan(ensemble_median_time([], 1))
    assert math.isnan(ensemble_median_time([], 0))


def test_no_forecast_while_the_ship_motion_ramps_in():
    """The ramp-in is the simulation's start-up, not a sea: forecasts start when it has ended, and the
    status says why none was issued before."""
    cfg = regular_wave_case()
    src = {"ship": MotionSource(build_motion(cfg.motion, np.asarray(cfg.ship_end.position, float), wave_components(cfg)))}
    driver = SimulationDriver(cfg, src, start_blend=False)
    service = ForecastService(cfg)
    driver.start(0.0)
    ramp = cfg.motion.ramp_time
    for k in range(1, int(ramp * RATE)):
        driver.tick(k / RATE)
        service.observe(driver, clock_origin=0.0, tick_index=k)
    assert service.issued == 0 and not service.poll()
    assert "ramp-in" in service.last_status
    for k in range(int(ramp * RATE), int((ramp + 1.0) * RATE) + 1):
        driver.tick(k / RATE)
        service.observe(driver, clock_origin=0.0, tick_index=k)
    got = service.poll()
    assert service.issued == 1 and len(got) == 2 and got[0].stamp >= ramp


def test_threaded_service_gives_the_inline_forecasts():
    """The node's worker thread computes the same forecasts (the tick only hands over a snapshot)."""
    import time

    cfg = regular_wave_case()
    src = {"ship": MotionSource(build_motion(cfg.motion, np.asarray(cfg.ship_end.position, float), wave_components(cfg)))}
    driver = SimulationDriver(cfg, src, start_blend=False)
    service = ForecastService(cfg, threaded=True)
    driver.start(0.0)
    got = []
    try:
        for k in range(1, int(8 * RATE) + 1):
            driver.tick(k / RATE)
            service.observe(driver, clock_origin=0.0, tick_index=k)
            got += service.poll()
            deadline = time.monotonic() + 30.0
            while service._busy and time.monotonic() < deadline:  # lock-step here, so nothing is skipped
                time.sleep(0.005)
        got += service.poll()
    finally:
        service.close()
    _, inline = run(cfg, duration=8.0)
    assert service.skipped == 0 and len(got) == len(inline) == 6  # stamped 5.1, 6.1, 7.1 s (after the ramp-in)
    for a, b in zip(got, inline):
        assert (a.stamp, a.end, a.probability) == (b.stamp, b.end, b.probability)
        assert a.time_to_snap == b.time_to_snap or (math.isnan(a.time_to_snap) and math.isnan(b.time_to_snap))


def test_missing_ship_motion_forecast_is_degraded_with_the_reason():
    """source external without an external forecast falls back to the pose predictor (degraded, saying
    why); with too little pose history there is no forecast at all: no members, NaN, the reason."""
    cfg = regular_wave_case(source="external", ar_order=10, ar_sample_period=0.5)
    src = {"ship": MotionSource(build_motion(cfg.motion, np.asarray(cfg.ship_end.position, float), wave_components(cfg)))}
    driver = SimulationDriver(cfg, src, start_blend=False)
    service = ForecastService(cfg)
    driver.start(0.0)
    out = []
    for k in range(1, int(25 * RATE) + 1):
        driver.tick(k / RATE)
        service.observe(driver, clock_origin=0.0, tick_index=k)
        out += service.poll()
    early = [f for f in out if f.stamp < 19.9]  # 4 x 10 x 0.5 s = 20 s of history needed
    late = [f for f in out if f.stamp > 20.1]
    assert early and late
    for f in early:
        assert f.degraded and f.members == 0 and math.isnan(f.probability)
        assert "no ship-motion forecast: pose history" in f.reason
    for f in late:
        assert f.degraded and f.members == 1 and f.source == "poses" and 0.0 <= f.probability <= 1.0
        assert "no external forecast received" in f.reason


def test_forecast_with_a_winch_is_refused():
    cfg = regular_wave_case()
    cfg = replace(cfg, winch=replace(cfg.winch, enabled=True))
    with pytest.raises(ValueError, match="winch.enabled"):
        ForecastService(cfg)


def test_exact_forecast_member_trough_is_the_runs_least_tension_within_the_horizon():
    """Each member reports its least end tension within the horizon (the ensemble's spread against the
    slack level, benchmarks/forecast_skill.py --near-misses); an exact forecast's is the run's own."""
    cfg = regular_wave_case(horizon=4.0)
    src = {"ship": MotionSource(build_motion(cfg.motion, np.asarray(cfg.ship_end.position, float), wave_components(cfg)))}
    driver = SimulationDriver(cfg, src, start_blend=False)
    service = ForecastService(cfg)
    driver.start(0.0)
    samples, drain = [], driver.solver.drain_end_tensions

    def recording_drain():
        out = drain()
        samples.append((np.asarray(out[0]) + driver.anchor, np.asarray(out[1]), np.asarray(out[2])))
        return out

    driver.solver.drain_end_tensions = recording_drain
    duration, forecasts = 12.0, []
    for k in range(1, int(duration * RATE) + 1):
        driver.tick(k / RATE)
        service.observe(driver, clock_origin=0.0, tick_index=k)
        forecasts += service.poll()
    t = np.concatenate([a for a, _, _ in samples])
    tension = {"ship": np.concatenate([b for _, b, _ in samples]), "vehicle": np.concatenate([c for _, _, c in samples])}
    checked = 0
    for f in forecasts:
        if f.stamp + f.horizon > duration:
            continue
        inside = (t > f.stamp - 1e-9) & (t < f.stamp + f.horizon - 1e-9)  # a sample's time: its substep's start
        assert len(f.member_troughs) == 1
        assert f.member_troughs[0] == pytest.approx(tension[f.end][inside].min(), rel=1e-9, abs=1e-6)
        checked += 1
    assert checked >= 6


def test_exact_forecast_member_depth_is_the_runs_least_tension_before_the_snap_and_the_margin_keeps_deep_slack():
    """Each snapping member reports its least end tension from the stamp to its snap's peak
    (member_slack_depths, NaN without a snap); an exact forecast's is the run's own. With
    forecast.slack_margin a member's snap counts only when that depth lies below (1 - margin) x the
    slack level (unless the end was already slack at the stamp): the same forecasts as the margin
    applied to the raw ones (deep_snaps); the regular wave's snaps, after a deep slack, are kept."""
    from tether_sim.forecast.lookahead import deep_snaps

    results = {}
    for margin in (0.0, 0.5):
        cfg = regular_wave_case(horizon=4.0, slack_margin=margin)
        src = {"ship": MotionSource(build_motion(cfg.motion, np.asarray(cfg.ship_end.position, float), wave_components(cfg)))}
        driver = SimulationDriver(cfg, src, start_blend=False)
        service = ForecastService(cfg)
        driver.start(0.0)
        samples, drain = [], driver.solver.drain_end_tensions

        def recording_drain(drain=drain, samples=samples, driver=driver):
            out = drain()
            samples.append((np.asarray(out[0]) + driver.anchor, np.asarray(out[1]), np.asarray(out[2])))
            return out

        driver.solver.drain_end_tensions = recording_drain
        forecasts = []
        for k in range(1, int(12.0 * RATE) + 1):
            driver.tick(k / RATE)
            service.observe(driver, clock_origin=0.0, tick_index=k)
            forecasts += service.poll()
        slack = dict(zip(driver.detector.locations, driver.detector.thresholds))
        results[margin] = (forecasts, samples, slack)
    raw, samples, slack = results[0.0]
    t = np.concatenate([a for a, _, _ in samples])
    tension = {"ship": np.concatenate([b for _, b, _ in samples]), "vehicle": np.concatenate([c for _, _, c in samples])}
    snapping = 0
    for f in raw:
        (depth,) = f.member_slack_depths
        if not f.member_snaps:
            assert math.isnan(depth)
            continue
        (peak_time, _), = f.member_snaps
        before = (t > f.stamp - 1e-9) & (t <= peak_time + 1e-12)
        assert depth == pytest.approx(tension[f.end][before].min(), rel=1e-9, abs=1e-6)
        snapping += 1
    assert snapping >= 4
    kept = 0
    for f, g in zip(raw, results[0.5][0]):
        assert (f.stamp, f.end, f.member_troughs) == (g.stamp, g.end, g.member_troughs)
        expected = f.member_snaps if f.slack_at_stamp else deep_snaps(f.member_snaps, f.member_slack_depths, slack[f.end], 0.5)
        assert g.member_snaps == expected and g.probability == len(expected)
        kept += bool(f.member_snaps and expected)
    assert kept >= 1  # the regular wave's snaps follow a deep slack (the cage's end tension near zero)


def test_deep_snaps_counts_the_members_below_the_margin():
    from tether_sim.forecast.lookahead import deep_snaps

    snaps = [(1.0, 10.0), (2.0, 11.0), (3.0, 12.0)]
    depths = [0.0, math.nan, 80.0, 69.0, math.nan]  # per finished member; NaN: no snap
    assert deep_snaps(snaps, depths, 100.0, 0.3) == [(1.0, 10.0), (3.0, 12.0)]
    assert deep_snaps(snaps, depths, 100.0, 0.0) == snaps
    with pytest.raises(ValueError):
        deep_snaps(snaps, depths[:2], 100.0, 0.3)


def test_tension_history_folds_old_ticks_without_changing_the_least_tension_before_a_peak():
    """The look-ahead's tension history keeps only the ticks within ``keep`` s of the newest sample and
    folds the older ones into a least tension per end: the least tension up to any time inside the
    kept span is the minimum over every sample up to it, as over the whole history."""
    from tether_sim.forecast.lookahead import _History

    rng = np.random.default_rng(3)
    tick, substeps, keep = 0.1, 7, 1.2
    history = _History(keep)
    clocks, tensions = [], []
    for k in range(200):
        clock = k * tick + np.arange(1, substeps + 1) * tick / substeps
        chunk = rng.uniform(-50.0, 500.0, size=(substeps, 2))
        history.append(clock, chunk)
        clocks.append(clock)
        tensions.append(chunk)
        every_t, every = np.concatenate(clocks), np.concatenate(tensions)
        for until in (clock[-1], clock[0] - 0.5 * keep, clock[-1] - keep + 1e-9):
            for column in (0, 1):
                upto = every[every_t <= until + 1e-12, column]
                assert history.least_before(column, until) == (upto.min() if upto.size else math.inf)
    assert len(history.chunks) <= math.ceil(keep / tick) + 1  # bounded, not the whole run
    with pytest.raises(ValueError):  # a peak before the folded ticks cannot be answered exactly
        history.least_before(0, 0.5)


def test_perfect_member_in_an_irregular_sea_repeats_the_run():
    """The perfect member: a look-ahead driven by the run's own ship motion, with no forecast error,
    restarted from the run's state, repeats the run. In a JONSWAP sea through the RAO table (Hs 7.5 m:
    the cage end goes slack and snaps; waves on the ship only, as in benchmarks/forecast_skill.py), at the
    node's 50 Hz on the node's own command grid its end tensions are the run's bit for bit over every
    horizon; on a 10 Hz command grid (the skill benchmark's) its least tension within the horizon is the
    run's within 0.02 slack levels (0.008 measured here, 0.015 on 15 min of the benchmark's Hs 3 m sea:
    benchmarks/forecast_perfect_member.py). Any difference of physics or set-up between the look-ahead
    and the run (mesh, step, an end's motion, the state copied, the start) would show here."""
    from tether_sim.forecast.lookahead import LookAhead
    from tether_sim.solvers.factory import build_solver

    rate, duration, horizon = 50.0, 40.0, 10.0
    over = {"waves.seed": 21, "waves.Hs": 7.5, "motion.ramp_time": 5.0, "forecast.members": 1, "forecast.sea_error": 0.0,
            "forecast.horizon": horizon, "forecast.rate": 1.0, "node.output_rate": rate}
    cfg = load_config("config/ropos_aframe_jonswap.yaml", over)
    cfg = replace(cfg, node=replace(cfg.node, max_lag=math.inf, input_delay=0.0))
    src = {"ship": MotionSource(build_motion(cfg.motion, np.asarray(cfg.ship_end.position, float), wave_components(cfg)))}
    cfg = replace(cfg, waves=replace(cfg.waves, kind="none"))
    driver = SimulationDriver(cfg, src, start_blend=False)
    driver.start(0.0)
    samples, drain = [], driver.solver.drain_end_tensions

    def recording_drain():
        out = drain()
        samples.append((np.asarray(out[0]) + driver.anchor, np.array(out[1]), np.array(out[2])))
        return out

    driver.solver.drain_end_tensions = recording_drain
    services = {}
    for command_rate in (0.0, 10.0):
        c = replace(cfg, forecast=replace(cfg.forecast, command_rate=command_rate))
        service, engine = ForecastService(c), LookAhead(replace(driver._solver_config, forecast=c.forecast), build_solver)
        trace, tick = [], engine.solver.tick

        def recording_tick(t, ship=None, vehicle=None, drain=True, _tick=tick, _trace=trace):
            out = _tick(t, ship=ship, vehicle=vehicle, drain=drain)
            if out.count:
                _trace.append((np.array(out.times) + driver.anchor, np.column_stack([out.ship_tension, out.vehicle_tension])))
            return out

        engine.solver.tick = recording_tick
        service._engine = engine
        services[command_rate] = (service, trace, [])
    for k in range(1, int(duration * rate) + 1):
        driver.tick(k / rate)
        for service, trace, members in services.values():
            trace.clear()
            done = service.completed
            service.observe(driver, clock_origin=0.0, tick_index=k)
            if service.completed > done:
                members.append((np.concatenate([a for a, _ in trace]), np.vstack([b for _, b in trace]),
                                {f.end: f for f in service.poll()}))
    t = np.concatenate([a for a, _, _ in samples])
    run = np.column_stack([np.concatenate([b for _, b, _ in samples]), np.concatenate([c for _, _, c in samples])])
    slack = np.asarray(driver.detector.thresholds, float)
    assert run[:, 1].min() < 1e-6 * slack[1]  # the sea makes the cage end slack: the case tests what matters
    for command_rate, (_, _, members) in services.items():
        checked = 0
        for mt, mT, fc in members:
            stamp = fc["ship"].stamp
            if stamp + horizon > duration:
                continue
            mine, runs = (mt > stamp - 1e-9) & (mt < stamp + horizon - 1e-9), (t > stamp - 1e-9) & (t < stamp + horizon - 1e-9)
            if command_rate == 0.0:
                assert np.array_equal(mt[mine], t[runs]) and np.array_equal(mT[mine], run[runs]), stamp
            for j, end in enumerate(("ship", "vehicle")):
                error = abs(fc[end].member_troughs[0] - run[runs, j].min()) / slack[j]
                assert error <= (0.0 if command_rate == 0.0 else 0.02), (command_rate, stamp, end, error)
            checked += 1
        assert checked >= 20


def test_a_staged_snap_is_reported_at_its_episode_maximum(monkeypatch):
    """A re-tensioning in two stages (the cage bouncing on the tether): the detector publishes the first
    stage (150 N at 2.5 s, a window old before the second passes it) and then the second, larger peak as
    the snap's new maximum (180 N at 4.6 s, after the 4 s horizon). The member's snap counts (its first
    event lies within the horizon) and is reported at the maximum, as the run's snaps are scored
    (episode_maxima); the first stage is kept beside it."""
    from types import SimpleNamespace as NS

    import tether_sim.forecast.lookahead as la
    from tether_sim.physics.snap import SnapConfig, SnapDetector, episode_maxima

    knots = np.array([(0.0, 100.0), (0.5, 100.0), (1.0, 0.0), (2.0, 0.0), (2.5, 150.0), (3.2, 120.0), (3.6, 120.0),
                      (4.6, 180.0), (5.5, 100.0), (60.0, 100.0)])
    vehicle = lambda t: np.interp(t, knots[:, 0], knots[:, 1])  # noqa: E731

    class Solver:  # end tensions of every 1 ms substep
        time = 0.0

        def restore(self, snapshot):
            self.time = snapshot

        def drain_end_tensions(self):
            return None

        def tick(self, t, ship=None, vehicle=None):
            times = np.arange(self.time + 1e-3, t + 1e-12, 1e-3)
            self.time = t
            return NS(count=times.size, times=times, ship_tension=np.full(times.size, 100.0), vehicle_tension=vehicle_of(times))

    vehicle_of = vehicle
    monkeypatch.setattr(la, "relative_end_speed", lambda solver, length: 0.0)
    config = NS(ship_end=NS(kind="prescribed"), vehicle_end=NS(kind="body"), cable=NS(length=100.0), forecast=NS(slack_margin=0.0))
    engine = la.LookAhead(config, lambda cfg: Solver())
    detector = SnapDetector(SnapConfig(), ["ship", "vehicle"], [100.0, 100.0], [0.0, 100.0])
    member = NS(at=lambda t: (np.zeros(3), np.zeros(3)))
    request = la.ForecastRequest(issued=0.0, solver_time=0.0, anchor=0.0, snapshot=0.0, detector=detector, end_state={},
                                 members=[member], horizon=4.0, tick=0.1, source="test")
    ship, veh = engine.run(request)
    assert ship.probability == 0.0
    assert veh.probability == 1.0
    assert veh.member_first_stages == [(pytest.approx(2.5), pytest.approx(150.0))]
    assert veh.member_snaps == [(pytest.approx(4.6), pytest.approx(180.0))]
    assert veh.time_to_snap == pytest.approx(4.6) and veh.predicted_peak == pytest.approx(180.0)
    # the run's own detector on the same tensions: one episode, its maximum is the forecast's snap
    run = SnapDetector(SnapConfig(), ["ship", "vehicle"], [100.0, 100.0], [0.0, 100.0])
    t = np.arange(1e-3, 12.0, 1e-3)
    events = [e for e in run.update(t, np.column_stack([np.full(t.size, 100.0), vehicle(t)]), 0.0) if hasattr(e, "peak_tension")]
    assert [round(e.time, 6) for e in events] == [2.5, 4.6]
    (best,) = episode_maxima(events)
    assert (best.time, best.peak_tension) == (pytest.approx(veh.member_snaps[0][0]), pytest.approx(veh.member_snaps[0][1]))
    # a horizon that ends before the first stage: no snap
    ship, veh = engine.run(replace(request, horizon=2.0))
    assert veh.probability == 0.0 and veh.member_snaps == []
