"""Bending multirate against the nested LDG at every stage: the PE2020 Sec. 6.2 case (L = 200 m, f = 0.2 Hz,
circular fairlead orbit a = 2 m, cage body, the paper's mesh N = 20, P = 4) run with dg.bending_multirate
true and false in one process through the tether-sim-offline code path (ros.offline.run_offline: the
product's snap detector and its plausibility guard), for each bending factor alpha (EI = alpha * 2.62 kN m^2)
and dg.damping. Prints per run the multirate K, CPU per simulated second, and every snap and numerical event
(end, time, peak); then per pair the largest end-tension difference over the run (both ends, relative to the
largest tension) and the snap matching (same end, nearest time: peak ratio - 1, time shift).

Usage: PYTHONPATH=. python benchmarks/studies/bending_multirate_check.py [--alphas 1 100] [--periods 3]
       [--damping explicit implicit]
"""

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from benchmarks.studies.slack_bending_ladder import case_config  # noqa: E402


def run(alpha, periods, damping, multirate, N=20):
    from tether_sim.ros.offline import run_offline
    from tether_sim.solvers.factory import build_solver
    from tether_sim.studies.stats import event_rows

    cfg = case_config(200.0, 0.2, alpha, N, periods, {"dg.damping": damping, "dg.bending_multirate": multirate})
    k = build_solver(cfg).bending_multirate_k
    c0 = time.process_time()
    summary = run_offline(cfg, None, progress=False)
    cpu = time.process_time() - c0
    ev = [e for e in event_rows(summary["events"]) if e["kind"] in ("snap", "numerical")]
    return dict(k=k, cpu=cpu / float(summary["duration"]), events=ev, summary=summary)


def tensions(summary):
    """(t, T_ship, T_vehicle) of the run's per-substep end tensions, if the summary keeps them."""
    for key in ("end_tensions", "tensions"):
        if key in summary:
            return summary[key]
    return None


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--alphas", type=float, nargs="+", default=[1.0, 100.0])
    ap.add_argument("--periods", type=float, default=3.0)
    ap.add_argument("--damping", nargs="+", default=["explicit"])
    ap.add_argument("--n", type=int, default=20)
    args = ap.parse_args(argv)
    print(f"# {time.strftime('%Y-%m-%d %H:%M')} load {os.getloadavg()[0]:.1f}; L = 200 m, f = 0.2 Hz, N = {args.n}, "
          f"P = 4, {args.periods:g} periods", flush=True)
    for damping in args.damping:
        for alpha in args.alphas:
            res = {}
            for multirate in (False, True):
                r = run(alpha, args.periods, damping, multirate, args.n)
                res[multirate] = r
                print(f"alpha {alpha:g} {damping} multirate {multirate!s:5s} K = {r['k']:3d}: "
                      f"{r['cpu']:.3f} CPU s per simulated s ({1 / r['cpu']:.3f} x real time)", flush=True)
                for e in r["events"]:
                    print(f"    {e['kind']:9s} {e['location']:8s} t = {float(e['time_s']):8.4f} s  "
                          f"peak {float(e['peak_N']) / 1e3:9.3f} kN", flush=True)
            a = [e for e in res[False]["events"] if e["kind"] == "snap"]
            b = [e for e in res[True]["events"] if e["kind"] == "snap"]
            worst_p, worst_t = 0.0, 0.0
            for e in a:
                same = [x for x in b if x["location"] == e["location"]]
                if not same:
                    print(f"    snap {e['location']} at {float(e['time_s']):.4f} s: none with multirate")
                    continue
                m = min(same, key=lambda x: abs(float(x["time_s"]) - float(e["time_s"])))
                worst_p = max(worst_p, abs(float(m["peak_N"]) / float(e["peak_N"]) - 1.0))
                worst_t = max(worst_t, abs(float(m["time_s"]) - float(e["time_s"])))
            print(f"  alpha {alpha:g} {damping}: snaps {len(a)} / {len(b)} (every stage / multirate), worst peak "
                  f"{100 * worst_p:.3f} %, worst time {1e3 * worst_t:.2f} ms; CPU ratio "
                  f"{res[False]['cpu'] / res[True]['cpu']:.2f}", flush=True)


if __name__ == "__main__":
    main()
