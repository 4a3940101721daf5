"""The excursion tether's force on the vehicle when the cage's rise jerks it taut: ladders.

The case of ``network_vs_moordyn.py`` (ROPOS orbit, 200 m tether, cage, 30 m excursion tether
EA 2 MN, EI 0, to a vehicle held 20 m off and 15 m below), first jerk taut near t = 3.6 s. Reported
for each run, in the window ``--window`` (default 3.0-4.5 s): the largest vehicle-end force |F|
(every solver substep for tether_sim; every coupling step for MoorDyn), the same sampled like
MoorDyn (one value per 2 ms), the duration above half of the peak, and what the network node's snap
detector makes of it (config/ropos_tms.yaml's excursion thresholds: slack 10 N, re-tension 100 N,
snap 1 kN) with the line's snap plausibility guard (docs/snap_guard.md): a snap, or a numerical
warning with its reason.

- tether_sim, excursion on DG: mesh ladder ``--dg`` N P ... (the tether on the 1 % rule mesh);
- tether_sim, excursion on the hybrid solver: ``--hybrid`` segments ... with ``--hybrid-dt`` steps
  (default 5 ms);
- MoorDyn v2: segment ladder ``--md`` for the excursion tether (tether 80 segments), and
  ``--md-coupling`` (the vehicle force is sampled once per coupling step).

Usage: PYTHONPATH=. python benchmarks/studies/network_excursion_spike.py [--dg 6 3 10 4 20 4] [--dg-cfl 0.8] [--hybrid 30 60]
       [--hybrid-dt 0.005 0.001] [--hybrid-zoning all_rod] [--excursion-EI 78.125] [--excursion-damping 0]
       [--md-scheme RK4] [--md 30 60 120] [--duration 4.5] [--json out/excursion_spike.json] [--figure docs/figures/excursion_spike.png]
"""

import argparse
import json
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from benchmarks.studies import network_vs_moordyn as nm  # noqa: E402
from benchmarks import ropos_case as rc  # noqa: E402
from tether_sim.physics.snap import NumericalSnapWarning, SnapConfig, SnapDetector, SnapEvent  # noqa: E402

THRESHOLDS = SnapConfig(slack_threshold=10.0, retension_threshold=100.0, snap_threshold=1000.0, min_slack_duration=0.1)


def run_ours(solver, duration, mesh, cfl=None, zoning=None):
    from tether_sim.network.solver import NetworkSolver
    from tether_sim.network.spec import parse_network
    from tether_sim.ros.network_driver import line_snap_guard

    kw = {"exc_dg": mesh} if solver == "dg" else {"exc_hybrid": (mesh[0], mesh[1] if len(mesh) > 1 else 0.005)}
    tree = nm.network_tree(solver, 0.005, **kw)
    if cfl is not None and solver == "dg":
        tree["lines"]["excursion"]["dg"]["cfl"] = cfl
    if zoning is not None and solver == "hybrid":
        tree["lines"]["excursion"]["hybrid"]["zoning"] = zoning
    spec = parse_network(tree)
    net = NetworkSolver(spec)
    guard = line_snap_guard(spec, "excursion", net.line("excursion"))
    static = [max(abs(net.end_load("excursion", e)[1]), 1.0) for e in ("ship", "vehicle")]
    det = SnapDetector(THRESHOLDS, ["cage", "vehicle"], static, [0.0, 30.0], guard)
    veh = nm.vehicle_position()
    ts, Tv, events = [], [], []
    c0 = time.process_time()
    error = ""
    try:
        for k in range(1, int(round(duration / 0.005)) + 1):
            t = k * 0.005
            p, v = rc.fairlead_motion(t)
            net.set_point_motion("ship", p, v)
            net.set_point_motion("vehicle", veh, np.zeros(3))
            out = net.tick(t)
            s = out["excursion"]["samples"]
            ts.append(s[0])
            Tv.append(s[2])
            from tether_sim.solvers.base import relative_end_speed
            events += det.update(s[0], np.column_stack([s[1], s[2]]), relative_end_speed(net.line("excursion"), 30.0))
    except Exception as exc:  # noqa: BLE001 - reported
        error = f"{type(exc).__name__}: {exc} at t = {t:.3f} s"
    events += det.flush()
    return dict(t=np.concatenate(ts), T=np.concatenate(Tv), events=events, cpu=time.process_time() - c0, error=error,
                crossing=guard.crossing_time)


def run_md(segments, duration, coupling):
    nm.MD_SEGMENTS[:] = [80, segments]
    md = nm.run_moordyn(duration, coupling)
    return dict(t=md["t"], T=md["veh"], cpu=md["cpu"], dt=md["dt"])


def measures(t, T, lo, hi):
    m = (t >= lo) & (t <= hi)
    tw, Tw = t[m], T[m]
    k = int(np.argmax(Tw))
    peak = float(Tw[k])
    above = tw[Tw >= 0.5 * peak]
    grid = np.arange(lo, hi, 0.002)
    sampled = float(np.max(np.interp(grid, t, T)))
    return dict(peak=peak, t_peak=float(tw[k]), width=float(above[-1] - above[0]) if above.size else 0.0,
                sampled_2ms=sampled)


def describe(events, lo, hi):
    out = []
    for ev in events:
        if getattr(ev, "location", "") != "vehicle" or not (lo - 1.0 <= ev.time <= hi + 1.0):
            continue
        if isinstance(ev, SnapEvent):
            out.append(f"snap {ev.peak_tension:.0f} N at {ev.time:.3f} s (rise {1e3 * ev.rise_time:.1f} ms)")
        elif isinstance(ev, NumericalSnapWarning):
            out.append(f"numerical {ev.tension_peak:.0f} N at {ev.time:.3f} s: {ev.reason}")
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dg", type=int, nargs="*", default=[6, 3, 10, 4, 20, 4])
    ap.add_argument("--dg-cfl", type=float, default=None, help="dg.cfl of the DG excursion tether (default: dg.cfl's)")
    ap.add_argument("--hybrid", type=int, nargs="*", default=[30, 60])
    ap.add_argument("--hybrid-dt", type=float, nargs="*", default=[0.005],
                    help="time steps of the hybrid excursion tether (s): every segment count with every step")
    ap.add_argument("--hybrid-zoning", default=None, choices=["adaptive", "all_rod", "all_catenary"],
                    help="hybrid.zoning of the hybrid excursion tether (default: hybrid.zoning's, adaptive)")
    ap.add_argument("--md", type=int, nargs="*", default=[30, 60, 120])
    ap.add_argument("--md-coupling", type=float, default=0.002)
    ap.add_argument("--duration", type=float, default=4.5)
    ap.add_argument("--window", type=float, nargs=2, default=[3.0, 4.5])
    ap.add_argument("--excursion-damping", type=float, default=None,
                    help="the excursion tether's axial damping in both codes (N s; default: 2000)")
    ap.add_argument("--excursion-EI", type=float, default=None,
                    help="the excursion tether's bending stiffness in every code (N m^2; default: 0)")
    ap.add_argument("--excursion-bending-damping", type=float, default=0.0,
                    help="tether_sim's cable.bending_damping of the excursion tether (N m^2 s; MoorDyn has none: "
                         "for tether_sim-only ladders)")
    ap.add_argument("--md-scheme", default="RK2", choices=["RK2", "RK4"], help="MoorDyn's time scheme")
    ap.add_argument("--json", default="out/excursion_spike.json")
    ap.add_argument("--figure", default="")
    args = ap.parse_args(argv)
    lo, hi = args.window
    if args.excursion_damping is not None:
        nm.set_excursion_damping(args.excursion_damping)
    if args.excursion_EI is not None:
        nm.set_excursion_bending(args.excursion_EI, args.excursion_bending_damping)
    nm.MD_SCHEME[:] = [args.md_scheme]
    print(f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load {os.getloadavg()[0]:.1f}", flush=True)
    runs, table = {}, {}
    for n in args.md:
        r = run_md(n, args.duration, args.md_coupling)
        name = f"MoorDyn {n} seg"
        runs[name], table[name] = r, measures(r["t"], r["T"], lo, hi)
        print(f"{name} (dt {r['dt']:.3g} s, coupling {args.md_coupling} s): {table[name]} cpu {r['cpu']:.1f} s", flush=True)
    for i in range(0, len(args.dg), 2):
        mesh = (args.dg[i], args.dg[i + 1])
        r = run_ours("dg", args.duration, mesh, args.dg_cfl)
        name = f"DG N={mesh[0]} P={mesh[1]}"
        runs[name], table[name] = r, dict(measures(r["t"], r["T"], lo, hi), detector=describe(r["events"], lo, hi),
                                          crossing_ms=1e3 * r["crossing"], error=r["error"])
        print(f"{name}: {table[name]} cpu {r['cpu']:.1f} s", flush=True)
    for n, dt in ((n, dt) for n in args.hybrid for dt in args.hybrid_dt):
        r = run_ours("hybrid", args.duration, (n, dt), zoning=args.hybrid_zoning)
        name = f"hybrid {n} seg, {1e3 * dt:g} ms"
        if r["t"].size and r["t"][-1] >= lo:
            table[name] = dict(measures(r["t"], r["T"], lo, min(hi, r["t"][-1])), detector=describe(r["events"], lo, hi),
                               error=r["error"])
        else:
            table[name] = dict(error=r["error"])
        runs[name] = r
        print(f"{name}: {table[name]} cpu {r['cpu']:.1f} s", flush=True)
    Path(args.json).parent.mkdir(parents=True, exist_ok=True)
    Path(args.json).write_text(json.dumps(table, indent=1))
    if args.figure:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(2, 1, figsize=(9, 7))
        greys = iter(["k", "0.55", "0.75"])
        for name, r in runs.items():
            if not r["t"].size or r.get("error"):
                continue
            md = name.startswith("MoorDyn")
            style = dict(color=next(greys, "0.8"), lw=1.4) if md else dict(lw=1.0, alpha=0.5)
            for a in ax:
                a.plot(r["t"], r["T"], "-", label=name, **style)
        ax[0].set_xlim(lo, hi)
        ok = [k for k in table if "peak" in table[k] and not table[k].get("error")]
        p = max(table[k]["peak"] for k in ok)
        tp = table[max(ok, key=lambda k: table[k]["peak"])]["t_peak"]
        ax[1].set_xlim(tp - 0.02, tp + 0.02)
        ax[0].set_ylabel("excursion tether |F| on vehicle (N)")
        ax[1].set_ylabel("zoom: 40 ms around the largest peak (N)")
        ax[1].set_xlabel("t (s)")
        ax[0].set_ylim(0, 1.05 * p)
        for a in ax:
            a.grid(alpha=0.3)
        ax[0].legend(fontsize=7, ncol=2)
        fig.tight_layout()
        fig.savefig(args.figure, dpi=110)
        print(f"figure {args.figure}")


if __name__ == "__main__":
    main()
