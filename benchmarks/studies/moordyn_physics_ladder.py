"""Where DG and MoorDyn differ on the ROPOS snap: the same case with model terms switched off in both codes.

The single-line ROPOS case (``ropos_case``: L = 200 m, the cage as a free body, the fairlead orbit
a = 2 m, 0.2 Hz) run by tether_sim's DG solver and by MoorDyn v2, each on a mesh ladder, in four
variants that change the same term in both codes:

- ``paper``: PE2020 Table 3 as everywhere else;
- ``no-cage-drag``: the cage's drag coefficients 0 (the two codes write body drag differently:
  tether_sim per body axis, 0.5 rho Cd_i A_i |v_i| v_i; MoorDyn with the speed,
  0.5 rho CdA_i |v| v_i);
- ``no-damping``: the tether's axial damping zeta = 0 (MoorDyn's BA); the two codes write it
  differently in slack segments: tether_sim's bilinear law has no tension at all when eps <= 0 and
  clips T = EA eps + zeta deps/dt at 0, MoorDyn's damping BA deps/dt acts in every segment,
  compressed ones included, unclipped (``Line::getStateDeriv``: T is zeroed in compression, Td is not);
- ``neither``: both off.

Reported: the first snap peak of the ship-end tension (``ropos_case.snap_peak`` in 5-10 s) of
each rung, both codes sampled at every step (DG substeps; MoorDyn coupled every ``--md-sample`` s),
and the largest tension in each window between consecutive ``--humps`` times (default 8.10, 8.20,
8.30 s: the paper case's first snap has two humps of nearly equal height, and which one is the
larger changes with the mesh, so the peak alone can jump by the difference of the humps).

Usage: PYTHONPATH=. python benchmarks/studies/moordyn_physics_ladder.py [--variants paper no-damping ...]
       [--dg 2:4 4:4 8:4] [--moordyn 40 80 160] [--duration 10] [--json out/moordyn_physics_ladder.json]
"""

import argparse
import json
import math
import os
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from benchmarks import bench_moordyn as bm  # noqa: E402
from benchmarks import drive  # noqa: E402
from benchmarks import ropos_case as rc  # noqa: E402

LENGTH = 200.0
VARIANTS = {"paper": (True, True), "no-cage-drag": (False, True), "no-damping": (True, False),
            "neither": (False, False)}  # (cage drag, tether damping)


def dg_config(variant, n, p):
    drag, damping = VARIANTS[variant]
    cfg = rc.ropos_config(LENGTH, solver="dg", n_elements=n, order=p)
    if not drag:
        cfg = replace(cfg, body=replace(cfg.body, drag_coefficients=(0.0, 0.0, 0.0)))
    if not damping:
        cfg = replace(cfg, cable=replace(cfg.cable, damping=0.0))
    return cfg


def moordyn_text(variant, n_segments, dt):
    """ropos_case's MoorDyn file with the variant's terms set to 0 (tether BA, body CdA); without
    damping RK4 (RK2 grows on the imaginary axis: an undamped lumped-mass line is unstable under it)."""
    drag, damping = VARIANTS[variant]
    rows = []
    for row in rc.moordyn_input(LENGTH, n_segments, dt, scheme="RK2" if damping else "RK4").splitlines():
        f = row.split()
        if f and f[0] == "tether" and not damping:
            f[4] = "0"
            row = " ".join(f)
        elif len(f) > 2 and f[1] == "Free" and not drag:
            f[12] = "0|0|0|0|0|0"
            row = " ".join(f)
        rows.append(row)
    return "\n".join(rows) + "\n"


def run_moordyn(variant, n_segments, duration, sample):
    import moordyn

    if VARIANTS[variant][1]:
        dt_stable = rc.moordyn_stable_dt(LENGTH, n_segments)
    else:  # RK4 on the imaginary axis: |z| <= 2.83; highest axial mode omega = 2 sqrt(EA / gamma0) / l
        dt_stable = 0.9 * 2.83 / (2.0 * math.sqrt(rc.EA / rc.GAMMA0) * n_segments / LENGTH)
    dt = sample / math.ceil(sample / dt_stable - 1e-9)
    path = Path(tempfile.mkdtemp(prefix="md_phys_")) / "ropos.txt"
    path.write_text(moordyn_text(variant, n_segments, dt))
    system, _ = bm._quiet_create(moordyn, path)
    n = int(round(duration / sample))
    t_out, ten = np.empty(n), np.empty(n)
    t, p_now = 0.0, rc.fairlead_motion(0.0)[0]
    c0 = time.process_time()
    try:
        for k in range(n):
            t_next = (k + 1) * sample
            p_next, _ = rc.fairlead_motion(t_next)
            f = moordyn.Step(system, list(p_now), list((p_next - p_now) / sample), t, sample)
            t, p_now = t_next, p_next
            t_out[k], ten[k] = t, math.sqrt(f[0] ** 2 + f[1] ** 2 + f[2] ** 2)
    finally:
        moordyn.Close(system)
    return t_out, ten, dt, time.process_time() - c0


def hump_peaks(t, tension, edges):
    """Largest tension in each window [edges[i], edges[i + 1]) (NaN where the record has no sample)."""
    t, tension = np.asarray(t), np.asarray(tension)
    out = []
    for lo, hi in zip(edges[:-1], edges[1:]):
        m = (t >= lo) & (t < hi)
        out.append(float(tension[m].max()) if m.any() else float("nan"))
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--variants", nargs="+", default=list(VARIANTS), choices=list(VARIANTS))
    ap.add_argument("--dg", nargs="*", default=["2:4", "4:4", "8:4"], help="DG rungs N:P (none: MoorDyn only)")
    ap.add_argument("--moordyn", nargs="*", type=int, default=[40, 80, 160], help="MoorDyn segment counts")
    ap.add_argument("--duration", type=float, default=10.0)
    ap.add_argument("--md-sample", type=float, default=0.001, help="MoorDyn coupling step = sampling (s)")
    ap.add_argument("--humps", type=float, nargs="*", default=[8.10, 8.20, 8.30],
                    help="window edges (s) of the humps of the first snap reported separately")
    ap.add_argument("--json", default="out/moordyn_physics_ladder.json")
    args = ap.parse_args(argv)
    print(f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load {os.getloadavg()[0]:.1f}", flush=True)
    out = {}
    for variant in args.variants:
        res = out[variant] = {"dg": {}, "moordyn": {}}
        for rung in args.dg:
            n, p = (int(v) for v in rung.split(":"))
            r = drive.run(dg_config(variant, n, p), args.duration, motion=rc.fairlead_motion)
            peak = rc.snap_peak(r["t"], r["ship"], *rc.FIRST_SNAP_WINDOW)
            humps = hump_peaks(r["t"], r["ship"], args.humps)
            res["dg"][rung] = {"first_peak": peak[0], "t": peak[1], "humps": humps, "time_step": r["time_step"],
                               "cpu": r["cpu"]}
            print(f"{variant:13s} DG {rung:>5s} dt {r['time_step']:.3g} s: first snap {peak[0] / 1e3:8.3f} kN at "
                  f"{peak[1]:.4f} s, humps {' / '.join(f'{h / 1e3:.3f}' for h in humps)} kN (cpu {r['cpu']:.1f} s)",
                  flush=True)
        for n in args.moordyn:
            t, ten, dt, cpu = run_moordyn(variant, n, args.duration, args.md_sample)
            peak = rc.snap_peak(t, ten, *rc.FIRST_SNAP_WINDOW)
            humps = hump_peaks(t, ten, args.humps)
            res["moordyn"][str(n)] = {"first_peak": peak[0], "t": peak[1], "humps": humps, "time_step": dt, "cpu": cpu}
            print(f"{variant:13s} MoorDyn N={n:<4d} dt {dt:.3g} s: first snap {peak[0] / 1e3:8.3f} kN at "
                  f"{peak[1]:.4f} s, humps {' / '.join(f'{h / 1e3:.3f}' for h in humps)} kN (cpu {cpu:.1f} s)",
                  flush=True)
        if args.dg and args.moordyn:
            dg_ref = res["dg"][args.dg[-1]]["first_peak"]
            md_ref = res["moordyn"][str(args.moordyn[-1])]["first_peak"]
            res["difference"] = (dg_ref - md_ref) / md_ref
            print(f"{variant:13s} finest DG against finest MoorDyn: {100 * res['difference']:+.2f} %", flush=True)
    Path(args.json).parent.mkdir(parents=True, exist_ok=True)
    Path(args.json).write_text(json.dumps(out, indent=1))
    print(f"wrote {args.json}")


if __name__ == "__main__":
    main()
