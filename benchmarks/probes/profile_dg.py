"""Where the DG solver's time goes, and what the speed-up options are worth (measured).

Variants of the ROPOS run (N = 20, P = 4 unless stated, 50 Hz ticks through ``advance_to``), each
timed in thread-CPU time so the shared machine's load does not enter, all in one process:

- ``base``: as configured (axial damping zeta = 45.5 kN s, alpha as given);
- ``no-damping``: zeta = 0 -- the stable step then follows the axial waves only; the gain is the
  upper bound of treating the damping term implicitly (IMEX), whose extra cost is not included;
- ``nq=P+1``: P + 1 Gauss points per element instead of ceil((3P+1)/2) (aliasing allowed):
  the cost per substep of a cheaper quadrature;
- ``alpha=1``: bending on (nested LDG), cost per substep;
- equal-DOF (N, P) pairs: cost per simulated second of h versus p.

The split between compiled code and Python is measured separately with py-spy
(docs/performance.md).

Usage: PYTHONPATH=. python benchmarks/probes/profile_dg.py [--length 200] [--duration 2] [--cage force]
"""

import argparse
import os
import sys
import time
from dataclasses import replace
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from benchmarks import drive  # noqa: E402
from benchmarks import ropos_case as rc  # noqa: E402


def measure(label, cfg, duration, patch_nq=False):
    """CPU time per simulated second, per substep, and the stable step of one variant."""
    import tether_sim.solvers.dg.solver as dgs

    original = dgs.element_operators
    if patch_nq:
        dgs.element_operators = lambda order, n_quad=None: original(order, n_quad=order + 1)
    try:
        drive.run(cfg, 0.1, motion=rc.fairlead_motion)  # compile / warm the cache
        res = drive.run(cfg, duration, motion=rc.fairlead_motion)
    finally:
        dgs.element_operators = original
    row = {
        "variant": label, "dt": res["time_step"], "substeps_per_s": res["substeps"] / duration,
        "cpu_per_s": res["cpu"] / duration, "us_per_substep": 1e6 * res["cpu"] / max(res["substeps"], 1),
        "rtf_cpu": duration / res["cpu"], "rtf_wall": duration / res["wall"],
    }
    print(f"  {label:<28s} dt={row['dt']:.3g}s substeps/s={row['substeps_per_s']:8.0f} "
          f"cpu/substep={row['us_per_substep']:7.1f} us  cpu/sim-s={1e3 * row['cpu_per_s']:9.1f} ms  "
          f"RTF(cpu)={row['rtf_cpu']:8.2f}  RTF(wall)={row['rtf_wall']:7.2f}", flush=True)
    return row


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--length", type=float, default=200.0)
    ap.add_argument("--duration", type=float, default=2.0)
    ap.add_argument("--alpha", type=float, default=0.0)
    ap.add_argument("--cage", default="body", choices=("body", "force"))
    args = ap.parse_args(argv)
    print(f"profile_dg L={args.length:.0f} m, {args.duration} s simulated per variant, cage={args.cage}, "
          f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load {os.getloadavg()[0]:.1f}")
    base = rc.ropos_config(args.length, alpha=args.alpha, cage=args.cage)
    rows = [measure("base N=20 P=4", base, args.duration)]
    rows.append(measure("no-damping (zeta=0)", replace(base, cable=replace(base.cable, damping=0.0)), args.duration))
    rows.append(measure("nq=P+1 quadrature", base, args.duration, patch_nq=True))
    if args.alpha == 0.0:
        rows.append(measure("alpha=1 (bending)", rc.ropos_config(args.length, alpha=1.0, cage=args.cage), args.duration))
    for n, p in ((50, 1), (33, 2), (25, 3), (14, 6)):
        rows.append(measure(f"N={n} P={p} (~same DOFs)", rc.ropos_config(args.length, alpha=args.alpha, cage=args.cage,
                                                                        n_elements=n, order=p), args.duration))
    b = rows[0]
    print("  ratios to base (cpu per simulated second):")
    for r in rows[1:]:
        print(f"    {r['variant']:<28s} x{b['cpu_per_s'] / r['cpu_per_s']:6.2f} faster "
              f"(step x{r['dt'] / b['dt']:6.2f}, cost/substep x{r['us_per_substep'] / b['us_per_substep']:5.2f})")


if __name__ == "__main__":
    main()
