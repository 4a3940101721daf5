"""Speed of the PE2020 Sec. 6.2 case on the paper's mesh: L = 200 m, N = 20, P = 4, f = 0.2 Hz, cage body.

Real time per CPU second of the solver alone (50 Hz ticks through ``advance_to`` with the fairlead's
circular orbit of motion.kind circle, a = 2 m, ramped over 5 s, as the node feeds it; compile and the first tick untimed), for alpha = 0, 1
(EI = alpha * 2.62 kN m^2), dg.damping = explicit / implicit and, with bending, dg.bending_multirate
false / true (K: the multirate's macro step in substeps), all in one process so the figures compare as
ratios on a shared machine. The window starts after the orbit's ramp (5 s) and covers the
slack and snap of the first full period.

    PYTHONPATH=. python benchmarks/bench_slack_bending.py [--start 5] [--seconds 10] [--alphas 0 1]
"""
import argparse
import os
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from benchmarks.studies.slack_bending_ladder import case_config  # noqa: E402
from tether_sim.physics.motion import build_motion  # noqa: E402
from tether_sim.solvers.factory import build_solver  # noqa: E402


def run(alpha, damping, start, seconds, N=20, rate=50.0, multirate=True):
    cfg = case_config(200.0, 0.2, alpha, N, 12, {"dg.damping": damping, "dg.bending_multirate": multirate})
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
    ap.add_argument("--n", type=int, default=20)
    args = ap.parse_args(argv)
    print(f"# {time.strftime('%Y-%m-%d %H:%M')} load {os.getloadavg()[0]:.1f}; L = 200 m, N = {args.n}, P = 4, "
          f"window {args.start:g}-{args.start + args.seconds:g} s")
    for alpha in args.alphas:
        for damping in ("explicit", "implicit"):
            for multirate in ((False, True) if alpha > 0 else (True,)):
                rt, per_s, k = run(alpha, damping, args.start, args.seconds, N=args.n, multirate=multirate)
                mr = f"multirate {'on, K = ' + str(k) if multirate else 'off':14s}" if alpha > 0 else " " * 24
                print(f"alpha {alpha:g} dg.damping {damping:8s} {mr}: {rt:6.2f} x real time per CPU s, "
                      f"{per_s:7.0f} substeps/s", flush=True)
    print(f"# load {os.getloadavg()[0]:.1f} at the end")


if __name__ == "__main__":
    main()
