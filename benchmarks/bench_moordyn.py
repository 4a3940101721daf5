"""MoorDyn (C core, lumped mass) on the ROPOS case: segment ladder, snap peaks, real-time factors.

For each length L and segment count N: write the MoorDyn v2 input (``ropos_case.moordyn_input``),
initialise (MoorDyn's static IC solve, fairlead held at the orbit centre), drive the coupled
fairlead point with ``ropos_case.fairlead_motion`` at the coupling step h (piecewise linear:
position at the step start, secant velocity), record the ship tension |F| on the fairlead at
every coupling step and report:

- the snap-peak figures of ``ropos_case.snap_metrics`` (first snap, 5-10 s: the accuracy
  metric; mean of the per-period peaks in 20-60 s; largest peak) and their relative errors against
  the finest N of the ladder (the converged reference of the same code);
- the real-time factor (simulated s per wall s) counting only the time inside ``moordyn.Step``
  (``rtf``), and the same at a node-like 50 Hz coupling in a second run (``rtf50``).

The internal step is the largest RK2-stable step of the highest axial mode dividing h
(``ropos_case.moordyn_time_step``): with zeta = 45.5 kN s it is damping-limited, dt ~ l^2, for
short segments.

Usage: PYTHONPATH=. python benchmarks/bench_moordyn.py [--lengths 200 1730]
       [--segments 20 40 80 160 320] [--duration 60] [--json out/bench_moordyn.json]
"""

import argparse
import contextlib
import json
import math
import os
import platform
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks import ropos_case as rc  # noqa: E402

COUPLING_STEP = 0.005  # s; tension sampled at 200 Hz for the peaks
NODE_STEP = 0.02  # s; 50 Hz, the node's output rate, for the speed figure


@contextlib.contextmanager
def c_stdout_silenced(fds=(1,)):
    """C-level stdout (``fds``: also stderr, 2) sent to /dev/null inside the block (MoorDyn prints its
    banner and log there, and the node positions when a run blows up)."""
    sys.stdout.flush()
    sys.stderr.flush()
    saved = [os.dup(fd) for fd in fds]
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        for fd in fds:
            os.dup2(devnull, fd)
        yield
    finally:
        sys.stdout.flush()
        sys.stderr.flush()
        for fd, old in zip(fds, saved):
            os.dup2(old, fd)
            os.close(old)
        os.close(devnull)


def _quiet_create(moordyn, path):
    """moordyn.Create with its console banner sent to /dev/null (C-level stdout)."""
    with c_stdout_silenced():
        system = moordyn.Create(str(path))
        p0, v0 = rc.fairlead_motion(0.0)
        t0 = time.perf_counter()
        err = moordyn.Init(system, list(p0), list(v0))
        init_wall = time.perf_counter() - t0
    if err != 0:
        raise RuntimeError(f"MoorDyn Init failed with code {err}")
    return system, init_wall


def run_moordyn(length, n_segments, duration, coupling_step=COUPLING_STEP, dt=None, alpha=0.0, workdir=None,
                cage="body", check=True):
    """One MoorDyn run; returns dict with t, tension (ship), dt, wall times. ``cage``: "body" (a free
    6-DOF body) or "point" (ropos_case.moordyn_input). ``check`` False: a non-finite tension ends the
    run without raising (``finite`` False in the result; the step searches use it)."""
    import moordyn

    dt = dt if dt is not None else rc.moordyn_time_step(length, n_segments, COUPLING_STEP)
    workdir = Path(workdir or tempfile.mkdtemp(prefix="md_ropos_"))
    tag = (f"_a{alpha:g}" if alpha else "") + ("" if cage == "body" else f"_{cage}")
    path = workdir / f"ropos_L{int(length)}_N{n_segments}{tag}.txt"
    path.write_text(rc.moordyn_input(length, n_segments, dt, alpha=alpha, cage=cage))
    system, init_wall = _quiet_create(moordyn, path)
    n = int(round(duration / coupling_step))
    times = np.empty(n)
    tension = np.empty(n)
    step_wall = step_cpu = 0.0
    t = 0.0
    p_now, _ = rc.fairlead_motion(0.0)
    finite = True
    try:
        for k in range(n):
            t_next = (k + 1) * coupling_step
            p_next, _ = rc.fairlead_motion(t_next)
            vel = (p_next - p_now) / coupling_step
            x, v = list(p_now), list(vel)
            w0, c0 = time.perf_counter(), time.thread_time()
            try:
                force = moordyn.Step(system, x, v, t, coupling_step)
            except RuntimeError:  # MoorDyn's NaN check
                if check:
                    raise
                force = (math.nan,) * 3
            step_wall += time.perf_counter() - w0
            step_cpu += time.thread_time() - c0
            t, p_now = t_next, p_next
            times[k] = t
            tension[k] = math.sqrt(force[0] ** 2 + force[1] ** 2 + force[2] ** 2)
            if not math.isfinite(tension[k]):
                if check:
                    raise FloatingPointError(f"non-finite tension at t = {t}")
                finite = False
                times, tension = times[:k + 1], tension[:k + 1]
                break
    finally:
        moordyn.Close(system)
    return {"t": times, "tension": tension, "dt": dt, "step_wall": step_wall, "step_cpu": step_cpu,
            "init_wall": init_wall, "finite": finite}


METRICS = ("first_peak", "mean_peak", "max_peak")


def best_wall(length, n_seg, duration, coupling_step, dt, workdir, repeats, alpha=0.0, cage="body"):
    """Smallest (wall, thread CPU) time inside moordyn.Step over ``repeats`` runs (the machine is
    shared: the CPU time is the robust cost figure, the wall time what a real-time loop sees).
    ``alpha``: the line's bending stiffness EI = alpha * EI_STAR (MoorDyn v2 line-type column EI)."""
    walls, cpus = [], []
    for _ in range(repeats):
        res = run_moordyn(length, n_seg, duration, coupling_step=coupling_step, dt=dt, alpha=alpha,
                          workdir=workdir, cage=cage)
        walls.append(res["step_wall"])
        cpus.append(res["step_cpu"])
        if walls[-1] > 20.0:  # expensive rung: one timing is enough
            break
    return min(walls), min(cpus)


def ladder(length, segments, duration, workdir, repeats=3, speed_duration=20.0):
    """Run the segment ladder for one length; the finest N is the reference.

    Accuracy: one ``duration`` run per N at 200 Hz coupling. Speed: best of ``repeats`` runs of
    ``speed_duration`` s with the same step and coupling (``wall_per_s``, ``rtf``) and at the
    node's 50 Hz coupling with the largest stable step dividing 0.02 s (``rtf50``).
    """
    rows = []
    for n_seg in segments:
        res = run_moordyn(length, n_seg, duration, workdir=workdir)
        metrics = rc.snap_metrics(res["t"], res["tension"])
        wall, cpu = best_wall(length, n_seg, speed_duration, COUPLING_STEP, res["dt"], workdir, repeats)
        wall50, cpu50 = best_wall(length, n_seg, speed_duration, NODE_STEP,
                                  rc.moordyn_time_step(length, n_seg, NODE_STEP), workdir, repeats)
        rows.append({
            "length": length, "segments": n_seg, "dt": res["dt"], **metrics,
            "min_tension": float(res["tension"][res["t"] >= rc.FIRST_SNAP_WINDOW[0]].min()),
            "wall_per_s": wall / speed_duration, "rtf": speed_duration / wall,
            "cpu_per_s": cpu / speed_duration, "rtf_cpu": speed_duration / cpu,
            "rtf50": speed_duration / wall50, "rtf50_cpu": speed_duration / cpu50, "init_wall": res["init_wall"],
            "load": os.getloadavg()[0],
        })
        np.savez(Path(workdir) / f"moordyn_L{int(length)}_N{n_seg}.npz", t=res["t"], tension=res["tension"])
        r = rows[-1]
        print(f"  L={length:6.0f} N={n_seg:4d} dt={r['dt']:.3g}s first={r['first_peak'] / 1e3:8.2f} kN "
              f"mean={r['mean_peak'] / 1e3:8.2f} max={r['max_peak'] / 1e3:8.2f} min={r['min_tension'] / 1e3:6.2f} kN  "
              f"wall/sim-s={1e3 * r['wall_per_s']:8.2f} ms cpu/sim-s={1e3 * r['cpu_per_s']:8.2f} ms "
              f"RTF={r['rtf']:7.1f} (cpu {r['rtf_cpu']:7.1f}) RTF50={r['rtf50']:7.1f} (cpu {r['rtf50_cpu']:7.1f}) "
              f"load={r['load']:.1f}", flush=True)
    for key in METRICS:
        ref = rows[-1][key]
        for r in rows:
            r[key + "_error"] = abs(r[key] - ref) / ref
    return rows


def wall_at_accuracy(rows, tol, key="first_peak", cost="wall_per_s"):
    """Cheapest ladder rung within tol of the reference such that every costlier rung (the
    reference, the last row, excluded) is within tol too -- a lucky coarse hit does not count.
    None if no rung qualifies."""
    coarse = sorted(rows[:-1], key=lambda r: r[cost])
    ok = [r for i, r in enumerate(coarse) if all(q[key + "_error"] <= tol for q in coarse[i:])]
    return ok[0] if ok else None


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lengths", type=float, nargs="+", default=[200.0, 1730.0])
    ap.add_argument("--segments", type=int, nargs="+", default=[20, 40, 80, 160, 320])
    ap.add_argument("--duration", type=float, default=60.0)
    ap.add_argument("--json", default="out/bench_moordyn.json")
    ap.add_argument("--workdir", default="out/moordyn")
    args = ap.parse_args(argv)
    import moordyn  # noqa: F401  (fail early when missing)
    from importlib.metadata import version

    Path(args.workdir).mkdir(parents=True, exist_ok=True)
    print(f"MoorDyn {version('moordyn')} on {platform.processor() or platform.machine()}, "
          f"{os.cpu_count()} cores, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")
    print(f"ROPOS case: circle a={rc.ORBIT_AMPLITUDE} m f={rc.ORBIT_FREQUENCY} Hz, duration {args.duration} s, "
          f"peak window {rc.PEAK_WINDOW} s, coupling {COUPLING_STEP} s")
    results = {}
    for length in args.lengths:
        rows = ladder(length, sorted(args.segments), args.duration, args.workdir)
        results[str(int(length))] = rows
        print(f"L={length:.0f} m: snap-peak error vs N={rows[-1]['segments']} reference")
        for r in rows:
            print(f"    N={r['segments']:4d}  first-peak={r['first_peak'] / 1e3:8.2f} kN err={100 * r['first_peak_error']:6.2f} %  "
                  f"mean err={100 * r['mean_peak_error']:6.2f} %  max err={100 * r['max_peak_error']:6.2f} %  "
                  f"wall/sim-s={1e3 * r['wall_per_s']:9.2f} ms  RTF={r['rtf']:8.1f}")
        for tol in (0.01, 0.05):
            best = wall_at_accuracy(rows, tol)
            if best is None:
                print(f"    {100 * tol:.0f}% on the snap peak: not reached below N={rows[-1]['segments']}")
            else:
                print(f"    {100 * tol:.0f}% on the snap peak: N={best['segments']}, "
                      f"{1e3 * best['wall_per_s']:.2f} ms wall per simulated s (RTF {best['rtf']:.1f})")
    Path(args.json).parent.mkdir(parents=True, exist_ok=True)
    Path(args.json).write_text(json.dumps(results, indent=1))
    print(f"wrote {args.json}")


if __name__ == "__main__":
    main()
