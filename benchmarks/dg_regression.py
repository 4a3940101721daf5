"""Bit-level regression check of the DG solver after kernel optimisations.

Runs the ROPOS case (cage body, circular fairlead a = 2 m, f = 0.2 Hz, through slack and snap)
for alpha = 0 and 1 and records the end tensions at every substep plus state() and end_forces()
at the end. ``--save ref.npz`` stores a reference; ``--compare ref.npz`` reports the largest
relative differences (acceptance: <= 1e-9 of the peak tension).

Usage: PYTHONPATH=. python benchmarks/dg_regression.py --save /tmp/dg_ref.npz [--length 1730 --duration 10]
       PYTHONPATH=. python benchmarks/dg_regression.py --compare /tmp/dg_ref.npz
"""

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks import drive  # noqa: E402
from benchmarks import ropos_case as rc  # noqa: E402


def record(length, duration, alphas=(0.0, 1.0)):
    """Arrays keyed '<alpha>/<field>' for every alpha."""
    out = {}
    for alpha in alphas:
        cfg = rc.ropos_config(length, alpha=alpha)
        res = drive.run(cfg, duration, motion=rc.fairlead_motion)
        sol = res["solver"]
        st = sol.state()
        ef = sol.end_forces()
        key = f"{alpha:g}"
        out[key + "/t"] = res["t"]
        out[key + "/ship"] = res["ship"]
        out[key + "/vehicle"] = res["vehicle"]
        for name in ("position", "velocity", "tension", "strain", "curvature", "bending_moment"):
            out[key + "/state_" + name] = np.asarray(getattr(st, name))
        for name, v in st.extra.items():
            out[key + "/extra_" + name] = np.asarray(v)
        out[key + "/end_forces"] = np.concatenate([ef.ship_force, ef.vehicle_force, ef.ship_moment,
                                                   ef.vehicle_moment, [ef.ship_tension, ef.vehicle_tension]])
        print(f"alpha={alpha:g}: {res['substeps']} substeps, ship T min {res['ship'].min():.4g} N "
              f"max {res['ship'].max():.4g} N, cpu {res['cpu']:.2f} s", flush=True)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--length", type=float, default=1730.0)
    ap.add_argument("--duration", type=float, default=10.0)
    ap.add_argument("--save")
    ap.add_argument("--compare")
    args = ap.parse_args(argv)
    rec = record(args.length, args.duration)
    if args.save:
        np.savez(args.save, length=args.length, duration=args.duration, **rec)
    if args.compare:
        ref = np.load(args.compare)
        worst = 0.0
        for k, v in rec.items():
            r = ref[k]
            if r.shape != v.shape:
                print(f"{k}: shape {v.shape} != reference {r.shape}")
                worst = np.inf
                continue
            scale = max(np.max(np.abs(r)), 1e-300)
            d = float(np.max(np.abs(v - r)) / scale) if r.size else 0.0
            worst = max(worst, d)
            print(f"  {k:<28s} max |diff| / max |ref| = {d:.3e}")
        print(f"worst relative difference {worst:.3e} ({'OK' if worst <= 1e-9 else 'EXCEEDS 1e-9'})")


if __name__ == "__main__":
    main()
