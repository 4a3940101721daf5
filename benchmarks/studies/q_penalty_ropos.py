"""The q-equation penalty form on the ROPOS snap (tension jump, the default since
2026-11-23, against PE2020 Eq. 24's lambda/2 [q]).

Runs the ROPOS case (cage body, circular fairlead a = 2 m, f = 0.2 Hz; benchmarks/ropos_case.py)
with dg.q_penalty_jump = strain and = tension for alpha = 0 and 1 and prints the first snap peak
(largest end tension in the window) at both ends, its time, the static tension, the largest
difference of the per-substep end tensions and the substep. The ship-end snap window is the one of
benchmarks/studies/resolution_ladder.py for L = 1730 m, 5-10 s for L = 200 m (docs/dg_solver.md).

    PYTHONPATH=. python benchmarks/studies/q_penalty_ropos.py [--length 1730] [--duration 20] [--alphas 0 1] [--n 20] [--cfl 0.5]
"""

import argparse
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from benchmarks import drive  # noqa: E402
from benchmarks import ropos_case as rc  # noqa: E402


def peak(t, T, window):
    m = (t >= window[0]) & (t <= window[1])
    k = np.argmax(np.where(m, T, -np.inf))
    return T[k], t[k]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--length", type=float, default=1730.0)
    ap.add_argument("--duration", type=float, default=20.0)
    ap.add_argument("--alphas", type=float, nargs="+", default=[0.0, 1.0])
    ap.add_argument("--window", type=float, nargs=2, default=None)
    ap.add_argument("--n", type=int, default=20, help="elements (P = 4)")
    ap.add_argument("--cfl", type=float, default=0.5)
    args = ap.parse_args(argv)
    window = args.window or ((5.0, 10.0) if args.length < 500 else (0.0, args.duration))
    for alpha in args.alphas:
        runs = {}
        for form in ("strain", "tension"):
            cfg = rc.ropos_config(args.length, alpha=alpha, duration=args.duration, n_elements=args.n, cfl=args.cfl)
            cfg = replace(cfg, dg=replace(cfg.dg, q_penalty_jump=form))
            res = drive.run(cfg, args.duration, motion=rc.fairlead_motion)
            runs[form] = res
            line = f"L={args.length:g} N={args.n} alpha={alpha:g} {form:8s} dt={res['t'][1] - res['t'][0]:.4g} s"
            for end in ("ship", "vehicle"):
                p, tp = peak(res["t"], res[end], window)
                line += f" | {end} static {res[end][0]:.2f} N peak {p:.2f} N at {tp:.4f} s"
            print(line + f" | cpu {res['cpu']:.1f} s", flush=True)
        a, b = runs["strain"], runs["tension"]
        n = min(a["t"].size, b["t"].size)
        for end in ("ship", "vehicle"):
            pa, pb = peak(a["t"], a[end], window)[0], peak(b["t"], b[end], window)[0]
            d = np.max(np.abs(a[end][:n] - b[end][:n]))
            print(f"  {end}: peak change {100 * (pb / pa - 1):+.4f} %, largest per-substep difference {d:.2f} N "
                  f"({100 * d / pa:.3f} % of the peak)", flush=True)


if __name__ == "__main__":
    main()
