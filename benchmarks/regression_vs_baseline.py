"""Bit-level comparison of this checkout's solvers with another checkout's, over many configurations.

``dg_regression.py`` compares one case (ROPOS, cage body) against a saved file; this script builds
the same configurations in both trees in one process (the other checkout imported as
``tether_sim_base`` through bench_tick.load_baseline), drives a prescribed ship end on a small
circle at 50 Hz for --duration s, and compares state() (position, velocity, tension, strain,
curvature, bending moment), end_forces() and the drained end tensions. Cases: every shipped solver
file and variants for bending, implicit damping, current, seabed, free surface, the linear law,
waves (the JONSWAP file), the winch (the descent file), the hybrid solver and a 24-element mesh
(the structure-of-arrays momentum path). Each case is driven twice: set_end_motion + advance_to with the
outputs read at the end, and solver.tick with state() read every tick (a node's calls). Prints the
largest relative difference of each case and which arrays differ.

Usage: PYTHONPATH=. python benchmarks/regression_vs_baseline.py --baseline /path/to/other/checkout [--duration 3]
       [--modes advance tick] [--only ropos_L200_hybrid goyal_perkins] [--set hybrid.reuse_factorisation=false]
"""

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from benchmarks.bench_tick import load_baseline  # noqa: E402

FILES = ("ropos_L200", "ropos_L500", "ropos_L1730", "ropos_aframe_jonswap", "ropos_descent", "koh_swinging_cable",
         "cantilever", "ring_beam", "goyal_perkins", "ropos_L200_hybrid", "ropos_L1730_hybrid")
VARIANTS = (
    ("ropos_L200", {"cable.EI": 2620.0}),
    ("ropos_L200", {"dg.damping": "implicit", "dg.resolution": "manual", "dg.n_elements": 4}),
    ("ropos_L200", {"environment.current_z": (-300.0, 0.0), "environment.current_x": (0.2, 0.8),
                    "environment.current_y": (0.0, 0.1)}),
    ("ropos_L200", {"environment.seabed": True, "environment.seabed_z": -199.0, "environment.seabed_friction": 0.3}),
    ("ropos_L200", {"environment.free_surface": True}),
    ("ropos_L200", {"cable.material": "linear"}),
    ("ropos_L500", {"cable.EI": 2620.0, "dg.damping": "implicit", "dg.resolution": "manual", "dg.n_elements": 6}),
    ("ropos_L1730", {"dg.n_elements": 24, "dg.resolution": "manual"}),
)


ARRAYS = ("position", "velocity", "tension", "strain", "curvature", "bending_moment", "end_forces", "drained")  # outputs()'s


def outputs(build, load, name, overrides, duration, mode="advance"):
    """The compared arrays of one run. mode "advance": set_end_motion + advance_to per 50 Hz step,
    outputs read at the end only; "tick": one solver.tick per step with state() read after each, as
    a node does (the DG solver's output evaluation is then reused as the next tick's first stage)."""
    cfg = load(ROOT / "config" / f"{name}.yaml", overrides=dict(overrides) or None)
    solver = build(cfg)
    p0 = np.asarray(cfg.ship_end.position, float)
    prescribed = cfg.ship_end.kind == "prescribed"
    t = solver.time
    for _ in range(int(round(duration / 0.02))):
        t += 0.02
        # a prescribed ship end follows a 0.5 m circle; other ends are left as configured
        motion = (p0 + 0.5 * np.array((np.cos(t) - 1.0, np.sin(t), 0.0)), 0.5 * np.array((-np.sin(t), np.cos(t), 0.0)))
        if mode == "tick":
            solver.tick(t, ship=motion if prescribed else None, drain=False)
            solver.state()
            continue
        if prescribed:
            solver.set_end_motion("ship", *motion)
        solver.advance_to(t)
    st = solver.state()
    arrays = [np.asarray(getattr(st, k), float) for k in ARRAYS[:6]]
    ef = solver.end_forces()
    arrays.append(np.concatenate([np.ravel(np.asarray(v, float)) for v in vars(ef).values()
                                  if np.asarray(v).dtype.kind == "f"]))
    arrays.append(np.concatenate([np.ravel(np.asarray(x, float)) for x in solver.drain_end_tensions()]))
    return arrays


def rel_diff(a, b):
    if a.shape != b.shape:
        return np.inf
    if a.size == 0:
        return 0.0
    return float(np.max(np.abs(a - b))) / max(1e-300, float(np.max(np.abs(b))))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--baseline", required=True, help="the other checkout (its tether_sim/ is copied and renamed)")
    ap.add_argument("--duration", type=float, default=3.0)
    ap.add_argument("--modes", nargs="+", choices=("advance", "tick"), default=["advance", "tick"],
                    help="the call paths compared (default both)")
    ap.add_argument("--only", nargs="+", default=None, metavar="NAME",
                    help="only the cases of these files (e.g. ropos_L200_hybrid goyal_perkins)")
    ap.add_argument("--set", nargs="+", default=[], metavar="KEY=VALUE",
                    help="overrides of this tree's configurations only (e.g. a new key whose off value must reproduce "
                         "the baseline: hybrid.reuse_factorisation=false)")
    args = ap.parse_args(argv)
    mine = {k: {"true": True, "false": False}.get(v.lower(), v) for k, v in (x.split("=", 1) for x in args.set)}
    factory_b, _ = load_baseline(args.baseline)
    import tether_sim_base.io.params as params_b

    from tether_sim.io.params import load_config
    from tether_sim.solvers.factory import build_solver
    worst = 0.0
    for mode in args.modes:
        for name, overrides in [(f, {}) for f in FILES] + list(VARIANTS):
            if args.only and name not in args.only:
                continue
            a = outputs(build_solver, load_config, name, {**dict(overrides), **mine}, args.duration, mode)
            b = outputs(factory_b.build_solver, params_b.load_config, name, overrides, args.duration, mode)
            each = [rel_diff(x, y) for x, y in zip(a, b)]
            d = max(each)
            worst = max(worst, d)
            differ = ", ".join(f"{n} {e:.1e}" for n, e in zip(ARRAYS, each) if e != 0.0)
            print(f"{mode:7s} {name:22s} {str(overrides)[:60]:60s} {len(a)} arrays, "
                  f"largest relative difference {d:.3e}" + (f" ({differ})" if differ else ""), flush=True)
    print(f"worst {worst:.3e}")
    return 0 if worst == 0.0 else 1


if __name__ == "__main__":
    sys.exit(main())
