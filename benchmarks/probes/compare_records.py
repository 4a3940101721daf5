"""Two codes (or settings) on the same cases: every event of the recorded runs in folder A against folder B.

Both folders hold benchmarks/probes/slack_record.py's ``L<L>f<f>a<alpha>N<N>.npz``; each record is replayed through
a fresh snap detector and guard of the current code (slack_record.replay, cut to the shorter of the two runs), and
every event of A is matched with the nearest event of B at the same end and of the same kind (snap or numerical).
Printed per case: the events of A with the change of peak (%) and time (ms) to B, B's events left unmatched, and the
worst change of a snap; the exit status is 1 when a snap is unmatched or outside --peak-tol / --time-tol.

    PYTHONPATH=. python benchmarks/probes/compare_records.py A B [--peak-tol 0.001] [--time-tol 0.001]
"""
import argparse
import re
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

RECORD = re.compile(r"L([0-9.]+)f([0-9.]+)a([0-9.]+)N([0-9]+)\.npz$")


def rows(path, config, cut):
    """(end, kind, time, peak) of every event of a record replayed with the current detector (studies.stats.event_rows:
    one snap per slack episode, then the guard's numerical warnings)."""
    from benchmarks.probes.slack_record import replay
    from tether_sim.studies.stats import event_rows

    return [(r["location"], r["kind"], r["time_s"], r["peak_N"]) for r in event_rows(replay(path, config, t_end=cut))]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("a", type=Path)
    ap.add_argument("b", type=Path)
    ap.add_argument("--peak-tol", type=float, default=0.001, help="relative")
    ap.add_argument("--time-tol", type=float, default=0.001, help="s")
    args = ap.parse_args(argv)
    from benchmarks.studies.slack_bending_ladder import case_config

    bad = 0
    for pa in sorted(args.a.glob("*.npz")):
        pb = args.b / pa.name
        m = RECORD.search(pa.name)
        if not m or not pb.exists():
            continue
        L, f, alpha, N = float(m[1]), float(m[2]), float(m[3]), int(m[4])
        cut = min(float(np.load(pa)["duration"]), float(np.load(pb)["duration"]))
        config = case_config(L, f, alpha, N, cut * f)
        ea, eb = rows(pa, config, cut), rows(pb, config, cut)
        print(f"\nL {L:g} m, f {f:g} Hz, alpha {alpha:g}, N {N}, {cut:.2f} s: {len(ea)} events in {args.a}, "
              f"{len(eb)} in {args.b}")
        used, worst_p, worst_t = set(), 0.0, 0.0
        for loc, kind, t, p in ea:
            cands = [(abs(tb - t), i) for i, (lb, kb, tb, _) in enumerate(eb) if lb == loc and kb == kind and i not in used]
            if not cands or min(cands)[0] > 0.05:
                print(f"  {loc:8s} {kind:9s} {t:9.4f} s {p / 1e3:9.2f} kN  -> unmatched")
                bad += kind == "snap"
                continue
            i = min(cands)[1]
            used.add(i)
            dp = eb[i][3] / p - 1.0
            dt = eb[i][2] - t
            print(f"  {loc:8s} {kind:9s} {t:9.4f} s {p / 1e3:9.2f} kN  -> {eb[i][2]:9.4f} s {eb[i][3] / 1e3:9.2f} kN: "
                  f"{100 * dp:+.4f} %, {1e3 * dt:+.3f} ms")
            if kind == "snap":
                worst_p, worst_t = max(worst_p, abs(dp)), max(worst_t, abs(dt))
                bad += abs(dp) > args.peak_tol or abs(dt) > args.time_tol
        for i, (lb, kb, tb, pb_) in enumerate(eb):
            if i not in used:
                print(f"  {lb:8s} {kb:9s} {tb:9.4f} s {pb_ / 1e3:9.2f} kN  (only in {args.b})")
                bad += kb == "snap"
        print(f"  worst snap change: {100 * worst_p:.4f} %, {1e3 * worst_t:.3f} ms")
    print(f"\n{'every snap matched within' if not bad else f'{bad} snap(s) unmatched or outside'} "
          f"{100 * args.peak_tol:g} % and {1e3 * args.time_tol:g} ms")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
