"""How far a hybrid line's end is from the body it is attached to, per zoning mode, on config/ropos_L200_hybrid.yaml.

The file's own orbit (fairlead on a = 2 m, f = 0.2 Hz, commanded every 0.01 s; slack and snap every 5 s), the cage
simulated. After every command: the distance between the line's end (its published shape) and the cage's attachment
point; after every step (stats["body_gap"]): the same before the zones are re-evaluated (so before any re-closing);
the drained end tensions; thread CPU time. Cases: all_catenary, all_rod, adaptive with hybrid.close_rod_shapes off
(the behaviour before re-closing), conversion, evaluation (the default), and adaptive with frames_from_curvature
false. Prints a table and, with --plot, draws gap vs time and the end tensions of off against evaluation.

    PYTHONPATH=. python benchmarks/studies/hybrid_body_closure.py [--duration 20] [--json out/body_closure.json]
        [--plot docs/figures/hybrid_body_closure.png]
"""

import argparse
import json
import os
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from tether_sim.errors import SolverDivergedError
from tether_sim.io.params import load_config
from tether_sim.physics.motion import build_motion
from tether_sim.solvers.factory import build_solver
from tether_sim.solvers.hybrid.state_io import end_target

ROOT = Path(__file__).resolve().parents[2]
CONFIG = ROOT / "config" / "ropos_L200_hybrid.yaml"
CASES = {
    "all_catenary": {"zoning": "all_catenary"},
    "all_rod": {"zoning": "all_rod"},
    "adaptive, off": {"close_rod_shapes": "off"},
    "adaptive, off, frames_from_curvature false": {"close_rod_shapes": "off", "frames_from_curvature": False},
    "adaptive, conversion": {"close_rod_shapes": "conversion"},
    "adaptive, evaluation (default)": {"close_rod_shapes": "evaluation"},
}


def run(hybrid, duration, dt=0.01):
    cfg = load_config(CONFIG)
    cfg = replace(cfg, hybrid=replace(cfg.hybrid, **hybrid))
    motion = build_motion(cfg.motion, np.asarray(cfg.ship_end.position, dtype=float))
    solver = build_solver(cfg)
    solver.drain_end_tensions()
    out = {"t": [], "gap": [], "step_gap": [], "error": None}
    c0 = time.thread_time()
    try:
        for k in range(1, int(round(duration / dt)) + 1):
            p, v = motion.at(k * dt)[:2]
            solver.set_end_motion("ship", p, v)
            solver.advance_to(k * dt)
            out["t"].append(solver.time)
            out["gap"].append(float(np.linalg.norm(solver.positions[-1] - end_target(solver, 1))))
            out["step_gap"].append(float(solver.stats.get("body_gap", 0.0)))
    except SolverDivergedError as exc:
        out["error"] = str(exc)
    out["cpu"] = time.thread_time() - c0
    t, ship, cage = solver.drain_end_tensions()
    out.update(tt=t.tolist(), ship=ship.tolist(), cage=cage.tolist(),
               stats={k: v for k, v in solver.stats.items() if isinstance(v, (int, float))})
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--duration", type=float, default=20.0)
    ap.add_argument("--cases", nargs="*", default=list(CASES))
    ap.add_argument("--json")
    ap.add_argument("--plot")
    args = ap.parse_args()
    res = {}
    for name in args.cases:
        r = res[name] = run(CASES[name], args.duration)
        g = np.array(r["gap"])
        t = np.array(r["t"])
        windows = " ".join(f"{t0:g}-{t0 + 4:g} s {g[(t > t0) & (t <= t0 + 4)].max():.3f}"
                           for t0 in range(0, int(args.duration), 4) if np.any((t > t0) & (t <= t0 + 4)))
        st = r["stats"]
        print(f"{name}: gap after each command max {g.max():.4f} m (final {g[-1]:.4f}); per step before re-closing "
              f"max {max(r['step_gap'], default=0.0):.4f} m; largest in 4 s windows: {windows}; "
              f"ship/cage tension max {max(r['ship']) / 1e3:.1f}/{max(r['cage']) / 1e3:.1f} kN; "
              f"re-zonings {st.get('rezonings', 0)}, closures {st.get('closures', 0)}, halvings {st.get('halvings', 0)}, "
              f"failure re-zonings {st.get('failure_rezonings', 0)}; CPU {r['cpu']:.1f} s"
              + (f"; STOPPED: {r['error']}" if r["error"] else ""), flush=True)
    print(f"load: {os.getloadavg()}")
    compare(res)
    if args.json:
        Path(args.json).parent.mkdir(parents=True, exist_ok=True)
        Path(args.json).write_text(json.dumps(res))
    if args.plot:
        plot(res, args.plot)


def compare(res, reference="all_rod"):
    """End tensions of each case against the reference: largest difference, snap peak of each 5 s period."""
    if reference not in res:
        return
    ref = res[reference]
    for name, r in res.items():
        t = np.arange(0.01, min(r["tt"][-1], ref["tt"][-1]) + 1e-9, 0.01)  # the command times (steps may be halved)
        a = {k: np.interp(t, r["tt"], r[k]) for k in ("ship", "cage")}
        b = {k: np.interp(t, ref["tt"], ref[k]) for k in ("ship", "cage")}
        d = [np.abs(a[k] - b[k]).max() / 1e3 for k in ("ship", "cage")]
        peaks = [a["ship"][(t > t0) & (t <= t0 + 5.0)].max() / 1e3 for t0 in np.arange(5.0, t[-1] - 1e-9, 5.0)]
        print(f"{name}: against {reference} ship/cage tension differ by at most {d[0]:.2f}/{d[1]:.2f} kN; "
              f"ship peaks per 5 s period from 5 s: " + ", ".join(f"{p:.1f}" for p in peaks) + " kN")


def plot(res, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(3, 1, figsize=(10, 10), sharex=True)
    for name, r in res.items():
        ax[0].semilogy(r["t"], np.maximum(r["gap"], 1e-6), label=name, lw=1)
    ax[0].axhline(2.0, color="k", ls=":", lw=0.8)
    ax[0].text(0.2, 2.3, "closure limit 1 % of L", fontsize=8)
    ax[0].set_ylabel("line end to cage attachment (m)")
    ax[0].legend(fontsize=7, loc="lower right")
    ax[0].set_title("config/ropos_L200_hybrid.yaml: gap after each 0.01 s command")
    for name, style in (("all_rod", "C1-"), ("adaptive, off", "C2-"), ("adaptive, evaluation (default)", "C5--")):
        if name in res:
            r = res[name]
            ax[1].plot(r["tt"], np.array(r["ship"]) / 1e3, style, lw=0.9, label=name)
            ax[2].plot(r["tt"], np.array(r["cage"]) / 1e3, style, lw=0.9, label=name)
    ax[1].set_ylabel("ship end tension (kN)")
    ax[2].set_ylabel("cage end tension (kN)")
    ax[2].set_xlabel("t (s)")
    ax[1].legend(fontsize=7)
    fig.tight_layout()
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
