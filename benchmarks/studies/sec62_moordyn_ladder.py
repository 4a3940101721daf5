"""MoorDyn at the same EI as the PE2020 Sec. 6.2 ladder: first snap per end, per length, frequency, alpha and mesh.

MoorDyn v2 (pip ``moordyn``) runs the ROPOS tether and cage of ``benchmarks/ropos_case.py`` (the cage a free
6-DOF body with the same mass, added mass, drag and buoyancy; the tether's EI = alpha * 2.62 kN m^2, MoorDyn's
bending between segments; no compression in a slack segment, as PE2020 Eq. 22) driven by the same circular
fairlead orbit (a = 2 m, ramped over one period) as ``slack_bending_ladder.py``. For every run it prints the
largest ship and cage tension between the end of the ramp (1/f) and ``--periods``/f, with their times: the
first re-tensioning snap at each end. One CSV row per run goes to ``--out``. MoorDyn is cheap here (0.2-13 CPU s
per run), so its own mesh ladder (N = 40, 80, 160 segments) shows where it has converged.

Usage: PYTHONPATH=. python benchmarks/studies/sec62_moordyn_ladder.py --lengths 200 500 --freqs 0.2 0.25
       --alphas 0 1 10 100 --segments 40 80 160 [--out out/sec62_moordyn]
"""

import argparse
import csv
import dataclasses
import math
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

FIELDS = ("L", "f", "alpha", "segments", "dt", "ship_peak_N", "ship_time_s", "cage_peak_N", "cage_time_s", "cpu_s")
COUPLING_STEP = 0.005  # s: MoorDyn sampled every 5 ms (finer sampling moves the peaks by <= 0.04 %, docs/network.md)


def run(L, f, alpha, n_segments, periods, workdir, series=None):
    """One MoorDyn run; returns the CSV row (and with ``series``, a folder, saves its end tensions there as
    L<L>_f<f>_a<alpha>_N<segments>.npz: t, ship, cage)."""
    import moordyn

    from benchmarks import ropos_case as rc
    from tether_sim.physics.motion import build_motion

    motion = build_motion(dataclasses.replace(rc.motion_config(), frequency=f, ramp_time=1.0 / f), rc.ORBIT_ORIGIN)
    dt = rc.moordyn_time_step(L, n_segments, 0.02)
    path = Path(workdir) / f"sec62_L{L:g}_f{f:g}_N{n_segments}_a{alpha:g}.txt"
    path.write_text(rc.moordyn_input(L, n_segments, dt, alpha=alpha))
    cpu0 = time.process_time()
    system = moordyn.Create(str(path))
    p0, v0, _ = motion.at(0.0)
    moordyn.Init(system, list(p0), list(v0))
    line = moordyn.GetLine(system, 1)  # end A (node 0) on the cage, end B at the fairlead
    t_end = periods / f
    times, ship, cage = [], [], []
    t = 0.0
    try:
        while t < t_end - 1e-9:
            p_now, _, _ = motion.at(t)
            p_next, _, _ = motion.at(t + COUPLING_STEP)
            vel = (np.asarray(p_next) - np.asarray(p_now)) / COUPLING_STEP
            force = moordyn.Step(system, list(p_now), list(vel), t, COUPLING_STEP)
            t += COUPLING_STEP
            times.append(t)
            ship.append(math.sqrt(sum(x * x for x in force)))
            cage.append(float(np.linalg.norm(moordyn.GetLineNodeTen(line, 0))))
    finally:
        moordyn.Close(system)
    times, ship, cage = np.asarray(times), np.asarray(ship), np.asarray(cage)
    if series is not None:
        Path(series).mkdir(parents=True, exist_ok=True)
        np.savez(Path(series) / f"L{L:g}_f{f:g}_a{alpha:g}_N{n_segments}.npz", t=times, ship=ship, cage=cage)
    window = times >= 1.0 / f
    i = int(np.argmax(np.where(window, ship, -1.0)))
    j = int(np.argmax(np.where(window, cage, -1.0)))
    return {"L": L, "f": f, "alpha": alpha, "segments": n_segments, "dt": dt, "ship_peak_N": ship[i],
            "ship_time_s": times[i], "cage_peak_N": cage[j], "cage_time_s": times[j],
            "cpu_s": time.process_time() - cpu0}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--lengths", type=float, nargs="+", default=[200.0, 500.0])
    ap.add_argument("--freqs", type=float, nargs="+", default=[0.2, 0.25])
    ap.add_argument("--alphas", type=float, nargs="+", default=[0.0, 1.0, 10.0, 100.0])
    ap.add_argument("--segments", type=int, nargs="+", default=[40, 80, 160])
    ap.add_argument("--periods", type=float, default=1.9)
    ap.add_argument("--out", type=Path, default=Path("out/sec62_moordyn"))
    ap.add_argument("--series", action="store_true", help="also save each run's end tensions in --out/series")
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    csv_path = args.out / "runs.csv"
    new = not csv_path.exists()
    print(f"# {time.strftime('%Y-%m-%d %H:%M')} load {os.getloadavg()[0]:.1f}", flush=True)
    with tempfile.TemporaryDirectory(prefix="sec62_md_") as work, open(csv_path, "a", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=FIELDS)
        if new:
            writer.writeheader()
        for L in args.lengths:
            for f in args.freqs:
                for alpha in args.alphas:
                    for n in args.segments:
                        row = run(L, f, alpha, n, args.periods, work, args.out / "series" if args.series else None)
                        writer.writerow(row)
                        fh.flush()
                        print(f"L {L:g} f {f:g} alpha {alpha:g} N {n}: ship {row['ship_peak_N'] / 1e3:.1f} kN at "
                              f"{row['ship_time_s']:.3f} s, cage {row['cage_peak_N'] / 1e3:.1f} kN at "
                              f"{row['cage_time_s']:.3f} s (cpu {row['cpu_s']:.1f} s)", flush=True)


if __name__ == "__main__":
    main()
