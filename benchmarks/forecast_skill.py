"""Skill of the snap forecast (docs/forecast.md) on seeded JONSWAP seas, the ship through the RAO table.

For each live file (default: the 1730 m and 200 m ROPOS files) and each ship-motion forecast source,
the run is simulated as the offline runner does (driver + forecast service, inline, on the run's tick
grid) and every forecast is scored against the snaps the run reports (tether_sim.forecast.skill): a
snap is warned when a forecast with probability >= 0.5 stamped >= ``--lead`` s before it predicted it
within +-1.5 s; a false alarm is such a forecast with no snap within +-1.5 s of its predicted time.

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
from tether_sim.forecast.skill import score  # noqa: E402
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


def run_case(cfgs, minutes, nominal_error, cable_waves=True):
    """One run of the sea of ``cfgs`` (one configuration per forecast source, the same sea) with a
    forecast service per source observing the same driver (the truth run is shared by the sources):
    (snaps [(end, time)], {source: forecasts}, wall s, {source: look-ahead wall s}, simulated s).
    ``cable_waves=False``: the waves move the ship (RAO) but do not act on the cable (still water)."""
    cfg = cfgs[0]
    src = {"ship": MotionSource(build_motion(cfg.motion, np.asarray(cfg.ship_end.position, float), wave_components(cfg)))}
    if not cable_waves:
        cfg = replace(cfg, waves=replace(cfg.waves, kind="none"))
    driver = SimulationDriver(cfg, src, start_blend=False)
    services = {c.forecast.source: ForecastService(c, nominal_error=nominal_error if c.forecast.source == "known_sea" else 0.0)
                for c in cfgs}
    driver.start(0.0)
    rate = cfg.node.output_rate
    snaps, slacks = [], []
    forecasts = {name: [] for name in services}
    look = {name: 0.0 for name in services}
    wall0 = time.perf_counter()
    for k in range(1, int(round(minutes * 60.0 * rate)) + 1):
        report = driver.tick(k / rate)
        snaps += [(e.location, e.time) for e in report.events if isinstance(e, SnapEvent)]
        slacks += [(e.location, e.time) for e in report.events if isinstance(e, SlackStarted)]
        for name, service in services.items():
            done = service.completed
            service.observe(driver, clock_origin=0.0, tick_index=k)
            if service.completed > done:
                look[name] += service.last_wall
            forecasts[name] += service.poll()
    snaps += [(e.location, e.time) for e in driver.detector.flush()]
    run_case.slacks = slacks  # slack periods begun (for --dump)
    return snaps, forecasts, time.perf_counter() - wall0, look, driver.solver.time


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
    ap.add_argument("--json", default=None, help="write every number here (after every run)")
    ap.add_argument("--dump", action="store_true", help="--json also lists every warning (p >= 0.5), every forecast with its members' snaps, every snap and slack start")
    args = ap.parse_args(argv)
    rows, dumps = [], []
    print(f"forecast skill: Hs {args.hs:g} m, Tp {args.tp:g} s, {args.directions} direction(s), horizon {args.horizon:g} s, {args.members} members, "
          f"{args.rate:g} forecasts/s, sea_error {args.sea_error:g}, nominal error {args.nominal_error:g}, "
          f"waves on the cable: {'yes' if args.cable_waves else 'no'}", flush=True)
    for path in args.files:
        for seed in args.seeds:
            cfgs = [case_config(path, source, seed, args) for source in args.sources]
            snaps, forecasts, wall, look, sim = run_case(cfgs, args.minutes, args.nominal_error, args.cable_waves)
            if args.dump:
                dumps.append({"file": path, "seed": seed, "snaps": snaps, "slack_starts": run_case.slacks,
                              "warnings": {src: [(f.end, f.stamp, f.probability, f.time_to_snap, f.time_to_snap_std,
                                                  f.predicted_peak) for f in fc if f.probability >= 0.5]
                                           for src, fc in forecasts.items()},
                              # every forecast with its members' snaps (reliability, other thresholds)
                              "forecasts": {src: [(f.end, f.stamp, f.probability, f.time_to_snap, f.members,
                                                   f.member_snaps) for f in fc]
                                            for src, fc in forecasts.items()}})
            for source in args.sources:
                fc = forecasts[source]
                for lead in (5.0, 3.0):
                    for end in ("ship", "vehicle"):
                        s = score(fc, snaps, end, lead=lead, until=sim)
                        row = {"file": path, "source": source, "seed": seed, "end": end, "lead": lead,
                               "minutes": args.minutes, "snaps": s.snaps, "warned": s.warned,
                               "warnings": s.warnings, "false_alarms": s.false_alarms,
                               "episodes": s.false_alarm_episodes, "forecast_minutes": s.minutes,
                               "snaps_in_run": sum(e == end for e, _ in snaps),
                               "wall_s": wall, "lookahead_wall_s": look[source], "forecasts": len(fc) // 2,
                               "degraded": sum(f.degraded for f in fc) // 2}
                        rows.append(row)
                        print(f"{Path(path).stem:12s} {source:9s} seed {seed} {end:7s} lead {lead:g} s: "
                              f"{s.warned}/{s.snaps} snaps warned, {s.warnings} warnings, {s.false_alarms} false alarms "
                              f"({s.false_alarms_per_10min:.2f}/10 min, {s.episodes_per_10min:.2f} episodes/10 min); "
                              f"run wall {wall:.0f} s (this source's look-ahead {look[source]:.0f} s)", flush=True)
            if args.json:  # after every run, so an interrupted study keeps what finished
                Path(args.json).parent.mkdir(parents=True, exist_ok=True)
                Path(args.json).write_text(json.dumps({"args": vars(args), "rows": rows, "runs": dumps}, indent=1))
    print("\ntotals (all seeds):")
    keys = sorted({(r["file"], r["source"], r["end"], r["lead"]) for r in rows})
    for key in keys:
        sel = [r for r in rows if (r["file"], r["source"], r["end"], r["lead"]) == key]
        snaps, warned = sum(r["snaps"] for r in sel), sum(r["warned"] for r in sel)
        minutes = sum(r["forecast_minutes"] for r in sel)
        fa, ep = sum(r["false_alarms"] for r in sel), sum(r["episodes"] for r in sel)
        frac = f"{100.0 * warned / snaps:.0f} %" if snaps else "-"
        print(f"  {Path(key[0]).stem:12s} {key[1]:9s} {key[2]:7s} lead {key[3]:g} s: {warned}/{snaps} warned ({frac}), "
              f"{10 * fa / max(minutes, 1e-9):.2f} false alarms/10 min ({10 * ep / max(minutes, 1e-9):.2f} episodes), "
              f"{minutes:.1f} min scored")
    return 0


if __name__ == "__main__":
    sys.exit(main())
