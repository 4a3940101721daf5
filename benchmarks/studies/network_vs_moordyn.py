"""A two-line network against MoorDyn: ship, ROPOS tether (200 m), cage, 30 m excursion tether, vehicle.

The ship's fairlead follows the ROPOS orbit (``ropos_case.fairlead_motion``: a = 2 m, 0.2 Hz, which
slackens the 200 m tether and snaps it); the cage (PE2020 Table 3) hangs on the tether's end at
2.1 m above its centre of gravity; a 30 m excursion tether runs from 2.1 m below it to a vehicle
held still 20 m off and 15 m below (a prescribed point, as in the node). Compared:

- tether_sim's network (docs/network.md) with the tether on the DG solver (dg.resolution auto,
  1 % first-snap tolerance) and the excursion tether on the DG or the hybrid solver;
- MoorDyn v2 (C core, lumped mass): the cage a free body, the fairlead and the vehicle coupled
  points, the tether 80 segments, the excursion tether 30, RK2 at the stable step, coupling
  ``--md-coupling`` s; line coefficients mapped as in ``ropos_case.moordyn_line_type``.

Reported: the first snap peak (``ropos_case.snap_metrics``, 5-10 s) of the tether tension at
the ship and at the cage, the excursion tether's force on the vehicle (largest |F| in 5-10 s and
the r.m.s. difference of |F| over the run against MoorDyn, relative to MoorDyn's largest), the
cage heave. Writes a JSON and a figure.

Usage: PYTHONPATH=. python benchmarks/studies/network_vs_moordyn.py [--duration 12] [--tick 0.005]
       [--coupling 0.005] [--solvers dg hybrid] [--tether-mesh N P | --tether-tolerance 0.005]
       [--excursion-EI 78.125] [--excursion-dg 10 4] [--excursion-hybrid 30 0.002] [--excursion-hybrid-zoning all_rod]
       [--json out/network_vs_moordyn.json] [--figure docs/figures/network_vs_moordyn.png]
"""

import argparse
import json
import math
import os
import sys
import tempfile
import time
from dataclasses import asdict, replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from benchmarks import ropos_case as rc  # noqa: E402
from benchmarks.bench_moordyn import c_stdout_silenced  # noqa: E402
from tether_sim.physics.cable import CableProperties  # noqa: E402

LENGTH = 200.0
ATTACH = rc.CAGE_ATTACH_HEIGHT
# the excursion tether of this check (a slightly heavy 30 m line, so that its static shape exists)
EXCURSION = CableProperties(length=30.0, EA=2.0e6, gamma0=1.0, density=1100.0, diameter=0.025, damping=2000.0,
                            material="bilinear", Cdn=1.2, Cdt=0.02, Cmn=1.0, Cmt=0.0)
VEHICLE_OFFSET = np.array([20.0, 0.0, -15.0])  # from the cage's lower attachment at rest
MD_SEGMENTS = [80, 30]
HYBRID_OPTIONS = {}  # further hybrid.* keys of a hybrid excursion tether (``--excursion-hybrid-zoning``)
MD_SCHEME = ["RK2"]  # MoorDyn's time scheme (RK4 for an undamped line: RK2 grows on the imaginary axis)


def set_excursion_damping(zeta):
    """The excursion tether's axial damping (N s) in both codes (``--excursion-damping``)."""
    global EXCURSION
    EXCURSION = replace(EXCURSION, damping=float(zeta))


def set_excursion_bending(EI, bending_damping=0.0):
    """The excursion tether's bending stiffness EI (N m^2) in both codes (``--excursion-EI``): tether_sim's
    cable.EI (DG: nested LDG bending; hybrid: rod zones) and MoorDyn's line-type EI column. MoorDyn v2 has no
    bending damping, so ``bending_damping`` (tether_sim's cable.bending_damping) stays 0 for a like-for-like check."""
    global EXCURSION
    EXCURSION = replace(EXCURSION, EI=float(EI), bending_damping=float(bending_damping))


def cage_bottom_at_rest():
    p0, _ = rc.fairlead_motion(0.0)
    return np.array([p0[0], p0[1], p0[2] - LENGTH - rc.static_elongation(LENGTH) - 2.0 * ATTACH])


def vehicle_position():
    return cage_bottom_at_rest() + VEHICLE_OFFSET


def network_tree(exc_solver="dg", coupling=0.005, exc_dg=(10, 4), exc_hybrid=(30, 0.005), tether_mesh=None,
                 tether_tolerance=0.01):
    p0, _ = rc.fairlead_motion(0.0)
    cage = rc.cage_properties(p0[2] - LENGTH)
    body = {k: (list(v) if isinstance(v, tuple) else v) for k, v in asdict(cage).items() if k != "attachment"}
    exc = {"from": "cage", "to": "vehicle", "from_attachment": [0.0, 0.0, -ATTACH], "solver": exc_solver,
           "cable": asdict(EXCURSION)}
    if exc_solver == "dg":
        exc["dg"] = dict(n_elements=exc_dg[0], order=exc_dg[1])
    else:
        exc["hybrid"] = dict(n_segments=exc_hybrid[0], time_step=exc_hybrid[1], **HYBRID_OPTIONS)
    return dict(
        environment=dict(g=rc.G, fluid_density=rc.RHO_F, seabed=False), coupling_step=coupling,
        points=dict(ship=dict(kind="prescribed", position=[float(x) for x in p0]),
                    vehicle=dict(kind="prescribed", position=vehicle_position().tolist())),
        bodies=dict(cage=body),
        lines={"tether": {"from": "ship", "to": "cage", "to_attachment": [0.0, 0.0, ATTACH],
                          "cable": asdict(rc.cable_properties(LENGTH)),
                          "dg": (dict(resolution="auto", snap_tolerance=tether_tolerance) if tether_mesh is None else
                                 dict(n_elements=tether_mesh[0], order=tether_mesh[1]))},
               "excursion": exc})


def run_network(exc_solver, duration, tick, coupling, **mesh):
    from tether_sim.network.solver import NetworkSolver
    from tether_sim.network.spec import parse_network

    w0 = time.perf_counter()
    net = NetworkSolver(parse_network(network_tree(exc_solver, coupling, **mesh)))
    build = time.perf_counter() - w0
    veh = vehicle_position()
    n = int(round(duration / tick))
    rec = {"t": [], "ship": [], "cage": [], "veh_t": [], "veh": [], "tick_t": [], "veh_force": [], "heave": []}
    c0, w0 = time.process_time(), time.perf_counter()
    for k in range(1, n + 1):
        t = k * tick
        p, v = rc.fairlead_motion(t)
        net.set_point_motion("ship", p, v)
        net.set_point_motion("vehicle", veh, np.zeros(3))
        out = net.tick(t)
        s = out["tether"]["samples"]
        rec["t"].append(s[0])
        rec["ship"].append(s[1])
        rec["cage"].append(s[2])
        e = out["excursion"]["samples"]
        rec["veh_t"].append(e[0])
        rec["veh"].append(e[2])
        rec["tick_t"].append(t)
        rec["veh_force"].append(net.end_load("excursion", "vehicle")[0])
        rec["heave"].append(net.bodies["cage"].state[2])
    cpu, wall = time.process_time() - c0, time.perf_counter() - w0
    out = {k: np.concatenate(v) if k in ("t", "ship", "cage", "veh_t", "veh") else np.array(v) for k, v in rec.items()}
    dg = net.line("tether").config.dg
    out.update(cpu=cpu, wall=wall, build=build, mesh=f"N={dg.n_elements} P={dg.order} cfl={dg.cfl}",
               coupling_steps=net.coupling_steps, coupling_limit=net.coupling_limit)
    return out


def moordyn_input(dt):
    lt, le = rc.moordyn_line_type(), rc.moordyn_line_type(EXCURSION)
    p0, _ = rc.fairlead_motion(0.0)
    cg_z = cage_bottom_at_rest()[2] + ATTACH
    veh = vehicle_position()
    volume = rc.CAGE_MASS / rc.CAGE_DENSITY
    ca = rc.CAGE_ADDED_MASS / (rc.RHO_F * volume)
    cda_h, cda_v = rc.CAGE_CD_SURGE * rc.CAGE_SIDE_AREA, rc.CAGE_CD_HEAVE * rc.CAGE_LID_AREA

    def row(name, d, EI=0.0):
        return (f"{name} {d['diam']:.8g} {d['mass']:.8g} {d['EA']:.8g} {d['BA']:.8g} {EI:.8g} {d['Cd']:.8g} {d['Ca']:.8g} "
                f"{d['CdAx']:.8g} {d['CaAx']:.8g}")

    return f"""--------------------- MoorDyn Input File ------------------------------------
ROPOS tether, cage and excursion tether (tether_sim benchmarks/studies/network_vs_moordyn.py)
---------------------- LINE TYPES -----------------------------------------------------
TypeName  Diam  Mass/m  EA  BA/-zeta  EI  Cd  Ca  CdAx  CaAx
(name) (m) (kg/m) (N) (N-s/-) (N-m^2) (-) (-) (-) (-)
{row('tether', lt)}
{row('excursion', le, EXCURSION.EI)}
---------------------- BODIES ---------------------------------------------------------
ID Attachment X0 Y0 Z0 r0 p0 y0 Mass CG* I* Volume CdA* Ca*
(#) (word) (m) (m) (m) (deg) (deg) (deg) (kg) (m) (kg-m^2) (m^3) (m^2) (-)
1 Free {p0[0]:.8g} {p0[1]:.8g} {cg_z:.8g} 0 0 0 {rc.CAGE_MASS:.8g} 0 {rc.CAGE_INERTIA:.8g} {volume:.8g} {cda_h:.8g}|{cda_h:.8g}|{cda_v:.8g}|0|0|0 {ca:.8g}
---------------------- POINTS ---------------------------------------------------------
ID Attachment X Y Z Mass Volume CdA Ca
(#) (word/ID) (m) (m) (m) (kg) (m^3) (m^2) (-)
1 Body1 0 0 {ATTACH:.8g} 0 0 0 0
2 Coupled {p0[0]:.8g} {p0[1]:.8g} {p0[2]:.8g} 0 0 0 0
3 Body1 0 0 {-ATTACH:.8g} 0 0 0 0
4 Coupled {veh[0]:.8g} {veh[1]:.8g} {veh[2]:.8g} 0 0 0 0
---------------------- LINES ----------------------------------------------------------
ID LineType AttachA AttachB UnstrLen NumSegs LineOutputs
(#) (name) (ID) (ID) (m) (-) (-)
1 tether 1 2 {LENGTH:.8g} {MD_SEGMENTS[0]} -
2 excursion 3 4 {EXCURSION.length:.8g} {MD_SEGMENTS[1]} -
{rc.moordyn_options(dt, MD_SCHEME[0], LENGTH + 500.0, tmax_ic=200, thresh_ic="1e-5")}------------------------- need this line ----------------------------------------------
"""


def run_moordyn(duration, coupling):
    import moordyn

    dt_stable = min(rc.moordyn_stable_dt(LENGTH, MD_SEGMENTS[0], scheme=MD_SCHEME[0]),
                    rc.moordyn_stable_dt(EXCURSION.length, MD_SEGMENTS[1], EA=EXCURSION.EA, zeta=EXCURSION.damping,
                                         gamma0=EXCURSION.gamma0, scheme=MD_SCHEME[0]))
    dt = coupling / math.ceil(coupling / dt_stable - 1e-9)
    path = Path(tempfile.mkdtemp(prefix="md_net_")) / "network.txt"
    path.write_text(moordyn_input(dt))
    veh = vehicle_position()
    with c_stdout_silenced():  # MoorDyn's console banner and log
        system = moordyn.Create(str(path))
        p0, v0 = rc.fairlead_motion(0.0)
        err = moordyn.Init(system, list(p0) + list(veh), list(v0) + [0.0, 0.0, 0.0])
    if err != 0:
        raise RuntimeError(f"MoorDyn Init failed with code {err}")
    line = moordyn.GetLine(system, 1)
    body = moordyn.GetBody(system, 1)
    lower = moordyn.GetPoint(system, 3)  # the excursion tether's attachment on the cage
    n = int(round(duration / coupling))
    out = {k: np.empty(n) for k in ("t", "ship", "cage", "veh", "heave")}
    out["veh_force"] = np.empty((n, 3))
    out["cage_attachment"] = np.empty((n, 3))
    t, p_now = 0.0, rc.fairlead_motion(0.0)[0]
    c0 = time.process_time()
    try:
        for k in range(n):
            t_next = (k + 1) * coupling
            p_next, _ = rc.fairlead_motion(t_next)
            vel = (p_next - p_now) / coupling
            f = moordyn.Step(system, list(p_now) + list(veh), list(vel) + [0.0, 0.0, 0.0], t, coupling)
            t, p_now = t_next, p_next
            out["t"][k] = t
            out["ship"][k] = math.sqrt(f[0] ** 2 + f[1] ** 2 + f[2] ** 2)
            out["veh"][k] = math.sqrt(f[3] ** 2 + f[4] ** 2 + f[5] ** 2)
            out["veh_force"][k] = f[3:6]
            out["cage"][k] = float(np.linalg.norm(moordyn.GetLineNodeTen(line, 0)))
            out["heave"][k] = moordyn.GetBodyPos(body)[2]
            out["cage_attachment"][k] = moordyn.GetPointPos(lower)
    finally:
        moordyn.Close(system)
    out.update(cpu=time.process_time() - c0, dt=dt)
    return out


def first_peak(t, x):
    return rc.snap_metrics(t, x)["first_peak"]


def window_max(t, x, lo=rc.FIRST_SNAP_WINDOW[0], hi=rc.FIRST_SNAP_WINDOW[1]):
    m = (t >= lo) & (t <= hi)
    return float(np.max(x[m]))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=12.0)
    ap.add_argument("--tick", type=float, default=0.005, help="network tick (s)")
    ap.add_argument("--coupling", type=float, default=0.005, help="network coupling step bound (s)")
    ap.add_argument("--md-coupling", type=float, default=0.002)
    ap.add_argument("--solvers", nargs="+", default=["dg", "hybrid"])
    ap.add_argument("--tether-mesh", type=int, nargs=2, default=None, help="N P of the tether (default: the rule, 1 %%)")
    ap.add_argument("--tether-tolerance", type=float, default=0.01,
                    help="dg.snap_tolerance of the tether's rule mesh (without --tether-mesh)")
    ap.add_argument("--excursion-dg", type=int, nargs=2, default=[10, 4], help="N P of a DG excursion tether")
    ap.add_argument("--excursion-hybrid", type=float, nargs=2, default=[30, 0.005],
                    help="segments and time step of a hybrid excursion tether")
    ap.add_argument("--excursion-EI", type=float, default=0.0,
                    help="the excursion tether's bending stiffness in both codes (N m^2; MoorDyn's EI column)")
    ap.add_argument("--excursion-hybrid-zoning", default=None, choices=["adaptive", "all_rod", "all_catenary"],
                    help="hybrid.zoning of a hybrid excursion tether (with EI: all_rod)")
    ap.add_argument("--md-segments", type=int, nargs=2, default=MD_SEGMENTS, help="MoorDyn segments: tether, excursion")
    ap.add_argument("--json", default="out/network_vs_moordyn.json")
    ap.add_argument("--figure", default="docs/figures/network_vs_moordyn.png")
    args = ap.parse_args(argv)
    print(f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load {os.getloadavg()[0]:.1f}")
    MD_SEGMENTS[:] = args.md_segments
    if args.excursion_EI:
        set_excursion_bending(args.excursion_EI)
    if args.excursion_hybrid_zoning:
        HYBRID_OPTIONS["zoning"] = args.excursion_hybrid_zoning
    md = run_moordyn(args.duration, args.md_coupling)
    ref = {"ship": first_peak(md["t"], md["ship"]), "cage": first_peak(md["t"], md["cage"]),
           "veh": window_max(md["t"], md["veh"])}
    print(f"MoorDyn N={MD_SEGMENTS}, dt={md['dt']:.3g} s: first snap ship {ref['ship'] / 1e3:.2f} kN, "
          f"cage {ref['cage'] / 1e3:.2f} kN, vehicle |F| max {ref['veh']:.2f} N (cpu {md['cpu']:.1f} s)")
    results = {"moordyn": {k: float(v) for k, v in ref.items()}, "network": {}}
    runs = {}
    for solver in args.solvers:
        r = run_network(solver, args.duration, args.tick, args.coupling, tether_mesh=args.tether_mesh,
                        tether_tolerance=args.tether_tolerance, exc_dg=tuple(args.excursion_dg),
                        exc_hybrid=(int(args.excursion_hybrid[0]), args.excursion_hybrid[1]))
        runs[solver] = r
        ours = {"ship": first_peak(r["t"], r["ship"]), "cage": first_peak(r["t"], r["cage"]),
                "veh": window_max(r["veh_t"], r["veh"])}
        veh_md = np.interp(r["veh_t"], md["t"], md["veh"])
        m = r["veh_t"] >= args.md_coupling
        rms = float(np.sqrt(np.mean((r["veh"][m] - veh_md[m]) ** 2)) / ref["veh"])
        err = {k: (ours[k] - ref[k]) / ref[k] for k in ours}
        results["network"][solver] = {"first_peak": ours, "error": err, "vehicle_rms": rms, "mesh": r["mesh"],
                                      "cpu": r["cpu"], "wall": r["wall"], "rtf_cpu": args.duration / r["cpu"],
                                      "coupling_steps": r["coupling_steps"], "coupling_limit": r["coupling_limit"]}
        print(f"network, excursion {solver:6s} (tether {r['mesh']}, tick {args.tick} s, coupling {args.coupling} s): "
              f"ship {ours['ship'] / 1e3:.2f} kN ({100 * err['ship']:+.2f} %), cage {ours['cage'] / 1e3:.2f} kN "
              f"({100 * err['cage']:+.2f} %), vehicle max {ours['veh']:.2f} N ({100 * err['veh']:+.2f} %), "
              f"vehicle r.m.s. diff {100 * rms:.2f} %; cpu {r['cpu']:.1f} s for {args.duration} s "
              f"(x{args.duration / r['cpu']:.2f} real time), coupling bound {r['coupling_limit']:.3g} s", flush=True)
    if "dg" in runs and "hybrid" in runs:
        a, b = runs["dg"], runs["hybrid"]
        d = (window_max(b["veh_t"], b["veh"]) - window_max(a["veh_t"], a["veh"])) / window_max(a["veh_t"], a["veh"])
        results["dg_vs_hybrid_vehicle"] = d
        print(f"hybrid vs DG excursion tether: vehicle |F| max {100 * d:+.2f} %")
    Path(args.json).parent.mkdir(parents=True, exist_ok=True)
    Path(args.json).write_text(json.dumps(results, indent=1))
    if args.figure:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(4, 1, figsize=(9, 10), sharex=True)
        ax[0].plot(md["t"], md["ship"] / 1e3, "k-", lw=1.2, label="MoorDyn")
        ax[1].plot(md["t"], md["cage"] / 1e3, "k-", lw=1.2, label="MoorDyn")
        ax[2].plot(md["t"], md["veh"], "k-", lw=1.2, label="MoorDyn")
        ax[3].plot(md["t"], md["heave"], "k-", lw=1.2, label="MoorDyn")
        for (solver, r), style in zip(runs.items(), ("C0--", "C1:")):
            lab = f"tether_sim, excursion {solver}"
            ax[0].plot(r["t"], r["ship"] / 1e3, style, lw=1, label=lab)
            ax[1].plot(r["t"], r["cage"] / 1e3, style, lw=1, label=lab)
            ax[2].plot(r["veh_t"], r["veh"], style, lw=1, label=lab)
            ax[3].plot(r["tick_t"], r["heave"], style, lw=1, label=lab)
        ax[0].set_ylabel("tether tension\nat the ship (kN)")
        ax[1].set_ylabel("tether tension\nat the cage (kN)")
        ax[2].set_ylabel("excursion tether\nforce on vehicle (N)")
        ax[3].set_ylabel("cage CoG z (m)")
        ax[3].set_xlabel("t (s)")
        for a_ in ax:
            a_.grid(alpha=0.3)
        ax[0].legend(fontsize=8)
        ax[0].set_title("Ship, 200 m ROPOS tether, cage, 30 m excursion tether, vehicle: fairlead orbit 2 m, 0.2 Hz")
        fig.tight_layout()
        Path(args.figure).parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(args.figure, dpi=110)
        print(f"wrote {args.figure}")
    print(f"wrote {args.json}")
    return results


if __name__ == "__main__":
    main()
