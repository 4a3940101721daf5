"""Markdown tables and equal-accuracy ratios from a bench_accuracy.py JSON (no new runs).

Our ladder mixes an N ladder (the reference's P) with P variants; "cost at equal accuracy" is read
on the N ladder (every costlier N-rung within the tolerance too), P variants are listed beside.

Usage: python benchmarks/summarize_accuracy.py out/bench_accuracy_L1730.json [...]
"""

import json
import sys


def _within(rows, tol, cost, key="first_peak"):
    rows = sorted(rows, key=lambda r: r[cost])
    ok = [r for i, r in enumerate(rows) if all(q[key + "_error"] <= tol for q in rows[i:])]
    return ok[0] if ok else None


def summarize(path):
    data = json.load(open(path))
    for length, d in data.items():
        ours, md = d["ours"], d["moordyn"]
        ref = ours[-1]
        p_ref = ref["rung"].split(":")[-1]
        print(f"\nL = {length} m (first snap peak; errors against each code's finest rung)\n")
        print("| code | rung | dt (s) | first snap (kN) | error | CPU ms / sim s | wall ms / sim s | load |")
        print("|---|---|---|---|---|---|---|---|")
        for r in ours:
            err = "ref" if r is ref else "%.2f %%" % (100 * r["first_peak_error"])
            rung = r["rung"].replace(":", " P=")
            print(f"| DG | N={rung} | {r['time_step']:.3g} | {r['first_peak'] / 1e3:.2f} | {err} | "
                  f"{1e3 * r['cpu_per_s']:.1f} | {1e3 * r['wall_per_s']:.0f} | {r['load']:.0f} |")
        for r in md:
            err = "ref" if r is md[-1] else "%.2f %%" % (100 * r["first_peak_error"])
            print(f"| MoorDyn | N={r['segments']} | {r['dt']:.3g} | {r['first_peak'] / 1e3:.2f} | {err} | "
                  f"{1e3 * r['cpu_per_s']:.2f} | {1e3 * r['wall_per_s']:.1f} | {r['load']:.0f} |")
        gap = abs(ref["first_peak"] - md[-1]["first_peak"]) / md[-1]["first_peak"]
        print(f"\nReferences differ by {100 * gap:.2f} % (DG {ref['first_peak'] / 1e3:.2f} kN, "
              f"MoorDyn {md[-1]['first_peak'] / 1e3:.2f} kN).\n")
        n_ladder = [r for r in ours[:-1] if r["rung"].endswith(":" + p_ref)]
        md_coarse = md[:-1]
        for tol in (0.01, 0.05):
            for cost in ("cpu_per_s", "wall_per_s"):
                a, b = _within(n_ladder, tol, cost), _within(md_coarse, tol, cost)
                if a and b:
                    print(f"- {100 * tol:.0f} % ({cost.split('_')[0]}): DG N={a['rung'].replace(':', ' P=')} "
                          f"{1e3 * a[cost]:.2f} ms/s vs MoorDyn N={b['segments']} {1e3 * b[cost]:.2f} ms/s: "
                          f"DG/MoorDyn = {a[cost] / b[cost]:.2f}")
                else:
                    print(f"- {100 * tol:.0f} % ({cost.split('_')[0]}): DG {'N=' + a['rung'] if a else 'not reached'}, "
                          f"MoorDyn {'N=' + str(b['segments']) if b else 'not reached'} below the reference")


if __name__ == "__main__":
    for p in sys.argv[1:]:
        summarize(p)
