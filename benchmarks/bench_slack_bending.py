"""Speed of the PE2020 Sec. 6.2 case on the paper's mesh: L = 200 m, N = 20, P = 4, f = 0.2 Hz, cage body.

Real time per CPU second of the solver alone (50 Hz ticks through ``advance_to`` with the fairlead's
circular orbit of motion.kind circle, a = 2 m, ramped over 5 s, as the node feeds it; compile and the first tick untimed), for alpha = 0, 1
(EI = alpha * 2.62 kN m^2), dg.damping = explicit / implicit and, with bending, dg.bending_multirate
false / true (K: the multirate's macro step in substeps), all in one process so the figures compare as
ratios on a shared machine. The window starts after the orbit's ramp (5 s) and covers the
slack and snap of the first full period. ``--baseline DIR`` runs every configuration in another checkout
too (imported as tether_sim_base, bench_tick.load_baseline), alternating with this one, best of ``--repeat``.

    PYTHONPATH=. python benchmarks/bench_slack_bending.py [--start 5] [--seconds 10] [--alphas 0 1]
        [--dampings explicit implicit] [--multirate off on] [--baseline DIR] [--repeat 1]
"""
import argparse
import importlib
import os
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from benchmarks.studies.slack_bending_ladder import EI_STAR  # noqa: E402


def tree(package):
    """(load_config, build_motion, build_solver) of a package (tether_sim or the baseline's tether_sim_base)."""
    return (importlib.import_module(f"{package}.io.params").load_config,
            importlib.import_module(f"{package}.physics.motion").build_motion,
            importlib.import_module(f"{package}.solvers.factory").build_solver)


def run(alpha, damping, start, seconds, N=20, rate=50.0, multirate=True, package="tether_sim"):
    """(real time per CPU s, substeps per simulated s, multirate K) of one configuration."""
    load_config, build_motion, build_solver = tree(package)
    overrides = {"cable.EI": alpha * EI_STAR, "motion.kind": "circle", "motion.amplitude": 2.0, "motion.frequency": 0.2,
                 "motion.ramp_time": 5.0, "duration": 60.0, "dg.n_elements": int(N), "dg.order": 4,
                 "dg.damping": damping, "dg.bending_multirate": multirate}
    cfg = load_config(ROOT / "config" / "ropos_L200_paper.yaml", overrides)
    motion = build_motion(cfg.motion, cfg.ship_end.position)
    s = build_solver(cfg)
    t0 = s.time
    k = 0
    cpu = 0.0
    steps = 0
    while k / rate < start + seconds - 1e-9:
        k += 1
        p, v, _ = motion.at(k / rate)
        s.set_end_motion("ship", p, v)
        timed = k / rate > start + 1.0 / rate
        c0 = time.process_time()
        n = s.advance_to(t0 + k / rate)
        if timed:
            cpu += time.process_time() - c0
            steps += n or 0
        s.drain_end_tensions()
    return seconds / cpu, steps / seconds, s.bending_multirate_k


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--start", type=float, default=5.0)
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--alphas", type=float, nargs="+", default=[0.0, 1.0])
    ap.add_argument("--dampings", nargs="+", default=["explicit", "implicit"], choices=["explicit", "implicit", "rkl2"])
    ap.add_argument("--multirate", nargs="+", default=["off", "on"], choices=["off", "on"])
    ap.add_argument("--n", type=int, default=20)
    ap.add_argument("--baseline", help="another checkout: run each configuration there too (same process)")
    ap.add_argument("--repeat", type=int, default=1, help="best of this many runs per configuration and tree")
    args = ap.parse_args(argv)
    trees = [("this", "tether_sim")]
    if args.baseline:
        from benchmarks.bench_tick import load_baseline

        load_baseline(args.baseline)
        trees.insert(0, ("baseline", "tether_sim_base"))
    print(f"# {time.strftime('%Y-%m-%d %H:%M')} load {os.getloadavg()[0]:.1f}; L = 200 m, N = {args.n}, P = 4, "
          f"window {args.start:g}-{args.start + args.seconds:g} s" + (f"; baseline {args.baseline}" if args.baseline else ""))
    for alpha in args.alphas:
        for damping in args.dampings:
            for multirate in ([m == "on" for m in args.multirate] if alpha > 0 else [True]):
                best = {}
                for _ in range(args.repeat):
                    for label, package in trees:
                        r = run(alpha, damping, args.start, args.seconds, N=args.n, multirate=multirate, package=package)
                        if label not in best or r[0] > best[label][0]:
                            best[label] = r
                mr = f"multirate {'on, K = ' + str(best['this'][2]) if multirate else 'off':14s}" if alpha > 0 else " " * 24
                for label, _ in trees:
                    rt, per_s, k = best[label]
                    print(f"alpha {alpha:g} dg.damping {damping:8s} {mr} {label:8s}: {rt:6.3f} x real time per CPU s, "
                          f"{per_s:7.0f} substeps/s, {1e6 / (rt * per_s):6.1f} us per substep", flush=True)
                if args.baseline:
                    print(f"    ratio this / baseline (CPU): {best['this'][0] / best['baseline'][0]:.3f}", flush=True)
    print(f"# load {os.getloadavg()[0]:.1f} at the end")


if __name__ == "__main__":
    main()
