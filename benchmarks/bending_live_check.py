"""Bending multirate on the live meshes: the nested LDG at every stage against the multirate, one process.

The ROPOS case of bench_vs_moordyn.py (cage, fairlead orbit a = 2 m, f = 0.2 Hz, 50 Hz node ticks through
solver.tick, 10.2 s through the first slack and snap) on the mesh `dg.resolution: auto` picks for 1 %
(L = 200 m: N = 2, P = 4; 1730 m: N = 6, P = 2; dg.cfl 0.8), EI = alpha * EI_STAR. For each length and alpha:
dg.bending_multirate false (every stage) and true (the rule's K, printed), interleaved, best of --repeat thread
CPU per simulated second, the first snap peaks at both ends against the ladder's reference (N = 20, P = 4) and
the multirate's peaks against the every-stage run's.

Usage: PYTHONPATH=. python benchmarks/bending_live_check.py [--lengths 200 1730] [--alphas 1] [--repeat 5]
"""

import argparse
import os
import sys
import time
from dataclasses import replace
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks import ropos_case as rc  # noqa: E402
from benchmarks.bench_vs_moordyn import dg_cost, peak_error, reference_peaks, rule_rung  # noqa: E402


class _Factory:
    """build_solver with dg.bending_multirate set (dg_cost takes a factory)."""

    def __init__(self, multirate):
        self.multirate = multirate
        self.k = None

    def build_solver(self, cfg):
        from tether_sim.solvers import factory
        s = factory.build_solver(replace(cfg, dg=replace(cfg.dg, bending_multirate=self.multirate)))
        self.k = s.bending_multirate_k
        return s


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lengths", type=float, nargs="+", default=[200.0, 1730.0])
    ap.add_argument("--alphas", type=float, nargs="+", default=[1.0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--duration", type=float, default=10.2)
    args = ap.parse_args(argv)
    print(f"bending_live_check {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load {os.getloadavg()[0]:.1f}; "
          f"thread CPU ms per simulated s, best of {args.repeat} x {args.duration:g} s", flush=True)
    for length in args.lengths:
        n, order, cfl = rule_rung(length)
        for alpha in args.alphas:
            facs = {False: _Factory(False), True: _Factory(True)}
            for f in facs.values():  # warm the JIT caches, untimed
                dg_cost(f, rc, length, n, alpha, 0.1, cfl, 0, order)
            best, peaks = {}, {}
            for _ in range(args.repeat):
                for m, f in facs.items():
                    c, p = dg_cost(f, rc, length, n, alpha, args.duration, cfl, 0, order)
                    best[m] = min(best.get(m, c), c)
                    peaks[m] = p
            ref = reference_peaks(length, alpha)
            e0, e1 = peak_error(peaks[False], ref), peak_error(peaks[True], ref)
            rel = peak_error(peaks[True], peaks[False])
            print(f"  L={length:6.0f} N={n} P={order} alpha={alpha:g}: every stage {1e3 * best[False]:7.3f} ms/s "
                  f"(first snap error {100 * e0:.3f} %), multirate K={facs[True].k} {1e3 * best[True]:7.3f} ms/s "
                  f"(error {100 * e1:.3f} %), every stage / multirate {best[False] / best[True]:.3f}; peaks "
                  f"ship {peaks[True][0] / 1e3:.3f} / {peaks[False][0] / 1e3:.3f} kN, cage {peaks[True][1] / 1e3:.3f} / "
                  f"{peaks[False][1] / 1e3:.3f} kN, worst difference {100 * rel:.4f} %", flush=True)


if __name__ == "__main__":
    main()
