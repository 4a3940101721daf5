"""ROPOS L = 200 m, f = 0.2 Hz, a = 2 m with bending (EI* = 2620 N m^2) and adaptive zoning: a rod
zone appears near the cage while the tether is slack and disappears when it is taut again.
Also the step-size study of the snap peaks (implicit steps can be stable yet smear snatch loads).

    PYTHONPATH=. python benchmarks/ropos_slack_zones.py config/ropos_L200.yaml --steps 0.01 0.02 0.05 0.1
Writes docs/figures/ropos_L200_zones.png (zones for the first step size).
"""

import argparse
import time
from dataclasses import replace
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from tether_sim.errors import SolverDivergedError  # noqa: E402
from tether_sim.io.params import load_config  # noqa: E402
from tether_sim.physics.motion import build_motion  # noqa: E402
from tether_sim.solvers.hybrid.solver import HybridRodCatenarySolver  # noqa: E402


def run(cfg, duration, dt):
    solver = HybridRodCatenarySolver(cfg)
    motion = build_motion(cfg.motion, np.asarray(cfg.ship_end.position, dtype=float))
    rec = {"t": [], "Ts": [], "Tv": [], "zones": [], "tz": []}
    c0 = time.process_time()
    k = 0
    while k * dt < duration - 1e-9:
        k += 1
        t = k * dt
        p, v, _ = motion.at(t)
        solver.set_end_motion("ship", p, v)
        try:
            solver.advance_to(t)
        except SolverDivergedError as exc:
            print(f"stopped: {exc}", flush=True)
            break
        tt, a, b = solver.drain_end_tensions()
        rec["t"].extend(tt)
        rec["Ts"].extend(a)
        rec["Tv"].extend(b)
        rec["tz"].append(t)
        rec["zones"].append(solver.zones.copy())
    return {k: np.array(v) for k, v in rec.items()}, time.process_time() - c0, solver


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("config")
    ap.add_argument("--EI", type=float, default=2620.0)
    ap.add_argument("--duration", type=float, default=40.0)
    ap.add_argument("--segments", type=int, default=100)
    ap.add_argument("--frequency", type=float, default=0.2)
    ap.add_argument("--rho", type=float, default=0.8)
    ap.add_argument("--zoning", default="adaptive")
    ap.add_argument("--softening", type=float, default=1000.0)
    ap.add_argument("--steps", type=float, nargs="+", default=[0.02])
    ap.add_argument("--out", default="docs/figures")
    args = ap.parse_args()
    base = load_config(args.config)
    first = None
    for dt in args.steps:
        cfg = replace(base, solver="hybrid", cable=replace(base.cable, EI=args.EI),
                      motion=replace(base.motion, frequency=args.frequency),
                      hybrid=replace(base.hybrid, time_step=dt, n_segments=args.segments, zoning=args.zoning, compression_softening=args.softening,
                                     rho_inf=args.rho),
                      initial=replace(base.initial, kind="static"))
        rec, cpu, solver = run(cfg, args.duration, dt)
        rod_frac = np.array([z.mean() for z in rec["zones"]])
        print(f"dt {dt:g} s, f {args.frequency:g} Hz, rho_inf {args.rho:g}: reached t = {rec['t'][-1]:.2f} s; cage tension max {rec['Tv'].max():.0f} N min {rec['Tv'].min():.0f} N; ship max "
              f"{rec['Ts'].max():.0f} N; rod fraction max {rod_frac.max():.3f}; cpu {cpu:.1f} s for {args.duration:g} s; "
              f"{solver.stats}", flush=True)
        if first is None:
            first = (dt, rec, solver)
    dt, rec, solver = first
    fig, ax = plt.subplots(2, 1, figsize=(10, 7), sharex=True)
    ax[0].plot(rec["t"], rec["Ts"] / 1e3, label="ship (s = 0)")
    ax[0].plot(rec["t"], rec["Tv"] / 1e3, label="cage (s = L)")
    ax[0].set(ylabel="tension (kN)", title=f"ROPOS L = 200 m, f = {args.frequency:g} Hz, EI = {args.EI:g} N m$^2$, hybrid dt = {dt:g} s")
    ax[0].legend()
    ax[0].grid(alpha=0.3)
    Z = np.array(rec["zones"]).T
    s = np.linspace(0, solver.length, Z.shape[0] + 1)
    ax[1].pcolormesh(rec["tz"], 0.5 * (s[1:] + s[:-1]), Z, cmap="Greys", vmin=0, vmax=1.5, shading="nearest")
    ax[1].set(xlabel="t (s)", ylabel="s (m)", title="rod zone (dark) / catenary (white)")
    fig.tight_layout()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    fig.savefig(out / "ropos_L200_zones.png", dpi=110)
    print(f"wrote {out / 'ropos_L200_zones.png'}")


if __name__ == "__main__":
    main()
