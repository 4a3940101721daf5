"""The hybrid solver with the winch under the node's driver, the clock stalled so that it re-synchronises
(no ROS, fake clock, deterministic; docs/node.md "Hybrid solver with the winch, re-synchronising").

    .venv/bin/python benchmarks/resync_winch.py payout-reverse [--stall-every 2.3]
    .venv/bin/python benchmarks/resync_winch.py search --seed 1 [--minutes 4] [--slowdown 1.3]

``config/ropos_L200_hybrid.yaml`` with ``winch.enabled``, the ship heaving 0.5 m at 0.1 Hz (20 Hz poses
arriving at their stamps), ticks at ``node.output_rate``. Winch commands go through the winch link as
topic commands do.

- ``payout-reverse``: pay out at 2 m/s from 2 s (the cage falls at about its terminal speed and the
  cage end goes slack), haul in at 2 m/s from 40 s, 60 s of clock; ``--stall-every S``: the clock
  skips 1.2 s every S s (from 3 s), beyond ``node.max_lag``, so the driver re-synchronises.
- ``search``: seeded random speed (+-2 m/s), length (120-260 m) and tension (30-70 kN) commands every
  5-30 s, stalls of 1.1-3 s every 2-15 s, ticks jittered by up to 9 ms; ``--slowdown K``: the solver
  charged K x the simulated time of its substeps on a fake wall clock (the node behind: capped
  ticks, re-synchronisations at ``node.max_lag``).

Prints the re-synchronisations, the end tension range (x the static tensions), the largest end
tension within 2 s after a re-synchronisation, the largest single-substep excess of the ship tension
over its running median (41 substeps) and the snap events (with their degraded flag).
"""

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
HEAVE, FREQUENCY = 0.5, 0.1  # m, Hz


def run(commands, stalls, clock_end, slowdown=0.0, jitter=None, overrides=None):
    """Tick the driver to ``clock_end``; ``commands``: (clock time, mode, setpoint); ``stalls``: (clock
    time, skipped s); ``jitter(k)``: the k-th tick's clock offset, s. Returns a dict of figures."""
    import tether_sim.ros.driver as driver_module
    from benchmarks.jitter_soak import FakeWall, SlowSolver
    from tether_sim.io.inputs import EndPoseInput
    from tether_sim.io.params import load_config
    from tether_sim.physics.snap import SnapEvent
    from tether_sim.ros.driver import SimulationDriver
    from tether_sim.ros.winch_link import link_of
    from tether_sim.solvers.factory import build_solver

    cfg = load_config(REPO / "config" / "ropos_L200_hybrid.yaml", {"winch.enabled": True, **(overrides or {})})
    node = cfg.node
    inp = EndPoseInput("ship", max_end_speed=node.max_end_speed, history_span=node.input_delay + node.max_lag + 1.0)
    fed = [0]

    def feed(now):
        while fed[0] * 0.05 <= now:
            t = fed[0] * 0.05
            inp.add_pose(t, (0.0, 0.0, HEAVE * math.sin(2 * math.pi * FREQUENCY * t)), (0, 0, 0, 1), now=now)
            fed[0] += 1

    if slowdown > 0.0:
        driver_module.wallclock = FakeWall
        FakeWall.t = 0.0
        driver = SimulationDriver(cfg, {"ship": inp}, solver_factory=lambda c: SlowSolver(build_solver(c), slowdown),
                                  wall_budget=node.tick_budget / node.output_rate)
    else:
        driver = SimulationDriver(cfg, {"ship": inp})
    feed(1.0)
    driver.start(1.0)
    link = link_of(driver)
    static = np.array(driver.static_tensions)
    substeps = []
    inner = driver.solver.inner
    drain = inner.drain_end_tensions

    def recording_drain():  # the substep tensions the driver drains, kept (clock times)
        t, a, b = drain()
        substeps.extend(zip(np.asarray(t) + driver.anchor, a, b))
        return t, a, b

    inner.drain_end_tensions = recording_drain
    commands, stalls = sorted(commands), sorted(stalls)
    states, resyncs, snaps, k, now, cpu0 = [], [], [], 0, 1.0, time.process_time()
    while now < clock_end:
        k += 1
        if stalls and 1.0 + k / node.output_rate >= stalls[0][0]:
            k += int(round(stalls.pop(0)[1] * node.output_rate))
        now = 1.0 + k / node.output_rate + (jitter(k) if jitter else 0.0)
        while commands and commands[0][0] <= now:
            _, mode, setpoint = commands.pop(0)
            link.request(mode, setpoint, "topic")
        if slowdown > 0.0:
            FakeWall.t = max(FakeWall.t, now)
        feed(now)
        report = driver.tick(now)
        if driver.solver.inner is not inner:  # rebuilt (static recovery): record its substeps too
            inner, drain = driver.solver.inner, driver.solver.inner.drain_end_tensions
            inner.drain_end_tensions = recording_drain
        if report.dropped > 0.0:
            resyncs.append(driver.stamp)
        bridged = getattr(driver, "bridged", lambda ev: False)  # (a driver before 2026-11-27 has none)
        snaps += [(ev, driver.degraded or bridged(ev)) for ev in report.events if isinstance(ev, SnapEvent)]
        f = driver.solver.end_forces()
        states.append((driver.stamp, f.ship_tension / static[0], f.vehicle_tension / static[1], link.winch.length))
    states, sub = np.array(states), np.array(substeps)
    after = np.zeros(len(states), bool)
    for t in resyncs:
        after |= (states[:, 0] >= t - 1e-9) & (states[:, 0] < t + 2.0)
    ship = sub[:, 1] / static[0]
    from scipy.ndimage import median_filter

    excess = ship - median_filter(ship, size=41, mode="nearest")
    i = int(np.argmax(excess))
    return {"static": static, "resyncs": len(resyncs), "divergences": driver.divergences,
            "ship": (float(ship.min()), float(ship.max())),
            "vehicle": (float(sub[:, 2].min() / static[1]), float(sub[:, 2].max() / static[1])),
            "after": float(states[after, 1:3].max()) if after.any() else math.nan,
            "excess": (float(excess[i]), float(sub[i, 0])), "snaps": snaps,
            "length": (float(states[:, 3].min()), float(states[:, 3].max())), "cpu": time.process_time() - cpu0}


def report(label, r):
    print(f"{label}: static {r['static'][0] / 1e3:.1f} / {r['static'][1] / 1e3:.1f} kN (ship / cage end); "
          f"{r['resyncs']} re-synchronisations, {r['divergences']} divergences; L {r['length'][0]:.1f}-{r['length'][1]:.1f} m; "
          f"ship {r['ship'][0]:.3f}-{r['ship'][1]:.3f}, cage end {r['vehicle'][0]:.3f}-{r['vehicle'][1]:.3f} x static; "
          f"within 2 s after a re-synchronisation at most {r['after']:.3f} x; largest single-substep excess "
          f"{r['excess'][0]:.3f} x static at t = {r['excess'][1]:.2f} s; {r['cpu']:.0f} s CPU", flush=True)
    for ev, degraded in r["snaps"]:
        print(f"  snap event at {ev.location}, t = {ev.time:.2f} s: {ev.peak_tension / 1e3:.1f} kN "
              f"({ev.amplification:.2f} x), slack {ev.slack_duration:.2f} s{', degraded' if degraded else ''}", flush=True)


def search_plan(seed, minutes):
    rng = np.random.default_rng(seed)
    end, commands, t = 60.0 * minutes, [], 2.0
    while t < end:
        mode = str(rng.choice(["speed", "length", "tension"]))
        setpoint = {"speed": rng.uniform(-2, 2), "length": rng.uniform(120, 260), "tension": rng.uniform(30e3, 70e3)}[mode]
        if mode == "speed" and rng.random() < 0.5:
            setpoint = math.copysign(2.0, setpoint)
        commands.append((t, mode, float(setpoint)))
        t += rng.uniform(5, 30)
    stalls, t = [], 3.0
    while t < end:
        stalls.append((t, float(rng.uniform(1.1, 3.0))))
        t += rng.uniform(2, 15)
    jitter = rng.uniform(-0.009, 0.009, int(end * 60) + 1000)
    return commands, stalls, end, (lambda k: jitter[k])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("case", choices=("payout-reverse", "search"))
    ap.add_argument("--stall-every", type=float, default=0.0, help="payout-reverse: a 1.2 s stall every S s")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--minutes", type=float, default=4.0)
    ap.add_argument("--slowdown", type=float, default=0.0)
    args = ap.parse_args(argv)
    if args.case == "payout-reverse":
        stalls = [(t, 1.2) for t in np.arange(3.0, 60.0, args.stall_every)] if args.stall_every > 0 else []
        r = run([(2.0, "speed", 2.0), (40.0, "speed", -2.0)], stalls, 60.0, args.slowdown)
        report(f"pay-out then haul-in, stall every {args.stall_every:g} s", r)
    else:
        commands, stalls, end, jitter = search_plan(args.seed, args.minutes)
        r = run(commands, stalls, end, args.slowdown, jitter)
        report(f"search seed {args.seed}, {args.minutes:g} min, slowdown {args.slowdown:g}", r)
    return 0


if __name__ == "__main__":
    sys.exit(main())
