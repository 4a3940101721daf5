"""The one-hour soak's input, offline and seeded: a jittery, stalling pose publisher and late ticks
against the stepping driver (no ROS, no wall clock; minutes of CPU for an hour).

    .venv/bin/python benchmarks/jitter_soak.py [--minutes 60] [--seed 1] [--min-spacing auto|0|S]
        [--params FILE] [--set KEY=VALUE ...] [--stall P] [--slowdown K]

The tether of ``config/ropos_L200.yaml`` (README mesh, N = 2, P = 4) under the soak's heave (0.5 m at
0.1 Hz: the tether never goes slack, so every slack warning, snap or rejected re-tensioning is
false). The publisher sends a pose every 50 ms, reading its clock (the stamp) and then its position;
with probability 5 % it is preempted in between for an exponential time of mean 10 ms (the stamp
is that much later than the position). With probability 2 % a send is stalled by 50-400 ms, and the
overdue poses then go out back to back, 0.5 ms apart, as the soak's loop does. Every 270 s the
publisher falls silent for 3 s (a dropout: input lost, held, resumed, blended). The node's timer
fires every 20 ms; 1 % of its ticks come 20-300 ms late. ``--min-spacing``: the pose inputs'
shortest knot interval (auto: the node's, half an output period; 0: every sample a knot, the
behaviour before 2026-11-27). Prints the counts of slack warnings, snap events and rejected
re-tensionings, the largest commanded ship-end speed and the end tension range (x static).

``--params`` / ``--set``: another file and overrides (YAML values), e.g. the hybrid solver with a
winch schedule. ``--stall P``: with probability P a tick comes 1.1-3 x ``node.max_lag`` late (the
node behind: the driver re-synchronises); the end tensions of the states within 1 s after each
re-synchronisation are reported apart (x static; they are marked degraded, as the node does).
``--slowdown K``: the solver behind (as test/ros/test_overload.py): a fake wall clock charged K x the
simulated time of every advance, the node's wall budget per tick (``node.tick_budget`` of a period);
above 1 / tick_budget the driver caps its ticks, lags and re-synchronises at ``node.max_lag``.
"""

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]


class FakeWall:
    """The driver's wall clock when --slowdown is given: the tick's clock plus what the solver was charged
    (also used by test/ros/test_overload.py)."""

    t = 0.0

    @classmethod
    def perf_counter(cls):
        return cls.t


class SlowSolver:
    """The real solver; every substep costs ``slowdown`` x its simulated time on the fake wall clock."""

    def __init__(self, inner, slowdown):
        self.inner, self.slowdown = inner, slowdown

    def __getattr__(self, name):
        return getattr(self.inner, name)

    @property
    def time(self):
        return self.inner.time

    def advance_to(self, t):
        t0 = self.inner.time
        n = self.inner.advance_to(t)
        FakeWall.t += self.slowdown * (self.inner.time - t0)
        return n


def run(minutes, seed, min_spacing, params=None, overrides=None, stall=0.0, slowdown=0.0):
    from tether_sim.io.inputs import EndPoseInput
    from tether_sim.io.params import load_config
    from tether_sim.physics.snap import NumericalSnapWarning, SlackStarted, SnapEvent
    from tether_sim.ros.driver import SimulationDriver

    config = load_config(params or REPO / "config" / "ropos_L200.yaml", overrides or {})
    node = config.node
    inp = EndPoseInput.for_node("ship", node)
    if min_spacing != "auto":
        inp.min_spacing = max(float(min_spacing), 0.0)
    rng = np.random.default_rng(seed)
    w = 2 * math.pi * 0.1

    # the publisher's sends over the whole run: (arrival = stamp, stamp, time the position was read)
    sends, t_end, k, busy_until = [], 60.0 * minutes + 1.0, 0, 0.0
    while k * 0.05 < t_end:
        due = k * 0.05
        k += 1
        if due % 270.0 > 267.0:
            continue  # dropout
        if rng.random() < 0.02:
            busy_until = max(busy_until, due + rng.uniform(0.05, 0.4))  # stalled
        read = max(due, busy_until)
        busy_until = read + 0.0005 if read > due else busy_until  # overdue sends go out back to back
        stamp = read + (rng.exponential(0.010) if rng.random() < 0.05 else rng.uniform(0.0, 2e-4))
        sends.append((stamp, read))
    sends.sort()
    stamps = np.array([s for s, _ in sends])
    z = 0.5 * np.sin(w * np.array([r for _, r in sends]))

    fed = 0

    def feed(now):
        nonlocal fed
        while fed < len(stamps) and stamps[fed] <= now:
            inp.add_pose(float(stamps[fed]), (0.0, 0.0, float(z[fed])), (0, 0, 0, 1), now=now)
            fed += 1

    feed(0.3)
    if slowdown > 0.0:
        import tether_sim.ros.driver as driver_module
        from tether_sim.solvers.factory import build_solver

        driver_module.wallclock = FakeWall
        driver = SimulationDriver(config, {"ship": inp}, solver_factory=lambda c: SlowSolver(build_solver(c), slowdown),
                                  wall_budget=node.tick_budget / node.output_rate)
    else:
        driver = SimulationDriver(config, {"ship": inp})
    driver.start(0.3)
    static = np.array(driver.static_tensions)
    counts = {"slack": 0, "snap": 0, "numerical": 0}
    vmax, lo, hi, late_ticks, cpu0 = 0.0, np.inf, 0.0, 0, time.process_time()
    now, skip_until = 0.3, 0.0
    resynced, after = -np.inf, [np.inf, 0.0, 0]  # after a re-synchronisation: min, max (x static), states
    while now < t_end:
        now += 1.0 / node.output_rate
        if now < skip_until:
            continue
        if rng.random() < 0.01:
            skip_until = now + rng.uniform(0.02, 0.3)  # this tick and those until then come late
            late_ticks += 1
            continue
        if stall > 0.0 and rng.random() < stall:
            skip_until = now + rng.uniform(1.1, 3.0) * node.max_lag  # the node behind: a re-synchronisation
            late_ticks += 1
            continue
        feed(now)
        FakeWall.t = max(FakeWall.t, now)
        report = driver.tick(now)
        for ev in report.events:
            key = "slack" if isinstance(ev, SlackStarted) else "snap" if isinstance(ev, SnapEvent) else \
                "numerical" if isinstance(ev, NumericalSnapWarning) else None
            if key:
                counts[key] += 1
                print(f"  t = {now:8.2f} s  {type(ev).__name__} at {ev.location}", flush=True)
        vmax = max(vmax, float(np.linalg.norm(driver._end_state["ship"][1])))
        if report.dropped > 0.0:
            resynced = now
        f = driver.solver.end_forces()
        ratio = np.array([f.ship_tension, f.vehicle_tension]) / static
        if now - resynced < 1.0:
            after = [min(after[0], ratio.min()), max(after[1], ratio.max()), after[2] + 1]
        elif now > 10.0 and not report.blending:
            lo, hi = min(lo, ratio.min()), max(hi, ratio.max())
    print(f"{minutes:g} min, seed {seed}, knot spacing {spacing * 1e3:g} ms: {len(stamps)} poses, {late_ticks} late ticks; "
          f"slack warnings {counts['slack']}, snap events {counts['snap']}, rejected re-tensionings "
          f"{counts['numerical']}; largest commanded ship speed {vmax:.3f} m/s (heave 0.314); end tension "
          f"{lo:.3f}-{hi:.3f} x static outside blends; {time.process_time() - cpu0:.0f} s CPU", flush=True)
    if stall > 0.0 or slowdown > 0.0:
        print(f"re-synchronisations {driver.resyncs}; the {after[2]} states within 1 s after them: end tension "
              f"{after[0]:.3f}-{after[1]:.3f} x static", flush=True)
    return counts


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--minutes", type=float, default=60.0)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--min-spacing", default="auto")
    ap.add_argument("--params", help="parameter file (default: config/ropos_L200.yaml)")
    ap.add_argument("--set", nargs="*", default=[], metavar="KEY=VALUE", help="overrides (YAML values)")
    ap.add_argument("--stall", type=float, default=0.0, help="probability per tick of a stall beyond node.max_lag")
    ap.add_argument("--slowdown", type=float, default=0.0, help="the solver at 1/K x real time (a fake wall clock)")
    args = ap.parse_args(argv)
    import yaml

    overrides = {k: yaml.safe_load(v) for k, v in (item.split("=", 1) for item in args.set)}
    counts = run(args.minutes, args.seed, args.min_spacing, args.params, overrides, args.stall, args.slowdown)
    return 1 if any(counts.values()) else 0


if __name__ == "__main__":
    sys.exit(main())
