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

Compared: the tension at the upper end (MoorDyn: the tension of its end node B, GetLineNodeTen; ours:
the ship-end force), amplitude and phase of its first harmonic at the wave frequency over the last 3 periods of the
run (least squares fit of T0 + a cos wt + b sin wt), and the time series.

Usage: PYTHONPATH=. python benchmarks/moordyn_waves.py [--duration 42] [--segments 40]
       [--solvers dg hybrid] [--figure docs/figures/moordyn_waves.png]
The cheap version is test/solvers/test_waves_vs_moordyn.py.
"""

import argparse
import math
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

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


def run_ours(solver, duration, step=0.02):
    """Upper-end tension |F_ship| (N) at every ``step`` s."""
    _, s = harness.make_solver(flat(solver))
    res = harness.run_sampled(s, np.arange(step, duration + 1e-9, step), keep=())
    return res["t"], res["ship_tension"]


def moordyn_input(n_segments, dt):
    return f"""--------------------- MoorDyn Input File ------------------------------------
tether_sim benchmarks/moordyn_waves.py: submerged line in a regular wave, external wave kinematics
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
---------------------- OPTIONS --------------------------------------------------------
0 writeLog
{dt:.10g} dtM
RK2 tScheme
{G} g
{RHO} rho
200 WtrDpth
1 WaveKin
0 Currents
1 disableOutput
1 disableOutTime
1.0 dtIC
200 TmaxIC
1e-5 threshIC
------------------------- need this line ----------------------------------------------
"""


def _quiet(fn, *args):
    """Call fn with the C-level stdout sent to /dev/null (MoorDyn's console banner)."""
    sys.stdout.flush()
    saved = os.dup(1)
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, 1)
        return fn(*args)
    finally:
        sys.stdout.flush()
        os.dup2(saved, 1)
        os.close(saved)
        os.close(devnull)


def run_moordyn(duration, n_segments=40, coupling_step=0.01, dt=None, workdir=None):
    """Upper-end tension (N) at every coupling step, MoorDyn v2 with our wave kinematics at its nodes."""
    import moordyn

    seg = L / n_segments
    # RK2 step: below the axial limit seg / c (c = sqrt(EA / gamma0) = 354 m/s) and the damping limit
    # gamma0 seg^2 / (2 zeta), with margin
    limit = min(seg / math.sqrt(EA / GAMMA0), GAMMA0 * seg * seg / (2.0 * ZETA))
    dt = dt if dt is not None else coupling_step / math.ceil(coupling_step / (0.5 * limit))
    workdir = Path(workdir or tempfile.mkdtemp(prefix="md_waves_"))
    path = workdir / f"waves_N{n_segments}.txt"
    path.write_text(moordyn_input(n_segments, dt))
    system = _quiet(moordyn.Create, str(path))
    comps = waves.wave_components(harness.make_config(flat()))
    try:
        if _quiet(moordyn.Init, system, [], []) != 0:
            raise RuntimeError("MoorDyn Init failed")
        moordyn.ExternalWaveKinInit(system)
        line = moordyn.GetLine(system, 1)
        n_top = moordyn.GetLineN(line)  # end B, the upper point
        n = int(round(duration / coupling_step))
        times, tension = np.empty(n), np.empty(n)
        u, a = np.zeros(3), np.zeros(3)
        t = 0.0
        for k in range(n):
            pts = np.asarray(moordyn.ExternalWaveKinGetCoordinates(system), float).reshape(-1, 3)
            tm = t + 0.5 * coupling_step
            U, A = np.empty_like(pts), np.empty_like(pts)
            for i, p in enumerate(pts):
                waves.wave_kinematics(p[0], p[1], p[2], tm, *comps.arrays(), comps.depth, comps.stretch, u, a)
                U[i], A[i] = u, a
            moordyn.ExternalWaveKinSet(system, U.tolist(), A.tolist(), tm)
            moordyn.Step(system, [], [], t, coupling_step)
            t = (k + 1) * coupling_step
            times[k] = t
            tension[k] = float(np.linalg.norm(moordyn.GetLineNodeTen(line, n_top)))
    finally:
        moordyn.Close(system)
    return times, tension, dt


def first_harmonic(t, y, periods=3):
    """(mean, amplitude, phase in deg) of y ~ m + A cos(w t - phase) over the last ``periods`` periods."""
    w = 2.0 * math.pi / PERIOD
    sel = t >= t[-1] - periods * PERIOD + 1e-9
    X = np.column_stack([np.ones(sel.sum()), np.cos(w * t[sel]), np.sin(w * t[sel])])
    m, a, b = np.linalg.lstsq(X, y[sel], rcond=None)[0]
    return m, math.hypot(a, b), math.degrees(math.atan2(b, a))


def compare(ours, md):
    """Relative amplitude difference and phase difference (deg) of the first harmonics."""
    m0, a0, p0 = first_harmonic(*ours)
    m1, a1, p1 = first_harmonic(*md)
    dphi = (p0 - p1 + 180.0) % 360.0 - 180.0
    return {"mean": m0, "mean_md": m1, "amp": a0, "amp_md": a1, "amp_rel": a0 / a1 - 1.0, "phase_deg": dphi}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=42.0)
    ap.add_argument("--segments", type=int, default=40)
    ap.add_argument("--solvers", nargs="+", default=["dg", "hybrid"])
    ap.add_argument("--figure", default="docs/figures/moordyn_waves.png")
    args = ap.parse_args(argv)
    w0 = time.time()
    md = run_moordyn(args.duration, args.segments)
    print(f"MoorDyn N = {args.segments}, dtM = {md[2]:.3g} s: {time.time() - w0:.1f} s wall")
    runs = {}
    for solver in args.solvers:
        w0 = time.time()
        runs[solver] = run_ours(solver, args.duration)
        c = compare(runs[solver], md[:2])
        print(f"{solver}: {time.time() - w0:.1f} s wall; upper-end tension mean {c['mean']:.1f} N (MoorDyn "
              f"{c['mean_md']:.1f}), first harmonic {c['amp']:.2f} N vs {c['amp_md']:.2f} N "
              f"({100 * c['amp_rel']:+.2f} %), phase {c['phase_deg']:+.2f} deg")
    if args.figure:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(9, 4))
        ax.plot(md[0], md[1] / 1e3, "k-", lw=1.2, label=f"MoorDyn, {args.segments} segments")
        for (solver, (t, T)), style in zip(runs.items(), ("C0--", "C3:")):
            ax.plot(t, T / 1e3, style, lw=1.4, label=f"tether_sim {solver}")
        ax.set_xlabel("t (s)")
        ax.set_ylabel("upper-end tension (kN)")
        ax.set_title(f"Submerged line in a regular wave H = {H} m, T = {PERIOD} s (same kinematics, same load terms)")
        ax.legend(loc="lower right")
        ax.grid(alpha=0.3)
        fig.tight_layout()
        Path(args.figure).parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(args.figure, dpi=110)
        print(f"wrote {args.figure}")


if __name__ == "__main__":
    main()
