"""The stiff held arc with the DG solver, old and new q-equation penalty.

The arc of benchmarks/studies/hybrid_held_arc.py (EA = 455 MN, EI = 2620 N m^2, L = 325 m, ends fixed at
(0, 0, -50) and (300, 0, -150), no material damping) held still for --duration s with
dg.q_penalty_jump = strain (PE2020 Eq. 24, the default before 2026-11-23) and = tension (the
default since), each from the discrete static equilibrium (dg/equilibrium.py), plus the new
default from the bare projected catenary (the start before 2026-11-23). Prints the largest
relative excursion of the end tensions and, with --plot, draws end tension against time.

    PYTHONPATH=. python benchmarks/studies/held_arc_q_penalty.py [--n 6 --order 4] [--duration 60] [--plot docs/figures/held_arc_q_penalty.png]
"""

import argparse
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from benchmarks.studies.hybrid_held_arc import held_arc_config  # noqa: E402
from tether_sim.solvers.dg import equilibrium  # noqa: E402
from tether_sim.solvers.dg.solver import DGCableSolver  # noqa: E402


def run(n, order, form, duration, polish=True, dt_out=0.05):
    cfg = held_arc_config(solver="dg", ship_kind="fixed")
    cfg = replace(cfg, dg=replace(cfg.dg, n_elements=n, order=order, q_penalty_jump=form))
    saved = equilibrium.polish_equilibrium
    if not polish:
        equilibrium_off = (lambda solver, chord: 0)
        import tether_sim.solvers.dg.solver as mod
        mod.polish_equilibrium = equilibrium_off
    try:
        s = DGCableSolver(cfg)
    finally:
        import tether_sim.solvers.dg.solver as mod
        mod.polish_equilibrium = saved
    out = []
    c0 = time.thread_time()
    for t in np.arange(0.0, duration + 1e-9, dt_out):
        if t > 0:
            s.advance_to(t)
        f = s.end_forces()
        out.append((t, f.ship_tension, f.vehicle_tension))
    return np.array(out), time.thread_time() - c0, s.stable_time_step()


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=6)
    ap.add_argument("--order", type=int, default=4)
    ap.add_argument("--duration", type=float, default=60.0)
    ap.add_argument("--plot", default="")
    args = ap.parse_args(argv)
    cases = [("strain", True, "PE2020 Eq. 24 penalty (old default), discrete equilibrium start"),
             ("tension", False, "tension-jump penalty (new default), projected catenary start"),
             ("tension", True, "tension-jump penalty (new default), discrete equilibrium start")]
    res = []
    for form, polish, label in cases:
        rec, cpu, dt = run(args.n, args.order, form, args.duration, polish)
        T0 = rec[0, 1:]
        dev = np.max(np.abs(rec[:, 1:] / T0 - 1.0))
        print(f"N={args.n} P={args.order} {label}: static {T0[0]:.2f} / {T0[1]:.2f} N, largest excursion "
              f"{100 * dev:.3g} %, substep {dt:.4g} s, cpu {cpu:.1f} s", flush=True)
        res.append((label, rec))
    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(2, 1, figsize=(8, 6.5), sharex=True)
        for (label, rec), st in zip(res, ("-", "--", "-")):
            ax[0].plot(rec[:, 0], rec[:, 1] / 1e3, st, lw=1, label=label)
            ax[1].plot(rec[:, 0], 100 * (rec[:, 1] / rec[0, 1] - 1), st, lw=1, label=label)
        ax[0].set_ylabel("ship-end tension (kN)")
        ax[0].set_ylim(0, 60)
        ax[0].legend(fontsize=7, loc="upper right")
        ax[1].set_ylim(-0.1, 0.1)
        ax[1].axhline(0.1, color="k", lw=0.5)
        ax[1].axhline(-0.1, color="k", lw=0.5)
        ax[1].set_ylabel("change from t = 0 (%)")
        ax[1].set_xlabel("time (s)")
        ax[0].set_title(f"Held stiff arc (EA 455 MN, EI 2620 N m$^2$, T ~ 11 kN), DG N = {args.n}, P = {args.order}",
                        fontsize=9)
        fig.tight_layout()
        fig.savefig(args.plot, dpi=110)
        print("wrote", args.plot)


if __name__ == "__main__":
    main()
