"""Skill of the snap forecast (docs/forecast.md) on seeded JONSWAP seas, the ship through the RAO table.

For each live file (default: the 1730 m and 200 m ROPOS files) and each ship-motion forecast source,
the run is simulated as the offline runner does (driver + forecast service, inline, on the run's tick
grid) and every forecast is scored against the snaps the run reports (tether_sim.forecast.skill): a
snap is warned when a forecast with probability >= 0.5 stamped >= ``--lead`` s before it predicted it
within +-1.5 s; a false alarm is such a forecast with no snap within +-1.5 s of its predicted time. Every
figure is also given at the alarm threshold ``--warn-probability`` (forecast.warn_probability, 0.75).

The sea (both files): JONSWAP Hs, Tp (``--hs``, ``--tp``), gamma 3.3, waves from 15 deg off the port
bow, 40 frequencies, short-crested (cos-2s, s = 6, ``--directions`` 5) or long-crested (1), seeds ``--seeds``; the fairlead on
the A-frame 35 m aft of the ship's reference point and 5 m up (config/ropos_aframe_jonswap.yaml's
ship), the motion ramped in over 30 s; waves act on the cable as well. Sources:

- ``known_sea``: the run's sea, each forecast's nominal sea in error by ``--nominal-error`` x Hs
  (a fresh draw per forecast, as a real sea-wave forecast would be), members spread by
  ``--sea-error`` x Hs about it;
- ``poses``: the autoregressive predictor on the fairlead history (no knowledge of the sea).

Usage (the figures of BENCHMARKS.md and docs/forecast.md):

    .venv/bin/python benchmarks/forecast_skill.py --minutes 10 --seeds 1 2 3
    .venv/bin/python benchmarks/forecast_skill.py --files config/ropos_L200.yaml --sources poses --minutes 5

Prints one line per (file, source, seed) and the totals; ``--json`` writes every number.
``--rescore`` scores the forecasts of ``--dump`` files again without running anything: totals at
several probability thresholds, the reliability of the probability (binned against the frequency of
a snap within the horizon), and the snap time as it was estimated before 2026-11-27 for comparison;
with ``--near-misses`` it runs each sea again without forecasts and sets every false-alarm episode
against the run's own end tension (a peak at the snap level at the predicted time? slack before it?).
"""

import argparse
import json
import math
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from tether_sim.forecast.service import ForecastService  # noqa: E402
from tether_sim.forecast.skill import (  # noqa: E402
    TIE_TOLERANCE, episode_snaps, fraction_interval, rate_interval, reliability, score, trough_rank,
)
from tether_sim.io.params import load_config  # noqa: E402
from tether_sim.physics.motion import build_motion  # noqa: E402
from tether_sim.physics.snap import SlackStarted, SnapEvent  # noqa: E402
from tether_sim.physics.waves import wave_components  # noqa: E402
from tether_sim.ros.driver import MotionSource, SimulationDriver  # noqa: E402


def case_config(path, source, seed, args):
    over = {"motion.kind": "rao", "motion.rao_path": "config/rao_support_vessel_80m.txt",
            "motion.rao_lever_arm": [-35.0, 0.0, 5.0], "motion.ship_heading": 0.0, "motion.ramp_time": 30.0,
            "waves.kind": "jonswap", "waves.Hs": args.hs, "waves.Tp": args.tp, "waves.gamma": 3.3,
            "waves.direction": 195.0, "waves.n_frequencies": 40, "waves.n_directions": args.directions, "waves.spreading": 6.0,
            "waves.seed": seed, "forecast.enabled": True, "forecast.source": source,
            "forecast.horizon": args.horizon, "forecast.rate": args.rate, "forecast.members": args.members,
            "forecast.sea_error": args.sea_error, "forecast.command_rate": args.command_rate,
            "forecast.seed": 1000 * seed}
    cfg = load_config(str(ROOT / path), over)
    return replace(cfg, node=replace(cfg.node, max_lag=math.inf, input_delay=0.0))


def run_case(cfgs, minutes, nominal_error, cable_waves=True, covariance=True):
    """One run of the sea of ``cfgs`` (one configuration per forecast source, the same sea) with a
    forecast service per source observing the same driver (the truth run is shared by the sources):
    (snaps [(end, time, event times)]: one per slack episode, tether_sim.forecast.skill.episode_snaps; {source:
    forecasts}, wall s, {source: look-ahead wall s}, simulated s).
    ``cable_waves=False``: the waves move the ship (RAO) but do not act on the cable (still water)."""
    cfg = cfgs[0]
    src = {"ship": MotionSource(build_motion(cfg.motion, np.asarray(cfg.ship_end.position, float), wave_components(cfg)))}
    if not cable_waves:
        cfg = replace(cfg, waves=replace(cfg.waves, kind="none"))
    driver = SimulationDriver(cfg, src, start_blend=False)
    services = {c.forecast.source: ForecastService(c, nominal_error=nominal_error if c.forecast.source == "known_sea" else 0.0,
                                                   covariance=covariance)
                for c in cfgs}
    driver.start(0.0)
    rate = cfg.node.output_rate
    events, slacks = [], []
    forecasts = {name: [] for name in services}
    look = {name: 0.0 for name in services}
    cpu = {"truth run": 0.0, **{f"look-ahead {name}": 0.0 for name in services}}
    wall0 = time.perf_counter()
    for k in range(1, int(round(minutes * 60.0 * rate)) + 1):
        c0 = time.thread_time()
        report = driver.tick(k / rate)
        events += [e for e in report.events if isinstance(e, SnapEvent)]
        slacks += [(e.location, e.time) for e in report.events if isinstance(e, SlackStarted)]
        cpu["truth run"] += time.thread_time() - c0
        for name, service in services.items():
            c0 = time.thread_time()
            done = service.completed
            service.observe(driver, clock_origin=0.0, tick_index=k)
            if service.completed > done:
                look[name] += service.last_wall
            forecasts[name] += service.poll()
            cpu[f"look-ahead {name}"] += time.thread_time() - c0
    events += [e for e in driver.detector.flush() if isinstance(e, SnapEvent)]
    snaps = episode_snaps(events)  # an episode once (its new maxima are no further snaps)
    run_case.snap_events = [(e.location, e.time, e.peak_tension, e.slack_start) for e in events]
    run_case.slacks = slacks  # slack periods begun (for --dump)
    run_case.slack_levels = dict(zip(driver.detector.locations, (float(x) for x in driver.detector.thresholds)))
    run_case.cpu = cpu  # CPU s of this thread: the truth run, each source's forecasts (tick side and look-ahead)
    return snaps, forecasts, time.perf_counter() - wall0, look, driver.solver.time


class CpuSplit:
    """``--cpu-split``: where the look-aheads spend their CPU (thread CPU s): the members' ship motion, the
    solver's ticks, the relative end speed for the snap guard, the snap detector, and the rest (building
    the members, copying the state, the loop itself). Wraps those calls while a look-ahead runs (the truth
    run's own calls are not counted); the wrappers cost a few per cent."""

    def __init__(self):
        import tether_sim.forecast.lookahead as la
        from tether_sim.physics.snap import SnapDetector

        self.cpu = {"motion": 0.0, "solver tick": 0.0, "relative end speed": 0.0, "snap detector": 0.0, "look-ahead total": 0.0}
        self.active = False
        split = self

        def timed(fn, key):
            def wrapper(*a, **kw):
                if not split.active:
                    return fn(*a, **kw)
                c0 = time.thread_time()
                try:
                    return fn(*a, **kw)
                finally:
                    split.cpu[key] += time.thread_time() - c0
            return wrapper

        run = la.LookAhead.run

        def timed_run(engine, request):
            if not getattr(engine, "_split_wrapped", False):
                engine.solver.tick = timed(engine.solver.tick, "solver tick")
                engine._split_wrapped = True
            split.active = True
            c0 = time.thread_time()
            try:
                return run(engine, request)
            finally:
                split.cpu["look-ahead total"] += time.thread_time() - c0
                split.active = False

        la.LookAhead.run = timed_run
        la._ShipPlan.at = timed(la._ShipPlan.at, "motion")
        la.relative_end_speed = timed(la.relative_end_speed, "relative end speed")
        SnapDetector.update = timed(SnapDetector.update, "snap detector")

    def report(self):
        total = self.cpu["look-ahead total"]
        parts = {k: v for k, v in self.cpu.items() if k != "look-ahead total"}
        parts["rest"] = total - sum(parts.values())
        return f"look-ahead CPU {total:.1f} s: " + ", ".join(f"{k} {v:.1f} s ({100 * v / max(total, 1e-9):.0f} %)"
                                                              for k, v in parts.items())


def truth_tensions(path, seed, dumped_args, at_stamp=None, events=None):
    """The run of a --dump file again, without forecasts, recording the end tensions of every substep:
    (times, {end: tensions}, {end: slack level N}, {end: snap level N}); ``at_stamp`` (a dict): filled
    with {tick index: {end: the end slack or re-tensioning after that tick}} (the run's detector, what a
    forecast stamped at that tick reports as ``slack_at_stamp``); ``events`` (a list): filled with every
    SnapEvent the run's detector publishes, its flush at the end included."""
    args = argparse.Namespace(**dumped_args)
    cfg = case_config(path, "known_sea", seed, args)
    src = {"ship": MotionSource(build_motion(cfg.motion, np.asarray(cfg.ship_end.position, float), wave_components(cfg)))}
    if not args.cable_waves:
        cfg = replace(cfg, waves=replace(cfg.waves, kind="none"))
    driver = SimulationDriver(cfg, src, start_blend=False)
    driver.start(0.0)
    samples = []
    drain = driver.solver.drain_end_tensions

    def recording_drain():
        out = drain()
        samples.append((np.asarray(out[0]) + driver.anchor, np.asarray(out[1]), np.asarray(out[2])))
        return out

    driver.solver.drain_end_tensions = recording_drain
    rate = cfg.node.output_rate
    for k in range(1, int(round(args.minutes * 60.0 * rate)) + 1):
        report = driver.tick(k / rate)
        if events is not None:
            events += [e for e in report.events if isinstance(e, SnapEvent)]
        if at_stamp is not None:
            flags = driver.detector.is_slack() | driver.detector.is_rising()
            at_stamp[k] = {end: bool(x) for end, x in zip(driver.detector.locations, flags)}
    if events is not None:
        events += [e for e in driver.detector.flush() if isinstance(e, SnapEvent)]
    det, snap = driver.detector, cfg.snap
    snap_levels = (np.full(2, snap.snap_threshold) if snap.snap_threshold > 0.0
                   else snap.snap_fraction * np.abs(det.static_tensions))
    t = np.concatenate([a for a, _, _ in samples])
    tensions = {"ship": np.concatenate([b for _, b, _ in samples]), "vehicle": np.concatenate([c for _, _, c in samples])}
    return t, tensions, dict(zip(det.locations, det.thresholds)), dict(zip(det.locations, snap_levels))


def motion_error(args) -> int:
    """The known sea's members against the truth, the fairlead's motion only (no cable; cheap): for
    forecasts stamped every 5 s of each seed's sea after the ramp, the rms of (member - truth) of the
    fairlead's heave (per cent of Hs) and of its vertical acceleration, and the members' rms vertical
    acceleration against the truth's, by lead time; members conditioned on the measured state by the
    covariance of the sea (as the forecast does) and by the exponential fade alone (as before
    2026-11-27), the same draws for both."""
    from tether_sim.forecast.ship_forecast import component_spread, perturb_motion, perturbed_members

    leads = np.arange(0.0, args.horizon + 1e-9, 0.25)
    h = 1e-3
    for path in args.files:
        stats = {}
        for seed in args.seeds:
            cfg = case_config(path, "known_sea", seed, args)
            truth = build_motion(cfg.motion, np.asarray(cfg.ship_end.position, float), wave_components(cfg))
            hs = cfg.waves.Hs
            stamps = np.arange(cfg.motion.ramp_time + 10.0, args.minutes * 60.0 - args.horizon, 5.0)
            heave = np.array([truth.at(t)[0][2] for t in np.arange(stamps[0], stamps[-1], 0.5)])
            print(f"{Path(path).stem} seed {seed}: the fairlead's heave 4 x rms = {4.0 * heave.std():.2f} m (Hs {hs:g} m)", flush=True)
            for covariance in (True, False):
                rng = np.random.default_rng(1000 * seed)
                err_z, err_a, acc_m, acc_t = (np.zeros(leads.size) for _ in range(4))
                n = 0
                for t0 in stamps:
                    p0, v0 = truth.at(t0)[:2]
                    nominal = perturb_motion(truth, component_spread(args.nominal_error), rng)
                    members = perturbed_members(nominal, 0.0, args.members, args.sea_error, rng, True,
                                                (t0, p0, v0, 2.0), True, covariance=covariance)
                    tt = t0 + leads
                    truth_z = np.array([truth.at(t)[0][2] for t in tt])
                    truth_a = np.array([truth.at(t)[2][2] for t in tt])
                    for m in members:
                        z = np.array([m.at(t)[0][2] for t in tt])
                        a = np.array([(m.at(t + h)[1][2] - m.at(t - h)[1][2]) / (2 * h) for t in tt])
                        err_z += (z - truth_z) ** 2
                        err_a += (a - truth_a) ** 2
                        acc_m += a ** 2
                        acc_t += truth_a ** 2
                        n += 1
                key = "covariance" if covariance else "exponential fade"
                prev = stats.get(key, (np.zeros(leads.size),) * 4 + (0,))
                stats[key] = (prev[0] + err_z, prev[1] + err_a, prev[2] + acc_m, prev[3] + acc_t, prev[4] + n)
        print(f"\n{Path(path).stem}, seeds {args.seeds}, {args.minutes:g} min each, members {args.members}, nominal error "
              f"{args.nominal_error:g} Hs, spread {args.sea_error:g} Hs (Hs {args.hs:g} m): member - truth, fairlead")
        print("  lead s | heave error % Hs: covariance, fade | accel error m/s^2: covariance, fade | "
              "member / truth rms accel: covariance, fade")
        for i, lead in enumerate(leads):
            if abs(lead - round(lead)) > 1e-9:
                continue
            row = []
            for key in ("covariance", "exponential fade"):
                ez, ea, am, at, n = stats[key]
                row.append((100.0 * math.sqrt(ez[i] / n) / args.hs, math.sqrt(ea[i] / n), math.sqrt(am[i] / max(at[i], 1e-30))))
            print(f"  {lead:5.1f} | {row[0][0]:5.1f} {row[1][0]:5.1f} | {row[0][1]:5.3f} {row[1][1]:5.3f} | "
                  f"{row[0][2]:5.3f} {row[1][2]:5.3f}")
    return 0


def near_misses(paths, tolerance=1.5, before=6.0, margin=0.0) -> int:
    """Every false-alarm episode of --dump files against the run's own end tension (the run again,
    without forecasts): the largest tension within +-``tolerance`` of the predicted time, the least in
    the ``before`` s before it, and what the snap detector made of it; ``margin`` > 0: of the forecasts
    with forecast.slack_margin = margin (with_margin)."""
    for path in paths:
        doc = json.loads(Path(path).read_text())
        for run in doc["runs"]:
            t, tensions, slack, level = truth_tensions(run["file"], run["seed"], doc["args"])
            end_time = doc["args"]["minutes"] * 60.0
            horizon = doc["args"]["horizon"]
            for source, fc in run["forecasts"].items():
                if margin > 0.0:
                    levels = run_slack_levels(run, doc["args"])
                    fc = [[g.end, g.stamp, g.probability, g.time_to_snap, g.members, g.member_snaps, *f[6:]]
                          for f, g in ((f, with_margin(f, horizon, source, levels, margin)) for f in fc)]
                classes, last = {}, {}
                print(f"\n{Path(run['file']).stem} {source} seed {run['seed']}: false-alarm episodes against the run's tension"
                      + (f" (slack margin {margin:g})" if margin > 0.0 else ""))
                for end, stamp, p, tts, members, _, *troughs in fc:
                    pred = stamp + tts
                    if not p >= 0.5 or pred > end_time - tolerance or any(
                            e == end and abs(pred - x) <= tolerance for e, x, *_ in run["snaps"]):
                        continue
                    if end in last and abs(pred - last[end]) <= tolerance:
                        last[end] = pred
                        continue  # the same episode
                    last[end] = pred
                    T = tensions[end]
                    peak = T[(t >= pred - tolerance) & (t <= pred + tolerance)].max()
                    trough = T[(t >= pred - before) & (t <= pred)].min()
                    near = min((abs(pred - x) for e, x, *_ in run["snaps"] if e == end), default=math.inf)
                    if near <= 2.0 * tolerance:
                        kind = f"timing: the run's snap within {2.0 * tolerance:g} s"
                    elif peak < level[end]:
                        kind = "no peak at the snap level"
                    elif trough >= slack[end]:
                        kind = "peak >= snap level, no slack before it"
                    else:
                        kind = "slack and a peak >= snap level, no snap reported"
                    classes[kind] = classes.get(kind, 0) + 1
                    print(f"  {end:7s} stamp {stamp:6.1f} p {p:.3f} predicted {pred:7.2f} s: run's peak {peak / level[end]:.2f} x the snap "
                          f"level, least tension in the {before:g} s before {trough / slack[end]:.2f} x the slack level: {kind}")
                    if troughs and troughs[0]:
                        horizon_trough = T[(t > stamp - 1e-9) & (t < stamp + horizon - 1e-9)].min()
                        print(f"          least tension within the horizon / slack level: run {horizon_trough / slack[end]:.2f}, "
                              f"members " + " ".join(f"{x / slack[end]:.2f}" for x in sorted(troughs[0])))
                    if len(troughs) > 1 and troughs[1]:
                        deep = sorted(x / slack[end] for x in troughs[1] if x is not None and not math.isnan(x))
                        print("          snapping members' least tension before the snap / slack level (as run): "
                              + " ".join(f"{x:.2f}" for x in deep))
                print("  episodes: " + ", ".join(f"{n} {k}" for k, n in sorted(classes.items())))
                ranks(fc, t, tensions, slack, horizon, end_time)
    return 0


def ranks(fc, t, tensions, slack, horizon, end_time):
    """The ensemble's spread against the run, per end: for every forecast with members' troughs (the least
    end tension of each member within the horizon) and a horizon inside the run, the rank of the run's own
    trough among the members' (a rank histogram: flat when the run is as likely anywhere in the ensemble
    as a member, U-shaped when the ensemble is too narrow, peaked in the middle when it is too wide), and,
    near the slack level (the run's trough within 2 x it), the fraction of members on the other side of it
    from the run."""
    for end in ("ship", "vehicle"):
        hist, wrong, near = None, [], 0
        for e, stamp, p, tts, members, _, *troughs in fc:
            if e != end or not troughs or not troughs[0] or stamp + horizon > end_time:
                continue
            m = np.asarray(troughs[0], float)
            truth = tensions[end][(t > stamp - 1e-9) & (t < stamp + horizon - 1e-9)].min()
            if hist is None:
                hist = np.zeros(m.size + 1)
            if m.size + 1 == hist.size:  # ties (round-off in slack, a trough at the stamp) spread over their ranks
                hist += trough_rank(m, truth, TIE_TOLERANCE * slack[end])
            if truth < 2.0 * slack[end]:
                near += 1
                wrong.append(float(np.mean((m < slack[end]) != (truth < slack[end]))))
        if hist is None:
            continue
        print(f"  {end}: rank of the run's least tension within the horizon among the members' (0: below all; ties "
              f"spread over their ranks): " + " ".join(f"{x:.1f}" for x in hist) + f"; {near} forecasts with the run's trough below 2 x the slack level: "
              f"{100 * np.mean(wrong) if wrong else float('nan'):.0f} % of their members on the other side of the slack level")


def fill_at_stamp(paths) -> int:
    """Dumps from before 2026-11-28 lack each forecast's ``slack_at_stamp``: run each sea again without
    forecasts, take the run's detector after the forecast's tick, and write ``<dump>_atstamp.json`` with
    it (the members' depths, absent, left None: with_margin then approximates them). Where a dump has the
    flags, they are checked against the rerun instead (the count of forecasts that differ is printed)."""
    for path in paths:
        doc = json.loads(Path(path).read_text())
        for run in doc["runs"]:
            flags = {}
            truth_tensions(run["file"], run["seed"], doc["args"], at_stamp=flags)
            cfg = case_config(run["file"], "known_sea", run["seed"], argparse.Namespace(**doc["args"]))
            out_rate = cfg.node.output_rate
            checked = differ = filled = 0
            for source, fc in run["forecasts"].items():
                for i, f in enumerate(fc):
                    k = int(round(f[1] * out_rate))
                    if abs(k / out_rate - f[1]) > 1e-6 or k not in flags:
                        raise ValueError(f"forecast stamp {f[1]} s is not on the tick grid of the rerun")
                    flag = flags[k][f[0]]
                    if len(f) > 8:
                        checked += 1
                        differ += bool(f[8]) != flag
                    else:
                        fc[i] = list(f[:7]) + [[]] * max(0, 7 - len(f)) + [None, flag]
                        filled += 1
            print(f"{Path(run['file']).stem} seed {run['seed']}: at-stamp flags filled for {filled} forecasts, "
                  f"{checked} checked against the dump ({differ} differ); "
                  f"{sum(v for k in flags for v in flags[k].values())} end-ticks slack or re-tensioning")
        out = Path(path).with_name(Path(path).stem + "_atstamp.json")
        out.write_text(json.dumps(doc, indent=1))
        print(f"written {out}")
    return 0


def dumped_snaps(run):
    """The snaps of a dumped run, one per slack episode (tether_sim.forecast.skill.episode_snaps): from its
    every published event where the dump keeps them (``snap_events``: end, time, peak, slack start; from
    2026-11-28 12:50 on), else as dumped."""
    if "snap_events" not in run:
        return run["snaps"]
    groups = {}
    for e, t, peak, start in run["snap_events"]:
        groups.setdefault((e, start), []).append((t, peak))
    return [(e, max(g, key=lambda x: x[1])[0], tuple(t for t, _ in g)) for (e, _), g in groups.items()]


def run_slack_levels(run, dumped_args):
    """{end: slack level N} of a dumped run (kept in dumps from 2026-11-28 on; else the run's detector at
    its start, the same numbers: no winch in these runs)."""
    if "slack_levels" in run:
        return run["slack_levels"]
    args = argparse.Namespace(**dumped_args)
    cfg = case_config(run["file"], "known_sea", run["seed"], args)
    src = {"ship": MotionSource(build_motion(cfg.motion, np.asarray(cfg.ship_end.position, float), wave_components(cfg)))}
    driver = SimulationDriver(replace(cfg, waves=replace(cfg.waves, kind="none")), src, start_blend=False)
    driver.start(0.0)
    return dict(zip(driver.detector.locations, (float(x) for x in driver.detector.thresholds)))


def with_margin(entry, horizon, source, slack, margin):
    """The EndForecast of a dumped forecast ``entry`` with ``forecast.slack_margin`` = ``margin``
    (tether_sim.forecast.lookahead.deep_snaps): exact from the members' depths before their snaps;
    for dumps without them (before 2026-11-28), approximated: the snapping members taken to be those
    with the least troughs within the horizon, each trough standing for its depth."""
    from tether_sim.forecast.lookahead import deep_snaps, summarise

    e, st, p, t, m, ms, *extra = entry
    snaps = [tuple(x) for x in ms]
    troughs = extra[0] if extra else []
    depths = extra[1] if len(extra) > 1 else None
    at_stamp = bool(extra[2]) if len(extra) > 2 else False
    if margin > 0.0 and m > 0 and not at_stamp:
        if depths is not None:
            snaps = deep_snaps(snaps, [math.nan if x is None else float(x) for x in depths], slack[e], margin)
        else:
            least = sorted(troughs)[:len(snaps)]
            snaps = snaps[:sum(x < (1.0 - margin) * slack[e] for x in least)]
    return summarise(st, e, horizon, snaps, m, source)


def rescore(paths, thresholds=(0.5, 0.625, 0.75, 0.875, 1.0), lagged=1, margin=0.0, first_stage=False) -> int:
    """Score the forecasts of ``--dump`` JSON files again, without running anything: per file and
    source, totals over the files at each probability threshold, the reliability of the probability,
    and (threshold 0.5) the time estimate as it was before 2026-11-27, the median over the members
    that snap only, for the same forecasts. ``lagged`` > 1: the forecasts a service with
    ``forecast.lagged`` = lagged publishes from the dumped ones (tether_sim.forecast.lagged)."""
    from types import SimpleNamespace

    from tether_sim.forecast.lagged import lagged_series
    from tether_sim.forecast.lookahead import EndForecast, ensemble_median_time

    runs = []
    for path in paths:
        doc = json.loads(Path(path).read_text())
        horizon, period = doc["args"]["horizon"], 1.0 / doc["args"]["rate"]
        for run in doc["runs"]:
            slack = run_slack_levels(run, doc["args"]) if margin > 0.0 else None
            snaps = dumped_snaps(run)
            if first_stage:  # as before 2026-11-28 12:50: every published peak a snap, each member at its first event
                snaps = [(e, t) for e, t, *_ in run["snap_events"]]
            for source, fc in run["forecasts"].items():
                if first_stage:
                    fc = [list(f[:3]) + [ensemble_median_time([x - f[1] for x, _ in f[9]], f[4]), f[4], f[9]] + list(f[6:9])
                          for f in fc]
                if margin > 0.0:
                    raw = [with_margin(f, horizon, source, slack, margin) for f in fc]
                else:
                    raw = [EndForecast(st, e, horizon, p, t, math.nan, math.nan, m, source,
                                       member_snaps=[tuple(x) for x in ms]) for e, st, p, t, m, ms, *_ in fc]
                published = lagged_series(raw, lagged, period)
                runs.append((run["file"], source, run["seed"], doc["args"]["minutes"] * 60.0, snaps,
                             [SimpleNamespace(end=f.end, stamp=f.stamp, probability=f.probability, time_to_snap=f.time_to_snap,
                                              members=f.members, horizon=horizon, member_snaps=f.member_snaps)
                              for f in published]))
    if margin > 0.0:
        print(f"\nslack margin {margin:g}: a member's snap counts when its least tension before it lay below "
              f"{1.0 - margin:g} x the slack level (forecast.slack_margin)")
    if lagged > 1:
        print(f"\nlagged ensemble: each forecast pooled with the {lagged - 1} before it (forecast.lagged {lagged})")
    old = lambda f: (float(np.median([t for t, _ in f.member_snaps])) - f.stamp if f.member_snaps else math.nan)  # noqa: E731
    for key in sorted({(r[0], r[1]) for r in runs}):
        sel = [r for r in runs if (r[0], r[1]) == key]
        seeds = ", ".join(str(r[2]) for r in sel)
        print(f"\n{Path(key[0]).stem} {key[1]} (seeds {seeds}, {sum(r[3] for r in sel) / 60:.1f} min of sea):")
        for end in ("ship", "vehicle"):
            if not any(x[0] == end for r in sel for x in r[4]) and not any(
                    f.end == end and f.probability >= min(thresholds) for r in sel for f in r[5]):
                continue  # no snap and no warning at this end
            for threshold, timing in [(t, None) for t in thresholds] + [(0.5, old)]:
                tot = np.zeros(6)
                for _, _, _, until, snaps, fc in sel:
                    if timing is not None:
                        fc = [SimpleNamespace(**{**vars(f), "time_to_snap": timing(f)}) for f in fc]
                    sc = score(fc, snaps, end, threshold=threshold, until=until)
                    sc3 = score(fc, snaps, end, threshold=threshold, until=until, lead=3.0)
                    tot += (sc.snaps, sc.warned, sc3.warned, sc.false_alarms, sc.minutes, sc.false_alarm_episodes)
                how = " (snap time as before 2026-11-27: median over the snapping members)" if timing else ""
                w_lo, _ = fraction_interval(int(tot[1]), int(tot[0]))
                e_lo, e_hi = rate_interval(int(tot[5]), tot[4])
                print(f"  {end:7s} p >= {threshold:5.3f}: {tot[1]:.0f}/{tot[0]:.0f} warned >= 5 s ({tot[2]:.0f} >= 3 s; "
                      f"95 % lower bound {100 * w_lo:.0f} %), {tot[3]:.0f} false alarms = {10 * tot[3] / max(tot[4], 1e-9):.2f} / 10 min, "
                      f"{tot[5]:.0f} episodes = {10 * tot[5] / max(tot[4], 1e-9):.2f} / 10 min (95 % interval {e_lo:.2f}-{e_hi:.2f}) "
                      f"({tot[4]:.1f} min scored){how}")
            bins = [reliability(fc, snaps, end, until=until) for _, _, _, until, snaps, fc in sel]
            print(f"  {end} reliability (probability bin: forecasts, mean probability, observed frequency of a snap within the horizon):")
            for i in range(len(bins[0])):
                n = sum(b[i].forecasts for b in bins)
                if n:
                    mp = sum(b[i].forecasts * b[i].mean_probability for b in bins if b[i].forecasts) / n
                    ob = sum(b[i].forecasts * b[i].observed for b in bins if b[i].forecasts) / n
                    print(f"    [{bins[0][i].low:.3f}, {bins[0][i].high:.3f}{']' if i == len(bins[0]) - 1 else ')'}: "
                          f"{n:4d}, {mp:.2f}, {ob:.2f}")
    return 0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--files", nargs="+", default=["config/ropos_L1730.yaml", "config/ropos_L200.yaml"])
    ap.add_argument("--sources", nargs="+", default=["known_sea", "poses"], choices=["known_sea", "poses"])
    ap.add_argument("--seeds", nargs="+", type=int, default=[1])
    ap.add_argument("--minutes", type=float, default=10.0, help="simulated minutes per seed")
    ap.add_argument("--hs", type=float, default=3.0)
    ap.add_argument("--tp", type=float, default=9.0)
    ap.add_argument("--directions", type=int, default=5, help="wave directions (1: long-crested; 5: cos-2s, s = 6)")
    ap.add_argument("--horizon", type=float, default=20.0)
    ap.add_argument("--rate", type=float, default=1.0, help="forecasts per second")
    ap.add_argument("--members", type=int, default=8)
    ap.add_argument("--sea-error", type=float, default=0.1, help="members' spread, fraction of Hs")
    ap.add_argument("--nominal-error", type=float, default=0.1, help="known_sea: error of each forecast's nominal sea, fraction of Hs")
    ap.add_argument("--command-rate", type=float, default=10.0)
    ap.add_argument("--no-cable-waves", dest="cable_waves", action="store_false",
                    help="the waves move the ship (RAO) but do not act on the cable (cheaper: no wave kinematics "
                         "at the quadrature points; the members never perturb the cable's waves anyway)")
    ap.add_argument("--warn-probability", type=float, default=0.75,
                    help="the alarm threshold scored beside the 0.5 of the definition (forecast.warn_probability)")
    ap.add_argument("--json", default=None, help="write every number here (after every run)")
    ap.add_argument("--dump", action="store_true", help="--json also lists every warning (p >= 0.5), every forecast with its members' snaps, every snap and slack start")
    ap.add_argument("--rescore", nargs="+", default=None, metavar="JSON",
                    help="run nothing: score the forecasts of --dump JSON files again (thresholds, reliability)")
    ap.add_argument("--lagged", type=int, nargs="+", default=[1],
                    help="with --rescore: score the forecasts a lagged ensemble of this many forecasts publishes "
                         "(forecast.lagged; 1: as run); several counts: each in turn")
    ap.add_argument("--slack-margin", type=float, nargs="+", default=[0.0],
                    help="with --rescore: score the forecasts with forecast.slack_margin = this (0: as run); several: each in turn")
    ap.add_argument("--first-stage", action="store_true",
                    help="with --rescore: also score as before 2026-11-28 12:50 (each member's snap at its first published "
                         "event, every published event of the run a snap of its own), for dumps that keep both")
    ap.add_argument("--near-misses", action="store_true",
                    help="with --rescore: run each dumped sea again without forecasts and compare every false-alarm "
                         "episode with the run's own end tension (the snap level, the slack level)")
    ap.add_argument("--fill-at-stamp", action="store_true",
                    help="with --rescore: run each dumped sea again without forecasts and write <dump>_atstamp.json with each "
                         "forecast's slack_at_stamp from the run's detector (dumps from before 2026-11-28 lack it); "
                         "checks it against dumps that have it")
    ap.add_argument("--fade", action="store_true",
                    help="known_sea: condition the members on the measured ship state by the exponential fade alone "
                         "(as before 2026-11-27) instead of the sea's covariance, for comparison")
    ap.add_argument("--motion-error", action="store_true",
                    help="run no cable: the known sea's members against the truth, fairlead motion only, by lead time")
    ap.add_argument("--cpu-split", action="store_true",
                    help="also print where the look-aheads spend their CPU (members' motion, solver, relative end speed, "
                         "snap detector, rest)")
    args = ap.parse_args(argv)
    split = CpuSplit() if args.cpu_split else None
    if args.motion_error:
        return motion_error(args)
    if args.rescore:
        if args.fill_at_stamp:
            return fill_at_stamp(args.rescore)
        if args.near_misses:
            for margin in args.slack_margin:
                near_misses(args.rescore, margin=margin)
            return 0
        for margin in args.slack_margin:
            for count in args.lagged:
                rescore(args.rescore, lagged=count, margin=margin)
                if args.first_stage:
                    rescore(args.rescore, lagged=count, margin=margin, first_stage=True)
        return 0
    rows, dumps, costs = [], [], []
    print(f"forecast skill: Hs {args.hs:g} m, Tp {args.tp:g} s, {args.directions} direction(s), horizon {args.horizon:g} s, {args.members} members, "
          f"{args.rate:g} forecasts/s, sea_error {args.sea_error:g}, nominal error {args.nominal_error:g}, "
          f"waves on the cable: {'yes' if args.cable_waves else 'no'}, members conditioned by {'the exponential fade' if args.fade else 'the covariance'}", flush=True)
    for path in args.files:
        for seed in args.seeds:
            cfgs = [case_config(path, source, seed, args) for source in args.sources]
            snaps, forecasts, wall, look, sim = run_case(cfgs, args.minutes, args.nominal_error, args.cable_waves, not args.fade)
            cpu = dict(run_case.cpu)
            c_score = time.thread_time()
            if args.dump:
                dumps.append({"file": path, "seed": seed, "snaps": snaps, "snap_events": run_case.snap_events,
                              "slack_starts": run_case.slacks,
                              "slack_levels": run_case.slack_levels,
                              "warnings": {src: [(f.end, f.stamp, f.probability, f.time_to_snap, f.time_to_snap_std,
                                                  f.predicted_peak) for f in fc if f.probability >= 0.5]
                                           for src, fc in forecasts.items()},
                              # every forecast with its members' snaps (reliability, other thresholds)
                              "forecasts": {src: [(f.end, f.stamp, f.probability, f.time_to_snap, f.members,
                                                   f.member_snaps, f.member_troughs, f.member_slack_depths, f.slack_at_stamp,
                                                   f.member_first_stages) for f in fc]
                                            for src, fc in forecasts.items()}})
            for source in args.sources:
                fc = forecasts[source]
                for lead, threshold in [(5.0, 0.5), (3.0, 0.5), (5.0, args.warn_probability), (3.0, args.warn_probability)]:
                    for end in ("ship", "vehicle"):
                        s = score(fc, snaps, end, lead=lead, until=sim, threshold=threshold)
                        row = {"file": path, "source": source, "seed": seed, "end": end, "lead": lead, "threshold": threshold,
                               "minutes": args.minutes, "snaps": s.snaps, "warned": s.warned,
                               "warnings": s.warnings, "false_alarms": s.false_alarms,
                               "episodes": s.false_alarm_episodes, "forecast_minutes": s.minutes,
                               "snaps_in_run": sum(s[0] == end for s in snaps),
                               "wall_s": wall, "lookahead_wall_s": look[source], "forecasts": len(fc) // 2,
                               "degraded": sum(f.degraded for f in fc) // 2}
                        rows.append(row)
                        print(f"{Path(path).stem:12s} {source:9s} seed {seed} {end:7s} p >= {threshold:g} lead {lead:g} s: "
                              f"{s.warned}/{s.snaps} snaps warned, {s.warnings} warnings, {s.false_alarms} false alarms "
                              f"({s.false_alarms_per_10min:.2f}/10 min, {s.episodes_per_10min:.2f} episodes/10 min); "
                              f"run wall {wall:.0f} s (this source's look-ahead {look[source]:.0f} s)", flush=True)
            cpu["scoring"] = time.thread_time() - c_score
            print(f"{Path(path).stem} seed {seed}: CPU s (this thread) " + ", ".join(f"{k} {v:.1f}" for k, v in cpu.items()),
                  flush=True)
            if split is not None:
                print(f"{Path(path).stem} seed {seed} (cumulative): {split.report()}", flush=True)
            costs.append({"file": path, "seed": seed, "cpu_s": cpu, "split": dict(split.cpu) if split else None})
            if args.json:  # after every run, so an interrupted study keeps what finished
                Path(args.json).parent.mkdir(parents=True, exist_ok=True)
                Path(args.json).write_text(json.dumps({"args": vars(args), "rows": rows, "runs": dumps, "cpu": costs}, indent=1))
    print("\ntotals (all seeds):")
    keys = sorted({(r["file"], r["source"], r["end"], r["threshold"], r["lead"]) for r in rows})
    for key in keys:
        sel = [r for r in rows if (r["file"], r["source"], r["end"], r["threshold"], r["lead"]) == key]
        snaps, warned = sum(r["snaps"] for r in sel), sum(r["warned"] for r in sel)
        minutes = sum(r["forecast_minutes"] for r in sel)
        fa, ep = sum(r["false_alarms"] for r in sel), sum(r["episodes"] for r in sel)
        frac = f"{100.0 * warned / snaps:.0f} %" if snaps else "-"
        print(f"  {Path(key[0]).stem:12s} {key[1]:9s} {key[2]:7s} p >= {key[3]:g} lead {key[4]:g} s: {warned}/{snaps} warned ({frac}), "
              f"{10 * fa / max(minutes, 1e-9):.2f} false alarms/10 min ({10 * ep / max(minutes, 1e-9):.2f} episodes), "
              f"{minutes:.1f} min scored")
    return 0


if __name__ == "__main__":
    sys.exit(main())
