"""Implicit against explicit damping, and against another checkout's implicit step: the PE2020 Sec. 6.2 case
(L = 200 m, f = 0.2 Hz, circular fairlead orbit a = 2 m, cage body, the paper's mesh N = 20, P = 4) run through
the tether-sim-offline code path (ros.offline.run_offline: the product's snap detector and its plausibility
guard) with dg.damping explicit and implicit in one process, for each bending factor alpha (EI = alpha *
2.62 kN m^2; dg.bending_multirate as configured, on by default). Prints per run the CPU per simulated second
and every snap and numerical event (end, time, peak), then per pair the snap matching (same end, nearest
time: peak ratio - 1, time shift). ``--baseline DIR``: another checkout's implicit step against this one's
(imported as tether_sim_base, bench_tick.load_baseline): both solvers driven by the same 50 Hz fairlead
orbit through advance_to, their per-substep end tensions (drain_end_tensions) compared: the largest
difference relative to the largest tension, and each end's maximum (peak, time) per forcing period.

Usage: PYTHONPATH=. python benchmarks/studies/implicit_damping_check.py [--alphas 1] [--periods 1.9]
       [--baseline DIR] [--no-offline]
"""

import argparse
import importlib
import os
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from benchmarks.studies.slack_bending_ladder import EI_STAR  # noqa: E402


def run(alpha, periods, damping, N=20, package="tether_sim"):
    load_config = importlib.import_module(f"{package}.io.params").load_config
    run_offline = importlib.import_module(f"{package}.ros.offline").run_offline
    event_rows = importlib.import_module(f"{package}.studies.stats").event_rows
    overrides = {"cable.EI": alpha * EI_STAR, "motion.kind": "circle", "motion.amplitude": 2.0, "motion.frequency": 0.2,
                 "motion.ramp_time": 5.0, "duration": periods / 0.2, "dg.n_elements": int(N), "dg.order": 4,
                 "dg.damping": damping}
    cfg = load_config(ROOT / "config" / "ropos_L200_paper.yaml", overrides)
    c0 = time.process_time()
    summary = run_offline(cfg, None, progress=False)
    cpu = (time.process_time() - c0) / float(summary["duration"])
    return cpu, [e for e in event_rows(summary["events"]) if e["kind"] in ("snap", "numerical")]


def tension_history(alpha, periods, N=20, package="tether_sim"):
    """(t, T_ship, T_cage) per substep of the implicit run, driven as bench_slack_bending.py drives it."""
    from benchmarks.bench_slack_bending import tree

    load_config, build_motion, build_solver = tree(package)
    overrides = {"cable.EI": alpha * EI_STAR, "motion.kind": "circle", "motion.amplitude": 2.0, "motion.frequency": 0.2,
                 "motion.ramp_time": 5.0, "duration": periods / 0.2, "dg.n_elements": int(N), "dg.order": 4,
                 "dg.damping": "implicit"}
    cfg = load_config(ROOT / "config" / "ropos_L200_paper.yaml", overrides)
    motion = build_motion(cfg.motion, cfg.ship_end.position)
    s = build_solver(cfg)
    t0, out = s.time, []
    for k in range(1, int(round(periods / 0.2 * 50)) + 1):
        p, v, _ = motion.at(k / 50.0)
        s.set_end_motion("ship", p, v)
        s.advance_to(t0 + k / 50.0)
        out.append(np.array([np.asarray(x, float) for x in s.drain_end_tensions()]))
    return np.concatenate(out, axis=1)


def compare_histories(a, b, periods):
    """Largest |a - b| / max |b| of the end tensions, and per end and period the maxima (time, peak) of both."""
    n = min(a.shape[1], b.shape[1])
    a, b = a[:, :n], b[:, :n]
    same_t = bool(np.array_equal(a[0], b[0]))
    diff = np.abs(a[1:] - b[1:]) / np.abs(b[1:]).max()
    end, i = np.unravel_index(np.argmax(diff), diff.shape)
    first = a[0, np.argmax(diff.max(axis=0) > 1e-9)] if (diff > 1e-9).any() else np.nan
    print(f"  end tensions, this implicit against the baseline's: {n} substeps (same times: {same_t}), largest "
          f"difference {diff.max():.3e} of the largest tension ({('ship', 'cage')[end]} at {a[0, i]:.5f} s: "
          f"{a[1 + end, i] / 1e3:.3f} against {b[1 + end, i] / 1e3:.3f} kN); first above 1e-9 at {first:.5f} s; "
          f"median difference {np.median(diff.max(axis=0)):.1e}", flush=True)
    for end, name in ((1, "ship"), (2, "cage")):
        for k in range(int(np.ceil(periods))):
            m = (a[0] >= k * 5.0) & (a[0] < (k + 1) * 5.0)
            if not m.any():
                continue
            ia, ib = np.argmax(np.where(m, a[end], -np.inf)), np.argmax(np.where(m, b[end], -np.inf))
            print(f"    {name} maximum in {5 * k:g}-{5 * (k + 1):g} s: this {a[end, ia] / 1e3:.4f} kN at {a[0, ia]:.5f} s, "
                  f"baseline {b[end, ib] / 1e3:.4f} kN at {b[0, ib]:.5f} s ({100 * (a[end, ia] / b[end, ib] - 1):+.4f} %, "
                  f"{1e3 * (a[0, ia] - b[0, ib]):+.3f} ms)", flush=True)


def match(a, b):
    """(snaps of a, snaps of b, worst |peak ratio - 1|, worst |time shift|, unmatched): every snap of a against the
    nearest-in-time snap of b at the same end."""
    sa = [e for e in a if e["kind"] == "snap"]
    sb = [e for e in b if e["kind"] == "snap"]
    worst_p = worst_t = 0.0
    missing = []
    for e in sa:
        same = [x for x in sb if x["location"] == e["location"]]
        if not same:
            missing.append(f"{e['location']} {float(e['time_s']):.4f} s")
            continue
        m = min(same, key=lambda x: abs(float(x["time_s"]) - float(e["time_s"])))
        worst_p = max(worst_p, abs(float(m["peak_N"]) / float(e["peak_N"]) - 1.0))
        worst_t = max(worst_t, abs(float(m["time_s"]) - float(e["time_s"])))
    return len(sa), len(sb), worst_p, worst_t, missing


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--alphas", type=float, nargs="+", default=[1.0])
    ap.add_argument("--periods", type=float, default=1.9)
    ap.add_argument("--n", type=int, default=20)
    ap.add_argument("--baseline", help="another checkout: its implicit step's end tensions against this one's")
    ap.add_argument("--no-offline", action="store_true", help="only the comparison with --baseline")
    args = ap.parse_args(argv)
    runs = [("explicit", "explicit", "tether_sim"), ("implicit", "implicit", "tether_sim")]
    if args.baseline:
        from benchmarks.bench_tick import load_baseline

        load_baseline(args.baseline)
    print(f"# {time.strftime('%Y-%m-%d %H:%M')} load {os.getloadavg()[0]:.1f}; L = 200 m, f = 0.2 Hz, N = {args.n}, "
          f"P = 4, {args.periods:g} periods", flush=True)
    for alpha in args.alphas:
        res = {}
        for label, damping, package in ([] if args.no_offline else runs):
            cpu, events = run(alpha, args.periods, damping, args.n, package)
            res[label] = (cpu, events)
            print(f"alpha {alpha:g} {label:18s}: {cpu:.3f} CPU s per simulated s ({1 / cpu:.3f} x real time)", flush=True)
            for e in events:
                print(f"    {e['kind']:9s} {e['location']:8s} t = {float(e['time_s']):8.4f} s  "
                      f"peak {float(e['peak_N']) / 1e3:10.4f} kN", flush=True)
        if args.baseline:
            compare_histories(tension_history(alpha, args.periods, args.n),
                              tension_history(alpha, args.periods, args.n, "tether_sim_base"), args.periods)
        if args.no_offline:
            continue
        for x, y in [("explicit", "implicit")]:
            na, nb, p, t, missing = match(res[x][1], res[y][1])
            print(f"  alpha {alpha:g} {y} against {x}: snaps {na} / {nb}, worst peak {100 * p:.4f} %, worst time "
                  f"{1e3 * t:.3f} ms, CPU ratio {res[x][0] / res[y][0]:.3f}"
                  + (f"; unmatched: {', '.join(missing)}" if missing else ""), flush=True)


if __name__ == "__main__":
    main()
