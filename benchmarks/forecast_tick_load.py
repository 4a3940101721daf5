"""Does the snap forecast make the live tick wait? Tick wall times with the forecast off and on.

The node's stepping core (SimulationDriver with the node's wall budget per tick, the ship on its RAO
motion) is ticked on a wall-clock schedule at ``node.output_rate`` as the node's timer does, for
alternating windows with the forecast off and on (the node's ForecastService: look-aheads in a worker
thread, the tick only hands over a snapshot and publishes finished forecasts), after the motion's
ramp-in (ticked through first, not recorded: no forecast is issued during it). Per window kind: the
p50 / p99 / max of the tick's wall time (driver.tick + the forecast hook), the ticks over the output
period, the lag behind the clock at the end, and the forecasts completed / skipped (a forecast falling
due while the worker is still busy is skipped). Message publishing is not included (no ROS here).

    .venv/bin/python benchmarks/forecast_tick_load.py                      # config/ropos_forecast.yaml
    .venv/bin/python benchmarks/forecast_tick_load.py --window 10 --rounds 2 --members 4 --horizon 10
"""

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from tether_sim.forecast.service import ForecastService  # noqa: E402
from tether_sim.io.params import load_config  # noqa: E402
from tether_sim.physics.motion import build_motion  # noqa: E402
from tether_sim.physics.waves import wave_components  # noqa: E402
from tether_sim.ros.driver import MotionSource, SimulationDriver  # noqa: E402


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--params", default="config/ropos_forecast.yaml")
    ap.add_argument("--window", type=float, default=20.0, help="wall seconds per window")
    ap.add_argument("--rounds", type=int, default=3, help="off/on window pairs")
    ap.add_argument("--members", type=int, default=None, help="override forecast.members")
    ap.add_argument("--horizon", type=float, default=None, help="override forecast.horizon")
    args = ap.parse_args(argv)
    over = {k: v for k, v in (("forecast.members", args.members), ("forecast.horizon", args.horizon)) if v is not None}
    cfg = load_config(str(ROOT / args.params), over)
    node = cfg.node
    motion = build_motion(cfg.motion, np.asarray(cfg.ship_end.position, float), wave_components(cfg))
    driver = SimulationDriver(cfg, {"ship": MotionSource(motion)}, wall_budget=node.tick_budget / node.output_rate)
    service = ForecastService(cfg, threaded=True)
    period = 1.0 / node.output_rate
    times = {"off": [], "on": []}
    lags = {"off": [], "on": []}
    counts = {"on": [0, 0]}
    t_start = time.perf_counter()
    driver.start(0.0)
    k = 0
    # the forecast starts once the motion has ramped in (forecast/service.py): tick through the ramp
    # first (not recorded), so every "on" window has forecasts
    while k * period < cfg.motion.ramp_time:
        k += 1
        pause = t_start + k * period - time.perf_counter()
        if pause > 0:
            time.sleep(pause)
        driver.tick(time.perf_counter() - t_start)
    try:
        for _ in range(args.rounds):
            for kind in ("off", "on"):
                done0, skipped0 = service.completed, service.skipped
                end = time.perf_counter() + args.window
                while time.perf_counter() < end:
                    k += 1
                    due = t_start + k * period
                    pause = due - time.perf_counter()
                    if pause > 0:
                        time.sleep(pause)
                    now = time.perf_counter() - t_start
                    w0 = time.perf_counter()
                    driver.tick(now)
                    if kind == "on":
                        service.observe(driver, now=now)
                        service.poll()
                    times[kind].append(time.perf_counter() - w0)
                lags[kind].append(driver.lag)
                if kind == "on":
                    counts["on"][0] += service.completed - done0
                    counts["on"][1] += service.skipped - skipped0
                    # the next "off" window starts with no look-ahead running: the node ticks on (not
                    # recorded) until the worker has finished the one it has
                    wait_end = time.perf_counter() + 120.0
                    while service._busy and time.perf_counter() < wait_end:
                        k += 1
                        pause = t_start + k * period - time.perf_counter()
                        if pause > 0:
                            time.sleep(pause)
                        driver.tick(time.perf_counter() - t_start)
                    service.next_due = None
    finally:
        service.close()
    fc = cfg.forecast
    print(f"{args.params}: {node.output_rate:g} Hz ticks, budget {1e3 * node.tick_budget * period:.1f} ms; forecast "
          f"{fc.members} members x {fc.horizon:g} s at {fc.rate:g} Hz; {args.rounds} x ({args.window:g} s off, "
          f"{args.window:g} s on)")
    for kind in ("off", "on"):
        t = 1e3 * np.array(times[kind])
        extra = (f"; forecasts completed {counts['on'][0]}, skipped {counts['on'][1]}, look-ahead wall "
                 f"{service.last_wall:.2f} s (last)") if kind == "on" else ""
        print(f"  forecast {kind:3s}: {t.size} ticks, tick p50 {np.percentile(t, 50):.2f} ms, p99 "
              f"{np.percentile(t, 99):.2f} ms, max {t.max():.2f} ms, over the period {np.mean(t > 1e3 * period) * 100:.1f} %, "
              f"lag at window ends {max(lags[kind]):.3f} s{extra}")
    p99 = {kind: np.percentile(times[kind], 99) for kind in times}
    print(f"  p99 on / off = {p99['on'] / p99['off']:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
