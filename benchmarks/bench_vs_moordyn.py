"""DG against MoorDyn at equal first-snap accuracy (1 %), both coupled at the node's 50 Hz, one process.

The DG rungs are what ``dg.resolution: auto`` chooses for a 1 % first-snap-peak tolerance
(resolution.choose, with its safety factor 1/2 on the measured ladders; docs/performance.md):
N = 2, P = 4 at L = 200 m and N = 6, P = 2 at L = 1730 m, both at dg.cfl 0.8 (--rungs, --order and
--cfl change them; until 2026-11-24 it timed the ladder rung N = 3, P = 4 at 1730 m). Each timed DG run also measures its own first snap peak (resolution_ladder's metric: largest
end tension in 5-10 s, 200 Hz resampling, both ends) against the reference rows of
docs/data/resolution_ladder.csv (N = max(10, L / 20 m), P = 4, cfl 0.5) and prints the error, so a
change of the kernels that moved the peak would show (needs --duration >= 10). MoorDyn N = 40 is
its 1 % rung of BENCHMARKS.md "Accuracy against cost" (0.71 % at 1730 m; 0.6 % at 200 m against its
own finest rung), with bending too (EI = EI_STAR, 10.2 s runs against N = 160: 0.89 % at 1730 m,
0.12 % at 200 m; BENCHMARKS.md "MoorDyn with bending stiffness (2026-11-25)",
moordyn_bending_rungs.py). Cost: thread CPU per simulated second, best of --repeat runs of --duration s, DG
and MoorDyn interleaved:

- DG: a node tick = solver.tick(t + 0.02, ship=(position, velocity)): the targets, the substeps,
  the drain of the end tensions and the end loads in one compiled call (since 2026-11-24; ``--compose``
  also times the four calls set_end_motion + advance_to + drain_end_tensions + end_forces used
  before, in the same run);
- MoorDyn: moordyn.Step over 0.02 s with its largest stable internal step dividing 0.02 s
  (bench_moordyn.best_wall with NODE_STEP), the fairlead fed the same orbit, and the same bending
  stiffness as the DG row: EI = alpha * EI_STAR in the line type's EI column (MoorDyn v2 lines
  carry bending stiffness: curvature at the internal nodes, bending forces from EI; pinned ends).

The fairlead orbit itself (ropos_case.fairlead_motion, ~20 us of Python a call) is computed outside
both timers, as bench_moordyn does for MoorDyn (until 2026-11-23 it was timed inside the DG tick only).

Each repeat runs MoorDyn once per alpha (EI = 0 and EI = EI_STAR), interleaved with the DG runs.
The alpha = 1 row gives DG/MoorDyn against MoorDyn with bending (like for like) and, labelled
"vs MoorDyn EI=0", against MoorDyn without bending (the figure printed before 2026-11-25, when
the alpha = 1 rows were wrongly compared with MoorDyn at EI = 0). ``--baseline DIR`` adds
another checkout's DG (bench_tick.load_baseline).

Usage: PYTHONPATH=. python benchmarks/bench_vs_moordyn.py [--duration 10.2] [--repeat 3] [--cfl 0.8]
       [--rungs 2 3] [--order 4] [--quad-points Q] [--baseline DIR]
"""

import argparse
import math
import os
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks import bench_moordyn  # noqa: E402
from benchmarks import ropos_case as rc  # noqa: E402
from benchmarks.bench_tick import load_baseline  # noqa: E402
from benchmarks.studies.resolution_ladder import WINDOW, _peaks  # noqa: E402
from benchmarks.studies.resolution_report import read_rows  # noqa: E402



def rule_rung(length, tolerance=0.01):
    """(N, P, dg.cfl) that ``dg.resolution: auto`` chooses for the cage case at this length and tolerance."""
    from tether_sim.solvers.resolution import choose
    r = choose(length, tolerance)
    return r.n_elements, r.order, r.cfl
MOORDYN_SEGMENTS = 40
LADDER_CSV = Path(__file__).resolve().parents[1] / "docs" / "data" / "resolution_ladder.csv"


def reference_peaks(length, alpha):
    """(ship, vehicle) first snap peaks (200 Hz grid) of the ladder's reference for the cage case."""
    case = f"{length:g}:stiff:{alpha:g}:cage"
    for r in read_rows(LADDER_CSV):
        if r["case"] == case and r["reference"] == 1.0:
            return r["ship_grid"], r["vehicle_grid"]
    return None


def dg_cost(factory, mod, length, n, alpha, duration, cfl=0.8, quad_points=0, order=4, path="tick"):
    """(thread CPU per simulated s of 50 Hz node ticks, (ship, vehicle) first snap peaks or None);
    construction and static solve excluded, the record of end tensions kept outside the timer.
    quad_points > 0 sets dg.quad_points (0: the automatic (3P+1)//2 + 1 = 7 at P = 4).
    path "tick": one solver.tick per node tick (one compiled call); "compose": set_end_motion +
    advance_to + drain_end_tensions + end_forces (the calls before 2026-11-24; a tree without tick() uses it)."""
    cfg = mod.ropos_config(length, alpha=alpha, n_elements=n, order=order, cfl=cfl)
    if quad_points:
        cfg = replace(cfg, dg=replace(cfg.dg, quad_points=int(quad_points)))
    sol = factory.build_solver(cfg)
    sol.drain_end_tensions()
    ticks = int(round(duration * 50))
    cpu = 0.0
    rec = []
    if not hasattr(sol, "tick"):
        path = "compose"
    for k in range(ticks):
        t1 = (k + 1) / 50.0
        motion = mod.fairlead_motion(t1)
        if path == "tick":
            c = time.thread_time()
            out = sol.tick(t1, ship=motion)
            cpu += time.thread_time() - c
            drained = out.samples[:, :out.count].copy()
        else:
            c = time.thread_time()
            sol.set_end_motion("ship", *motion)
            sol.advance_to(t1)
            drained = sol.drain_end_tensions()
            sol.end_forces()
            cpu += time.thread_time() - c
        rec.append(drained)
    peaks = None
    if duration >= WINDOW[1]:
        t, ship, veh = (np.concatenate([d[i] for d in rec]) for i in range(3))
        peaks = (_peaks(t, ship)[1], _peaks(t, veh)[1])
    return cpu / duration, peaks


STEP_CHECK_TOL = 0.002  # relative; the step check's bound on the first snap peak and the run's largest tension


def moordyn_first_peak(length, n_seg, alpha, cage, dt, workdir, duration, coupling_step):
    """(first snap peak at the ship (ropos_case.snap_metrics, 5-10 s), largest ship tension, finite)
    of one MoorDyn run, or NaNs when the tension became non-finite."""
    with bench_moordyn.c_stdout_silenced((1, 2)):  # a run that blows up prints every node
        try:
            res = bench_moordyn.run_moordyn(length, n_seg, duration, coupling_step=coupling_step, dt=dt,
                                            alpha=alpha, workdir=workdir, cage=cage, check=False)
        except RuntimeError:  # Init failed
            return float("nan"), float("nan"), False
    if not res["finite"] or not np.all(np.isfinite(res["tension"])):
        return float("nan"), float("nan"), False
    return rc.snap_metrics(res["t"], res["tension"])["first_peak"], float(res["tension"].max()), True


def bisect_moordyn_step(length, n_seg, alpha, cage, workdir, duration, coupling=bench_moordyn.NODE_STEP,
                        tol=STEP_CHECK_TOL):
    """Largest stable MoorDyn step dividing ``coupling``, coupling / n with the least n, by bisection on n.

    Upper end: n_safe of the linear bound (ropos_case.moordyn_time_step, 0.9 of RK2's limit of the highest
    axial mode, slack segments included). The check of a step: a run of ``duration`` s at the node's coupling
    with every tension finite, and its first snap peak (5-10 s) and its largest tension within
    ``tol`` (STEP_CHECK_TOL, 0.2 %) of the run at n_safe: a step past the limit either blows up or, near
    it, moves the peak (at 200 m, 0.02/23-0.02/20 stay finite but move the first peak by 0.5-1.2 %, most of
    MoorDyn's 1 % budget; 0.02/19 blows up). ``tol`` inf: finite is enough. Assumes that every n above a passing n passes (the stable steps form an interval).
    Returns (dt, n, n_safe, runs)."""
    n_safe = int(round(coupling / rc.moordyn_time_step(length, n_seg, coupling)))
    ref_peak, ref_max, ok = moordyn_first_peak(length, n_seg, alpha, cage, coupling / n_safe, workdir, duration,
                                               coupling)
    if not ok:
        raise FloatingPointError(f"MoorDyn unstable at its linear step bound, L={length:g} N={n_seg}")
    lo, hi, runs = 0, n_safe, 1  # n = lo fails (0: none tried), n = hi passes
    while hi - lo > 1:
        mid = (lo + hi) // 2
        peak, top, ok = moordyn_first_peak(length, n_seg, alpha, cage, coupling / mid, workdir, duration, coupling)
        runs += 1
        if ok and abs(peak - ref_peak) <= tol * ref_peak and abs(top - ref_max) <= tol * ref_max:
            hi = mid
        else:
            lo = mid
    return coupling / hi, hi, n_safe, runs


def moordyn_accuracy(length, alpha, cage, dt, workdir, duration, reference_segments=160):
    """(first snap peak of N = 40 at step dt, of N = reference_segments at its linear step bound, of the
    body cage at N = 40 and its linear step): MoorDyn's own error figures. The 50 Hz samples would miss
    the peak, so these runs couple at ~200 Hz: N = 40 every m steps dt, m = round(5 ms / dt) (so that it
    runs with exactly the step timed), the others every 5 ms (bench_moordyn.COUPLING_STEP)."""
    cs = bench_moordyn.COUPLING_STEP
    peak, _, _ = moordyn_first_peak(length, MOORDYN_SEGMENTS, alpha, cage, dt, workdir, duration,
                                    dt * max(1, round(cs / dt)))
    ref, _, _ = moordyn_first_peak(length, reference_segments, alpha, cage,
                                   rc.moordyn_time_step(length, reference_segments, cs), workdir, duration, cs)
    body = float("nan")
    if cage != "body":
        body, _, _ = moordyn_first_peak(length, MOORDYN_SEGMENTS, alpha, "body",
                                        rc.moordyn_time_step(length, MOORDYN_SEGMENTS, cs), workdir, duration, cs)
    return peak, ref, body


def peak_error(peaks, ref):
    """Worst relative first-snap-peak error over both ends, or None."""
    if peaks is None or ref is None:
        return None
    return max(abs(p - r) / r for p, r in zip(peaks, ref))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=10.2)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--lengths", type=float, nargs="+", default=[200.0, 1730.0])
    ap.add_argument("--cfl", type=float, default=0.0, help="dg.cfl of the DG rungs (0: the rule's)")
    ap.add_argument("--rungs", type=int, nargs="+", help="DG elements per length (default: the rule's, rule_rung)")
    ap.add_argument("--order", type=int, default=0, help="DG order P of the rungs (0: the rule's)")
    ap.add_argument("--quad-points", type=int, default=0, help="dg.quad_points of the DG runs (0: automatic)")
    ap.add_argument("--baseline")
    ap.add_argument("--compose", action="store_true",
                    help="also time this tree's DG through the composition of four calls per tick (old path)")
    ap.add_argument("--moordyn-cage", choices=("point", "body"), default="point",
                    help="MoorDyn's cage: a point with the cage's mass, added mass, drag and buoyancy (default), "
                         "or a free 6-DOF body")
    ap.add_argument("--moordyn-step", choices=("bisect", "bound"), default="bisect",
                    help="MoorDyn's step: bisection of 0.02 / n with the step check (default), or the linear bound")
    ap.add_argument("--step-tol", type=float, default=STEP_CHECK_TOL,
                    help="the step check's relative bound on the first snap peak and largest tension against the "
                         "linear bound's step (inf: a finite run passes)")
    ap.add_argument("--no-accuracy", action="store_true",
                    help="skip MoorDyn's accuracy runs (N = 40 and N = 160 at 200 Hz, the body cage at N = 40)")
    ap.add_argument("--workdir", default="out/moordyn")
    args = ap.parse_args(argv)
    from tether_sim.solvers import factory
    trees = [("dg", factory, rc, "tick")]
    if args.compose:
        trees.append(("dg_compose", factory, rc, "compose"))
    if args.baseline:
        trees.append(("dg_base",) + tuple(load_baseline(args.baseline)) + ("tick",))
    Path(args.workdir).mkdir(parents=True, exist_ok=True)
    print(f"bench_vs_moordyn {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load {os.getloadavg()[0]:.1f}; "
          f"thread CPU ms per simulated s, best of {args.repeat} x {args.duration:g} s, 50 Hz coupling", flush=True)
    if args.rungs and len(args.rungs) != len(args.lengths):
        ap.error("--rungs needs one N per length")
    for i, length in enumerate(args.lengths):
        n, order, cfl = rule_rung(length)
        if args.rungs:
            n = args.rungs[i]
        order = args.order or order
        cfl = args.cfl or cfl
        for _, fac, mod, path in trees:  # warm the JIT caches, untimed
            for alpha in (0.0, 1.0):
                dg_cost(fac, mod, length, n, alpha, 0.1, cfl, args.quad_points, order, path)
        best, err = {}, {}
        dt_md = {}
        for alpha in (0.0, 1.0):
            if args.moordyn_step == "bisect":
                dt, n_sub, n_safe, runs = bisect_moordyn_step(length, MOORDYN_SEGMENTS, alpha, args.moordyn_cage,
                                                              args.workdir, max(args.duration, 10.2),
                                                              tol=args.step_tol)
            else:
                dt = rc.moordyn_time_step(length, MOORDYN_SEGMENTS, bench_moordyn.NODE_STEP)
                n_sub = n_safe = int(round(bench_moordyn.NODE_STEP / dt))
                runs = 0
            dt_md[alpha] = dt
            line = (f"  L={length:6.0f} alpha={alpha:g}: MoorDyn {args.moordyn_cage} cage N={MOORDYN_SEGMENTS} "
                    f"step 0.02/{n_sub} = {1e3 * dt:.4g} ms (linear bound 0.02/{n_safe}, {runs} check runs)")
            if not args.no_accuracy:
                peak, ref, body = moordyn_accuracy(length, alpha, args.moordyn_cage, dt, args.workdir,
                                                   max(args.duration, 10.2))
                line += (f"; first snap at the ship (~200 Hz coupling) {peak / 1e3:.2f} kN, "
                         f"error vs its own N=160 {100 * (peak - ref) / ref:+.3f} %")
                if math.isfinite(body):
                    line += (f", vs the body cage at N={MOORDYN_SEGMENTS} {body / 1e3:.2f} kN "
                             f"{100 * (peak - body) / body:+.3f} %")
            print(line, flush=True)
        for _ in range(args.repeat):
            for name, fac, mod, path in trees:
                for alpha in (0.0, 1.0):
                    c, peaks = dg_cost(fac, mod, length, n, alpha, args.duration, cfl, args.quad_points,
                                       order, path)
                    best[(name, alpha)] = min(best.get((name, alpha), c), c)
                    err[(name, alpha)] = peak_error(peaks, reference_peaks(length, alpha))
            for alpha in (0.0, 1.0):  # MoorDyn with the DG row's bending stiffness
                _, cpu = bench_moordyn.best_wall(length, MOORDYN_SEGMENTS, args.duration, bench_moordyn.NODE_STEP,
                                                 dt_md[alpha], args.workdir, 1, alpha=alpha, cage=args.moordyn_cage)
                best[("md", alpha)] = min(best.get(("md", alpha), cpu / args.duration), cpu / args.duration)
        md0 = best[("md", 0.0)]
        for alpha in (0.0, 1.0):
            md = best[("md", alpha)]
            line = (f"  L={length:6.0f} alpha={alpha:g}: MoorDyn N={MOORDYN_SEGMENTS} EI={alpha * rc.EI_STAR:4.0f} "
                    f"{1e3 * md:7.2f} ms/s")
            for name, _, _, _ in trees:
                c = best[(name, alpha)]
                e = err[(name, alpha)]
                line += (f" | {name} N={n} P={order} cfl {cfl:g} {1e3 * c:7.2f} ms/s, "
                         f"{name}/MoorDyn {c / md:.3f}, MoorDyn/{name} {md / c:.2f}")
                if alpha:
                    line += f" (vs MoorDyn EI=0 {c / md0:.3f})"
                line += f", first snap peak error {'n/a' if e is None else f'{100 * e:.3f} %'}"
            print(line, flush=True)


if __name__ == "__main__":
    main()
