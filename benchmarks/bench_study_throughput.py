"""Throughput of snap-load studies: cases per core-hour from the results of ``tether-sim-study``.

    .venv/bin/tether-sim-study config/studies/heave_sweep.yaml --out out/bench/heave_sweep --cases 0-3
    .venv/bin/python benchmarks/bench_study_throughput.py out/bench/heave_sweep [more results folders]

Per results folder: the cases done, their thread-CPU time and the figures derived from it. CPU time
(``cpu_s`` of each row, ``time.thread_time()`` around the whole case in the worker) is what the
machine's load does not inflate; wall-clock throughput on a shared machine is not a code property.
The first case of each worker process also loads the compiled kernels (``nth_in_process == 1``);
the steady figures leave those cases out.
"""

import argparse
import statistics
from pathlib import Path

from tether_sim.studies.results import read_results


def summarize(folder) -> dict:
    rows = [r for r in read_results(folder) if r.get("status") == "ok"]
    steady = [r for r in rows if r.get("nth_in_process", 1) > 1]
    out = {"folder": str(folder), "cases": len(rows), "steady_cases": len(steady)}
    for name, sel in (("all", rows), ("steady", steady)):
        cpu = sum(r["cpu_s"] for r in sel)
        sim = sum(r["sim_s"] for r in sel)
        out[f"{name}_cpu_s"] = cpu
        out[f"{name}_cases_per_core_hour"] = len(sel) / (cpu / 3600.0) if cpu > 0 else float("nan")
        out[f"{name}_sim_per_cpu"] = sim / cpu if cpu > 0 else float("nan")
    out["median_case_cpu_s"] = statistics.median(r["cpu_s"] for r in rows) if rows else float("nan")
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("results", nargs="+", help="results folders of tether-sim-study")
    args = ap.parse_args(argv)
    for folder in args.results:
        s = summarize(Path(folder))
        rows = sorted(read_results(folder), key=lambda r: r["index"])
        print(f"{s['folder']}: {s['cases']} cases ok")
        for r in rows:
            if r.get("status") != "ok":
                print(f"  case {r['index']}: failed ({r['error']})")
                continue
            print(f"  case {r['index']}: L = {r['cable.length']:g} m, a = {r['fairlead_amplitude_m']:.3g} m, "
                  f"f = {r['fairlead_frequency_Hz']:.3g} Hz, N = {r['dg_N']}, P = {r['dg_P']}: {r['sim_s']:g} s "
                  f"simulated in {r['cpu_s']:.1f} s CPU ({r['sim_s'] / r['cpu_s']:.3g} x real time per CPU s; "
                  f"wall {r['wall_s']:.0f} s), case {r['nth_in_process']} of its process")
        print(f"  all cases: {s['all_cases_per_core_hour']:.4g} cases per core-hour "
              f"({s['all_sim_per_cpu']:.3g} simulated s per CPU s; median case {s['median_case_cpu_s']:.1f} s CPU)")
        if s["steady_cases"]:
            print(f"  without each process's first case ({s['steady_cases']} cases): "
                  f"{s['steady_cases_per_core_hour']:.4g} cases per core-hour ({s['steady_sim_per_cpu']:.3g} sim s / CPU s)")


if __name__ == "__main__":
    main()
