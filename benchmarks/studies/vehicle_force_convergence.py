"""The excursion tether's force on the vehicle: which measures converge, in MoorDyn, DG and the hybrid.

The case of ``network_vs_moordyn.py`` (the ROPOS orbit slackens and snaps the 200 m tether; the cage
hangs on it; a 30 m excursion tether, EA 2 MN, EI 0, runs from the cage to a vehicle held 20 m off and
15 m below; the cage's rises jerk the slack excursion tether taut near 3.6 s and 9.4 s). Every code
runs the same case with the excursion tether on a ladder of meshes (the tether held: MoorDyn 80
segments, DG on the 1 % rule mesh):

- MoorDyn v2 ``--md`` segments (vehicle force sampled every ``--md-coupling`` s);
- DG ``--dg`` N P ... (every substep);
- hybrid ``--hybrid`` segments:step ... (every step), or segments:step:zoning (``hybrid.zoning``: adaptive,
  all_rod, all_catenary; default the solver's, adaptive).

``--excursion-EI`` gives the excursion tether a bending stiffness in every code (tether_sim's cable.EI, MoorDyn's
line-type EI column; use its own ``--cache``, since the run keys do not hold it). A hybrid run that the solver stops
(the closure check of an adaptive line with bending) is reported and left out of the table; ``--no-closure-stop``
lets it go on, to measure what the check prevents (diagnosis only, its own ``--cache``).

Each run's vehicle |F| is turned into a uniform series of bin means (width ``--bin``, from the running
impulse, so a one-substep spike keeps its impulse and loses its height) and the measures are:

- ``F(t)``: bin means at given times (``--times``);
- ``mean``, ``rms``: over the slack window (``--slack-window``: the excursion tether hangs slack
  between the jerks, pulled by the swinging cage);
- ``lp<f>``: the largest force after a zero-phase 4th-order Butterworth low-pass at f Hz
  (``--cutoffs``), in each jerk window (``--jerk-windows``);
- ``J``: the impulse of the force in each jerk window (N s);
- ``raw``: the largest force as the code samples it (a one-substep spike included), for contrast.

Runs are cached in ``--cache`` (one .npz per run; ``--fresh`` recomputes). Writes a JSON of every
measure per run, a table (markdown) of the measures' spread over each code's finest two meshes and
the codes' finest values against each other, and a figure.

With ``--prescribed-cage md_40`` every code runs the excursion tether alone, its cage end following the cage
attachment's path of that run (a C2 spline through its samples), the vehicle held: the comparison of the
excursion tether without the tether's and the cage's differences between the codes.

Usage: PYTHONPATH=. python benchmarks/studies/vehicle_force_convergence.py [--md 10 20 40 80]
       [--dg 5:4 10:4 20:4 40:4:5] [--hybrid 15:0.002 30:0.002 30:0.001 60:0.002 60:0.001] [--duration 11]
       [--prescribed-cage md_40] [--excursion-EI 78.125] [--figure docs/figures/vehicle_force_convergence.png]
       [--json out/vehicle_force_convergence.json] [--table out/vehicle_force_convergence.md]
"""

import argparse
import json
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from benchmarks import ropos_case as rc  # noqa: E402
from benchmarks.studies import network_vs_moordyn as nm  # noqa: E402

TICK = 0.005


def run_md(segments, duration, coupling):
    nm.MD_SEGMENTS[:] = [80, segments]
    md = nm.run_moordyn(duration, coupling)
    return dict(t=md["t"], F=md["veh"], ship_t=md["t"], ship=md["ship"], cpu=md["cpu"], note=f"dt {md['dt']:.3g} s",
                cage_t=md["t"], cage_x=md["cage_attachment"])


def hybrid_zoning(zoning):
    """nm.HYBRID_OPTIONS with ``hybrid.zoning`` set (or left to the solver's default) for the next network built."""
    nm.HYBRID_OPTIONS.pop("zoning", None)
    if zoning:
        nm.HYBRID_OPTIONS["zoning"] = zoning


def run_ours(solver, duration, mesh):
    from tether_sim.network.solver import NetworkSolver
    from tether_sim.network.spec import parse_network

    kw = {"exc_dg": tuple(mesh)} if solver == "dg" else {"exc_hybrid": (int(mesh[0]), float(mesh[1]))}
    if solver == "hybrid":
        hybrid_zoning(mesh[2] if len(mesh) > 2 else None)
    net = NetworkSolver(parse_network(nm.network_tree(solver, TICK, **kw)))
    veh = nm.vehicle_position()
    body = net.bodies["cage"]
    lower = int(np.argmin(body.attachments[:, 2]))  # the excursion tether's attachment
    ts, F, st, S, ct, cx = [], [], [], [], [], []
    c0 = time.process_time()
    for k in range(1, int(round(duration / TICK)) + 1):
        t = k * TICK
        p, v = rc.fairlead_motion(t)
        net.set_point_motion("ship", p, v)
        net.set_point_motion("vehicle", veh, np.zeros(3))
        out = net.tick(t)
        e, s = out["excursion"]["samples"], out["tether"]["samples"]
        ts.append(e[0])
        F.append(e[2])
        st.append(s[0])
        S.append(s[1])
        ct.append(t)
        cx.append(body.attachment_points()[0][lower])
    return dict(t=np.concatenate(ts), F=np.concatenate(F), ship_t=np.concatenate(st), ship=np.concatenate(S),
                cpu=time.process_time() - c0, note="", cage_t=np.array(ct), cage_x=np.array(cx))


# ---------------------------------------------------------------- the excursion tether alone, its cage end prescribed

def cage_track(r):
    """The cage attachment's path of a run as a C2 cubic spline (position, velocity at any t)."""
    from scipy.interpolate import CubicSpline

    t = np.concatenate([[0.0], r["cage_t"]])
    x0 = nm.cage_bottom_at_rest()
    x = np.vstack([x0[None, :], r["cage_x"]])
    return CubicSpline(t, x, axis=0)


def run_ours_alone(solver, duration, mesh, track):
    """The excursion tether alone, its cage end following ``track`` (a prescribed point), the vehicle held."""
    from tether_sim.network.solver import NetworkSolver
    from tether_sim.network.spec import parse_network

    if solver == "hybrid":
        hybrid_zoning(mesh[2] if len(mesh) > 2 else None)
    tree = nm.network_tree(solver, TICK, **({"exc_dg": tuple(mesh)} if solver == "dg"
                                           else {"exc_hybrid": (int(mesh[0]), float(mesh[1]))}))
    exc = dict(tree["lines"]["excursion"])
    exc.pop("from_attachment")
    exc["from"] = "cage"
    tree["points"]["cage"] = dict(kind="prescribed", position=[float(x) for x in track(0.0)])
    del tree["points"]["ship"]
    tree["bodies"] = {}
    tree["lines"] = {"excursion": exc}
    net = NetworkSolver(parse_network(tree))
    veh = nm.vehicle_position()
    dtrack = track.derivative()
    ts, F = [], []
    c0 = time.process_time()
    for k in range(1, int(round(duration / TICK)) + 1):
        t = k * TICK
        net.set_point_motion("cage", track(t), dtrack(t))
        net.set_point_motion("vehicle", veh, np.zeros(3))
        e = net.tick(t)["excursion"]["samples"]
        ts.append(e[0])
        F.append(e[2])
    return dict(t=np.concatenate(ts), F=np.concatenate(F), cpu=time.process_time() - c0, note="alone")


def moordyn_alone_input(dt, segments, x_cage):
    le = rc.moordyn_line_type(nm.EXCURSION)
    veh = nm.vehicle_position()
    row = (f"excursion {le['diam']:.8g} {le['mass']:.8g} {le['EA']:.8g} {le['BA']:.8g} {nm.EXCURSION.EI:.8g} "
           f"{le['Cd']:.8g} {le['Ca']:.8g} {le['CdAx']:.8g} {le['CaAx']:.8g}")
    return f"""--------------------- MoorDyn Input File ------------------------------------
The excursion tether alone, its cage end prescribed (tether_sim benchmarks/studies/vehicle_force_convergence.py)
---------------------- LINE TYPES -----------------------------------------------------
TypeName  Diam  Mass/m  EA  BA/-zeta  EI  Cd  Ca  CdAx  CaAx
(name) (m) (kg/m) (N) (N-s/-) (N-m^2) (-) (-) (-) (-)
{row}
---------------------- POINTS ---------------------------------------------------------
ID Attachment X Y Z Mass Volume CdA Ca
(#) (word/ID) (m) (m) (m) (kg) (m^3) (m^2) (-)
1 Coupled {x_cage[0]:.10g} {x_cage[1]:.10g} {x_cage[2]:.10g} 0 0 0 0
2 Coupled {veh[0]:.10g} {veh[1]:.10g} {veh[2]:.10g} 0 0 0 0
---------------------- LINES ----------------------------------------------------------
ID LineType AttachA AttachB UnstrLen NumSegs LineOutputs
(#) (name) (ID) (ID) (m) (-) (-)
1 excursion 1 2 {nm.EXCURSION.length:.8g} {segments} -
{rc.moordyn_options(dt, nm.MD_SCHEME[0], 600.0, tmax_ic=200, thresh_ic="1e-5")}------------------------- need this line ----------------------------------------------
"""


def run_md_alone(segments, duration, coupling, track):
    import math
    import tempfile

    import moordyn
    from benchmarks.bench_moordyn import c_stdout_silenced

    e = nm.EXCURSION
    dt_stable = rc.moordyn_stable_dt(e.length, segments, EA=e.EA, zeta=e.damping, gamma0=e.gamma0, scheme=nm.MD_SCHEME[0])
    dt = coupling / math.ceil(coupling / dt_stable - 1e-9)
    path = Path(tempfile.mkdtemp(prefix="md_exc_")) / "excursion.txt"
    path.write_text(moordyn_alone_input(dt, segments, track(0.0)))
    veh = list(nm.vehicle_position())
    dtrack = track.derivative()
    with c_stdout_silenced():
        system = moordyn.Create(str(path))
        err = moordyn.Init(system, list(track(0.0)) + veh, list(dtrack(0.0)) + [0.0, 0.0, 0.0])
    if err != 0:
        raise RuntimeError(f"MoorDyn Init failed with code {err}")
    n = int(round(duration / coupling))
    t_out, F = np.empty(n), np.empty(n)
    t = 0.0
    c0 = time.process_time()
    try:
        for k in range(n):
            t_next = (k + 1) * coupling
            f = moordyn.Step(system, list(track(t)) + veh, list(dtrack(t)) + [0.0, 0.0, 0.0], t, coupling)
            t = t_next
            t_out[k] = t
            F[k] = math.sqrt(f[3] ** 2 + f[4] ** 2 + f[5] ** 2)
    finally:
        moordyn.Close(system)
    return dict(t=t_out, F=F, cpu=time.process_time() - c0, note=f"alone, dt {dt:.3g} s")


TRACK = {}  # the cage track of --prescribed-cage (one spline)


def run_cached(key, duration, args, need_cage=False):
    path = Path(args.cache) / f"{key}_{duration:g}s.npz"
    if path.exists() and not args.fresh:
        d = np.load(path)
        r = {k: (d[k] if d[k].shape else d[k].item()) for k in d.files}
        if not need_cage or "cage_x" in r:
            return r
    alone = key.startswith("pc_")
    kind, *rest = key.removeprefix("pc_").split("_")
    track = TRACK.get("spline")
    if kind == "md":
        r = run_md_alone(int(rest[0]), duration, args.md_coupling, track) if alone else run_md(int(rest[0]), duration,
                                                                                              args.md_coupling)
    elif kind == "dg":
        mesh = (int(rest[0]), int(rest[1]))
        r = run_ours_alone("dg", duration, mesh, track) if alone else run_ours("dg", duration, mesh)
    else:
        mesh = (int(rest[0]), float(rest[1])) + (("_".join(rest[2:]),) if rest[2:] else ())
        r = run_ours_alone("hybrid", duration, mesh, track) if alone else run_ours("hybrid", duration, mesh)
    path.parent.mkdir(parents=True, exist_ok=True)
    np.savez(path, **r)
    return r


def bin_means(t, F, h, t_end):
    """Means of F over bins [k h, (k+1) h) from the running trapezoidal impulse of the samples (t, F), with
    F taken as F[0] before the first sample. Returns the bin centres and means."""
    t = np.concatenate([[0.0], t])
    F = np.concatenate([[F[0]], F])
    J = np.concatenate([[0.0], np.cumsum(0.5 * (F[1:] + F[:-1]) * np.diff(t))])
    edges = np.arange(0.0, t_end + 0.5 * h, h)
    edges = edges[edges <= t[-1] + 1e-12]
    Je = np.interp(edges, t, J)
    return 0.5 * (edges[1:] + edges[:-1]), np.diff(Je) / h


def lowpass(x, h, fc):
    from scipy.signal import butter, sosfiltfilt

    sos = butter(4, fc, fs=1.0 / h, output="sos")
    return sosfiltfilt(sos, x)


def measures(r, args):
    """Every measure of one run; NaN for a window the run does not reach (a shorter run)."""
    end = float(r["t"][-1])
    tc, Fb = bin_means(r["t"], r["F"], args.bin, end)
    nan = float("nan")
    out = {}
    for tq in args.times:
        out[f"F({tq:g})"] = float(np.interp(tq, tc, Fb)) if tq <= end else nan
    lo, hi = args.slack_window
    m = (tc >= lo) & (tc <= hi)
    out["mean"] = float(np.mean(Fb[m])) if hi <= end + args.bin else nan
    out["rms"] = float(np.sqrt(np.mean(Fb[m] ** 2))) if hi <= end + args.bin else nan
    for i in range(0, len(args.jerk_windows), 2):
        a, b = args.jerk_windows[i], args.jerk_windows[i + 1]
        tag = f"{a:g}-{b:g}"
        names = [f"J {tag}"] + [f"lp{fc:g} {tag}" for fc in args.cutoffs] + [f"raw {tag}"]
        if b > end + args.bin:  # (a run of T s ends within a substep of T)
            out.update({k: nan for k in names})
            continue
        w = (tc >= a) & (tc <= b)
        out[f"J {tag}"] = float(np.sum(Fb[w]) * args.bin)
        for fc in args.cutoffs:
            out[f"lp{fc:g} {tag}"] = float(np.max(lowpass(Fb, args.bin, fc)[w]))
        wr = (r["t"] >= a) & (r["t"] <= b)
        out[f"raw {tag}"] = float(np.max(r["F"][wr]))
    return out


def _dg_key(spec):
    n, p, *t = spec.split(":")
    return f"dg_{n}_{p}" + (f"@{t[0]}" if t else "")


def _label(key):
    """The mesh of a run key: md_40 -> 40, dg_10_4 -> 10:4, hy_30_0.002_all_rod -> 30:0.002:all_rod."""
    return ":".join(key.removeprefix("pc_").split("_", 3)[1:])


def spread(values):
    """Relative change between the two finest meshes of a ladder that have the measure (last two finite values)."""
    values = [v for v in values if np.isfinite(v)]
    if len(values) < 2:
        return float("nan")
    a, b = values[-2], values[-1]
    return (b - a) / max(abs(b), 1e-9)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--md", type=int, nargs="*", default=[10, 20, 40, 80])
    ap.add_argument("--dg", nargs="*", default=["5:4", "10:4", "20:4", "40:4:5"],
                    help="DG excursion meshes N:P, or N:P:T for a run of T s only (the windows it reaches)")
    ap.add_argument("--hybrid", nargs="*", default=["15:0.002", "30:0.002", "30:0.001", "60:0.002", "60:0.001"])
    ap.add_argument("--md-coupling", type=float, default=0.001)
    ap.add_argument("--duration", type=float, default=11.0)
    ap.add_argument("--bin", type=float, default=0.001, help="bin width of the uniform series (s)")
    ap.add_argument("--times", type=float, nargs="*", default=[3.6, 4.35, 6.0, 9.6])
    ap.add_argument("--slack-window", type=float, nargs=2, default=[5.0, 7.6],
                    help="window of the mean and r.m.s. (default: the tether's slack period)")
    ap.add_argument("--jerk-windows", type=float, nargs="*", default=[3.3, 5.0, 9.0, 10.5],
                    help="windows of the impulse and the peaks (default: the excursion tether's two take-ups)")
    ap.add_argument("--cutoffs", type=float, nargs="*", default=[2.0, 5.0, 10.0, 20.0])
    ap.add_argument("--prescribed-cage", default="",
                    help="a run (e.g. md_40) whose cage attachment path drives the excursion tether alone in every code")
    ap.add_argument("--excursion-damping", type=float, default=None,
                    help="the excursion tether's axial damping in every code (N s; default 2000; 0 wants --md-scheme RK4)")
    ap.add_argument("--excursion-EI", type=float, default=0.0,
                    help="the excursion tether's bending stiffness in every code (N m^2; give it its own --cache)")
    ap.add_argument("--no-closure-stop", action="store_true",
                    help="diagnosis only: let a hybrid run go on past the closure check (its shape off its driven end; "
                         "docs/hybrid_solver.md, \"Zoning\"); give it its own --cache")
    ap.add_argument("--md-scheme", default="RK2", choices=["RK2", "RK4"], help="MoorDyn's time scheme")
    ap.add_argument("--cache", default="out/vehicle_force_convergence")
    ap.add_argument("--fresh", action="store_true")
    ap.add_argument("--json", default="out/vehicle_force_convergence.json")
    ap.add_argument("--table", default="out/vehicle_force_convergence.md")
    ap.add_argument("--figure", default="")
    args = ap.parse_args(argv)
    print(f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load {os.getloadavg()[0]:.1f}", flush=True)
    if args.excursion_damping is not None:
        nm.set_excursion_damping(args.excursion_damping)
    if args.excursion_EI:
        nm.set_excursion_bending(args.excursion_EI)
    nm.MD_SCHEME[:] = [args.md_scheme]
    keys = {"MoorDyn": [f"md_{n}" for n in args.md],
            "DG": [_dg_key(s) for s in args.dg],
            "hybrid": [f"hy_{s.replace(':', '_')}" for s in args.hybrid]}
    if args.prescribed_cage:
        TRACK["spline"] = cage_track(run_cached(args.prescribed_cage, args.duration, args, need_cage=True))
        keys = {c: ["pc_" + k for k in ks] for c, ks in keys.items()}
    runs, table = {}, {}
    if args.no_closure_stop:
        import tether_sim.solvers.hybrid.solver as hybrid_solver

        hybrid_solver.CLOSURE_LIMIT = float("inf")
    from tether_sim.errors import SolverDivergedError

    for code, ks in keys.items():
        for k in list(ks):
            key, _, dur = k.partition("@")
            try:
                r = run_cached(key, float(dur) if dur else args.duration, args)
            except SolverDivergedError as exc:  # a run that stops is reported, and left out of the table
                print(f"{k}: stopped: {exc}", flush=True)
                ks.remove(k)
                continue
            runs[k] = r
            table[k] = dict(measures(r, args), cpu=float(r["cpu"]))
            print(f"{k}: " + ", ".join(f"{m} {v:.4g}" for m, v in table[k].items()), flush=True)
    names = [m for m in next(iter(table.values())) if m != "cpu"]
    lines = ["| measure | " + " | ".join(f"{c} ({', '.join(_label(k) for k in ks)})" for c, ks in keys.items() if ks)
             + " | DG vs MoorDyn | hybrid vs MoorDyn | hybrid vs DG |",
             "|---|" + "---|" * (sum(1 for ks in keys.values() if ks) + 3)]
    summary = {}
    for m in names:
        cells, finest = [], {}
        for c, ks in keys.items():
            if not ks:
                continue
            vals = [table[k][m] for k in ks]
            ok = [v for v in vals if np.isfinite(v)]
            finest[c] = ok[-1] if ok else float("nan")
            cells.append(" / ".join(f"{v:.4g}" for v in vals) + f" ({100 * spread(vals):+.1f} %)")
        rel = {}
        for a, b in (("DG", "MoorDyn"), ("hybrid", "MoorDyn"), ("hybrid", "DG")):
            rel[f"{a} vs {b}"] = ((finest[a] - finest[b]) / abs(finest[b]) if a in finest and b in finest and finest[b]
                                  else float("nan"))
        summary[m] = dict(finest=finest, **rel, spread={c: spread([table[k][m] for k in ks]) for c, ks in keys.items() if ks})
        lines.append(f"| {m} | " + " | ".join(cells) + " | " + " | ".join(f"{100 * v:+.1f} %" for v in rel.values()) + " |")
    text = "\n".join(lines)
    print(text)
    Path(args.json).parent.mkdir(parents=True, exist_ok=True)
    Path(args.json).write_text(json.dumps(dict(runs=table, summary=summary, args=vars(args)), indent=1))
    Path(args.table).write_text(text + "\n")
    if args.figure:
        plot(runs, keys, args)
    return table, summary


def plot(runs, keys, args):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fc = args.cutoffs[len(args.cutoffs) // 2]
    fig, ax = plt.subplots(4, 1, figsize=(10, 12))
    cmaps = {"MoorDyn": plt.cm.Greys, "DG": plt.cm.Blues, "hybrid": plt.cm.Oranges}
    for code, ks in keys.items():
        for i, k in enumerate(ks):
            col = cmaps[code](0.35 + 0.65 * (i + 1) / len(ks))
            r = runs[k]
            tc, Fb = bin_means(r["t"], r["F"], args.bin, float(r["t"][-1]))
            lab = f"{code} {_label(k)}"
            ax[0].plot(r["t"], r["F"], color=col, lw=0.7, label=lab)
            ax[1].plot(tc, Fb, color=col, lw=0.8, label=lab)
            ax[2].plot(tc, lowpass(Fb, args.bin, fc), color=col, lw=1.0, label=lab)
            ax[3].plot(tc, lowpass(Fb, args.bin, fc), color=col, lw=1.0, label=lab)
    ax[0].set_ylabel("|F| on vehicle, as sampled (N)")
    ax[0].set_yscale("symlog", linthresh=1000.0)
    ax[0].set_xlim(0.0, args.duration)
    ax[1].set_ylim(0.0, 2000.0)
    ax[1].set_ylabel(f"|F|, {1e3 * args.bin:g} ms bin means (N)")
    ax[2].set_ylabel(f"|F| low-passed at {fc:g} Hz (N)")
    ax[2].set_xlim(*args.jerk_windows[:2])
    ax[3].set_ylabel(f"|F| low-passed at {fc:g} Hz (N)")
    ax[3].set_xlim(*args.jerk_windows[-2:])
    ax[3].set_xlabel("t (s)")
    for a in ax:
        a.grid(alpha=0.3)
    ax[0].legend(fontsize=7, ncol=3)
    title = "Excursion tether force on the vehicle: mesh ladders of MoorDyn, DG and the hybrid"
    if args.prescribed_cage:
        title += f"\n(the excursion tether alone, its cage end on {args.prescribed_cage}'s path"
        title += ", damping 0)" if args.excursion_damping == 0 else ")"
    ax[0].set_title(title)
    fig.tight_layout()
    Path(args.figure).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.figure, dpi=100)
    print(f"wrote {args.figure}")


if __name__ == "__main__":
    main()
