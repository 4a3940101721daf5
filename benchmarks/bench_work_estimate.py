"""The load-time work estimate (tether_sim/solvers/work.py) against the measured CPU time of the solvers.

    .venv/bin/python benchmarks/bench_work_estimate.py [--substeps 200]
    .venv/bin/python benchmarks/bench_work_estimate.py --offline [ropos_L200.yaml:20 ...]

For meshes of the ROPOS L = 200 m tether (DG, manual meshes, its axial damping explicit) and of the
hybrid file (segments), prints the estimated and the measured CPU seconds per simulated second and
their ratio. The stepping alone is timed (after a warm-up; no node, no outputs). Figures of
2026-11-27 in BENCHMARKS.md (measured / estimated 0.56-2.1).

``--offline FILE:SECONDS ...``: whole tether-sim-offline runs instead, one process each, the CPU
they took (from the solver's start to the file's close) against the estimate they print before
they start (ros/offline.py run_estimate: this work estimate plus the outputs and the start).
"""

import argparse
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from tether_sim.io.params import load_config
from tether_sim.solvers.factory import build_solver
from tether_sim.solvers.work import estimate

ROOT = Path(__file__).resolve().parents[1]
DG = [(20, 4), (60, 2), (200, 2), (600, 2), (2000, 2)]
HYBRID = [50, 200, 800]


def measure(config, steps):
    solver = build_solver(config)
    dt = solver.stable_time_step()
    solver.advance_to(5 * dt)  # warm-up (compiled kernels, caches)
    t0 = time.process_time()
    solver.advance_to((5 + steps) * dt)
    return (time.process_time() - t0) / (steps * dt)


OFFLINE = ["ropos_L200.yaml:20", "ropos_L1730.yaml:20", "ropos_L200_paper.yaml:3", "ropos_L500_paper.yaml:6",
           "ropos_descent.yaml:40", "ropos_L200_hybrid.yaml:10", "ropos_L1730_hybrid.yaml:10",
           "koh_swinging_cable.yaml:3", "cantilever.yaml:20"]


def offline(runs):
    print(f"{'file':28s} {'simulated s':>11s} {'estimate':>9s} {'measured':>9s} {'measured/est':>12s}  (CPU s)")
    with tempfile.TemporaryDirectory() as tmp:
        for run in runs:
            name, _, seconds = run.partition(":")
            out = subprocess.run([sys.executable, "-m", "tether_sim.ros.offline", "--params", str(ROOT / "config" / name),
                                  "--duration", seconds or "10", "--output", f"{tmp}/out.mcap", "--no-progress"],
                                 capture_output=True, text=True)
            m = re.search(r"; ([0-9.e+-]+) s of CPU, ([0-9.e+-]+) s expected\)", out.stdout)
            if out.returncode != 0 or m is None:
                print(f"{name:28s} failed: {(out.stderr or out.stdout).strip().splitlines()[-1:]}", flush=True)
                continue
            cpu, est = float(m.group(1)), float(m.group(2))
            print(f"{name:28s} {float(seconds or 10):11.4g} {est:9.3g} {cpu:9.3g} {cpu / est:12.2f}", flush=True)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--substeps", type=int, default=200)
    ap.add_argument("--offline", nargs="*", metavar="FILE:SECONDS", default=None,
                    help=f"whole offline runs of config/FILE (default: {' '.join(OFFLINE)})")
    args = ap.parse_args(argv)
    if args.offline is not None:
        return offline(args.offline or OFFLINE)
    print(f"{'case':34s} {'substep s':>10s} {'estimate':>10s} {'measured':>10s} {'measured/est':>12s}  (CPU s per simulated s)")
    cases = [(f"dg N = {n}, P = {p}", "ropos_L200.yaml", {"dg.resolution": "manual", "dg.n_elements": n, "dg.order": p,
                                                          "work_limit": 0.0}) for n, p in DG]
    cases += [(f"dg N = {n}, P = 4, implicit (axial)", "ropos_L200_paper.yaml", {"dg.damping": "implicit",
                                                                            "dg.n_elements": n}) for n in (20, 40)]
    cases += [("dg N = 20, P = 4, implicit (bending)", "koh_swinging_cable.yaml", {"dg.n_elements": 20})]
    cases += [(f"hybrid n_segments = {n}", "ropos_L200_hybrid.yaml", {"hybrid.n_segments": n}) for n in HYBRID]
    for name, path, overrides in cases:
        config = load_config(ROOT / "config" / path, overrides)
        work = estimate(config)
        steps = args.substeps if config.solver == "dg" else 20
        if work.cpu * steps * work.substep > 120.0:
            steps = max(3, int(120.0 / (work.cpu * work.substep)))  # at most ~2 min per case
        cpu = measure(config, steps)
        print(f"{name:34s} {work.substep:10.3g} {work.cpu:10.3g} {cpu:10.3g} {cpu / work.cpu:12.2f}", flush=True)


if __name__ == "__main__":
    main()
