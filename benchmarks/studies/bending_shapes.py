"""Shape of the slack lower tether before the first snap at L = 200 m: DG against MoorDyn, EI = 0 and EI*.

Companion of benchmarks/studies/bending_effect_study.py (docs/performance.md "Bending effect at 200 m").
Runs the ROPOS slack-snap case to the snapshot times ``--times`` and prints, per model / rung /
alpha, the slack length (unstretched length with T < 1 kN), the largest geometric curvature
(|d tangent / ds| of the sampled positions, the same estimate for both models) and where, the
fold spacing: the mean arc-length distance between successive curvature maxima over the slack part (a proxy of the
half-wavelength the slack cable folds into), and the largest lateral (x) excursion of the
lower 60 m relative to the straight line between its ends, and the chord strain |dx| / ds - 1 of the
sampling intervals in the slack part (min / mean: how far the slack cable shortens axially; both
models carry no compression, T = 0 for strain < 0). DG: ``resolution_ladder.case_config``
driven at 50 Hz like ``drive.run`` (set_end_motion + advance_to), sampled with ``solver.state`` at
the element nodes refined 8x; MoorDyn: ``ropos_case.moordyn_input`` at 200 Hz coupling as
``bench_moordyn.run_moordyn``, node positions / curvatures / tensions from the moordyn API.

Usage: PYTHONPATH=. python benchmarks/studies/bending_shapes.py [--dg 20:4:0.5] [--moordyn 160]
       [--times 7.0 7.4 7.6] [--npz out/bending_effect/shapes.npz]
"""

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from benchmarks import bench_moordyn  # noqa: E402
from benchmarks.studies import resolution_ladder as rl  # noqa: E402
from benchmarks import ropos_case as rc  # noqa: E402
from tether_sim.solvers.factory import build_solver  # noqa: E402

LENGTH = 200.0
SLACK_T = 1.0e3  # N


def dg_shapes(n, p, cfl, alpha, times, rate=50.0):
    cfg = rl.case_config(f"{LENGTH:g}:stiff:{alpha:g}:cage", n, p, cfl, max(times) + 0.1)
    solver = build_solver(cfg)
    s = np.linspace(0.0, LENGTH, 8 * n * p + 1)
    out, k = {}, 0
    for t_snap in sorted(times):
        while (k + 1) / rate <= t_snap + 1e-9:
            k += 1
            pos, vel = rc.fairlead_motion(k / rate)
            solver.set_end_motion("ship", pos, vel)
            solver.advance_to(k / rate)
        st = solver.state(s)
        out[t_snap] = {"s": st.arc_length, "x": st.position, "T": st.tension, "kappa": st.curvature}
    return out


def moordyn_shapes(n_seg, alpha, times, workdir):
    import moordyn

    dt = rc.moordyn_time_step(LENGTH, n_seg, bench_moordyn.COUPLING_STEP)
    path = Path(workdir) / f"shapes_L{LENGTH:g}_N{n_seg}_a{alpha:g}.txt"
    path.write_text(rc.moordyn_input(LENGTH, n_seg, dt, alpha=alpha))
    system, _ = bench_moordyn._quiet_create(moordyn, path)
    line = moordyn.GetLine(system, 1)
    h = bench_moordyn.COUPLING_STEP
    out, t, k = {}, 0.0, 0
    p_now, _ = rc.fairlead_motion(0.0)
    try:
        for t_snap in sorted(times):
            while (k + 1) * h <= t_snap + 1e-9:
                p_next, _ = rc.fairlead_motion((k + 1) * h)
                moordyn.Step(system, list(p_now), list((p_next - p_now) / h), t, h)
                k += 1
                t, p_now = k * h, p_next
            # node 0 = cage (end A), node N = ship: flip so that s runs from the ship like DG
            x = np.array([moordyn.GetLineNodePos(line, i) for i in range(n_seg + 1)])[::-1]
            T = np.array([np.linalg.norm(moordyn.GetLineNodeTen(line, i)) for i in range(n_seg + 1)])[::-1]
            kap = np.array([moordyn.GetLineNodeCurv(line, i) for i in range(n_seg + 1)])[::-1]
            out[t_snap] = {"s": np.linspace(0.0, LENGTH, n_seg + 1), "x": x, "T": T, "kappa": kap}
    finally:
        moordyn.Close(system)
    return out


def geometric_curvature(s, x):
    """|d tangent / ds| from the sampled positions (the same estimate for both models; DG reports no
    curvature at EI = 0): unit chord directions, their change over the mean unstretched spacing."""
    d = np.diff(x, axis=0)
    tng = d / np.linalg.norm(d, axis=1)[:, None]
    ds = np.diff(s)
    kap = np.zeros(len(s))
    kap[1:-1] = np.linalg.norm(np.diff(tng, axis=0), axis=1) / (0.5 * (ds[1:] + ds[:-1]))
    return kap


def describe(snap):
    """Slack length, max curvature (and s), fold spacing, lateral excursion of the lower 60 m."""
    s, x, T = snap["s"], snap["x"], snap["T"]
    kap = geometric_curvature(s, x)
    slack = T < SLACK_T
    ds = np.gradient(s)
    slack_len = float(np.sum(ds[slack]))
    i = int(np.argmax(kap))
    # curvature maxima within the slack part
    peaks = [j for j in range(1, len(s) - 1) if slack[j] and kap[j] > kap[j - 1] and kap[j] >= kap[j + 1]
             and kap[j] > 0.1 * kap.max()]
    spacing = float(np.mean(np.diff(s[peaks]))) if len(peaks) > 1 else float("nan")
    low = s >= LENGTH - 60.0
    a, b = x[low][0], x[low][-1]
    d = x[low] - (a + np.outer((s[low] - s[low][0]) / (s[low][-1] - s[low][0]), b - a))
    chord = np.linalg.norm(np.diff(x, axis=0), axis=1) / np.diff(s) - 1.0  # geometric strain per interval
    mid_slack = slack[1:] & slack[:-1]
    strain = (float(np.min(chord[mid_slack])), float(np.mean(chord[mid_slack]))) if mid_slack.any() else (0.0, 0.0)
    return slack_len, float(kap[i]), float(s[i]), spacing, len(peaks), float(np.max(np.abs(d[:, 0]))), strain


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dg", nargs="*", default=["20:4:0.5"])
    ap.add_argument("--moordyn", type=int, nargs="*", default=[160])
    ap.add_argument("--times", type=float, nargs="+", default=[7.0, 7.4, 7.6])
    ap.add_argument("--npz", default="out/bending_effect/shapes.npz")
    args = ap.parse_args(argv)
    Path(args.npz).parent.mkdir(parents=True, exist_ok=True)
    print(f"bending_shapes: {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, commit {rl._commit()}; "
          f"L = {LENGTH:g} m, EI* = {rc.EI_STAR:g} N m^2; slack = T < {SLACK_T / 1e3:g} kN", flush=True)
    print("model / rung            alpha    t (s) | slack length (m) | max |kappa| (1/m) at s (m) | "
          "curvature maxima: n, mean spacing (m) | max x-excursion lower 60 m (m) | "
          "chord strain in the slack part min / mean (%)")
    saved = {}
    runs = [("dg", x) for x in args.dg] + [("moordyn", str(n)) for n in args.moordyn]
    for model, rung in runs:
        for alpha in (0.0, 1.0):
            if model == "dg":
                n, p, c = rung.split(":")
                snaps = dg_shapes(int(n), int(p), float(c), alpha, args.times)
                name = f"DG N={n} P={p}"
            else:
                snaps = moordyn_shapes(int(rung), alpha, args.times, Path(args.npz).parent)
                name = f"MoorDyn N={rung}"
            for t_snap, snap in snaps.items():
                sl, km, ks, sp, npk, ex, strain = describe(snap)
                print(f"{name:22s} {alpha:5g} {t_snap:8.2f} | {sl:16.1f} | {km:10.4f} at {ks:6.1f}       "
                      f"| {npk:3d}, {sp:6.2f}                         | {ex:6.3f}"
                      f"                         | {100 * strain[0]:+7.2f} / {100 * strain[1]:+7.2f}", flush=True)
                for k, v in snap.items():
                    saved[f"{model}_{rung}_a{alpha:g}_t{t_snap:g}_{k}"] = v
    np.savez_compressed(args.npz, **saved)
    print(f"wrote {args.npz}; done {time.strftime('%H:%M UTC', time.gmtime())}")


if __name__ == "__main__":
    main()
