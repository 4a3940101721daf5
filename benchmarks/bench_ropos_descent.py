"""The ROPOS descent (config/ropos_descent.yaml) offline: MCAP, report, real-time factor.

    .venv/bin/python benchmarks/bench_ropos_descent.py [--duration S] [--out out/ropos_descent]

Runs ``tether-sim-offline``'s ``run_offline`` on the descent (the winch lowers the cage from 200 m
to 1730 m at 1 m/s in a 2 m, 0.2 Hz heave, holds, recovers), writes the MCAP and the report
(``tether-sim-report``: winch figures with tension against length and time, slack periods, snaps),
and prints the real-time factor: simulated seconds per thread-CPU second of the whole run (stepping,
snap detection, message building and MCAP writing) and per wall second, plus the stepping cost per
length band (thread-CPU time inside the solver's ``advance_to``, binned by the length at the tick),
and the load (``uptime``) at the start and end.
"""

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

from tether_sim.io.params import load_config
from tether_sim.report import make_report
from tether_sim.ros.offline import run_offline
from tether_sim.solvers.factory import build_solver

ROOT = Path(__file__).resolve().parents[1]


class TimedSolver:
    """Delegates to a solver; records (length at the start, simulated span, thread-CPU s) of each advance_to."""

    def __init__(self, solver, log):
        self.inner, self.log = solver, log

    def __getattr__(self, name):
        return getattr(self.inner, name)

    def advance_to(self, t):
        length, t0, c0 = self.inner.unstretched_length, self.inner.time, time.thread_time()
        k = self.inner.advance_to(t)
        self.log.append((length, t - t0, time.thread_time() - c0))
        return k


def load() -> str:
    return ", ".join(f"{x:.2f}" for x in os.getloadavg())


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--params", default=str(ROOT / "config/ropos_descent.yaml"))
    ap.add_argument("--duration", type=float, default=None, help="simulated s (default: the file's, the whole descent)")
    ap.add_argument("--out", default=str(ROOT / "out/ropos_descent"))
    args = ap.parse_args(argv)
    config = load_config(args.params)
    out = Path(args.out)
    log = []
    print(f"load average at the start: {load()}", flush=True)
    wall0, cpu0 = time.perf_counter(), time.thread_time()
    summary = run_offline(config, out / "ropos_descent.mcap", duration=args.duration, progress=False,
                          solver_factory=lambda c: TimedSolver(build_solver(c), log))
    wall, cpu = time.perf_counter() - wall0, time.thread_time() - cpu0
    duration = summary["duration"]
    print(f"load average at the end: {load()}")
    print(f"simulated {duration:.0f} s: thread-CPU {cpu:.1f} s (RTF {duration / cpu:.1f}), wall {wall:.1f} s "
          f"(RTF {duration / wall:.1f}); {summary['snap_events']} snap events, {summary['slack_warnings']} slack "
          f"warnings, {summary['divergences']} divergences")
    arr = np.array(log)
    edges = [0.0, 300.0, 600.0, 900.0, 1200.0, 1500.0, 1800.0]
    print("stepping cost by length (thread-CPU inside advance_to):")
    for lo, hi in zip(edges, edges[1:]):
        sel = (arr[:, 0] >= lo) & (arr[:, 0] < hi)
        if sel.any():
            sim, c = arr[sel, 1].sum(), arr[sel, 2].sum()
            print(f"  L in [{lo:.0f}, {hi:.0f}) m: {sim:7.1f} s simulated, {c:7.1f} s CPU, RTF {sim / c:7.1f}")
    result = make_report(out / "ropos_descent.mcap", out / "figures")
    print(result["markdown"].split("## Winch", 1)[-1] if "## Winch" in result["markdown"] else result["markdown"])
    return 0


if __name__ == "__main__":
    sys.exit(main())
