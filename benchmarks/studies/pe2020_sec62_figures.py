"""PE2020 Sec. 6.2 figures: analogues of the paper's Fig. 5 (ship tension per L and alpha) and Fig. 6
(L = 200 m, f = 0.2 Hz: end tensions, cage and fairlead vertical acceleration, tension along the cable at
t0 / t1 / t2, cable position near the cage at t0) from runs of the paper's cases.

Each run: config/ropos_L<L>_paper.yaml with the circular fairlead orbit (a = 2 m, frequency f, ramped over
one period, as config/studies/pe2020_sec62.yaml), EI = alpha * 2.62 kN m^2, N elements at P = 4 and
dg.damping as --damping (explicit by default: the ladder's; docs/dg_solver.md "Slack with bending"), driven at 50 Hz through ``advance_to`` (the fairlead pose of the scenario's own motion
model). Stored per run (npz in --out): end tensions at every substep, cage and fairlead vertical
acceleration per tick, tension and position along the cable at the snapshot times. Runs already stored
are reused; the table of the first snap after ``--from`` s (time, peak, per end) is printed, then the delay of every
re-tensioning front and the change of its peak against alpha = 0 of the same length.

    PYTHONPATH=. python benchmarks/studies/pe2020_sec62_figures.py --lengths 200 --alphas 0 1 10 100 --N 40
        --f 0.2 --periods 9 --out out/sec62 --figures docs/figures

Without running anything:
    --study out/studies/pe2020_sec62   the study's snap table per length, frequency and alpha (first and largest snap
                                       per end, every event the snap guard rejected) and the shifts against alpha 0
    --records A.npz B.npz ...          end tensions of runs recorded by benchmarks/probes/slack_record.py (--window,
                                       --zoom) into --figures/sec62_records.png
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


def fronts(t, T, static, f, hold=0.005):
    """Every re-tensioning of an end after the ramp (1/f): (time its tension first climbs back to ``static`` after
    falling below 10 % of it and stays there for ``hold`` s, the largest tension within half a period after that).
    The hold skips the one-substep spikes the snap guard rejects (docs/dg_solver.md "Slack with bending", part 6)."""
    out, k = [], int(np.searchsorted(t, 1.0 / f))
    while True:
        below = np.where(T[k:] < 0.1 * static)[0]
        if not len(below):
            return out
        k += below[0]
        while True:
            up = np.where(T[k:] >= static)[0]
            if not len(up):
                return out
            k += up[0]
            held = (t >= t[k]) & (t <= t[k] + hold)
            if T[held].min() >= static:
                break
            k += int(np.argmax(T[k:] < static))
        w = (t >= t[k]) & (t <= t[k] + 0.5 / f)
        out.append((float(t[k]), float(T[w].max())))
        k = int(np.searchsorted(t, t[k] + 0.5 / f))


def lag(t, T, t_ref, T_ref, t0, t1, max_lag, step=1e-4):
    """The delay (s) of T against T_ref over [t0, t1]: the shift that brings T(t + lag) closest to T_ref(t) in the
    least-squares sense, to ``step`` within +-``max_lag`` (a 10-step grid, then ``step`` around its best)."""
    grid = np.arange(t0, t1, step)
    ref = np.interp(grid, t_ref, T_ref)
    m = (t >= t0 - max_lag - step) & (t <= t1 + max_lag + step)
    t, T = t[m], T[m]

    def best(lags):
        err = [float(np.sum((np.interp(grid + d, t, T) - ref) ** 2)) for d in lags]
        return float(lags[int(np.argmin(err))])

    coarse = best(np.arange(-max_lag, max_lag + 5 * step, 10 * step))
    return best(np.arange(max(coarse - 10 * step, -max_lag), min(coarse + 10 * step, max_lag) + step / 2, step))


def front_shift_lines(runs, f):
    """Against alpha = 0 of the same length, per alpha and end: each re-tensioning front (``fronts``) paired with the
    nearest one of alpha = 0; its delay (ms, + = later than alpha 0; the least-squares shift of the whole rise, from 0.02
    periods before the alpha = 0 front to 0.1 after it, so a fixed level on a flat step of the front does not decide it)
    and the change of its peak (%), median [min, max] (markdown lines)."""
    lines = ["| L (m) | alpha | end | first front: delay (ms), peak (%) | fronts | delay of the front (ms) | "
             "peak change (%) |", "|---|---|---|---|---|---|---|"]
    fr, level, data = {}, {}, {}
    for r in sorted(runs, key=lambda r: float(r["meta"][2])):  # one level per length and end: alpha 0's static
        L, alpha = float(r["meta"][0]), float(r["meta"][2])
        for end in ("ship", "cage"):
            static = level.setdefault((L, end), float(np.median(r[end][(r["t"] > 1.0) & (r["t"] < 2.0)])))
            fr[(L, alpha, end)] = fronts(r["t"], r[end], static, f)
            data[(L, alpha, end)] = (r["t"], r[end])
    for (L, alpha, end), mine in sorted(fr.items()):
        base = fr.get((L, 0.0, end))
        if alpha == 0.0 or base is None:
            continue
        pairs = [(a, min(base, key=lambda b: abs(b[0] - a[0]))) for a in mine] if base else []
        pairs = [(a, b) for a, b in pairs if abs(a[0] - b[0]) < 0.25 / f]
        dt = [lag(*data[(L, alpha, end)], *data[(L, 0.0, end)], b[0] - 0.02 / f, b[0] + 0.1 / f, 0.02 / f) * 1e3
              for a, b in pairs]
        dp = [(a[1] / b[1] - 1.0) * 100.0 for a, b in pairs]
        cell = (lambda x, fmt: "-" if not x else f"{np.median(x):{fmt}} [{min(x):{fmt}}, {max(x):{fmt}}]")
        first = "-" if not pairs else f"{dt[0]:+.1f}, {dp[0]:+.2f}"
        lines.append(f"| {L:g} | {alpha:g} | {end} | {first} | {len(pairs)} / {len(mine)} | {cell(dt, '+.1f')} | "
                     f"{cell(dp, '+.2f')} |")
    return lines


def study_cases(study_dir):
    """(L, f, alpha) -> (results row, events) of a tether-sim-study output folder of
    config/studies/pe2020_sec62.yaml (its results.parquet and events.parquet)."""
    import pyarrow.parquet as pq

    rows = pq.read_table(study_dir / "results.parquet").to_pylist()
    ev_path = study_dir / "events.parquet"
    events = pq.read_table(ev_path).to_pylist() if ev_path.exists() else []
    out = {}
    for r in rows:
        mine = sorted((e for e in events if e["key"] == r["key"]), key=lambda e: e["time_s"])
        out[(float(r["var.L"]), float(r["var.f"]), float(r["var.alpha"]))] = (r, mine)
    return out


def _snaps(events, end):
    return [e for e in events if e["kind"] == "snap" and (e["location"] == "ship") == (end == "ship")]


def _cell(e):
    return "-" if e is None else f"{e['time_s']:.3f} s, {e['peak_N'] / 1e3:.2f} kN"


def study_table(cases):
    """The snap table of the study, per length and frequency against alpha (markdown lines): per end the number of
    snaps, the first and the largest (peak time, peak), and every re-tensioning the snap guard rejected (a numerical
    event, never a snap: its end, time, peak, rise and the guard's bound)."""
    lines = ["| L (m) | f (Hz) | alpha | ship snaps | ship: first | ship: largest | cage snaps | cage: first | "
             "cage: largest | rejected by the guard (end, time, peak, rise, bound) | status, divergences, CPU s |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for (L, f, alpha), (r, ev) in sorted(cases.items()):
        cells = []
        for end in ("ship", "cage"):
            sn = _snaps(ev, end)
            cells += [str(len(sn)), _cell(sn[0] if sn else None), _cell(max(sn, key=lambda e: e["peak_N"]) if sn else None)]
        rej = [e for e in ev if e["kind"] != "snap"]
        rej_txt = "; ".join(f"{'ship' if e['location'] == 'ship' else 'cage'} {e['time_s']:.3f} s, {e['peak_N'] / 1e3:.1f} kN, "
                            f"{e['rise_time_s'] * 1e6:.0f} us, bound {e['bound_N'] / 1e3:.0f} kN" for e in rej) or "none"
        run = f"{r['status']}, {int(r.get('divergences') or 0)}, {float(r.get('cpu_s') or 0):.0f}"
        lines.append(f"| {L:g} | {f:g} | {alpha:g} | " + " | ".join(cells) + f" | {rej_txt} | {run} |")
    return lines


def _pairs(events, ref, window):
    """One-to-one pairs (event, reference) within ``window`` s of each other, the closest first."""
    cand = sorted(((abs(e["time_s"] - m["time_s"]), i, k) for i, e in enumerate(events) for k, m in enumerate(ref)
                   if abs(e["time_s"] - m["time_s"]) <= window), key=lambda x: x[0])
    used_e, used_m, out = set(), set(), []
    for _, i, k in cand:
        if i not in used_e and k not in used_m:
            used_e.add(i)
            used_m.add(k)
            out.append((events[i], ref[k]))
    return sorted(out, key=lambda p: p[0]["time_s"])


def alpha_shift_table(cases, window=0.05):
    """Against alpha = 0, per length, frequency, alpha and end: the first snap's shift and change, then the snaps paired
    one to one with the alpha = 0 snaps of the same end, the closest in peak time first (within ``window`` periods:
    the same re-tensioning; where the runs' snap sequences part, the unpaired ones say so); the shift of the peak time and of the onset (the up-crossing
    of the re-tension level, peak time - rise time), in ms (+ = later than alpha 0), and the peak change in %, each as
    median [min, max] over the matched snaps (markdown lines). PE2020 Sec. 6.2: the lower alpha, the earlier the snap
    at the ship; alpha 0 the smaller snap; the difference grows as L shrinks."""
    lines = ["| L (m) | f (Hz) | alpha | end | first snap: shift (ms), change (%) | paired / snaps | peak time shift (ms) "
             "| onset shift (ms) | peak change (%) |", "|---|---|---|---|---|---|---|---|---|"]

    def stats(x, fmt):
        return "-" if not x else f"{np.median(x):{fmt}} [{min(x):{fmt}}, {max(x):{fmt}}]"

    for (L, f, alpha), (r, ev) in sorted(cases.items()):
        base = cases.get((L, f, 0.0))
        if alpha == 0.0 or base is None:
            continue
        for end in ("ship", "cage"):
            ref, sn = _snaps(base[1], end), _snaps(ev, end)
            dts, dons, dps = [], [], []
            for e, m in _pairs(sn, ref, window / f):
                dts.append((e["time_s"] - m["time_s"]) * 1e3)
                dons.append((e["time_s"] - e["rise_time_s"] - m["time_s"] + m["rise_time_s"]) * 1e3)
                dps.append((e["peak_N"] / m["peak_N"] - 1.0) * 100.0)
            first = "-" if not (sn and ref) else (f"{(sn[0]['time_s'] - ref[0]['time_s']) * 1e3:+.1f}, "
                                                   f"{(sn[0]['peak_N'] / ref[0]['peak_N'] - 1.0) * 100.0:+.2f}")
            lines.append(f"| {L:g} | {f:g} | {alpha:g} | {end} | {first} | {len(dts)} / {len(sn)} | {stats(dts, '+.1f')} | "
                         f"{stats(dons, '+.1f')} | {stats(dps, '+.2f')} |")
    return lines


def figures(runs, f, out_dir):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    styles = {0.0: "-", 1.0: "--", 10.0: "-.", 100.0: ":"}
    lengths = sorted({float(r["meta"][0]) for r in runs})
    P = 1.0 / f
    fig, axes = plt.subplots(len(lengths), 2, figsize=(12, 2.6 * len(lengths)), squeeze=False,
                             gridspec_kw={"width_ratios": [2, 1]})
    for (ax, az), L in zip(axes, lengths):
        mine = [r for r in runs if float(r["meta"][0]) == L]
        # the zoom: around the largest ship tension of the last period of the stiffest-free run (PE2020 Fig. 5d, f)
        ref = min(mine, key=lambda r: float(r["meta"][2]))
        last = ref["t"] > ref["t"].max() - P
        tz = ref["t"][last][np.argmax(ref["ship"][last])] / P
        for r in mine:
            alpha = float(r["meta"][2])
            m = r["t"] > r["t"].max() - 2.5 * P
            ax.plot(r["t"][m] / P, r["ship"][m] / 1e3, styles.get(alpha, "-"), lw=1, label=f"alpha = {alpha:g}")
            mz = np.abs(r["t"] / P - tz) < 0.08
            az.plot(r["t"][mz] / P, r["ship"][mz] / 1e3, styles.get(alpha, "-"), lw=1, label=f"alpha = {alpha:g}")
        ax.set_ylabel(f"ship tension (kN)\nL = {L:g} m")
        ax.legend(fontsize=7, loc="upper left")
        az.set_title(f"L = {L:g} m, the last snap", fontsize=8)
    axes[-1, 0].set_xlabel("t / period")
    axes[-1, 1].set_xlabel("t / period")
    N = int(runs[0]["meta"][3])
    fig.suptitle(f"PE2020 Fig. 5 analogue: tension at the ship, f = {f:g} Hz, a = 2 m, N = {N}, P = 4")
    fig.tight_layout()
    p5 = out_dir / f"sec62_fig5_f{f:g}_N{N}.png"
    fig.savefig(p5, dpi=110)
    plt.close(fig)

    r200 = [r for r in runs if float(r["meta"][0]) == 200.0]
    if not r200:
        return [p5]
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
    p6 = out_dir / f"sec62_fig6_L200_f{f:g}_N{N}.png"
    fig.savefig(p6, dpi=110)
    plt.close(fig)
    return [p5, p6]


def records_figure(paths, window, zoom, out_png):
    """End tensions of runs recorded by benchmarks/probes/slack_record.py (every substep's ship and cage tension)
    over ``window`` (t0, t1) s and over ``zoom``: the same case on several meshes and bending factors
    (labels from the file names, e.g. L200f0.2a100N80)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(2, 1, figsize=(11, 8))
    for k, path in enumerate(paths):
        d = np.load(path)
        t, T = d["times"], d["tensions"]
        ls = ("-", "--", ":", "-.")[k % 4]
        for a, (lo, hi) in zip(ax, (window, zoom)):
            m = (t >= lo) & (t <= hi)
            step = max(1, int(m.sum()) // 20000)
            a.plot(t[m][::step], T[m, 0][::step] / 1e3, ls, color=f"C{k}", lw=0.9, label=f"ship, {Path(path).stem}")
            a.plot(t[m][::step], T[m, 1][::step] / 1e3, ls, color=f"C{k}", lw=0.9, alpha=0.55,
                   label=f"cage, {Path(path).stem}")
    ax[0].set_ylim(-10, None)
    ax[1].set_ylim(150, None)
    for a in ax:
        a.set_xlabel("t (s)")
        a.set_ylabel("end tension (kN)")
        a.legend(fontsize=6, ncol=2)
    ax[0].set_title("end tensions (recorded at every substep); below: the snap (ship dark, cage light)", fontsize=9)
    fig.tight_layout()
    fig.savefig(out_png, dpi=100)
    plt.close(fig)
    return out_png


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
    ap.add_argument("--study", type=Path, default=None, help="a tether-sim-study output folder of "
                    "config/studies/pe2020_sec62.yaml: print its snap table and the shifts against alpha 0, run nothing")
    ap.add_argument("--records", type=Path, nargs="*", default=[], help="slack_record.py runs (npz): draw their end "
                    "tensions over --window into --figures (sec62_records.png), run nothing")
    ap.add_argument("--window", type=float, nargs=2, default=[7.4, 8.5], help="s, for --records")
    ap.add_argument("--zoom", type=float, nargs=2, default=[8.0, 8.35], help="s, for --records: the snap")
    args = ap.parse_args(argv)
    if args.records:
        (args.figures or args.out).mkdir(parents=True, exist_ok=True)
        print("figure:", records_figure(args.records, args.window, args.zoom, (args.figures or args.out) / "sec62_records.png"))
        return
    if args.study:
        cases = study_cases(args.study)
        print("\n".join(study_table(cases) + [""] + alpha_shift_table(cases)))
        return
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
    print("\n".join(front_shift_lines(runs, args.f)))
    if args.figures:
        args.figures.mkdir(parents=True, exist_ok=True)
        for p in figures(runs, args.f, args.figures):
            print("figure:", p)


if __name__ == "__main__":
    main()
