"""ROPOS L = 200 m, f = 0.2 Hz, a = 2 m with bending (EI* = 2620 N m^2) and adaptive zoning: a rod
zone appears near the cage while the tether is slack and disappears when it is taut again.

The shared slack-snap case of benchmarks/ropos_case.py (orbit centre 3 m deep, one-period ramp, the
cage simulated as a rigid body), hybrid solver, fairlead commanded once per implicit step:

    PYTHONPATH=. python benchmarks/studies/ropos_slack_zones.py --dt 0.01 --duration 30

Writes docs/figures/ropos_L200_zones.png: end tensions (with the DG N = 20, P = 4 ship tension if its
record is cached by benchmarks/studies/ropos_hybrid.py --slack), and tension over (t, s) with the rod zone outlined.
"""

import argparse
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from benchmarks import ropos_case as rc  # noqa: E402
from benchmarks.studies.ropos_hybrid import DG_CACHE, slack_config  # noqa: E402
from tether_sim.solvers.hybrid.solver import HybridRodCatenarySolver  # noqa: E402
from tether_sim.solvers.hybrid.state_io import node_profile  # noqa: E402


def run(cfg, duration, dt):
    """Step the hybrid solver; per step the element zones and the tension on the grid nodes."""
    solver = HybridRodCatenarySolver(cfg)
    rec = {"t": [], "Ts": [], "Tv": [], "zones": [], "tz": [], "T": []}
    c0 = time.process_time()
    k = 0
    while k * dt < duration - 1e-9:
        k += 1
        t = k * dt
        p, v = rc.fairlead_motion(t)
        solver.set_end_motion("ship", p, v)
        solver.advance_to(t)
        tt, a, b = solver.drain_end_tensions()
        rec["t"].extend(tt)
        rec["Ts"].extend(a)
        rec["Tv"].extend(b)
        rec["tz"].append(t)
        rec["zones"].append(solver.zones.copy())
        prof = node_profile(solver)
        T_grid = np.full(solver.s_grid.size, np.inf)
        np.minimum.at(T_grid, solver.chain.grid, prof["tension"])
        rec["T"].append(T_grid)
    return {k: np.array(v) for k, v in rec.items()}, time.process_time() - c0, solver


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--dt", type=float, default=0.01)
    ap.add_argument("--duration", type=float, default=30.0)
    ap.add_argument("--segments", type=int, default=50)
    ap.add_argument("--rho", type=float, default=0.0)
    ap.add_argument("--softening", type=float, default=1e4)
    ap.add_argument("--out", default="docs/figures")
    args = ap.parse_args()
    cfg = slack_config(args.dt, args.segments, args.rho, args.softening)
    rec, cpu, solver = run(cfg, args.duration, args.dt)
    Z = rec["zones"].astype(float)
    rod_frac = Z.mean(axis=1)
    print(f"dt {args.dt:g} s, rho_inf {args.rho:g}, {args.segments} segments: cpu {cpu:.1f} s for {args.duration:g} s; "
          f"ship max {rec['Ts'].max() / 1e3:.1f} kN; rod fraction max {rod_frac.max():.2f}, "
          f"steps with rod elements {np.mean(rod_frac > 0):.2f}; {solver.stats}", flush=True)
    onsets = np.nonzero(np.diff((rod_frac > 0).astype(int)) != 0)[0]
    print("rod zone on/off at t =", [round(float(rec["tz"][i + 1]), 2) for i in onsets])
    fig, ax = plt.subplots(3, 1, figsize=(11, 10), sharex=True, gridspec_kw={"height_ratios": [1.1, 1.4, 0.6]})
    if DG_CACHE.exists():
        d = np.load(DG_CACHE)
        m = d["t"] <= args.duration
        ax[0].plot(d["t"][m], d["ship"][m] / 1e3, color="0.6", lw=2.5, label="ship, DG N=20 P=4 (explicit)")
    ax[0].plot(rec["t"], rec["Ts"] / 1e3, color="C0", lw=1, label=f"ship (s = 0), hybrid dt = {args.dt:g} s")
    ax[0].plot(rec["t"], rec["Tv"] / 1e3, color="C3", lw=1, label="cage (s = L), hybrid")
    ax[0].set(ylabel="tension (kN)", title="ROPOS L = 200 m, a = 2 m, f = 0.2 Hz, EI = 2620 N m$^2$, "
              "cage simulated; hybrid rod-catenary, adaptive zoning")
    ax[0].legend(loc="upper left", fontsize=8)
    ax[0].grid(alpha=0.3)
    s = solver.s_grid
    Tk = np.clip(rec["T"].T / 1e3, -1.0, 250.0)
    pc = ax[1].pcolormesh(rec["tz"], s, Tk, cmap="viridis", shading="nearest", vmin=-1.0, vmax=250.0)
    fig.colorbar(pc, ax=ax[1], label="tension (kN)", pad=0.01)
    centres = 0.5 * (s[1:] + s[:-1])
    ax[1].contourf(rec["tz"], centres, Z.T, levels=[0.5, 1.5], colors="none", hatches=["////"])
    ax[1].contour(rec["tz"], centres, Z.T, levels=[0.5], colors="w", linewidths=1.0)
    ax[1].set(ylabel="s (m)  [0 ship, 200 cage]", title="tension along the tether; rod elements hatched, "
              "outlined white (catenary elsewhere)")
    ax[1].invert_yaxis()
    ax[2].fill_between(rec["tz"], 0, rod_frac, step="mid", color="k", alpha=0.6, label="rod fraction of the length")
    ax[2].set(xlabel="t (s)", ylabel="rod fraction", ylim=(0, 1))
    ax[2].grid(alpha=0.3)
    fig.tight_layout()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    fig.savefig(out / "ropos_L200_zones.png", dpi=100)
    print(f"wrote {out / 'ropos_L200_zones.png'}")


if __name__ == "__main__":
    main()
