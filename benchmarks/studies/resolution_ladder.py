"""Resolution ladders of the DG solver: first-snap-peak error against cost, per tether case.

The measurements behind ``dg.resolution: auto`` (``tether_sim/solvers/resolution.py``,
docs/performance.md "Accuracy-chosen resolution"). For each case (length L, cable, bending
factor alpha, vehicle end) the ROPOS slack-snap run of ``ropos_case`` (circular fairlead orbit
a = 2 m, f = 0.2 Hz, ramped over the first period) is run for ``--duration`` simulated seconds on

* the reference: N_ref = max(10, ceil(L / 20 m)) elements, P = 4, dg.cfl 0.5 (the converged
  explicit run, h <= 20 m; on 2026-11-21 N = 3 was found within 0.1 % of N = 20 at L = 200 m);
* the candidate rungs: N = 1, 2, 3, 4, 6, 8, 12, 16, 24, 32 (below N_ref) at P = 4 and dg.cfl 0.8;
  with ``--variants`` also N = 2 and 3 at dg.cfl 0.5 (the time-step part of the error) and
  N = 2, 3, 4 at P = 3; with ``--orders`` (2026-11-23) the P = 3 (N = 1-32) and P = 2 (N = 2-32)
  ladders at dg.cfl 0.8 and N = 2-8 at dg.cfl 0.65 and 1.0 (P = 3, 4) and N = 4-8 at dg.cfl 0.5;
  ``--extra N:P:cfl`` adds single rungs (975 m: N = 40, 48 at P = 3, 4).

Metric (both ends): the largest end tension in the first full-amplitude period (5-10 s, the first
slack-snap event), interpolated onto a common 200 Hz grid (``grid``: like-for-like with the tables
of 2026-11-21); the error of a rung is the relative difference to the reference, the worse of the two
ends. The substep record's maximum (``raw``) is stored too but not used: the finest references
(h ~ 20 m) show one-substep spikes where a slack end re-tensions (171 kN for one 7e-5 s substep
at the L = 1730 m cage, absent at N = 20 and 40, whose peaks agree to 0.05 %). Cost: thread CPU per
simulated second of the same run, 50 Hz ticks through ``advance_to`` (includes the ramp).

Cables: ``stiff`` = ROPOS [PE2020 Table 3] (EA = 45.5 MN, zeta = 45.5 kN s); ``soft`` = a
synthetic-fibre tether, same mass and diameter, EA = 2 MN and zeta = 2 kN s (the same
zeta / EA = 1 ms). Ends: ``cage`` = the ROPOS cage as a simulated body; ``free`` = no cage,
free cable end (kind free).

Every run appends one row to the CSV at once (``--csv``), so an interrupted ladder loses nothing;
rows already present are skipped, so the same command resumes. ``--summary`` prints the error
tables from the CSV, ``--table`` writes the rule's table (tether_sim/solvers/resolution_table.py)
and ``--markdown docs/resolution_ladder.md`` the generated page (no runs; benchmarks/studies/resolution_report.py).

Usage: PYTHONPATH=. python benchmarks/studies/resolution_ladder.py --cases 200:stiff:0:cage 200:stiff:1:cage
       [--duration 10.2] [--csv docs/data/resolution_ladder.csv] [--summary]
"""

import argparse
import csv
import math
import os
import subprocess
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from benchmarks import drive  # noqa: E402
from benchmarks import ropos_case as rc  # noqa: E402
from benchmarks.studies.resolution_report import FIELDS, TABLE_MODULE, markdown, read_rows, summary, table_module  # noqa: E402
from tether_sim.physics.boundary import EndCondition  # noqa: E402

GRID_STEP = 0.005  # s, 200 Hz common sampling (bench_moordyn.COUPLING_STEP)
WINDOW = rc.FIRST_SNAP_WINDOW  # (5, 10) s
SOFT_EA, SOFT_ZETA = 2.0e6, 2.0e3  # N, N s
CANDIDATES = (("1", 4, 0.8), ("2", 4, 0.8), ("3", 4, 0.8), ("4", 4, 0.8), ("6", 4, 0.8), ("8", 4, 0.8),
              ("12", 4, 0.8), ("16", 4, 0.8), ("24", 4, 0.8), ("32", 4, 0.8))
VARIANTS = (("2", 4, 0.5), ("3", 4, 0.5), ("2", 3, 0.8), ("3", 3, 0.8), ("4", 3, 0.8))  # --variants
# --orders: the P = 2 and P = 3 ladders and the safety factor dg.cfl (0.5, 0.65, 1.0 next to 0.8) at P = 3, 4
ORDER_LADDERS = (tuple((str(n), 3, 0.8) for n in (1, 2, 3, 4, 6, 8, 12, 16, 24, 32))
                 + tuple((str(n), 2, 0.8) for n in (2, 3, 4, 6, 8, 12, 16, 24, 32))
                 + tuple((str(n), p, c) for p in (3, 4) for c in (0.65, 1.0) for n in (2, 3, 4, 6, 8))
                 + tuple((str(n), p, 0.5) for p in (3, 4) for n in (4, 6, 8)))
RECORDS = ""  # directory for the end-tension records (5 s on) of every run; "" = none


def reference_elements(length):
    """N of the converged reference: h <= 20 m, at least 10 elements."""
    return max(10, math.ceil(length / 20.0))


def case_config(case, n_elements, order, cfl, duration):
    """SimConfig of a case 'L:cable:alpha:end' at one rung."""
    length, cable, alpha, end = case.split(":")
    cfg = rc.ropos_config(float(length), alpha=float(alpha), n_elements=n_elements, order=order, cfl=cfl,
                          duration=duration)
    if cable == "soft":
        cfg = replace(cfg, cable=replace(cfg.cable, EA=SOFT_EA, damping=SOFT_ZETA))
    elif cable != "stiff":
        raise ValueError(f"cable: stiff or soft, got {cable!r}")
    if end == "free":
        cfg = replace(cfg, vehicle_end=EndCondition(kind="free", position=cfg.vehicle_end.position))
    elif end != "cage":
        raise ValueError(f"end: cage or free, got {end!r}")
    return cfg


def _peaks(t, tension):
    grid = np.arange(int(round(WINDOW[0] / GRID_STEP)), int(round(WINDOW[1] / GRID_STEP)) + 1) * GRID_STEP
    mask = (t >= WINDOW[0]) & (t <= WINDOW[1])
    i = np.argmax(np.where(mask, tension, -np.inf))
    return float(tension[i]), float(np.max(np.interp(grid, t, tension))), float(t[i])


def run_rung(case, n_elements, order, cfl, duration, reference):
    cfg = case_config(case, n_elements, order, cfl, duration)
    drive.run(cfg, 0.1, motion=rc.fairlead_motion)  # JIT cache warm, untimed
    res = drive.run(cfg, duration, motion=rc.fairlead_motion)
    t = res["t"]
    if RECORDS:
        Path(RECORDS).mkdir(parents=True, exist_ok=True)
        keep = t >= WINDOW[0]
        np.savez_compressed(Path(RECORDS) / f"{case.replace(':', '_')}_N{n_elements}P{order}c{cfl:g}.npz",
                            t=t[keep], ship=res["ship"][keep], vehicle=res["vehicle"][keep])
    ship = _peaks(t, res["ship"])
    veh = _peaks(t, res["vehicle"])
    length, cable, alpha, end = case.split(":")
    return {
        "case": case, "length": float(length), "cable": cable, "EA": cfg.cable.EA, "zeta": cfg.cable.damping,
        "alpha": float(alpha), "end": end, "n_elements": n_elements, "order": order, "cfl": cfl,
        "reference": int(reference), "time_step": res["time_step"],
        "ship_raw": ship[0], "ship_grid": ship[1], "ship_t": ship[2],
        "vehicle_raw": veh[0], "vehicle_grid": veh[1], "vehicle_t": veh[2],
        "cpu_per_s": res["cpu"] / duration, "wall_per_s": res["wall"] / duration, "substeps": res["substeps"],
        "load": os.getloadavg()[0], "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
        "commit": _commit(),
    }


def _commit():
    try:
        return subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                              cwd=Path(__file__).resolve().parents[2]).stdout.strip()
    except OSError:
        return ""


def _append(path, row):
    new = not Path(path).exists()
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    with open(path, "a", newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS)
        if new:
            w.writeheader()
        w.writerow(row)


def ladder(case, duration, csv_path, candidates=CANDIDATES, extra=()):
    done = {(r["case"], int(r["n_elements"]), int(r["order"]), round(r["cfl"], 3)) for r in read_rows(csv_path)}
    n_ref = reference_elements(float(case.split(":")[0]))
    plan = [(n_ref, 4, 0.5, True)] + [(int(n), p, c, False) for n, p, c in candidates if int(n) < n_ref]
    plan += [(int(n), int(p), float(c), False) for n, p, c in (x.split(":") for x in extra)]
    plan = list(dict.fromkeys(plan))  # a rung listed twice (--variants and --orders) runs once
    for n, p, c, is_ref in plan:
        if (case, n, p, round(c, 3)) in done:
            continue
        try:
            row = run_rung(case, n, p, c, duration, is_ref)
        except Exception as exc:  # a rung that diverges is a result too: recorded as NaN
            print(f"  {case} N={n} P={p} cfl={c}: FAILED {type(exc).__name__}: {exc}", flush=True)
            row = {k: float("nan") for k in FIELDS}
            row.update(case=case, n_elements=n, order=p, cfl=c, reference=int(is_ref), date="", commit=_commit(),
                       cable=case.split(":")[1], end=case.split(":")[3], length=float(case.split(":")[0]),
                       alpha=float(case.split(":")[2]), load=os.getloadavg()[0])
        _append(csv_path, row)
        print(f"  {case:22s} N={n:3d} P={p} cfl={c:.1f} dt={row['time_step']:.3g} ship={row['ship_raw'] / 1e3:9.3f} "
              f"veh={row['vehicle_raw'] / 1e3:9.3f} kN cpu/sim-s={1e3 * row['cpu_per_s']:8.1f} ms "
              f"load={row['load']:.1f}", flush=True)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", nargs="*", default=[])
    ap.add_argument("--duration", type=float, default=10.2)
    ap.add_argument("--csv", default="docs/data/resolution_ladder.csv")
    ap.add_argument("--extra", nargs="*", default=[], help="more rungs 'N:P:cfl' for every case (e.g. 20:4:0.5)")
    ap.add_argument("--records", default="", help="save each run's end-tension record (npz) in this folder")
    ap.add_argument("--variants", action="store_true", help="also the dg.cfl 0.5 and P = 3 rungs")
    ap.add_argument("--orders", action="store_true", help="also the P = 2, 3 ladders and dg.cfl 0.5 / 0.65 / 1.0 rungs")
    ap.add_argument("--summary", action="store_true")
    ap.add_argument("--markdown", default="", help="write the generated tables to this file (docs/resolution_ladder.md)")
    ap.add_argument("--table", action="store_true", help=f"write the rule's table ({TABLE_MODULE}) from the CSV")
    args = ap.parse_args(argv)
    global RECORDS
    RECORDS = args.records
    for case in args.cases:
        ladder(case, args.duration, args.csv, candidates=CANDIDATES + (VARIANTS if args.variants else ())
               + (ORDER_LADDERS if args.orders else ()), extra=args.extra)
    if args.summary:
        summary(args.csv)
    if args.markdown:
        Path(args.markdown).write_text(markdown(read_rows(args.csv)))
        print(f"wrote {args.markdown}")
    if args.table:
        (ROOT / TABLE_MODULE).write_text(table_module(read_rows(args.csv)))
        print(f"wrote {TABLE_MODULE}")


if __name__ == "__main__":
    main()
