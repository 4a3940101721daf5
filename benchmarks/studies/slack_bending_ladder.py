"""Slack with bending, mesh ladder: the PE2020 Sec. 6.2 cases on N = 20, 40, 80 elements (P = 4).

For every length L, frequency f, bending factor alpha (EI = alpha * 2.62 kN m^2) and mesh N the case of
config/studies/pe2020_sec62.yaml (base config/ropos_L<L>_paper.yaml, circular fairlead orbit a = 2 m) is
run through the tether-sim-offline code path (``ros.offline.run_offline``: the product's snap detector and
its plausibility guard) for ``--periods`` forcing periods. One CSV row per run (divergences, snap events
per end, numerical warnings, CPU seconds per simulated second) and one row per event go to ``--out``.
Rows already present are skipped (resume). ``--compare`` then checks, per (L, f, alpha), that every snap
of the N = 40 run is present on N = 80 (same end) within ``--peak-tol`` in peak and ``--time-tol`` in
time, and prints the table that docs/dg_solver.md quotes.

Usage: PYTHONPATH=. python benchmarks/studies/slack_bending_ladder.py --lengths 200 500 --freqs 0.2 0.25
       --alphas 0 1 10 100 --meshes 20 40 80 --periods 12 --out out/slack_ladder [--set dg.damping=explicit] [--compare]
       (--compare --coarse 20 --fine 40: the same check one rung lower; --compare --records DIR ...: the recorded
       runs of benchmarks/probes/slack_record.py re-detected with the current snap detector first)
"""

import argparse
import csv
import os
import platform
import re
import subprocess
import sys
import time
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

EI_STAR = 2620.0  # N m^2 [PE2020 Eq. 48]
RUN_FIELDS = ("L", "f", "alpha", "N", "periods", "status", "error", "divergences", "n_snap_ship", "n_snap_vehicle",
              "n_numerical", "max_snap_ship_N", "max_snap_vehicle_N", "sim_s", "cpu_s", "cpu_per_sim_s", "load",
              "date", "commit")
EVENT_FIELDS = ("L", "f", "alpha", "N", "kind", "location", "time_s", "peak_N", "rise_time_s", "bound_N")


def case_config(L, f, alpha, N, periods, extra=None):
    from tether_sim.io.params import load_config

    overrides = {"cable.EI": alpha * EI_STAR, "motion.kind": "circle", "motion.amplitude": 2.0,
                 "motion.frequency": f, "motion.ramp_time": 1.0 / f, "duration": periods / f,
                 "dg.n_elements": int(N), "dg.order": 4}
    overrides.update(extra or {})
    return load_config(ROOT / "config" / f"ropos_L{L:g}_paper.yaml", overrides)


def run_case(L, f, alpha, N, periods, extra=None):
    """One run; returns (run row, event rows)."""
    from tether_sim.ros.offline import run_offline

    cpu0 = time.process_time()
    try:
        summary, error = run_offline(case_config(L, f, alpha, N, periods, extra), None, progress=False), ""
    except Exception as exc:  # noqa: BLE001 - a failed run is a row of the table
        summary, error = None, f"{type(exc).__name__}: {exc}"
    return case_rows(L, f, alpha, N, periods, summary, time.process_time() - cpu0, error)


def case_rows(L, f, alpha, N, periods, summary, cpu, error=""):
    """(run row, event rows) of one run from its ``run_offline`` summary (None: the run failed with ``error``);
    also used by benchmarks/probes/slack_record.py (``--ladder``), so a recorded run is a row of the ladder."""
    from tether_sim.studies.stats import event_rows

    row = {"L": L, "f": f, "alpha": alpha, "N": N, "periods": periods, "status": "failed", "error": error}
    events = []
    if summary is not None:
        rows = event_rows(summary["events"])
        snaps = [e for e in rows if e["kind"] == "snap"]
        ship = [e["peak_N"] for e in snaps if e["location"] == "ship"]
        veh = [e["peak_N"] for e in snaps if e["location"] != "ship"]
        row.update(status="ok", divergences=int(summary["divergences"]), n_snap_ship=len(ship), n_snap_vehicle=len(veh),
                   n_numerical=sum(e["kind"] == "numerical" for e in rows),
                   max_snap_ship_N=max(ship, default=0.0), max_snap_vehicle_N=max(veh, default=0.0),
                   sim_s=float(summary["duration"]))
        events = [{"L": L, "f": f, "alpha": alpha, "N": N, **{k: e.get(k, "") for k in EVENT_FIELDS[4:]}} for e in rows]
    row.update(cpu_s=cpu, cpu_per_sim_s=cpu / row["sim_s"] if row.get("sim_s") else "", load=os.getloadavg()[0],
               date=time.strftime("%Y-%m-%d"), commit=_commit())
    return row, events


def append_case(out, row, events):
    """Append one run's rows to the ladder's CSVs in ``out``."""
    out.mkdir(parents=True, exist_ok=True)
    _append(out / "runs.csv", RUN_FIELDS, [row])
    _append(out / "events.csv", EVENT_FIELDS, events)


def _commit():
    try:
        return subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True, text=True).stdout.strip()
    except OSError:
        return ""


def _read(path):
    if not path.exists():
        return []
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def _append(path, fields, rows):
    new = not path.exists()
    with open(path, "a", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=fields, extrasaction="ignore")
        if new:
            w.writeheader()
        w.writerows(rows)


def _key(r):
    return (float(r["L"]), float(r["f"]), float(r["alpha"]), int(r["N"]))


RECORD = re.compile(r"L([0-9.]+)f([0-9.]+)a([0-9.]+)N([0-9]+)\.npz$")


def redetect(records, out, also=()):
    """The ladder's rows from recorded runs (benchmarks/probes/slack_record.py's ``L<L>f<f>a<alpha>N<N>.npz`` in
    the folders ``records``, the first folder naming a run wins) with the snap detector and guard of the current
    code, written to ``out`` (runs.csv, events.csv; replaced). The runs of one case (L, f, alpha) are cut to the
    shortest of them, so every rung is compared over the same periods; CPU s, load, date and commit are the
    recording run's (from the runs.csv of ``also`` or the record's own folder and its ``ladder`` sibling)."""
    from benchmarks.probes.slack_record import replay
    from tether_sim.studies.stats import event_rows

    import numpy as np

    found = {}
    for folder in records:
        for path in sorted(Path(folder).glob("*.npz")):
            m = RECORD.search(path.name)
            if m:
                found.setdefault((float(m[1]), float(m[2]), float(m[3]), int(m[4])), path)
    meta = {}
    for folder in [*also, *records, *(Path(r).parent / Path(r).name.replace("rec", "ladder") for r in records)]:
        for r in _read(Path(folder) / "runs.csv"):
            meta.setdefault((_key(r), round(float(r["sim_s"] or 0), 6)), r)
    out.mkdir(parents=True, exist_ok=True)
    for name in ("runs.csv", "events.csv"):
        (out / name).unlink(missing_ok=True)
    durations = {}
    for key, path in found.items():
        durations[key] = float(np.load(path)["duration"])
    for key, path in sorted(found.items()):
        L, f, alpha, N = key
        d = np.load(path)
        cut = min(v for k, v in durations.items() if k[:3] == key[:3])
        events = replay(path, case_config(L, f, alpha, N, cut * f), t_end=cut)
        rows = event_rows(events)
        snaps = [e for e in rows if e["kind"] == "snap"]
        ship = [e["peak_N"] for e in snaps if e["location"] == "ship"]
        veh = [e["peak_N"] for e in snaps if e["location"] != "ship"]
        src = meta.get((key, round(durations[key], 6)), {})
        cpu = float(d["cpu"])
        row = {"L": L, "f": f, "alpha": alpha, "N": N, "periods": round(cut * f, 6), "status": "ok", "error": "",
               "divergences": int(d["divergences"]), "n_snap_ship": len(ship), "n_snap_vehicle": len(veh),
               "n_numerical": sum(e["kind"] == "numerical" for e in rows), "max_snap_ship_N": max(ship, default=0.0),
               "max_snap_vehicle_N": max(veh, default=0.0), "sim_s": cut, "cpu_s": cpu,
               "cpu_per_sim_s": cpu / durations[key], "load": float(d["load"]), "date": src.get("date", ""),
               "commit": src.get("commit", "")}
        append_case(out, row, [{"L": L, "f": f, "alpha": alpha, "N": N, **{k: e.get(k, "") for k in EVENT_FIELDS[4:]}}
                               for e in rows])
    return found


def compare(outs, coarse=40, fine=80, peak_tol=0.02, time_tol=0.010):
    """Per case: every snap on ``coarse`` matched on ``fine`` (same end, nearest time); returns the table rows.
    ``outs``: one or more output folders (runs of different lengths may sit in different folders)."""
    runs, events = {}, {}
    for out in ([outs] if isinstance(outs, Path) else outs):
        runs.update({_key(r): r for r in _read(out / "runs.csv")})
        for e in _read(out / "events.csv"):
            events.setdefault(_key(e), []).append(e)
    table = []
    for (L, f, alpha, N), run in sorted(runs.items()):
        if N != coarse or (L, f, alpha, fine) not in runs:
            continue
        fine_run = runs[(L, f, alpha, fine)]
        # events in the span both runs cover (a shorter fine run is compared on its span; 1 s of peak window)
        span = min(float(run["sim_s"] or 0.0), float(fine_run["sim_s"] or 0.0)) - 1.0
        a = [e for e in events.get((L, f, alpha, coarse), []) if e["kind"] == "snap" and float(e["time_s"]) <= span]
        b = [e for e in events.get((L, f, alpha, fine), []) if e["kind"] == "snap" and float(e["time_s"]) <= span]
        worst_dp, worst_dt, missing = 0.0, 0.0, 0
        for e in a:
            same = [x for x in b if x["location"] == e["location"]]
            if not same:
                missing += 1
                continue
            m = min(same, key=lambda x: abs(float(x["time_s"]) - float(e["time_s"])))
            dt = abs(float(m["time_s"]) - float(e["time_s"]))
            dp = abs(float(m["peak_N"]) / float(e["peak_N"]) - 1.0)
            if dt > time_tol or dp > peak_tol:
                missing += 1
            worst_dp, worst_dt = max(worst_dp, dp), max(worst_dt, dt)
        extra = len(b) - (len(a) - missing)
        # the acceptance: both runs finished without divergence and every coarse snap is matched; a numerical
        # warning is an event the snap guard kept out of the snaps (counted in its own column, not a failure)
        ok = (missing == 0 and run["status"] == fine_run["status"] == "ok" and int(run["divergences"] or 0) == 0
              and int(fine_run["divergences"] or 0) == 0)
        table.append({"L": L, "f": f, "alpha": alpha, "snaps_coarse": len(a), "snaps_fine": len(b),
                      "unmatched": missing, "extra_fine": extra, "worst_peak_rel": worst_dp, "worst_dt_s": worst_dt,
                      "numerical": f"{run['n_numerical']}/{fine_run['n_numerical']}", "ok": ok})
    return table


def event_table(outs, meshes=(20, 40, 80), window=0.05):
    """Every event of every case across the meshes: per (L, f, alpha), the events of one end and kind (snap or
    numerical, i.e. rejected by the snap guard) whose times lie within ``window`` s of the first of them form one
    row, with each mesh's time, peak, rise time (and for a rejected one its bound) and the change from each mesh to
    the next. Returns (case runs, rows)."""
    runs, events = {}, {}
    for out in ([outs] if isinstance(outs, Path) else outs):
        runs.update({_key(r): r for r in _read(out / "runs.csv")})
        for e in _read(out / "events.csv"):
            events.setdefault(_key(e), []).append(e)
    cases = sorted({k[:3] for k in runs})
    rows = []
    for case in cases:
        have = [N for N in meshes if case + (N,) in runs]
        span = min(float(runs[case + (N,)]["sim_s"] or 0.0) for N in have) - 1.0 if have else 0.0
        pool = sorted(((e["location"], e["kind"], float(e["time_s"]), int(N), e) for N in have
                       for e in events.get(case + (N,), []) if float(e["time_s"]) <= span), key=lambda x: x[:3])
        groups = []
        for loc, kind, t, N, e in pool:
            g = groups[-1] if groups else None
            if g is None or (g["location"], g["kind"]) != (loc, kind) or t - g["t0"] > window or N in g["by_mesh"]:
                g = {"location": loc, "kind": kind, "t0": t, "by_mesh": {}}
                groups.append(g)
            g["by_mesh"][N] = e
        for g in sorted(groups, key=lambda g: (g["kind"] != "snap", g["t0"], g["location"])):
            rows.append({"case": case, "meshes": have, **g})
    return runs, rows


def print_event_table(outs, meshes=(20, 40, 80)):
    runs, rows = event_table(outs, meshes)
    for case in sorted({k[:3] for k in runs}):
        have = [N for N in meshes if case + (N,) in runs]
        print(f"\nL {case[0]:g} m, f {case[1]:g} Hz, alpha {case[2]:g}: " + "; ".join(
            f"N {N}: {runs[case + (N,)]['status']}, divergences {runs[case + (N,)].get('divergences', '')}, "
            f"{float(runs[case + (N,)]['sim_s'] or 0):.2f} s simulated, {float(runs[case + (N,)]['cpu_s']):.0f} CPU s "
            f"(load {float(runs[case + (N,)]['load']):.1f})" for N in have))
        print("end | verdict | " + " | ".join(f"N {N}: time s, peak kN, rise ms" for N in have)
              + " | " + " | ".join(f"{a}->{b}: peak %, dt ms" for a, b in zip(have, have[1:])))
        for r in (r for r in rows if r["case"] == case):
            cells = []
            for N in have:
                e = r["by_mesh"].get(N)
                if e is None:
                    cells.append("none")
                    continue
                cell = f"{float(e['time_s']):.4f}, {float(e['peak_N']) / 1e3:.2f}, {float(e['rise_time_s']) * 1e3:.3g}"
                if r["kind"] != "snap":
                    cell += f" (bound {float(e['bound_N']) / 1e3:.4g} kN)"
                cells.append(cell)
            diffs = []
            for a, b in zip(have, have[1:]):
                ea, eb = r["by_mesh"].get(a), r["by_mesh"].get(b)
                diffs.append("-" if ea is None or eb is None else
                             f"{(float(eb['peak_N']) / float(ea['peak_N']) - 1) * 100:+.2f}, "
                             f"{(float(eb['time_s']) - float(ea['time_s'])) * 1e3:+.1f}")
            verdict = "snap" if r["kind"] == "snap" else "rejected"
            print(f"{r['location']} | {verdict} | " + " | ".join(cells) + " | " + " | ".join(diffs))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--lengths", type=float, nargs="+", default=[200.0, 500.0])
    ap.add_argument("--freqs", type=float, nargs="+", default=[0.2, 0.25])
    ap.add_argument("--alphas", type=float, nargs="+", default=[0.0, 1.0, 10.0, 100.0])
    ap.add_argument("--meshes", type=int, nargs="+", default=[20, 40, 80])
    ap.add_argument("--periods", type=float, default=12.0)
    ap.add_argument("--out", type=Path, default=Path("out/slack_ladder"))
    ap.add_argument("--also", type=Path, nargs="*", default=[], help="further output folders for --compare")
    ap.add_argument("--set", nargs="*", default=[], metavar="KEY=VALUE",
                    help="further parameter overrides for every run, e.g. dg.damping=implicit (cheaper, but not clean "
                         "in slack phases at N = 40: docs/dg_solver.md \"Slack with bending\")")
    ap.add_argument("--compare", action="store_true", help="only print the N = 40 / 80 comparison table")
    ap.add_argument("--events", action="store_true",
                    help="with --compare: also print every event of every case on every mesh (time, peak, rise, verdict)")
    ap.add_argument("--coarse", type=int, default=40, help="--compare: the mesh whose snaps must be on --fine")
    ap.add_argument("--fine", type=int, default=80)
    ap.add_argument("--records", type=Path, nargs="*", default=[],
                    help="with --compare: re-detect the recorded runs in these folders (slack_record.py's npz) with "
                         "the current snap detector into --out, every case cut to its shortest rung, then compare")
    ap.add_argument("--peak-tol", type=float, default=0.02)
    ap.add_argument("--time-tol", type=float, default=0.010)
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    if args.compare and args.records:
        redetect(args.records, args.out, args.also)
        args.also = []
    elif not args.compare:
        done = {_key(r) for r in _read(args.out / "runs.csv")}
        extra = {k: yaml.safe_load(v) for k, _, v in (item.partition("=") for item in args.set)}  # as a YAML value
        print(f"# overrides {extra}", flush=True)
        print(f"# {platform.node()} {time.strftime('%Y-%m-%d %H:%M')} load {os.getloadavg()[0]:.1f}", flush=True)
        for L in args.lengths:
            for f in args.freqs:
                for alpha in args.alphas:
                    for N in args.meshes:
                        if (L, f, alpha, N) in done:
                            continue
                        row, events = run_case(L, f, alpha, N, args.periods, extra)
                        append_case(args.out, row, events)
                        print(" ".join(f"{k}={row.get(k, '')}" for k in RUN_FIELDS[:16]), flush=True)
    print(f"L f alpha | snaps N{args.coarse} N{args.fine} | unmatched extra | worst peak rel | worst dt s | numerical | ok")
    for r in compare([args.out, *args.also], args.coarse, args.fine, peak_tol=args.peak_tol, time_tol=args.time_tol):
        print(f"{r['L']:g} {r['f']:g} {r['alpha']:g} | {r['snaps_coarse']} {r['snaps_fine']} | {r['unmatched']} "
              f"{r['extra_fine']} | {r['worst_peak_rel']:.4f} | {r['worst_dt_s']:.4f} | {r['numerical']} | {r['ok']}")
    if args.events:
        print_event_table([args.out, *args.also], tuple(args.meshes))


if __name__ == "__main__":
    main()
