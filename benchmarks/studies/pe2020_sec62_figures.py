"""PE2020 Sec. 6.2 figures: analogues of the paper's Fig. 5 (ship tension per L and alpha) and Fig. 6
(L = 200 m, f = 0.2 Hz: end tensions, cage and fairlead vertical acceleration, tension along the cable at
t0 / t1 / t2, cable position near the cage at t0) from runs of the paper's cases.

Each run: config/ropos_L<L>_paper.yaml with the circular fairlead orbit (a = 2 m, frequency f, ramped over
one period, as config/studies/pe2020_sec62.yaml), EI = alpha * 2.62 kN m^2, N elements at P = 4 and
dg.damping as --damping (explicit by default: the ladder's; docs/dg_solver.md "Slack with bending"), driven at 50 Hz through ``advance_to`` (the fairlead pose of the scenario's own motion
model). Stored per run (npz in --out): end tensions at every substep, cage and fairlead vertical
acceleration per tick, tension and position along the cable at the snapshot times. Runs already stored
are reused; the table of the first snap after ``--from`` s (time, peak, per end) is printed.

    PYTHONPATH=. python benchmarks/studies/pe2020_sec62_figures.py --lengths 200 --alphas 0 1 10 100 --N 40
        --f 0.2 --periods 9 --out out/sec62 --figures docs/figures
"""

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from benchmarks.studies.slack_bending_ladder import case_config  # noqa: E402

SNAP_PERIODS = (8.65, 8.665, 8.67)  # t0, t1, t2 of PE2020 Fig. 6c, in forcing periods


def run(L, f, alpha, N, periods, out, damping="explicit"):
    path = out / f"L{L:g}_f{f:g}_a{alpha:g}_N{N}_p{periods:g}_{damping}.npz"
    if path.exists():
        return dict(np.load(path))
    from tether_sim.physics.motion import build_motion
    from tether_sim.solvers.factory import build_solver

    cfg = case_config(L, f, alpha, N, periods, {"dg.damping": damping})
    motion = build_motion(cfg.motion, cfg.ship_end.position)
    s = build_solver(cfg)
    t0 = s.time
    snaps = sorted(p / f for p in SNAP_PERIODS)
    grid = sorted(set(np.round(np.arange(1, int(periods / f * 50) + 1) / 50.0, 9)) | set(snaps))
    arc = np.linspace(0.0, L, 401)
    fair_az = []
    ts, tsh, tve, tick_t, cage_az, shape_t, shape_T, shape_r = [], [], [], [], [], [], [], []
    cpu0 = time.process_time()
    for t in grid:
        p, v, acc = motion.at(t)
        s.set_end_motion("ship", p, v)
        fair_az.append(acc[2])
        s.advance_to(t0 + t)
        a, b, c = s.drain_end_tensions()
        ts.append(np.asarray(a) - t0)
        tsh.append(b)
        tve.append(c)
        body = s.body_state("vehicle")
        tick_t.append(t)
        cage_az.append(body.acceleration[2] if body is not None else np.nan)
        if any(abs(t - x) < 1e-9 for x in snaps):
            st = s.state(arc)
            shape_t.append(t)
            shape_T.append(st.tension)
            shape_r.append(st.position)
    data = dict(t=np.concatenate(ts), ship=np.concatenate(tsh), cage=np.concatenate(tve), tick_t=np.array(tick_t),
                cage_az=np.array(cage_az), fair_az=np.array(fair_az), shape_t=np.array(shape_t), shape_T=np.array(shape_T),
                shape_r=np.array(shape_r), arc=arc, cpu_s=time.process_time() - cpu0,
                meta=np.array([L, f, alpha, N, periods]))
    np.savez(path, **data)
    return data


def first_snap(t, T, t_from, static):
    """(time of the first up-crossing of the static tension after t_from, peak within 1 s after it)."""
    m = t > t_from
    tt, TT = t[m], T[m]
    below = np.where(TT < 0.1 * static)[0]
    if not len(below):
        return np.nan, np.nan
    up = np.where((TT[below[0]:] >= static))[0]
    if not len(up):
        return np.nan, np.nan
    k = below[0] + up[0]
    w = (tt >= tt[k]) & (tt <= tt[k] + 1.0)
    return float(tt[k]), float(TT[w].max())


def figures(runs, f, out_dir):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    styles = {0.0: "-", 1.0: "--", 10.0: "-.", 100.0: ":"}
    lengths = sorted({float(r["meta"][0]) for r in runs})
    fig, axes = plt.subplots(len(lengths), 1, figsize=(8, 2.6 * len(lengths)), squeeze=False)
    for ax, L in zip(axes[:, 0], lengths):
        for r in runs:
            if float(r["meta"][0]) != L:
                continue
            alpha = float(r["meta"][2])
            P = 1.0 / f
            m = r["t"] > r["t"].max() - 2.5 * P
            ax.plot(r["t"][m] / P, r["ship"][m] / 1e3, styles.get(alpha, "-"), lw=1, label=f"alpha = {alpha:g}")
        ax.set_ylabel(f"ship tension (kN), L = {L:g} m")
        ax.legend(fontsize=7)
    axes[-1, 0].set_xlabel("t / period")
    fig.suptitle(f"PE2020 Fig. 5 analogue: tension at the ship, f = {f:g} Hz, a = 2 m")
    fig.tight_layout()
    p5 = out_dir / f"sec62_fig5_f{f:g}.png"
    fig.savefig(p5, dpi=110)
    plt.close(fig)

    r200 = [r for r in runs if float(r["meta"][0]) == 200.0]
    if not r200:
        return [p5]
    P = 1.0 / f
    fig, ax = plt.subplots(2, 2, figsize=(11, 7.5))
    for r in r200:
        alpha = float(r["meta"][2])
        ls = styles.get(alpha, "-")
        m = (r["t"] / P > 8.55) & (r["t"] / P < 8.85)
        ax[0, 0].plot(r["t"][m] / P, r["ship"][m] / 1e3, ls, color="C0", lw=1, label=f"ship, alpha {alpha:g}")
        ax[0, 0].plot(r["t"][m] / P, r["cage"][m] / 1e3, ls, color="C3", lw=1, label=f"cage, alpha {alpha:g}")
        mt = (r["tick_t"] / P > 8.55) & (r["tick_t"] / P < 8.85)
        ax[0, 1].plot(r["tick_t"][mt] / P, r["cage_az"][mt], ls, color="C3", lw=1, label=f"cage, alpha {alpha:g}")
        if alpha == float(r200[0]["meta"][2]):
            ax[0, 1].plot(r["tick_t"][mt] / P, r["fair_az"][mt], color="C0", lw=1, label="fairlead")
        for k, (tk, Tk) in enumerate(zip(r["shape_t"], r["shape_T"])):
            ax[1, 0].plot(r["arc"], Tk / 1e3, ls, color=("k", "r", "b")[k % 3], lw=1,
                          label=f"t = {tk / P:.3f} P, alpha {alpha:g}" if alpha in (0.0, 100.0) else None)
        if len(r["shape_r"]):
            rr = r["shape_r"][0]
            near = r["arc"] > 150.0
            ax[1, 1].plot(rr[near, 0], rr[near, 2], ls, lw=1, label=f"alpha {alpha:g}")
    ax[0, 0].set_ylabel("end tension (kN)")
    ax[0, 1].set_ylabel("vertical acceleration (m/s^2)")
    for a in ax[0]:
        a.set_xlabel("t / period")
        a.legend(fontsize=6)
    ax[1, 0].set_xlabel("s (m)")
    ax[1, 0].set_ylabel("tension (kN)")
    ax[1, 0].legend(fontsize=6)
    ax[1, 1].set_xlabel("x (m)")
    ax[1, 1].set_ylabel("z (m)")
    ax[1, 1].set_title("cable near the cage (s > 150 m) at t0", fontsize=9)
    ax[1, 1].legend(fontsize=6)
    fig.suptitle(f"PE2020 Fig. 6 analogue: L = 200 m, f = {f:g} Hz (t0, t1, t2 = 8.65, 8.665, 8.67 periods)")
    fig.tight_layout()
    p6 = out_dir / f"sec62_fig6_f{f:g}.png"
    fig.savefig(p6, dpi=110)
    plt.close(fig)
    return [p5, p6]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--lengths", type=float, nargs="+", default=[200.0])
    ap.add_argument("--alphas", type=float, nargs="+", default=[0.0, 1.0, 10.0, 100.0])
    ap.add_argument("--f", type=float, default=0.2)
    ap.add_argument("--N", type=int, default=40)
    ap.add_argument("--damping", choices=("explicit", "implicit"), default="explicit")
    ap.add_argument("--periods", type=float, default=9.0)
    ap.add_argument("--from", dest="t_from", type=float, default=None, help="first snap after this time (s); "
                    "default: 8.4 periods (the paper's Fig. 6 slack period)")
    ap.add_argument("--out", type=Path, default=Path("out/sec62"))
    ap.add_argument("--figures", type=Path, default=None)
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    print(f"# {time.strftime('%Y-%m-%d %H:%M')} load {os.getloadavg()[0]:.1f}", flush=True)
    t_from = args.t_from if args.t_from is not None else 8.4 / args.f
    runs = []
    print("L alpha N | ship: first snap t (s), peak (kN) | cage: t, peak | CPU s")
    for L in args.lengths:
        for alpha in args.alphas:
            r = run(L, args.f, alpha, args.N, args.periods, args.out, args.damping)
            runs.append(r)
            static = float(np.median(r["ship"][(r["t"] > 1.0) & (r["t"] < 2.0)]))
            static_c = float(np.median(r["cage"][(r["t"] > 1.0) & (r["t"] < 2.0)]))
            ts, ps = first_snap(r["t"], r["ship"], t_from, static)
            tc, pc = first_snap(r["t"], r["cage"], t_from, static_c)
            print(f"{L:g} {alpha:g} {args.N} | {ts:.3f} {ps / 1e3:.1f} | {tc:.3f} {pc / 1e3:.1f} | {float(r['cpu_s']):.0f}",
                  flush=True)
    if args.figures:
        args.figures.mkdir(parents=True, exist_ok=True)
        for p in figures(runs, args.f, args.figures):
            print("figure:", p)


if __name__ == "__main__":
    main()
