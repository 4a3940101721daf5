"""The perfect member: a look-ahead run driven by the run's own ship motion, exactly (no forecast error),
against the run itself, over every forecast of a seeded sea (docs/forecast.md, "The members' bias").

A member restarted from the run's state and commanded with the run's own future must repeat the run: its
end tensions over the horizon are the run's to round-off (on the node's command grid) or to the
difference of a coarser command grid (``forecast.command_rate``, Hermite interpolation in between).
This script runs the skill benchmark's sea (benchmarks/forecast_skill.py: the same configuration,
driver and tick grid) with one-member services of zero forecast error (no nominal error, no spread),
one per command rate asked for, and prints, per command rate, the error of the member's least end
tension within the horizon against the run's (in slack levels) and the largest difference of its
end tension history from the run's (the run interpolated to the member's sample times).

``--ranks DUMP``: also the rank histogram of the run's least tension among the members' of the
forecasts dumped for the same seeds (forecast_skill.py --dump), from this script's run of the sea.

    nice -n 19 .venv/bin/python benchmarks/forecast_perfect_member.py --seeds 21 --minutes 5 \\
        --command-rates 10 0 --ranks out/forecast_skill/tune14_L1730_s21-23.json
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
sys.path.insert(0, str(ROOT / "benchmarks"))

from forecast_skill import case_config  # noqa: E402
from tether_sim.forecast.lookahead import LookAhead  # noqa: E402
from tether_sim.forecast.service import ForecastService  # noqa: E402
from tether_sim.forecast.skill import TIE_TOLERANCE, trough_rank  # noqa: E402
from tether_sim.physics.motion import build_motion  # noqa: E402
from tether_sim.physics.waves import wave_components  # noqa: E402
from tether_sim.ros.driver import MotionSource, SimulationDriver  # noqa: E402
from tether_sim.solvers.factory import build_solver  # noqa: E402


def run_seed(path, seed, args, rates):
    """The run of the sea with one perfect-member service per command rate: (times, {end: tensions}
    of the run, {end: slack level}, {rate: [(stamp, {end: member trough}, (member times, member
    tensions (k, 2)))]})."""
    base = argparse.Namespace(hs=args.hs, tp=args.tp, directions=args.directions, horizon=args.horizon,
                              rate=args.rate, members=1, sea_error=0.0, command_rate=0.0)
    cfg = case_config(path, "known_sea", seed, base)
    src = {"ship": MotionSource(build_motion(cfg.motion, np.asarray(cfg.ship_end.position, float), wave_components(cfg)))}
    cfg = replace(cfg, waves=replace(cfg.waves, kind="none"))  # waves on the ship only (--no-cable-waves)
    driver = SimulationDriver(cfg, src, start_blend=False)
    driver.start(0.0)
    samples = []
    drain = driver.solver.drain_end_tensions

    def recording_drain():
        out = drain()
        samples.append((np.asarray(out[0]) + driver.anchor, np.array(out[1]), np.array(out[2])))
        return out

    driver.solver.drain_end_tensions = recording_drain
    services, records = {}, {}
    for r in rates:
        c = replace(cfg, forecast=replace(cfg.forecast, command_rate=float(r)))
        service = ForecastService(c, nominal_error=0.0)
        engine = LookAhead(replace(driver._solver_config, forecast=c.forecast), build_solver)
        tick = engine.solver.tick
        trace = []

        def recording_tick(t, ship=None, vehicle=None, drain=True, _tick=tick, _trace=trace, _anchor=driver.anchor):
            out = _tick(t, ship=ship, vehicle=vehicle, drain=drain)
            if out.count:
                _trace.append((np.array(out.times) + _anchor, np.column_stack([out.ship_tension, out.vehicle_tension])))
            return out

        engine.solver.tick = recording_tick
        service._engine = engine
        services[r], records[r] = (service, trace), []
    rate = cfg.node.output_rate
    for k in range(1, int(round(args.minutes * 60.0 * rate)) + 1):
        driver.tick(k / rate)
        for r, (service, trace) in services.items():
            done = service.completed
            trace.clear()
            service.observe(driver, clock_origin=0.0, tick_index=k)
            if service.completed > done:
                fc = {f.end: f for f in service.poll()}
                stamp = fc["ship"].stamp
                history = (np.concatenate([a for a, _ in trace]), np.vstack([b for _, b in trace])) if trace else None
                records[r].append((stamp, {e: float(f.member_troughs[0]) for e, f in fc.items()}, history))
    t = np.concatenate([a for a, _, _ in samples])
    tensions = {"ship": np.concatenate([b for _, b, _ in samples]), "vehicle": np.concatenate([c for _, _, c in samples])}
    slack = dict(zip(driver.detector.locations, (float(x) for x in driver.detector.thresholds)))
    return t, tensions, slack, records


def perfect_member_errors(t, tensions, slack, records, horizon, end_time):
    """Per end: the member's least tension within the horizon minus the run's (slack levels), and the
    largest |member - run| end tension over the horizon (slack levels), over every forecast."""
    out = {}
    for end, j in (("ship", 0), ("vehicle", 1)):
        d_trough, d_max = [], []
        for stamp, troughs, history in records:
            if stamp + horizon > end_time or history is None:
                continue
            inside = (t > stamp - 1e-9) & (t < stamp + horizon - 1e-9)
            run_trough = tensions[end][inside].min()
            d_trough.append((troughs[end] - run_trough) / slack[end])
            ht, hT = history
            sel = (ht > stamp - 1e-9) & (ht < stamp + horizon - 1e-9)
            run_at = np.interp(ht[sel], t, tensions[end])
            d_max.append(float(np.max(np.abs(hT[sel, j] - run_at))) / slack[end])
        out[end] = (np.asarray(d_trough), np.asarray(d_max))
    return out


def rank_histogram(dump, seed, t, tensions, slack, horizon, end_time, end="vehicle"):
    """Rank of the run's least tension within the horizon among the dumped members' troughs (0: below all; ties
    spread over their ranks: tether_sim.forecast.skill.trough_rank)."""
    doc = json.loads(Path(dump).read_text())
    run = next((r for r in doc["runs"] if r["seed"] == seed), None)
    if run is None:
        return None
    hist = None
    for e, stamp, p, tts, members, _, *extra in run["forecasts"]["known_sea"]:
        if e != end or not extra or not extra[0] or stamp + horizon > end_time:
            continue
        m = np.asarray(extra[0], float)
        truth = tensions[end][(t > stamp - 1e-9) & (t < stamp + horizon - 1e-9)].min()
        if hist is None:
            hist = np.zeros(m.size + 1)
        hist += trough_rank(m, truth, TIE_TOLERANCE * slack[end])  # ties spread over their ranks
    return hist


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--file", default="config/ropos_L1730.yaml")
    ap.add_argument("--seeds", nargs="+", type=int, default=[21])
    ap.add_argument("--minutes", type=float, default=5.0)
    ap.add_argument("--hs", type=float, default=3.0)
    ap.add_argument("--tp", type=float, default=9.0)
    ap.add_argument("--directions", type=int, default=5)
    ap.add_argument("--horizon", type=float, default=15.0)
    ap.add_argument("--rate", type=float, default=0.5)
    ap.add_argument("--command-rates", nargs="*", type=float, default=[10.0, 0.0],
                    help="forecast.command_rate of the perfect members (0: the node's output rate)")
    ap.add_argument("--ranks", default=None, help="a forecast_skill.py --dump file of the same seeds")
    ap.add_argument("--npz", default=None, help="save the run's end tensions here (per seed: <npz>_s<seed>.npz)")
    args = ap.parse_args(argv)
    for seed in args.seeds:
        wall0 = time.perf_counter()
        t, tensions, slack, records = run_seed(args.file, seed, args, args.command_rates)
        end_time = args.minutes * 60.0
        print(f"{Path(args.file).stem} seed {seed}: {args.minutes:g} min, wall {time.perf_counter() - wall0:.0f} s", flush=True)
        if args.npz:
            np.savez_compressed(f"{args.npz}_s{seed}.npz", t=t, ship=tensions["ship"], vehicle=tensions["vehicle"],
                                slack=np.array([slack["ship"], slack["vehicle"]]))
        for r in args.command_rates:
            errs = perfect_member_errors(t, tensions, slack, records[r], args.horizon, end_time)
            for end, (dt, dm) in errs.items():
                if not dt.size:
                    continue
                print(f"  command rate {r:g} Hz{' (output rate)' if r == 0 else ''}, {end}: {dt.size} forecasts; member - run "
                      f"least tension within the horizon, slack levels: mean {dt.mean():+.4f}, rms {math.sqrt(np.mean(dt ** 2)):.4f}, "
                      f"min {dt.min():+.4f}, max {dt.max():+.4f}; largest |member - run| tension over the horizon: "
                      f"median {np.median(dm):.4f}, max {dm.max():.4f} slack levels", flush=True)
        if args.ranks:
            hist = rank_histogram(args.ranks, seed, t, tensions, slack, args.horizon, end_time)
            if hist is not None:
                print(f"  vehicle: rank of the run's trough among the dumped members' (0: below all): "
                      + " ".join(f"{x:.1f}" for x in hist), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
