"""Real-time factor of the shipped live configurations at the resolution they choose (dg.resolution auto).

For each parameter file (default: config/ropos_L{200,500,975,1730}.yaml) and bending factor
(alpha = 0 as shipped, and alpha = 1: EI* = 2620 N m^2 set with ``cable.EI``, the mesh re-chosen
by the rule), the file's own configuration is built through the public interface
(``load_config`` -> ``build_solver``) and driven the way the node drives it: 50 Hz ticks of
``set_end_motion`` + ``advance_to`` on the file's fairlead motion (circle a = 2 m, f = 0.2 Hz,
ramped over one period), through slack and snap. Reported: the chosen mesh, the real-time factor
on thread CPU and on wall time, the tick median / p99 (wall), and the same for the paper-resolution
file (``*_paper.yaml``, N = 20, P = 4) run in the same process for a shorter stretch (``--paper``),
so the speed-up is a ratio taken in one process. The load average is printed with every line.

Usage: PYTHONPATH=. python benchmarks/bench_live_configs.py [--duration 30] [--alphas 0 1]
       [--paper 5] [--params config/ropos_L200.yaml ...] [--set dg.snap_tolerance=0.02 ...]
       [--json out/bench_live_configs.json]
"""

import argparse
import json
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks import drive  # noqa: E402
from tether_sim.io.params import load_config  # noqa: E402
from tether_sim.physics.motion import build_motion  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
LIVE = [f"config/ropos_L{n}.yaml" for n in (200, 500, 975, 1730)]
EI_STAR = 2620.0  # N m^2 [PE2020 Sec. 6.2]


def timed_run(config, duration):
    """Warm (untimed, fills the JIT cache) then timed run on the config's own fairlead motion."""
    motion = build_motion(config.motion, config.ship_end.position)

    def fairlead(t):
        pos, vel, _ = motion.at(t)
        return pos, vel

    drive.run(config, 0.2, motion=fairlead)
    out = drive.summary(drive.run(config, duration, motion=fairlead))
    out["mesh"] = f"N={config.dg.n_elements} P={config.dg.order} cfl={config.dg.cfl:g}"
    return out


def _line(label, r):
    return (f"  {label:<34s} {r['mesh']:<18s} RTF cpu {r['rtf_cpu']:8.1f}  wall {r['rtf']:7.1f}  "
            f"dt {r['time_step']:.3g} s  tick med/p99 {r['tick_median_ms']:6.2f}/{r['tick_p99_ms']:6.2f} ms  "
            f"load {r['load']:.1f}")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--params", nargs="+", default=LIVE)
    ap.add_argument("--alphas", type=float, nargs="+", default=[0.0, 1.0])
    ap.add_argument("--duration", type=float, default=30.0, help="simulated s of each live run")
    ap.add_argument("--paper", type=float, default=5.0, help="simulated s of the paper-resolution run (0: none)")
    ap.add_argument("--set", nargs="*", default=[], metavar="KEY=VALUE",
                    help="parameter overrides of the live files (e.g. dg.snap_tolerance=0.02); the mesh is re-chosen")
    ap.add_argument("--json", default="out/bench_live_configs.json")
    args = ap.parse_args(argv)
    print(f"bench_live_configs, {os.cpu_count()} cores, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, "
          f"{args.duration:g} s per live run at 50 Hz, load average {os.getloadavg()[0]:.2f}", flush=True)
    rows = []
    for params in args.params:
        for alpha in args.alphas:
            overrides = {"cable.EI": alpha * EI_STAR} if alpha else {}
            extra = {k: float(v) for k, v in (item.split("=", 1) for item in args.set)}
            live = load_config(ROOT / params, overrides={**overrides, **extra})
            r = timed_run(live, args.duration)
            r.update(params=params, alpha=alpha, kind="live")
            rows.append(r)
            print(_line(f"{Path(params).name} alpha={alpha:g}", r), flush=True)
            paper_path = ROOT / params.replace(".yaml", "_paper.yaml")
            if args.paper > 0 and paper_path.exists():
                p = timed_run(load_config(paper_path, overrides=overrides), args.paper)
                p.update(params=str(paper_path.relative_to(ROOT)), alpha=alpha, kind="paper")
                rows.append(p)
                print(_line(f"{paper_path.name} alpha={alpha:g}", p)
                      + f"  -> live/paper CPU speed-up x{r['rtf_cpu'] / p['rtf_cpu']:.1f}", flush=True)
    Path(args.json).parent.mkdir(parents=True, exist_ok=True)
    Path(args.json).write_text(json.dumps(rows, indent=1, default=float))
    print(f"wrote {args.json}")


if __name__ == "__main__":
    main()
