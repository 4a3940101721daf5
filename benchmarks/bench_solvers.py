"""Real-time factor of each solver through the public interface (build_solver / advance_to).

Cases: ROPOS L = 1730 m and 200 m (DG: N = 20, P = 4; alpha = 0, 1, 100; hybrid: its config
defaults), circular fairlead a = 2 m at f = 0.2 Hz through slack and snap, driven at the node's
50 Hz output rate; and, when their parameter files exist, the scenario configs of the other
benchmarks (config/koh_swinging_cable.yaml, ring_beam.yaml, goyal_perkins.yaml), run as
configured (no end motion) for a short stretch.

Each case is built once to warm the numba cache (not timed), then built again and timed:
``build`` (construction incl. static solve), then ``--duration`` simulated seconds; reported are
the real-time factor (simulated s per wall s), substeps per simulated second, wall per substep,
and the 50 Hz tick median / p99.

Usage: PYTHONPATH=. python benchmarks/bench_solvers.py [--duration 20] [--solvers dg hybrid]
       [--lengths 200 1730] [--alphas 0 1 100] [--json out/bench_solvers.json]
"""

import argparse
import json
import os
import platform
import sys
import time
import traceback
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks import drive  # noqa: E402
from benchmarks import ropos_case as rc  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
SCENARIO_FILES = {
    "koh_swinging_cable": "config/koh_swinging_cable.yaml",
    "ring_beam": "config/ring_beam.yaml",
    "goyal_perkins": "config/goyal_perkins.yaml",
}


def time_case(name, config, duration, motion=None, warm_duration=0.2):
    """Warm-up run (compiles/caches kernels), then the timed run; returns the summary dict."""
    drive.run(config, warm_duration, motion=motion)
    res = drive.run(config, duration, motion=motion)
    out = drive.summary(res)
    out["case"] = name
    out["duration"] = duration
    return out


def scenario_configs(names=None):
    """(name, SimConfig) of the scenario parameter files present in the repository (all, or names)."""
    from tether_sim.io.params import load_config

    for name, rel in SCENARIO_FILES.items():
        if names and name not in names:
            continue
        path = ROOT / rel
        if path.exists():
            yield name, load_config(path)


def _print(row):
    print(f"  {row['case']:<34s} RTF={row['rtf']:9.2f} (cpu {row['rtf_cpu']:9.2f})  dt={row['time_step']:.3g}s  "
          f"substeps/s={row['substeps_per_s']:9.0f}  us/substep={row['us_per_substep']:7.2f}  "
          f"tick med/p99={row['tick_median_ms']:7.2f}/{row['tick_p99_ms']:7.2f} ms  build={row['build_wall']:.2f}s load={row['load']:.1f}",
          flush=True)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=20.0, help="simulated seconds per timed ROPOS run")
    ap.add_argument("--scenario-duration", type=float, default=2.0)
    ap.add_argument("--solvers", nargs="+", default=["dg", "hybrid"])
    ap.add_argument("--lengths", type=float, nargs="+", default=[1730.0, 200.0])
    ap.add_argument("--alphas", type=float, nargs="+", default=[0.0, 1.0, 100.0])
    ap.add_argument("--no-scenarios", action="store_true")
    ap.add_argument("--scenarios", nargs="+", choices=tuple(SCENARIO_FILES), help="only these scenario configs")
    ap.add_argument("--cage", default="body", choices=("body", "force"),
                    help="force: cage as its submerged weight (cost figures while body coupling is missing)")
    ap.add_argument("--damping", default="explicit", choices=("explicit", "implicit"), help="dg.damping of the ROPOS DG runs")
    ap.add_argument("--json", default="out/bench_solvers.json")
    args = ap.parse_args(argv)
    print(f"bench_solvers on {platform.machine()}, {os.cpu_count()} cores, "
          f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}; ROPOS runs {args.duration} s at 50 Hz")
    rows = []
    for solver in args.solvers:
        for length in args.lengths:
            alphas = args.alphas if solver == "dg" else [0.0]
            for alpha in alphas:
                name = f"{solver} ROPOS L={length:.0f} alpha={alpha:g}" + (" (cage=force)" if args.cage == "force" else "")
                damping = args.damping if solver == "dg" else "explicit"
                if damping != "explicit":
                    name += f" ({damping} damping)"
                try:
                    cfg = rc.ropos_config(length, alpha=alpha, solver=solver, cage=args.cage, damping=damping)
                    row = time_case(name, cfg, args.duration, motion=rc.fairlead_motion)
                except Exception as exc:  # a missing or failing solver is reported, not fatal
                    print(f"  {name:<34s} FAILED: {type(exc).__name__}: {exc}")
                    traceback.print_exc(limit=2, file=sys.stdout)
                    continue
                row.update(solver=solver, length=length, alpha=alpha, cage=args.cage, damping=damping,
                           load_avg=os.getloadavg())
                rows.append(row)
                _print(row)
    if not args.no_scenarios:
        for name, cfg in scenario_configs(args.scenarios):
            try:
                row = time_case(f"{cfg.solver} {name}", cfg, args.scenario_duration)
            except Exception as exc:
                print(f"  {name:<34s} FAILED: {type(exc).__name__}: {exc}")
                continue
            row.update(solver=cfg.solver)
            rows.append(row)
            _print(row)
    Path(args.json).parent.mkdir(parents=True, exist_ok=True)
    Path(args.json).write_text(json.dumps(rows, indent=1))
    print(f"wrote {args.json}")


if __name__ == "__main__":
    main()
