"""Resolution ladders of the DG solver: first-snap-peak error against cost, per tether case.

The measurements behind ``dg.resolution: auto`` (``tether_sim/solvers/resolution.py``,
docs/performance.md "Accuracy-chosen resolution"). For each case (length L, cable, bending
factor alpha, vehicle end) the ROPOS slack-snap run of ``ropos_case`` (circular fairlead orbit
a = 2 m, f = 0.2 Hz, ramped over the first period) is run for ``--duration`` simulated seconds on

* the reference: N_ref = max(10, ceil(L / 20 m)) elements, P = 4, dg.cfl 0.5 (the converged
  explicit run, h <= 20 m; session 2 found N = 3 within 0.1 % of N = 20 at L = 200 m);
* the candidate rungs: N = 1, 2, 3, 4, 6, 8, 12, 16, 24, 32 (below N_ref) at P = 4 and dg.cfl 0.8;
  with ``--variants`` also N = 2 and 3 at dg.cfl 0.5 (the time-step part of the error) and
  N = 2, 3, 4 at P = 3.

Metric (both ends): the largest end tension in the first full-amplitude period (5-10 s, the first
slack-snap event), interpolated onto a common 200 Hz grid (``grid``: like-for-like with session 2's
tables); the error of a rung is the relative difference to the reference, the worse of the two
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
tables from the CSV (no runs).

Usage: PYTHONPATH=. python benchmarks/resolution_ladder.py --cases 200:stiff:0:cage 200:stiff:1:cage
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

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks import drive  # noqa: E402
from benchmarks import ropos_case as rc  # noqa: E402
from tether_sim.errors import ConfigError  # noqa: E402
from tether_sim.physics.boundary import EndCondition  # noqa: E402
from tether_sim.solvers.resolution import choose  # noqa: E402

ORDER, CFL = 4, 0.8  # the rule's rungs (tether_sim/solvers/resolution.py)
GRID_STEP = 0.005  # s, 200 Hz common sampling (bench_moordyn.COUPLING_STEP)
WINDOW = rc.FIRST_SNAP_WINDOW  # (5, 10) s
SOFT_EA, SOFT_ZETA = 2.0e6, 2.0e3  # N, N s
CANDIDATES = (("1", 4, 0.8), ("2", 4, 0.8), ("3", 4, 0.8), ("4", 4, 0.8), ("6", 4, 0.8), ("8", 4, 0.8),
              ("12", 4, 0.8), ("16", 4, 0.8), ("24", 4, 0.8), ("32", 4, 0.8))
VARIANTS = (("2", 4, 0.5), ("3", 4, 0.5), ("2", 3, 0.8), ("3", 3, 0.8), ("4", 3, 0.8))  # --variants
# --orders: the P = 2 and P = 3 ladders and the safety factor dg.cfl (0.5, 0.65, 1.0 next to 0.8) at P = 3, 4
ORDER_LADDERS = (tuple((str(n), 3, 0.8) for n in (1, 2, 3, 4, 6, 8, 12, 16, 24))
                 + tuple((str(n), 2, 0.8) for n in (2, 3, 4, 6, 8, 12, 16, 24, 32))
                 + tuple((str(n), p, c) for p in (3, 4) for c in (0.65, 1.0) for n in (2, 3, 4, 6, 8))
                 + tuple((str(n), p, 0.5) for p in (3, 4) for n in (4, 6, 8)))
RECORDS = ""  # directory for the end-tension records (5 s on) of every run; "" = none
FIELDS = ("case", "length", "cable", "EA", "zeta", "alpha", "end", "n_elements", "order", "cfl", "reference",
          "time_step", "ship_raw", "ship_grid", "ship_t", "vehicle_raw", "vehicle_grid", "vehicle_t",
          "cpu_per_s", "wall_per_s", "substeps", "load", "date", "commit")


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
                              cwd=Path(__file__).resolve().parents[1]).stdout.strip()
    except OSError:
        return ""


def read_rows(path):
    if not Path(path).exists():
        return []
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        for k in FIELDS:
            if k not in ("case", "cable", "end", "date", "commit"):
                r[k] = float(r[k])
    return rows


def _append(path, row):
    new = not Path(path).exists()
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    with open(path, "a", newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS)
        if new:
            w.writeheader()
        w.writerow(row)


def rung_error(row, ref, sampling="grid"):
    """Worst relative error of the first snap peak over both ends (a free end carries no tension).

    ``grid`` (the rule's metric): the 200 Hz resampling. ``raw``: the substep record, where the
    finest references show one-substep spikes at the re-tension of a slack end (docs/performance.md).
    """
    errs = [abs(row[f"{end}_{sampling}"] - ref[f"{end}_{sampling}"]) / ref[f"{end}_{sampling}"]
            for end in ("ship", "vehicle") if ref[f"{end}_{sampling}"] > 1.0]
    return max(errs)


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


def error_table(rows):
    """{case: [(N, P, cfl, error, cpu_per_s, time_step)]} against each case's reference row."""
    out = {}
    for case in dict.fromkeys(r["case"] for r in rows):
        mine = [r for r in rows if r["case"] == case]
        refs = [r for r in mine if r["reference"] == 1 and np.isfinite(r["ship_raw"])]
        if not refs:
            continue
        ref = refs[-1]
        out[case] = (ref, [(int(r["n_elements"]), int(r["order"]), r["cfl"],
                            rung_error(r, ref) if np.isfinite(r["ship_raw"]) else float("inf"),
                            r["cpu_per_s"], r["time_step"]) for r in mine if r is not ref])
    return out


def _bending_effect_errors(rows):
    """{(L, end, N): worst |effect(rung) - effect(ref)| / ref(alpha 0)}, effect = peak(alpha 1) - peak(alpha 0)."""
    out = {}
    table = error_table(rows)
    pairs = {}
    for r in rows:
        key = (r["length"], r["cable"], r["end"])
        pairs.setdefault(key, {}).setdefault(r["alpha"], []).append(r)
    for (length, _, end), by_alpha in pairs.items():
        if 0.0 not in by_alpha or 1.0 not in by_alpha:
            continue
        case0, case1 = by_alpha[0.0][0]["case"], by_alpha[1.0][0]["case"]
        if case0 not in table or case1 not in table:
            continue
        ref0, ref1 = table[case0][0], table[case1][0]
        rung1 = {(int(r["n_elements"]), int(r["order"]), round(r["cfl"], 3)): r for r in by_alpha[1.0]}
        for r0 in by_alpha[0.0]:
            key = (int(r0["n_elements"]), int(r0["order"]), round(r0["cfl"], 3))
            if r0["reference"] == 1 or key not in rung1 or key[1:] != (ORDER, CFL):
                continue
            errs = [abs((rung1[key][c] - r0[c]) - (ref1[c] - ref0[c])) / ref0[c]
                    for c in ("ship_grid", "vehicle_grid") if ref0[c] > 1.0]
            err = max(errs) if np.isfinite(errs).all() else float("inf")
            out[(length, end, key[0])] = max(out.get((length, end, key[0]), 0.0), err)
    return out


END_KINDS = {"cage": "body", "free": "free"}  # case name -> vehicle_end.kind


def worst_errors(rows):
    """{vehicle_end.kind: {L: {N: worst first-snap-peak error}}} at P = ORDER, cfl = CFL over every
    case measured with that end at L, the bending effect's error included: the table of
    tether_sim/solvers/resolution.py."""
    out = {}
    for case, (ref, rungs) in error_table(rows).items():
        by_length = out.setdefault(END_KINDS[ref["end"]], {})
        for n, p, c, err, _, _ in rungs:
            if (p, round(c, 3)) == (ORDER, CFL):
                row = by_length.setdefault(ref["length"], {})
                row[n] = max(row.get(n, 0.0), err)
    for (length, end, n), err in _bending_effect_errors(rows).items():
        row = out[END_KINDS[end]][length]
        row[n] = max(row[n], err)
    return {kind: {length: dict(sorted(v.items())) for length, v in sorted(t.items())}
            for kind, t in sorted(out.items())}


def table_source(rows):
    """The _WORST_ERROR literal, each error rounded up to 1e-4."""
    lines = ["_WORST_ERROR = {"]
    for kind, table in worst_errors(rows).items():
        lines.append(f'    "{kind}": {{')
        for length, errs in table.items():
            items = ", ".join(f"{n}: {math.ceil(e * 1e4) / 1e4:.4f}" if np.isfinite(e) else f"{n}: math.inf"
                              for n, e in errs.items())
            lines.append(f"        {length:g}: {{{items}}},")
        lines.append("    },")
    return "\n".join(lines + ["}"])


def markdown(rows):
    """docs/resolution_ladder.md: per-case errors, the rule's table and its choices (generated)."""
    table = error_table(rows)
    worst = worst_errors(rows)
    ns = sorted({n for table in worst.values() for errs in table.values() for n in errs})
    out = ["# DG resolution ladders (generated by `benchmarks/resolution_ladder.py --markdown`)", "",
           "First-snap-peak error (largest end tension in 5-10 s, worse of the two ends, 200 Hz "
           f"resampling) of N elements at P = {ORDER}, dg.cfl {CFL}, against the case's reference "
           "(N_ref = max(10, ceil(L / 20 m)), P = 4, cfl 0.5). Case = L (m) : cable : alpha : vehicle end. "
           "Cost: thread CPU per simulated second of the 10.2 s run (50 Hz ticks, ramp included) at the "
           "load in the CSV (`docs/data/resolution_ladder.csv`, with dates and commits).", "",
           "| case | reference ship / vehicle (kN) | " + " | ".join(f"N={n}" for n in ns) + " |",
           "|---|---|" + "---|" * len(ns)]
    for case, (ref, rungs) in table.items():
        errs = {n: e for n, p, c, e, _, _ in rungs if (p, round(c, 3)) == (ORDER, CFL)}
        veh = f"{ref['vehicle_grid'] / 1e3:.2f}" if ref["vehicle_grid"] > 1.0 else "-"
        cells = [f"{100 * errs[n]:.2f} %" if n in errs else "" for n in ns]
        out.append(f"| {case} | {ref['ship_grid'] / 1e3:.2f} / {veh} | " + " | ".join(cells) + " |")
    out += ["", "Bending effect on the first snap peak, peak(alpha 1) - peak(alpha 0) relative to peak(alpha 0), "
            "ship / vehicle end: in the references, and its error at the rule's 1 % mesh (this error is "
            "included in the worst-error table below):", "",
            "| L : cable : end | effect, reference | 1 % mesh | effect error there |", "|---|---|---|---|"]
    effect_err = _bending_effect_errors(rows)
    for case0 in table:
        length, cable, alpha, end = case0.split(":")
        case1 = f"{length}:{cable}:1:{end}"
        if alpha != "0" or case1 not in table:
            continue
        r0, r1 = table[case0][0], table[case1][0]
        eff = [100 * (r1[f"{e}_grid"] - r0[f"{e}_grid"]) / r0[f"{e}_grid"] if r0[f"{e}_grid"] > 1.0 else float("nan")
               for e in ("ship", "vehicle")]
        try:
            n = choose(float(length), 0.01, END_KINDS[end]).n_elements
            err = effect_err.get((float(length), end, n), float("nan"))
            mesh, etxt = f"N = {n}", f"{100 * err:.3f} %"
        except ConfigError:
            mesh, etxt = "refused", ""
        out.append(f"| {length}:{cable}:{end} | {eff[0]:+.3f} % / {eff[1]:+.3f} % | {mesh} | {etxt} |")
    out += ["",
            "Cost (ms CPU per simulated s) of the same rungs:", "",
            "| case | reference | " + " | ".join(f"N={n}" for n in ns) + " |", "|---|---|" + "---|" * len(ns)]
    for case, (ref, rungs) in table.items():
        cost = {n: c for n, p, cf, _, c, _ in rungs if (p, round(cf, 3)) == (ORDER, CFL)}
        out.append(f"| {case} | {1e3 * ref['cpu_per_s']:.0f} | "
                   + " | ".join(f"{1e3 * cost[n]:.1f}" if n in cost else "" for n in ns) + " |")
    out += ["", "Worst error over the cases with each vehicle end at each length (the table of "
            "`tether_sim/solvers/resolution.py`):", "",
            "| vehicle end | L (m) | " + " | ".join(f"N={n}" for n in ns) + " |", "|---|---|" + "---|" * len(ns)]
    for kind, table_l in worst.items():
        for length, errs in table_l.items():
            out.append(f"| {kind} | {length:g} | "
                       + " | ".join(f"{100 * errs[n]:.2f} %" if n in errs else "" for n in ns) + " |")
    out += ["", "The rule's choice with the cage (`tether_sim/solvers/resolution.py`, its table as committed) per "
            "tolerance; cost = ms CPU per simulated s of that rung in the stiff, alpha = 0, cage case above:", "",
            "| L (m) | 0.5 % | 1 % | 2 % | 5 % |", "|---|---|---|---|---|"]
    for length in worst["body"]:
        cells = []
        for tol in (0.005, 0.01, 0.02, 0.05):
            try:
                n = choose(length, tol).n_elements
            except ConfigError:
                cells.append("refused")
                continue
            key = f"{length:g}:stiff:0:cage"
            cost = {m: c for m, p, cf, _, c, _ in table.get(key, (None, []))[1] if (p, round(cf, 3)) == (ORDER, CFL)}
            cells.append(f"N = {n}" + (f" ({1e3 * cost[n]:.0f} ms/s)" if n in cost else ""))
        out.append(f"| {length:g} | " + " | ".join(cells) + " |")
    others = [(case, n, p, c, e) for case, (ref, rungs) in table.items() for n, p, c, e, _, _ in rungs
              if (p, round(c, 3)) != (ORDER, CFL)]
    if others:
        out += ["", "Other rungs (P = 3, or dg.cfl 0.5: the time-step part of the error):", "",
                "| case | rung | error |", "|---|---|---|"]
        out += [f"| {case} | N={n} P={p} cfl={c:g} | {100 * e:.2f} % |" for case, n, p, c, e in others]
    return "\n".join(out) + "\n"


def summary(csv_path):
    rows = read_rows(csv_path)
    for case, (ref, rungs) in error_table(rows).items():
        print(f"\n{case}: reference N={int(ref['n_elements'])} P=4 cfl 0.5: ship {ref['ship_raw'] / 1e3:.2f} kN, "
              f"vehicle {ref['vehicle_raw'] / 1e3:.2f} kN, {1e3 * ref['cpu_per_s']:.0f} ms CPU / sim s")
        for n, p, c, err, cpu, dt in sorted(rungs, key=lambda x: (x[1], x[2], x[0])):
            print(f"   N={n:2d} P={p} cfl={c:.1f}  error {100 * err:7.3f} %  dt {dt:.3g} s  {1e3 * cpu:7.1f} ms CPU/sim s")


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
    ap.add_argument("--table", action="store_true", help="print the rule's _WORST_ERROR table from the CSV")
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
        print(table_source(read_rows(args.csv)))


if __name__ == "__main__":
    main()
