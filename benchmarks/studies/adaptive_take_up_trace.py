"""Step by step through the first take-up of the cross-check network's bending excursion tether, adaptive zoning.

The case of ``network_vs_moordyn.py`` with the excursion tether on the hybrid solver (EI ``--excursion-EI`` N m^2,
``--segments``, ``--dt``, ``hybrid.zoning: adaptive``), the closure check lifted (diagnosis only: the solver stops such
a run at its first take-up; docs/hybrid_solver.md, "Zoning"). For every dynamic step of the excursion tether from
``--from`` s on it prints the gap between the rod shape's end and the driven vehicle end before and after the step
(the zone evaluations re-close it), the largest angular velocity |omega| of the rod nodes and that of each rod
block's first node (the block's anchor: its frame is advanced in time by omega and the block's frames and shape are
re-derived from it, solver._commit), the largest curvature, the re-zonings so far and the rod blocks (chain nodes).

Usage: PYTHONPATH=. python benchmarks/studies/adaptive_take_up_trace.py [--excursion-EI 78.125] [--segments 30]
       [--dt 0.002] [--from 3.5] [--to 3.58]
"""

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from benchmarks.studies import network_vs_moordyn as nm  # noqa: E402
from benchmarks.studies import vehicle_force_convergence as vfc  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--excursion-EI", type=float, default=78.125)
    ap.add_argument("--segments", type=int, default=30)
    ap.add_argument("--dt", type=float, default=0.002)
    ap.add_argument("--from", dest="start", type=float, default=3.5)
    ap.add_argument("--to", type=float, default=3.58)
    args = ap.parse_args(argv)
    print(f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load {os.getloadavg()[0]:.1f}", flush=True)
    import tether_sim.solvers.hybrid.solver as hs
    from tether_sim.solvers.hybrid import zoning
    from tether_sim.solvers.hybrid.chain import rod_blocks
    from tether_sim.solvers.hybrid.layout import ROD_KAPPA, ROD_OMEGA

    hs.CLOSURE_LIMIT = float("inf")
    nm.set_excursion_bending(args.excursion_EI)
    step = hs.HybridRodCatenarySolver._step

    def gap(s):
        return float(np.linalg.norm(s.positions[-1] - s.end_motion[1].position_at(s.time)))

    def traced(s, h):
        if s.config.cable.EI <= 0.0 or s._rho is not None or s.time < args.start - 1e-12:
            return step(s, h)
        g0 = gap(s)
        step(s, h)
        rod = s.chain.kind == zoning.ROD
        blocks = rod_blocks(s.chain)
        w = np.linalg.norm(s.Y[:, ROD_OMEGA:ROD_OMEGA + 3], axis=1)
        kap = np.linalg.norm(s.Y[:, ROD_KAPPA:ROD_KAPPA + 3], axis=1)
        print(f"t {s.time:.4f} s, dt {h:.4f}: gap {g0:.4f} -> {gap(s):.4f} m, |omega| max {w[rod].max() if rod.any() else 0:.3g}"
              f" rad/s, at block starts {[round(float(w[a]), 2) for a, _ in blocks]}, |kappa| max "
              f"{kap[rod].max() if rod.any() else 0:.3g} 1/m, re-zonings {s.stats['rezonings']}, rod blocks {blocks}",
              flush=True)

    hs.HybridRodCatenarySolver._step = traced
    vfc.run_ours("hybrid", args.to, (args.segments, args.dt, "adaptive"))


if __name__ == "__main__":
    main()
