"""Tables of the DG resolution ladders (docs/data/resolution_ladder.csv): per-rung errors, the
worst-error table of ``dg.resolution: auto`` and docs/resolution_ladder.md. No runs here: the
runs are ``benchmarks/studies/resolution_ladder.py``, which writes the CSV and calls this module for
``--summary``, ``--markdown`` and ``--table``.
"""

import csv
import math
from pathlib import Path

import numpy as np

FIELDS = ("case", "length", "cable", "EA", "zeta", "alpha", "end", "n_elements", "order", "cfl", "reference",
          "time_step", "ship_raw", "ship_grid", "ship_t", "vehicle_raw", "vehicle_grid", "vehicle_t",
          "cpu_per_s", "wall_per_s", "substeps", "load", "date", "commit")
END_KINDS = {"cage": "body", "free": "free"}  # case name -> vehicle_end.kind
TABLE_MODULE = "tether_sim/solvers/resolution_table.py"
DURATION = 10.2  # s simulated per ladder run (the CSV's cpu_per_s is per simulated s, substeps per run)


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


def rung_error(row, ref, sampling="grid"):
    """Worst relative error of the first snap peak over both ends (a free end carries no tension).

    ``grid`` (the rule's metric): the 200 Hz resampling. ``raw``: the substep record, where the
    finest references show one-substep spikes at the re-tension of a slack end (docs/performance.md).
    """
    errs = [abs(row[f"{end}_{sampling}"] - ref[f"{end}_{sampling}"]) / ref[f"{end}_{sampling}"]
            for end in ("ship", "vehicle") if ref[f"{end}_{sampling}"] > 1.0]
    return max(errs)


def family(row):
    """The ladder a row belongs to: (P, dg.cfl)."""
    return int(row["order"]), round(float(row["cfl"]), 3)


def error_table(rows):
    """{case: (reference row, [(N, P, cfl, error, cpu_per_s, time_step)])}."""
    out = {}
    for case in dict.fromkeys(r["case"] for r in rows):
        mine = [r for r in rows if r["case"] == case]
        refs = [r for r in mine if r["reference"] == 1 and np.isfinite(r["ship_raw"])]
        if not refs:
            continue
        ref = refs[-1]
        out[case] = (ref, [(int(r["n_elements"]), int(r["order"]), round(r["cfl"], 3),
                            rung_error(r, ref) if np.isfinite(r["ship_raw"]) else float("inf"),
                            r["cpu_per_s"], r["time_step"]) for r in mine if r["reference"] != 1])
    return out


def bending_effect_errors(rows):
    """{(L, cable, end, (P, cfl), N): |effect(rung) - effect(ref)| / ref(alpha 0)}, the worse of the
    two ends, effect = peak(alpha 1) - peak(alpha 0)."""
    out = {}
    table = error_table(rows)
    pairs = {}
    for r in rows:
        pairs.setdefault((r["length"], r["cable"], r["end"]), {}).setdefault(r["alpha"], []).append(r)
    for (length, cable, end), by_alpha in pairs.items():
        if 0.0 not in by_alpha or 1.0 not in by_alpha:
            continue
        case0, case1 = by_alpha[0.0][0]["case"], by_alpha[1.0][0]["case"]
        if case0 not in table or case1 not in table:
            continue
        ref0, ref1 = table[case0][0], table[case1][0]
        rung1 = {(int(r["n_elements"]),) + family(r): r for r in by_alpha[1.0] if r["reference"] != 1}
        for r0 in by_alpha[0.0]:
            key = (int(r0["n_elements"]),) + family(r0)
            if r0["reference"] == 1 or key not in rung1:
                continue
            errs = [abs((rung1[key][c] - r0[c]) - (ref1[c] - ref0[c])) / ref0[c]
                    for c in ("ship_grid", "vehicle_grid") if ref0[c] > 1.0]
            err = max(errs) if np.isfinite(errs).all() else float("inf")
            out[(length, cable, end, key[1:], key[0])] = err
    return out


def worst_errors(rows):
    """{vehicle_end.kind: {L: {(P, cfl): {N: worst first-snap-peak error}}}} over every case measured
    with that end at L, the bending effect's error included: the table of the rule."""
    out = {}
    for case, (ref, rungs) in error_table(rows).items():
        by_length = out.setdefault(END_KINDS[ref["end"]], {})
        for n, p, c, err, _, _ in rungs:
            ladder = by_length.setdefault(ref["length"], {}).setdefault((p, c), {})
            ladder[n] = max(ladder.get(n, 0.0), err)
    for (length, _, end, fam, n), err in bending_effect_errors(rows).items():
        ladder = out[END_KINDS[end]][length][fam]
        ladder[n] = max(ladder[n], err)
    return {kind: {length: {fam: dict(sorted(v.items())) for fam, v in sorted(t.items())}
                   for length, t in sorted(by_l.items())}
            for kind, by_l in sorted(out.items())}


def _up(e):
    return f"{math.ceil(e * 1e4) / 1e4:.4f}" if np.isfinite(e) else "math.inf"


def table_module(rows):
    """Source of tether_sim/solvers/resolution_table.py: the worst errors rounded up to 1e-4."""
    lines = ['"""The measured worst first-snap-peak errors behind ``dg.resolution: auto`` (GENERATED by',
             "``benchmarks/studies/resolution_ladder.py --table`` from docs/data/resolution_ladder.csv; do not edit).",
             "", "WORST_ERROR[vehicle_end.kind][L (m)][(P, dg.cfl)][N]: worst relative error over the cases",
             "measured at L with that end (and of the bending effect), rounded up to 1e-4.", '"""', "",
             "import math  # noqa: F401 (math.inf marks a rung that diverged)", "", "WORST_ERROR = {"]
    for kind, table in worst_errors(rows).items():
        lines.append(f'    "{kind}": {{')
        for length, fams in table.items():
            lines.append(f"        {length:g}: {{")
            for (p, c), errs in fams.items():
                items = ", ".join(f"{n}: {_up(e)}" for n, e in errs.items())
                lines.append(f"            ({p}, {float(c)!r}): {{{items}}},")
            lines.append("        },")
        lines.append("    },")
    return "\n".join(lines + ["}", ""])


def summary(csv_path):
    rows = read_rows(csv_path)
    for case, (ref, rungs) in error_table(rows).items():
        print(f"\n{case}: reference N={int(ref['n_elements'])} P=4 cfl 0.5: ship {ref['ship_raw'] / 1e3:.2f} kN, "
              f"vehicle {ref['vehicle_raw'] / 1e3:.2f} kN, {1e3 * ref['cpu_per_s']:.0f} ms CPU / sim s")
        for n, p, c, err, cpu, dt in sorted(rungs, key=lambda x: (x[1], x[2], x[0])):
            print(f"   N={n:2d} P={p} cfl={c:.2f}  error {100 * err:7.3f} %  dt {dt:.3g} s  {1e3 * cpu:7.1f} ms CPU/sim s")


def cost_fit(rows):
    """Least squares of the per-substep thread CPU over the stiff-cable rows:
    (fixed s, per node s, extra per node with bending s), nodes = N (P + 1)."""
    sel = [r for r in rows if r["cable"] == "stiff" and r["substeps"] > 0 and np.isfinite(r["cpu_per_s"])]
    nodes = np.array([r["n_elements"] * (r["order"] + 1) for r in sel])
    bend = np.array([r["alpha"] > 0 for r in sel], float)
    y = np.array([r["cpu_per_s"] * DURATION / r["substeps"] for r in sel])
    coef, *_ = np.linalg.lstsq(np.column_stack([np.ones_like(y), nodes, bend * nodes]), y, rcond=None)
    return tuple(float(c) for c in coef), len(sel)


RULE_TEXT = """\
## The rule (`tether_sim/solvers/resolution.py`)

1. **Per ladder** (P, dg.cfl): the smallest N >= 2 whose worst error, *and that of every finer N of
   that ladder*, is at most tolerance / 2 (the margin for what the ladders did not vary: forcing,
   body, current). "Every finer N" because the error is not monotone in N: a rung that sits on a
   zero crossing is not converged (one element, N = 1, is never chosen). A ladder takes part at a length only if it was measured up to
   the finest rung below the reference there (N = 8 at 100-200 m, 24 at 500 m, 32 beyond): the
   dg.cfl 0.5 / 0.65 / 1.0 ladders (N = 2-8) count at 100 and 200 m only.
2. **Between measured lengths**: the same (P, cfl, N) must satisfy 1 at both bracketing lengths.
3. **dg.cfl at most 0.8**: 1.0 is the calibrated stability limit itself (straight taut cable) and
   a run of 2026-11-21 measured +68 % at cfl 1.1. The measured dg.cfl rungs below show that at the coarse
   meshes the error is spatial: cfl 0.5 and 0.65 are not more accurate than 0.8 (e.g. 975 m,
   P = 4, N = 3: 2.07 / 1.85 / 1.65 % at cfl 0.5 / 0.65 / 0.8), so a smaller factor only costs.
4. **The cheapest** of the rungs that pass, by the cost model: substeps per simulated second from
   the solver's own stability rule (`solvers/dg/timestep.py`, with the configuration's EA, gamma0,
   zeta, EI) times a per-substep cost fitted to the ladders' thread CPU (below).

Outside the measured lengths, EA 2-45.5 MN, EI <= 2620 N m^2, the prescribed ship end, the cage or
a free vehicle end, explicit damping and a uniform mesh, the rule refuses (ConfigError): set
`dg.resolution: manual` there.
"""


def _choice_cell(length, tol, end, cable=None):
    from tether_sim.errors import ConfigError
    from tether_sim.solvers.resolution import choose

    try:
        c = choose(length, tol, end, cable)
    except ConfigError:
        return "refused", None
    return f"N = {c.n_elements}, P = {c.order}, cfl {c.cfl:g} ({100 * c.measured_error:.2f} %)", c


def markdown(rows):
    """docs/resolution_ladder.md: the rule, its choices and every measured rung (generated)."""
    from tether_sim.solvers.resolution import EI_MAX

    table = error_table(rows)
    worst = worst_errors(rows)
    ns = sorted({n for _, rungs in table.values() for n, *_ in rungs})
    (c0, c1, c2), n_fit = cost_fit(rows)
    dates = sorted(r["date"] for r in rows if r["date"])
    out = ["# DG resolution ladders (generated by `benchmarks/studies/resolution_ladder.py --markdown`)", "",
           "First-snap-peak error (largest end tension in 5-10 s, worse of the two ends, 200 Hz resampling) "
           "of N elements of order P at safety factor dg.cfl, against the case's reference (N_ref = "
           "max(10, ceil(L / 20 m)), P = 4, cfl 0.5), ROPOS slack-snap case (fairlead circle a = 2 m, "
           "f = 0.2 Hz, ramped over one period), 10.2 s at 50 Hz ticks. Case = L (m) : cable : alpha : "
           "vehicle end (stiff = ROPOS EA 45.5 MN; soft = EA 2 MN; alpha 1 = EI* 2620 N m^2). "
           f"{len(rows)} runs, {dates[0]} to {dates[-1]}, with per-run load and commit in "
           "`docs/data/resolution_ladder.csv`.", "", RULE_TEXT,
           f"**Cost model** (least squares over {n_fit} stiff-cable rungs, thread CPU per substep): "
           f"{1e6 * c0:.1f} us + {1e6 * c1:.3f} us x N (P + 1), + {1e6 * c2:.3f} us x N (P + 1) with bending "
           "(the constants in resolution.py). At these coarse meshes the fixed part dominates: the "
           "rule mostly minimises substeps.", "",
           "## The rule's choices", "",
           "Chosen rung (its worst measured error) per tolerance, ROPOS cable (alpha = 0); the modelled and the "
           "measured cost (ms CPU per simulated s of that rung in the stiff alpha = 0 case, at the CSV's load):", "",
           "| end | L (m) | 0.5 % | 1 % | 2 % | 5 % | 1 %: modelled / measured ms/s |", "|---|---|---|---|---|---|---|"]
    for kind in worst:
        for length in worst[kind]:
            cells = [_choice_cell(length, tol, kind)[0] for tol in (0.005, 0.01, 0.02, 0.05)]
            _, c = _choice_cell(length, 0.01, kind)
            meas = ""
            if c is not None:
                key = f"{length:g}:stiff:0:{'cage' if kind == 'body' else 'free'}"
                got = [cp for n, p, cf, _, cp, _ in table.get(key, (None, []))[1]
                       if (n, p, cf) == (c.n_elements, c.order, round(c.cfl, 3))]
                meas = f"{1e3 * c.cost:.1f} / " + (f"{1e3 * got[0]:.1f}" if got else "-")
            out.append(f"| {kind} | {length:g} | " + " | ".join(cells) + f" | {meas} |")
    out += ["", f"With bending (EI = {EI_MAX:g} N m^2, cage), 1 %: " + "; ".join(
        f"{length:g} m: {_choice_cell(length, 0.01, 'body', {'EI': EI_MAX})[0]}" for length in worst["body"]) + ".", ""]
    out += ["## Bending effect on the first snap peak", "",
            "peak(alpha 1) - peak(alpha 0), relative to peak(alpha 0), ship / vehicle end, in the references; "
            "its error at the rule's 1 % rung (included in the rule's table):", "",
            "| L : cable : end | effect, reference | 1 % rung | effect error there |", "|---|---|---|---|"]
    effect_err = bending_effect_errors(rows)
    for case0 in table:
        length, cable, alpha, end = case0.split(":")
        case1 = f"{length}:{cable}:1:{end}"
        if alpha != "0" or case1 not in table:
            continue
        r0, r1 = table[case0][0], table[case1][0]
        eff = [f"{100 * (r1[f'{e}_grid'] - r0[f'{e}_grid']) / r0[f'{e}_grid']:+.3f} %" if r0[f"{e}_grid"] > 1.0
               else "-" for e in ("ship", "vehicle")]
        cab = {"EA": r0["EA"], "damping": r0["zeta"], "EI": EI_MAX}
        text, c = _choice_cell(float(length), 0.01, END_KINDS[end], cab)
        err = effect_err.get((float(length), cable, end, (c.order, round(c.cfl, 3)), c.n_elements)) if c else None
        out.append(f"| {length}:{cable}:{end} | {eff[0]} / {eff[1]} | {text} | "
                   + (f"{100 * err:.3f} %" if err is not None else "") + " |")
    out += ["", "## Every rung", "", "Error (and cost, ms CPU per simulated s) per case and ladder:", "",
            "| case | reference ship / vehicle (kN) | P | cfl | " + " | ".join(f"N={n}" for n in ns) + " |",
            "|---|---|---|---|" + "---|" * len(ns)]
    for case, (ref, rungs) in table.items():
        veh = f"{ref['vehicle_grid'] / 1e3:.2f}" if ref["vehicle_grid"] > 1.0 else "-"
        for fam in sorted({(p, c) for _, p, c, *_ in rungs}):
            errs = {n: (e, cp) for n, p, c, e, cp, _ in rungs if (p, c) == fam}
            cells = [f"{100 * errs[n][0]:.2f} % ({1e3 * errs[n][1]:.0f})" if n in errs else "" for n in ns]
            out.append(f"| {case} | {ref['ship_grid'] / 1e3:.2f} / {veh} | {fam[0]} | {fam[1]:g} | "
                       + " | ".join(cells) + " |")
    return "\n".join(out) + "\n"
