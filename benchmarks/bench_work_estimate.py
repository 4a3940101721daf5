"""The load-time work estimate (tether_sim/solvers/work.py) against the measured CPU time of the solvers.

    .venv/bin/python benchmarks/bench_work_estimate.py [--substeps 200]

For meshes of the ROPOS L = 200 m tether (DG, manual meshes, its axial damping explicit) and of the
hybrid file (segments), prints the estimated and the measured CPU seconds per simulated second and
their ratio. The stepping alone is timed (after a warm-up; no node, no outputs). Figures of
2026-11-27 in BENCHMARKS.md (measured / estimated 0.56-2.1).
"""

import argparse
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


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--substeps", type=int, default=200)
    args = ap.parse_args(argv)
    print(f"{'case':34s} {'substep s':>10s} {'estimate':>10s} {'measured':>10s} {'measured/est':>12s}  (CPU s per simulated s)")
    cases = [(f"dg N = {n}, P = {p}", "ropos_L200.yaml", {"dg.resolution": "manual", "dg.n_elements": n, "dg.order": p,
                                                          "work_limit": 0.0}) for n, p in DG]
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
