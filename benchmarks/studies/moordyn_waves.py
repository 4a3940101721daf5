"""Cross-code check of the wave loads: a submerged mooring-like line in a regular wave, ours vs MoorDyn.

The line: 66 m, d = 0.05 m, gamma0 = 8 kg/m (A = gamma0 / rho_c = pi d^2 / 4, so the buoyancy, the
Froude-Krylov and the added-mass areas are one, as MoorDyn has them), EA = 1e6 N, hanging as a slack
catenary between a fixed anchor point at (0, 0, -50) m and a fixed upper end at (40, 0, -4) m (chord
61 m), fully submerged (the trough of the wave is 1.5 m above the upper end: no surface crossing).
C_dn = 1.2, C_dt = 0.2, C_mn = 1, C_mt = 0.5. Regular deep-water wave H = 3 m, T = 7 s along +x,
switched on at t = 0 on the static shape. No seabed, no current, no bending stiffness.

Both codes take the same kinematics: physics/waves.py (Wheeler; below the surface it is Airy) at our
own quadrature points, and at MoorDyn's nodes through MoorDyn's external-kinematics interface
(WaveKin = 1: ExternalWaveKinSet every coupling step, evaluated at the step's midpoint time). The
same load terms on both sides: MoorDyn v2's line loads are rho V (1 + C_an) a_w,perp + rho V
(1 + C_at) a_w,par - (added mass) + drag 0.5 rho d C_dn |v_perp| v_perp + 0.5 rho pi d C_dt' |v_par| v_par
(so C_dt' = C_dt / pi) + (m - rho V) g: docs/waves.md's load with A = A_h.

Compared: the force on the upper end point, amplitude and phase of its first harmonic at the wave
frequency over the last 3 periods of the run (least squares fit of T0 + a cos wt + b sin wt), and the
time series. MoorDyn's end quantity is |Fnet| of its end node N (GetLineNodeForce, its TenB output
channel): the end segment's tension plus the weight, buoyancy and wave loads of the node's half
segment, i.e. the force on the fixed point. GetLineNodeTen(N) is the end segment's tension, which acts
half a segment below the end: it misses that half segment's ~48 N of wet weight (N = 40) and its wave
loads and converges to the end force only as 1/N (shown here: the ladder, and our tension at
s = L / (2N) against it). MoorDyn is run on a segment ladder, ours on a DG mesh ladder and a hybrid
segment ladder; the reference is MoorDyn's finest. MoorDyn is also run once without the axial
Froude-Krylov part (PE2020 Eq. 13's form), which shows what that term does to the answer.

Usage: PYTHONPATH=. python benchmarks/studies/moordyn_waves.py [--duration 42] [--segments 20 40 80 160]
       [--dg-elements 4 8 16] [--hybrid-segments 20 40 80] [--figure docs/figures/moordyn_waves.png]
The cheap version is test/solvers/test_waves_vs_moordyn.py.
"""

import argparse
import math
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from benchmarks import ropos_case as rc  # noqa: E402
from benchmarks.bench_moordyn import c_stdout_silenced  # noqa: E402
from tether_sim.physics import waves  # noqa: E402
from tether_sim.scenarios import harness  # noqa: E402

L, D, GAMMA0, EA = 66.0, 0.05, 8.0, 1.0e6
RHO, G = 1025.0, 9.81
CDN, CDT, CMN, CMT = 1.2, 0.2, 1.0, 0.5
ANCHOR, TOP = (0.0, 0.0, -50.0), (40.0, 0.0, -4.0)
H, PERIOD = 3.0, 7.0
DENSITY = GAMMA0 / (math.pi * D * D / 4.0)  # rho_c: A = gamma0 / rho_c = pi d^2 / 4
ZETA = 2.0e3  # axial material damping (N s), both codes (MoorDyn BA): damps the axial start transient


def flat(solver="dg", **extra):
    f = {"solver": solver, "dg.n_elements": 8, "dg.order": 4, "dg.damping": "implicit",
         "hybrid.n_segments": 40, "hybrid.time_step": 0.01, "hybrid.zoning": "all_catenary",
         "cable.length": L, "cable.EA": EA, "cable.gamma0": GAMMA0, "cable.density": DENSITY, "cable.diameter": D,
         "cable.Cdn": CDN, "cable.Cdt": CDT, "cable.Cmn": CMN, "cable.Cmt": CMT, "cable.damping": ZETA,
         "ship_end.kind": "fixed", "ship_end.position": list(TOP),
         "vehicle_end.kind": "fixed", "vehicle_end.position": list(ANCHOR), "initial.kind": "static",
         "environment.fluid_density": RHO, "environment.g": G,
         "waves.kind": "regular", "waves.height": H, "waves.period": PERIOD, "waves.direction": 0.0}
    f.update(extra)
    return f


def run_ours(solver, duration, step=0.02, arc_lengths=None, **extra):
    """(t, |F_ship|, T(arc_lengths)): the force on the upper end (N) and the tension at the given
    unstretched arc lengths from the upper end (N, (nt, n); None without arc_lengths), every ``step`` s."""
    _, s = harness.make_solver(flat(solver, **extra))
    keep = ("tension",) if arc_lengths is not None else ()
    res = harness.run_sampled(s, np.arange(step, duration + 1e-9, step), arc_lengths=arc_lengths, keep=keep)
    return res["t"], np.linalg.norm(res["ship_force"], axis=1), res.get("tension")


def moordyn_input(n_segments, dt):
    return f"""--------------------- MoorDyn Input File ------------------------------------
tether_sim benchmarks/studies/moordyn_waves.py: submerged line in a regular wave, external wave kinematics
---------------------- LINE TYPES -----------------------------------------------------
TypeName  Diam  Mass/m  EA  BA/-zeta  EI  Cd  Ca  CdAx  CaAx
(name) (m) (kg/m) (N) (N-s/-) (N-m^2) (-) (-) (-) (-)
line {D:.10g} {GAMMA0:.10g} {EA:.10g} {ZETA:.10g} 0 {CDN:.10g} {CMN:.10g} {CDT / math.pi:.10g} {CMT:.10g}
---------------------- POINTS ---------------------------------------------------------
ID Attachment X Y Z Mass Volume CdA Ca
(#) (word/ID) (m) (m) (m) (kg) (m^3) (m^2) (-)
1 Fixed {ANCHOR[0]:.10g} {ANCHOR[1]:.10g} {ANCHOR[2]:.10g} 0 0 0 0
2 Fixed {TOP[0]:.10g} {TOP[1]:.10g} {TOP[2]:.10g} 0 0 0 0
---------------------- LINES ----------------------------------------------------------
ID LineType AttachA AttachB UnstrLen NumSegs LineOutputs
(#) (name) (ID) (ID) (m) (-) (-)
1 line 1 2 {L:.10g} {int(n_segments)} -
{rc.moordyn_options(dt, "RK2", 200, wave_kin=1, cfl=None, tmax_ic=200, thresh_ic="1e-5", digits=10)}------------------------- need this line ----------------------------------------------
"""


def run_moordyn(duration, n_segments=40, coupling_step=0.01, dt=None, workdir=None, axial_fk=True):
    """MoorDyn v2 with our wave kinematics at its nodes, sampled every coupling step.

    Returns (t, end_force, end_segment_tension, dtM): end_force = |Fnet| of the upper end node N
    (GetLineNodeForce, MoorDyn's TenB output channel: the force the line exerts on the fixed point,
    the end segment's tension plus the weight, buoyancy and wave loads of the node's half segment),
    end_segment_tension = |T + Td| of the last segment (GetLineNodeTen(N)), which acts half a segment
    below the end. axial_fk=False removes the Froude-Krylov part along MoorDyn's node tangent
    (MoorDyn applies rho V (1 + C_at) a_w,par; we pass a_w,par C_at / (1 + C_at)): the PE2020 Eq. 13 form."""
    import moordyn

    seg = L / n_segments
    # RK2 step: below the axial limit seg / c (c = sqrt(EA / gamma0) = 354 m/s) and the damping limit
    # gamma0 seg^2 / (2 zeta), with margin
    limit = min(seg / math.sqrt(EA / GAMMA0), GAMMA0 * seg * seg / (2.0 * ZETA))
    dt = dt if dt is not None else coupling_step / math.ceil(coupling_step / (0.5 * limit))
    workdir = Path(workdir or tempfile.mkdtemp(prefix="md_waves_"))
    path = workdir / f"waves_N{n_segments}.txt"
    path.write_text(moordyn_input(n_segments, dt))
    with c_stdout_silenced():  # MoorDyn prints its console banner to the C-level stdout
        system = moordyn.Create(str(path))
    comps = waves.wave_components(harness.make_config(flat()))
    try:
        with c_stdout_silenced():
            err = moordyn.Init(system, [], [])
        if err != 0:
            raise RuntimeError("MoorDyn Init failed")
        moordyn.ExternalWaveKinInit(system)
        line = moordyn.GetLine(system, 1)
        n_top = moordyn.GetLineN(line)  # end B, the upper point
        n = int(round(duration / coupling_step))
        times, force, tension = np.empty(n), np.empty(n), np.empty(n)
        u, a = np.zeros(3), np.zeros(3)
        t = 0.0
        for k in range(n):
            pts = np.asarray(moordyn.ExternalWaveKinGetCoordinates(system), float).reshape(-1, 3)
            tm = t + 0.5 * coupling_step
            U, A = np.empty_like(pts), np.empty_like(pts)
            for i, p in enumerate(pts):
                waves.wave_kinematics(p[0], p[1], p[2], tm, *comps.arrays(), comps.depth, comps.stretch, u, a)
                U[i], A[i] = u, a
            if not axial_fk:  # the first n_top + 1 points are the line's nodes; MoorDyn's node tangents
                r = pts[: n_top + 1]
                q = np.empty_like(r)
                q[1:-1] = r[2:] - r[:-2]
                q[0], q[-1] = r[1] - r[0], r[-1] - r[-2]
                q /= np.linalg.norm(q, axis=1)[:, None]
                A[: n_top + 1] -= (np.sum(A[: n_top + 1] * q, axis=1) / (1.0 + CMT))[:, None] * q
            moordyn.ExternalWaveKinSet(system, U.tolist(), A.tolist(), tm)
            moordyn.Step(system, [], [], t, coupling_step)
            t = (k + 1) * coupling_step
            times[k] = t
            force[k] = float(np.linalg.norm(moordyn.GetLineNodeForce(line, n_top)))
            tension[k] = float(np.linalg.norm(moordyn.GetLineNodeTen(line, n_top)))
    finally:
        moordyn.Close(system)
    return times, force, tension, dt


def first_harmonic(t, y, periods=3):
    """(mean, amplitude, phase in deg) of y ~ m + A cos(w t - phase) over the last ``periods`` periods."""
    w = 2.0 * math.pi / PERIOD
    sel = t >= t[-1] - periods * PERIOD + 1e-9
    X = np.column_stack([np.ones(sel.sum()), np.cos(w * t[sel]), np.sin(w * t[sel])])
    m, a, b = np.linalg.lstsq(X, y[sel], rcond=None)[0]
    return m, math.hypot(a, b), math.degrees(math.atan2(b, a))


def compare(ours, md, periods=3):
    """Relative amplitude difference and phase difference (deg) of the first harmonics of two (t, y)."""
    m0, a0, p0 = first_harmonic(*ours, periods=periods)
    m1, a1, p1 = first_harmonic(*md, periods=periods)
    dphi = (p0 - p1 + 180.0) % 360.0 - 180.0
    return {"mean": m0, "mean_md": m1, "amp": a0, "amp_md": a1, "amp_rel": a0 / a1 - 1.0, "phase_deg": dphi}


def _row(label, c):
    return (f"| {label} | {c['mean']:.2f} | {c['amp']:.3f} | {100 * c['amp_rel']:+.2f} % | {c['phase_deg']:+.2f} |")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=42.0)
    ap.add_argument("--segments", type=int, nargs="+", default=[20, 40, 80, 160], help="MoorDyn ladder")
    ap.add_argument("--dg-elements", type=int, nargs="+", default=[4, 8, 16], help="DG ladder (P = 4)")
    ap.add_argument("--hybrid-segments", type=int, nargs="+", default=[20, 40, 80])
    ap.add_argument("--figure", default="docs/figures/moordyn_waves.png")
    args = ap.parse_args(argv)
    md, ours = {}, {}
    for n in args.segments:
        w0 = time.time()
        t, force, ten, dt = run_moordyn(args.duration, n)
        md[n] = (t, force, ten)
        print(f"MoorDyn N = {n}, dtM = {dt:.3g} s: {time.time() - w0:.1f} s wall")
    t, force, _, _ = run_moordyn(args.duration, args.segments[0], axial_fk=False)
    md_no_fk = (t, force)
    for solver, key, sizes in (("dg", "dg.n_elements", args.dg_elements),
                               ("hybrid", "hybrid.n_segments", args.hybrid_segments)):
        for n in sizes:
            w0 = time.time()
            # the finest DG mesh also gives the tension half a MoorDyn segment below the end
            arcs = [L / (2 * m) for m in args.segments] if (solver == "dg" and n == sizes[-1]) else None
            ours[(solver, n)] = run_ours(solver, args.duration, arc_lengths=arcs, **{key: n})
            print(f"{solver} {n}: {time.time() - w0:.1f} s wall")
    ref = md[args.segments[-1]][:2]
    print(f"\nUpper-end force, first harmonic over the last 3 periods; reference MoorDyn N = {args.segments[-1]} "
          f"end-node force")
    print("| run | mean (N) | amplitude (N) | amplitude vs ref | phase vs ref (deg) |\n|---|---|---|---|---|")
    for n in args.segments:
        print(_row(f"MoorDyn N = {n}, end-node force (TenB)", compare(md[n][:2], ref)))
    for n in args.segments:
        print(_row(f"MoorDyn N = {n}, end-segment tension (GetLineNodeTen)", compare((md[n][0], md[n][2]), ref)))
    print(_row(f"MoorDyn N = {args.segments[0]}, end-node force, no axial Froude-Krylov", compare(md_no_fk, ref)))
    for (solver, n), (t, force, _) in ours.items():
        print(_row(f"tether_sim {solver} {n}" + (" elements, P = 4" if solver == "dg" else " segments"),
                   compare((t, force), ref)))
    fine = ("dg", args.dg_elements[-1])
    t, _, T = ours[fine]
    print(f"\nLike with like: tether_sim dg {fine[1]} tension at s = L / (2 N) below the end vs MoorDyn's "
          "end-segment tension at N")
    print("| N | ours mean (N) | MoorDyn mean (N) | ours amp (N) | MoorDyn amp (N) | amp diff | phase diff (deg) |")
    print("|---|---|---|---|---|---|---|")
    for j, n in enumerate(args.segments):
        c = compare((t, T[:, j]), (md[n][0], md[n][2]))
        print(f"| {n} | {c['mean']:.2f} | {c['mean_md']:.2f} | {c['amp']:.3f} | {c['amp_md']:.3f} | "
              f"{100 * c['amp_rel']:+.2f} % | {c['phase_deg']:+.2f} |")
    if args.figure:
        _figure(args, md, ours, ref)


def _figure(args, md, ours, ref):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 4.4), gridspec_kw={"width_ratios": [1.7, 1]})
    nf, nc = args.segments[-1], args.segments[0]
    ax.plot(md[nf][0], md[nf][1], "k-", lw=1.3, label=f"MoorDyn {nf} segments, end-node force")
    ax.plot(md[nc][0], md[nc][2], "-", color="0.6", lw=1.0,
            label=f"MoorDyn {nc} segments, end-segment tension")
    styles = {"dg": "C0--", "hybrid": "C3:"}
    for solver, sizes in (("dg", args.dg_elements), ("hybrid", args.hybrid_segments)):
        n = sizes[len(sizes) // 2]
        t, force, _ = ours[(solver, n)]
        ax.plot(t, force, styles[solver], lw=1.5,
                label=f"tether_sim {solver} " + (f"N = {n}, P = 4" if solver == "dg" else f"{n} segments"))
    ax.set_xlabel("t (s)")
    ax.set_ylabel("force on the upper end (N)")
    ax.set_title(f"66 m submerged line, regular wave H = {H} m, T = {PERIOD} s", fontsize=10)
    ax.legend(loc="lower right", fontsize=8)
    ax.grid(alpha=0.3)
    _, a_ref, _ = first_harmonic(*ref)
    pts = {"MoorDyn end-node force": [(n, first_harmonic(*md[n][:2])[1]) for n in args.segments],
           "MoorDyn end-segment tension": [(n, first_harmonic(md[n][0], md[n][2])[1]) for n in args.segments],
           "tether_sim dg (N P points)": [(4 * n, first_harmonic(*ours[("dg", n)][:2])[1]) for n in args.dg_elements],
           "tether_sim hybrid (segments)": [(n, first_harmonic(*ours[("hybrid", n)][:2])[1])
                                            for n in args.hybrid_segments]}
    for (label, xy), style in zip(pts.items(), ("ko-", "o-", "C0s--", "C3^:")):
        x, y = np.array(xy).T
        kw = {"color": "0.6"} if style == "o-" else {}
        bx.plot(x, 100 * (y / a_ref - 1.0), style, label=label, **kw)
    bx.axhspan(-3, 3, color="C2", alpha=0.12, label="3 % target")
    bx.set_xscale("log")
    ticks = sorted({x for xy in pts.values() for x, _ in xy})
    bx.set_xticks(ticks, [str(int(x)) for x in ticks])
    bx.minorticks_off()
    bx.set_xlabel("points along the line")
    bx.set_ylabel(f"first-harmonic amplitude vs MoorDyn {nf} (%)")
    bx.set_title(f"first harmonic, last 3 periods (MoorDyn {nf}: {a_ref:.2f} N)", fontsize=10)
    bx.legend(fontsize=8)
    bx.grid(alpha=0.3, which="both")
    fig.tight_layout()
    Path(args.figure).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.figure, dpi=110)
    print(f"wrote {args.figure}")


if __name__ == "__main__":
    main()
