"""How many Gauss points transmit tension (damping coefficient Z != 0) in the slack phase of the PE2020 Sec. 6.2
case on the paper's mesh (L = 200 m, N = 20, P = 4, alpha as given, dg.damping implicit, the fairlead orbit of
bench_slack_bending.py): the size of the block a damping solve restricted to those points would have
(docs/performance.md "What blocks 2x, with numbers").

Per 50 Hz tick in the window, after the tick: the points with Z != 0 (of N Q), the span from the first to the
last of them, and the points clipped for the step (constant damping tension); printed as quantiles over the window.

    PYTHONPATH=. python benchmarks/probes/taut_block_probe.py [--alpha 1] [--start 5] [--seconds 3]
"""
import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from benchmarks.probes.damping_rhs_gate import sec62_case  # noqa: E402
from tether_sim.solvers.dg.damping_layout import WP_TC, WP_Z  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--alpha", type=float, default=1.0)
    ap.add_argument("--start", type=float, default=5.0)
    ap.add_argument("--seconds", type=float, default=3.0)
    args = ap.parse_args(argv)
    motion, s = sec62_case(args.alpha)
    print(f"# {time.strftime('%Y-%m-%d %H:%M')} load {os.getloadavg()[0]:.1f}; alpha {args.alpha:g}, window "
          f"{args.start:g}-{args.start + args.seconds:g} s", flush=True)
    rate, t0, k, rows = 50.0, s.time, 0, []
    while k / rate < args.start + args.seconds - 1e-9:
        k += 1
        p, v, _ = motion.at(k / rate)
        s.set_end_motion("ship", p, v)
        s.advance_to(t0 + k / rate)
        s.drain_end_tensions()
        if k / rate > args.start:
            wp = s._damp.wp
            taut = np.flatnonzero(wp[:, :, WP_Z].ravel() != 0.0)
            span = taut[-1] - taut[0] + 1 if taut.size else 0
            rows.append((taut.size, span, int((wp[:, :, WP_TC] != 0.0).sum())))
    r = np.array(rows, float)
    q = [0.0, 0.1, 0.25, 0.5, 0.75, 0.9, 1.0]
    print(f"points {s._damp.wp.shape[0] * s._damp.wp.shape[1]}, ticks {len(r)}; quantiles {q}")
    for i, name in enumerate(("points with Z != 0", "their span", "clipped points")):
        print(f"  {name:20s} " + " ".join(f"{x:6.1f}" for x in np.quantile(r[:, i], q)))
    print(f"# load {os.getloadavg()[0]:.1f} at the end")


if __name__ == "__main__":
    main()
