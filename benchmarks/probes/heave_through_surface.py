"""A top end heaved in and out of the water (2026-11-26): robustness of the surface crossing with waves.

The line of tether_sim/scenarios/free_surface.py (L = 100 m, gamma0 = 2 kg/m, rho_c = 2000 kg/m^3,
d = 0.03 m, EA = 2e5 N, hanging with a free lower end, free surface on), its top end heaved
z = -10 cos(2 pi t / 27 s) m about the still-water level from rest at 10 m depth (10 m out of the water
at 13.5 s and 40.5 s, back under it at 27 s and 54 s), for 60 s; once in still water and once under a regular wave H = 3 m, T = 7 s. Prints, per solver,
whether the run went through and the top-tension range; with both solvers, the largest and RMS difference
of the hybrid top tension from the DG one.

    PYTHONPATH=. python benchmarks/probes/heave_through_surface.py [--solvers dg hybrid] [--hybrid-dt 0.01]
        [--line hanging|catenary]
"""

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from tether_sim.scenarios import free_surface as fs  # noqa: E402
from tether_sim.scenarios import harness  # noqa: E402

AMPLITUDE, PERIOD, DURATION = 10.0, 27.0, 60.0
X0 = 0.0  # horizontal position of the top end (main sets it for --line catenary)


def motion(t):
    w = 2.0 * math.pi / PERIOD
    return {"ship": ([X0, 0.0, -AMPLITUDE * math.cos(w * t)], [0.0, 0.0, AMPLITUDE * w * math.sin(w * t)])}


def run(solver, wave, hybrid_dt=0.01, line="hanging"):
    """(t, top tension) or the exception that stopped the run (and the time it was reached)."""
    extra = {"waves.kind": "regular", "waves.height": 3.0, "waves.period": 7.0} if wave else {}
    if solver == "hybrid":
        extra["hybrid.time_step"] = hybrid_dt
    if line == "catenary":
        from benchmarks.studies import moordyn_waves as mw

        top = [mw.TOP[0], 0.0, -AMPLITUDE]
        flat = mw.flat(solver, **{"ship_end.kind": "prescribed", "ship_end.position": top,
                                  "environment.free_surface": True, **extra})
        for k in [k for k in flat if k.startswith("waves.")] if not wave else []:
            del flat[k]
    else:
        flat = fs.flat(solver, -AMPLITUDE, **extra)
    _, s = harness.make_solver(flat)
    try:
        r = harness.run_sampled(s, np.arange(0.02, DURATION + 1e-9, 0.02), motion=motion, keep=())
    except Exception as exc:  # noqa: BLE001 - the probe reports any solver failure with its time
        return exc, s.time
    return np.asarray(r["t"]), np.asarray(r["ship_tension"])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--solvers", nargs="+", default=["dg", "hybrid"])
    ap.add_argument("--hybrid-dt", type=float, default=0.01)
    ap.add_argument("--line", choices=("hanging", "catenary"), default="hanging")
    args = ap.parse_args(argv)
    global X0
    if args.line == "catenary":
        from benchmarks.studies import moordyn_waves as mw

        X0 = mw.TOP[0]
    for wave in (False, True):
        out = {}
        for solver in args.solvers:
            w0 = time.time()
            res = run(solver, wave, args.hybrid_dt, args.line)
            label = f"{solver:6s} {'wave H 3 m T 7 s' if wave else 'still water':16s}"
            if isinstance(res[0], Exception):
                print(f"{label} FAILED at t = {res[1]:.3f} s: {type(res[0]).__name__}: {res[0]}")
                continue
            out[solver] = res
            print(f"{label} through {DURATION:.0f} s, top tension {res[1].min():.1f} to {res[1].max():.1f} N "
                  f"({time.time() - w0:.0f} s wall)", flush=True)
        if "dg" in out and "hybrid" in out:
            d = out["hybrid"][1] - out["dg"][1]
            print(f"  hybrid - DG top tension: largest {np.max(np.abs(d)):.1f} N, RMS {np.sqrt(np.mean(d * d)):.1f} N "
                  f"(DG range {np.ptp(out['dg'][1]):.1f} N)")


if __name__ == "__main__":
    main()
