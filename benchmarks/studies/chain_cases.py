"""The chain cases of MoorDyn's validation against OrcaFlex: a studless chain at 50, 200 and 600 m
depth under two heave motions of its fairlead, with seabed friction.

Data (test/data/moordyn/, BSD-3, SOURCE.md): the decks decks/WD0050_Chain.txt, WD0200_Chain.txt,
WD0600_Chain.txt (chain d = 0.252 m, 390 kg/m, EA 1.674 GN, Cd 1.37, Ca 1, CdAx 0.64; L = 410, 760,
1700 m; anchor 400, 700, 1500 m from the fairlead; seabed kBot 1e5 Pa/m, cBot 1e4 Pa s/m, friction
coefficient 0.5), the fairlead motions chain/ZZP1_A1.txt, ZZP1_A2.txt (heave 2 m and 5 m, period
10 s, from t = -10 s) and OrcaFlex's fairlead and anchor tensions chain/WD*_Chain_ZZP1_A*.txt
(0-20 s every 0.1 s). Static tensions of the quasi-static codes (MoorDyn's tests/quasi_static_chain.cpp):
STATIC_FAIR, STATIC_ANCHOR below.

Our run: the deck through tether_sim.network.moordyn (one line, s = 0 at the fairlead), started in
its static state (the elastic catenary on the frictionless seabed), the fairlead driven through the
motion file from t = -10 s (positions at the file's 0.1 s samples, velocities by central
differences, Hermite in between: NetworkSolver.set_point_motion), the force of the line on the
fairlead and on the anchor taken at every 0.1 s tick.

OrcaFlex's samples lag the motion file by TAU = 0.029 s (its fairlead z column against the file's z:
-0.036 m at t = 0 for the 2 m heave, -0.09 m for the 5 m heave, 2 pi TAU / 10 s = 0.018 rad in both);
our tension is read at t - TAU (linear between our 0.1 s ticks).

Metrics against the reference at every sample 0 <= t <= 20 s:
- ``pointwise``: max |T - T_ref| / T_ref(t) (the total fairlead tension, sample by sample);
- ``moordyn``: MoorDyn's own metric, max |dT - dT_ref| / (2 max |dT_ref|) with dT = T - T_static
  (the dynamic part against twice its amplitude; MoorDyn passes at 15 %);
- static: our static fairlead and anchor tension against STATIC_FAIR / STATIC_ANCHOR.

DG settings (docs/verification.md "Chain with seabed friction against OrcaFlex"): the deck's mesh
(P = 4, N = ceil(NumSegs / 4): 11, 19, 43 elements, about 9 m between nodes), explicit material
damping (the deck's BA = -1 with 10 m segments: 8.1 MN s in all three), dg.q_penalty_jump tension. The automatic choice
takes the same at 50 m (static EA / T_min 1990, above dg.q_penalty_auto_ratio 1500; with the
strain penalty of PE2020 Eq. 24, as auto chose before 2026-11-27 at its old threshold 2000, the troughs
of the 5 m heave (EA / T ~ 4500) ring: ~0.4 s period, +-80 kN, 27.1 % at the worst sample) and Eq. 24
at 200 and 600 m (ratios ~1.2e3 and ~5e2; at 200 m, 5 m heave: 14.78 % against 14.95 %).

``--moordyn`` runs pip moordyn on the same deck and motion instead (its fairlead force GetPointForce,
stepped every 0.1 s with the velocity of the next interval, as MoorDyn's test does), for the same
metrics: a second code on the reference.

Usage: PYTHONPATH=. python benchmarks/studies/chain_cases.py [--solver hybrid|dg] [--moordyn] [--segments N] [--order P]
       [--elements N] [--cases WD0050:A1 ...] [--friction-speed V] [--plot DIR]
"""

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from tether_sim.network.moordyn import network_spec, read_deck, static_point_forces  # noqa: E402

DATA = Path(__file__).resolve().parents[2] / "test" / "data" / "moordyn"
DEPTHS = ("WD0050", "WD0200", "WD0600")
MOTIONS = ("A1", "A2")
STATIC_FAIR = {"WD0050": 991.6e3, "WD0200": 2065.4e3, "WD0600": 5232.6e3}  # N
STATIC_ANCHOR = {"WD0050": 826.2e3, "WD0200": 1402.2e3, "WD0600": 3244.2e3}
TAU = 0.029  # s, the reference's lag behind the motion file (module doc)


def motion(name):
    """(t, xyz (n, 3)) of a fairlead motion file."""
    m = np.loadtxt(DATA / "chain" / f"ZZP1_{name}.txt")
    return m[:, 0], m[:, 1:4]


def reference(depth, name):
    """(t, fairlead tension (N), anchor tension (N), fairlead z (m)) of OrcaFlex's run."""
    r = np.loadtxt(DATA / "chain" / f"{depth}_Chain_ZZP1_{name}.txt")
    return r[:, 0], 1e3 * r[:, 3], 1e3 * r[:, 4], r[:, 2]


def reference_lag(name, depth="WD0050"):
    """Least-squares lag (s) of the reference's fairlead z behind the motion file's z."""
    tm, xm = motion(name)
    tr, _, _, zr = reference(depth, name)
    lags = np.linspace(-0.1, 0.1, 2001)
    err = [np.sum((np.interp(tr - lag, tm, xm[:, 2]) - zr) ** 2) for lag in lags]
    return float(lags[int(np.argmin(err))])


def case_spec(depth, solver="dg", segments=None, order=4, elements=None, friction_speed=None, extra=None,
              friction=None):
    deck = read_deck(DATA / "decks" / f"{depth}_Chain.txt")
    over = {}
    if solver == "hybrid":
        over["hybrid"] = {"n_segments": segments or deck.lines[0].n_segments}
    else:
        over["dg"] = {"order": order, "n_elements": elements or max(1, math.ceil(deck.lines[0].n_segments / order))}
    for k, v in (extra or {}).items():
        over.setdefault(k, {}).update(v)
    spec = network_spec(deck, solver, overrides=over)
    env_over = {k: v for k, v in (("seabed_friction_speed", friction_speed), ("seabed_friction", friction))
                if v is not None}
    if env_over:
        from dataclasses import replace
        env = replace(spec.environment, **env_over)
        lines = {n: replace(ln, config=replace(ln.config, environment=env)) for n, ln in spec.lines.items()}
        spec = replace(spec, environment=env, lines=lines)
    return spec


def static_tensions(spec):
    """(fairlead, anchor) static force magnitudes (N) of our static state."""
    f = static_point_forces(spec)
    return float(np.linalg.norm(f["point2"])), float(np.linalg.norm(f["point1"]))


def run(spec, name, t_end=20.0):
    """Drive the fairlead through motion ``name`` from its first sample to t_end (+ TAU); returns
    (t (motion-file time), fairlead force |F| (N), anchor force |F| (N)) at every 0.1 s sample, and the
    wall time (s)."""
    from tether_sim.network.solver import NetworkSolver

    tm, xm = motion(name)
    keep = tm <= t_end + 0.1 + 1e-9
    tm, xm = tm[keep], xm[keep]
    vm = np.gradient(xm, tm, axis=0)
    net = NetworkSolver(spec)
    t0 = tm[0]
    out_t, fair, anch = [tm[0]], [], []
    f, _, _ = net.end_load("line1", "ship")
    a, _, _ = net.end_load("line1", "vehicle")
    fair.append(np.linalg.norm(f))
    anch.append(np.linalg.norm(a))
    wall = time.perf_counter()
    for i in range(1, len(tm)):
        net.set_point_motion("point2", xm[i], vm[i])
        net.tick(tm[i] - t0)
        f, _, _ = net.end_load("line1", "ship")
        a, _, _ = net.end_load("line1", "vehicle")
        out_t.append(tm[i])
        fair.append(np.linalg.norm(f))
        anch.append(np.linalg.norm(a))
    return np.array(out_t), np.array(fair), np.array(anch), time.perf_counter() - wall


def with_segments(text, n_segments):
    """The deck text with every line's NumSegs set to ``n_segments`` (MoorDyn picks its step from the
    deck's CFL, so the step follows the mesh)."""
    out, in_lines = [], False
    for line in text.splitlines():
        tok = line.split()
        if line.startswith("---"):
            in_lines = "LINES" in line.upper()
        elif in_lines and len(tok) >= 6 and tok[0].isdigit():
            tok[5] = str(int(n_segments))
            line = "  ".join(tok)
        out.append(line)
    return "\n".join(out) + "\n"


def run_moordyn(depth, name, t_end=20.0, n_segments=None):
    """The same drive through pip moordyn (the deck as MoorDyn's test runs it, its stored initial state
    dropped; ``n_segments`` replaces the deck's NumSegs): (t, fairlead force |F| (N), anchor tension (N))
    every 0.1 s, wall time (s). The anchor value is MoorDyn's GetFASTtens anchor tension (its fixed points
    report no force)."""
    import tempfile

    import moordyn

    from benchmarks.bench_moordyn import c_stdout_silenced
    from benchmarks.studies.moordyn_decks import _without_file_ic

    tm, xm = motion(name)
    keep = tm <= t_end + 0.1 + 1e-9
    tm, xm = tm[keep], xm[keep]
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / f"{depth}_Chain.txt"
        text = _without_file_ic((DATA / "decks" / f"{depth}_Chain.txt").read_text())
        path.write_text(text if n_segments is None else with_segments(text, n_segments))
        with c_stdout_silenced():
            system = moordyn.Create(str(path))
            moordyn.Init(system, list(xm[0]), [0.0, 0.0, 0.0])
            point = moordyn.GetPoint(system, 2)
            fair = [np.linalg.norm(moordyn.GetPointForce(point))]
            anch = [math.hypot(*[v[0] for v in moordyn.GetFASTtens(system, 1)[2:]])]
            wall = time.perf_counter()
            for i in range(len(tm) - 1):
                dt = tm[i + 1] - tm[i]
                v = (xm[i + 1] - xm[i]) / dt
                moordyn.Step(system, list(xm[i]), list(v), tm[i] - tm[0], dt)
                fair.append(np.linalg.norm(moordyn.GetPointForce(point)))
                anch.append(math.hypot(*[v[0] for v in moordyn.GetFASTtens(system, 1)[2:]]))
            wall = time.perf_counter() - wall
            moordyn.Close(system)
    return tm, np.array(fair), np.array(anch), wall


def compare(depth, name, t, fair, anch, t_end=20.0):
    """Metrics against the reference (module doc), over 0 <= t <= t_end."""
    tr, fr, ar, _ = reference(depth, name)
    keep = tr <= t_end + 1e-9
    tr, fr, ar = tr[keep], fr[keep], ar[keep]
    ours = np.interp(tr - TAU, t, fair)
    ours_a = np.interp(tr - TAU, t, anch)
    rel = np.abs(ours - fr) / fr
    dyn = np.abs((ours - fair[0]) - (fr - STATIC_FAIR[depth]))
    k = int(np.argmax(rel))
    return {
        "pointwise": float(rel.max()), "at": float(tr[k]), "mean_abs": float(rel.mean()),
        "moordyn": float(dyn.max() / (2.0 * np.max(np.abs(fr - STATIC_FAIR[depth])))),
        "range_ours": (float(ours.min()), float(ours.max())), "range_ref": (float(fr.min()), float(fr.max())),
        "anchor_pointwise": float((np.abs(ours_a - ar) / ar).max()),
    }


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--solver", default="dg", choices=("dg", "hybrid"),
                    help="default dg (the tables); hybrid: docs/moordyn.md")
    ap.add_argument("--segments", type=int, default=None, help="hybrid (or with --moordyn, MoorDyn's) segments (default: the deck's NumSegs)")
    ap.add_argument("--order", type=int, default=4)
    ap.add_argument("--elements", type=int, default=None, help="DG elements (default ceil(NumSegs / order))")
    ap.add_argument("--time-step", type=float, default=None, help="hybrid.time_step (s)")
    ap.add_argument("--damping", default=None, choices=("explicit", "implicit"), help="dg.damping")
    ap.add_argument("--cfl", type=float, default=None, help="dg.cfl")
    ap.add_argument("--q-penalty-jump", default="tension", choices=("auto", "tension", "strain"),
                    help="dg.q_penalty_jump (default tension as in the tables; auto: module doc)")
    ap.add_argument("--t-end", type=float, default=20.0, help="last compared time (s; the reference ends at 20 s)")
    ap.add_argument("--friction", type=float, default=None, help="environment.seabed_friction (default: the deck's)")
    ap.add_argument("--friction-speed", type=float, default=None, help="environment.seabed_friction_speed (m/s)")
    ap.add_argument("--cases", nargs="*", default=[f"{d}:{m}" for d in DEPTHS for m in MOTIONS])
    ap.add_argument("--plot", default=None, help="directory for a PNG per case")
    ap.add_argument("--moordyn", action="store_true", help="run pip moordyn instead of our solver (same metrics)")
    ap.add_argument("--versus-moordyn", type=int, default=None, metavar="SEGMENTS",
                    help="also run pip moordyn with SEGMENTS segments and print the largest difference of the two "
                         "codes' fairlead tensions, sample by sample over 0 <= t <= t_end")
    args = ap.parse_args(argv)
    extra = {}
    if args.time_step:
        extra["hybrid"] = {"time_step": args.time_step}
    dg = {k: v for k, v in (("damping", args.damping), ("cfl", args.cfl), ("q_penalty_jump", args.q_penalty_jump))
          if v is not None}
    if dg:
        extra["dg"] = dg
    print(f"solver {args.solver}, segments {args.segments}, order {args.order}, elements {args.elements}, "
          f"time_step {args.time_step}, dg {dg}, friction speed {args.friction_speed}, friction {args.friction}, "
          f"t_end {args.t_end}")
    print("| case | static fairlead (kN): ours / ref / diff | static anchor (kN): ours / ref / diff | "
          "max pointwise | at t (s) | MoorDyn metric | tension range ours (kN) | reference (kN) | wall (s) |")
    print("|---|---|---|---:|---:|---:|---|---|---:|")
    for case in args.cases:
        depth, name = case.split(":")
        spec = case_spec(depth, args.solver, args.segments, args.order, args.elements, args.friction_speed, extra,
                         args.friction)
        sf, sa = static_tensions(spec)
        if args.moordyn:
            t, fair, anch, wall = run_moordyn(depth, name, args.t_end, args.segments)
            sf, sa = fair[0], anch[0]
        else:
            t, fair, anch, wall = run(spec, name, args.t_end)
        m = compare(depth, name, t, fair, anch, args.t_end)
        ef = 100 * (sf / STATIC_FAIR[depth] - 1)
        print(f"| {depth} {name} | {sf / 1e3:.1f} / {STATIC_FAIR[depth] / 1e3:.1f} / {ef:+.2f} % "
              f"| {sa / 1e3:.1f} / {STATIC_ANCHOR[depth] / 1e3:.1f} / {100 * (sa / STATIC_ANCHOR[depth] - 1):+.2f} % "
              f"| {100 * m['pointwise']:.2f} % | {m['at']:.1f} | {100 * m['moordyn']:.2f} % "
              f"| {m['range_ours'][0] / 1e3:.0f}-{m['range_ours'][1] / 1e3:.0f} "
              f"| {m['range_ref'][0] / 1e3:.0f}-{m['range_ref'][1] / 1e3:.0f} | {wall:.1f} |", flush=True)
        if args.versus_moordyn:
            tm, fm, _, _ = run_moordyn(depth, name, args.t_end, args.versus_moordyn)
            keep = (tm >= 0.0) & (tm <= args.t_end + 1e-9)
            ours_m = np.interp(tm[keep], t, fair)
            d = np.abs(ours_m - fm[keep]) / fm[keep]
            k = int(np.argmax(d))
            print(f"  against pip moordyn with {args.versus_moordyn} segments: largest difference {100 * d[k]:.2f} % "
                  f"at t = {tm[keep][k]:.1f} s (mean {100 * d.mean():.2f} %); moordyn's range "
                  f"{fm[keep].min() / 1e3:.0f}-{fm[keep].max() / 1e3:.0f} kN", flush=True)
        if args.plot:
            import matplotlib
            matplotlib.use("Agg")
            import matplotlib.pyplot as plt
            tr, fr, _, _ = reference(depth, name)
            fig, ax = plt.subplots(figsize=(8, 3.5))
            ax.plot(tr, fr / 1e3, "k.", ms=3, label="OrcaFlex (reference)")
            who = "pip moordyn" if args.moordyn else f"ours ({args.solver})"
            ax.plot(t + TAU, fair / 1e3, "C1-" if args.moordyn else "C0-", label=who)
            ax.set_xlim(-10, 20)
            ax.set_xlabel("t (s)")
            ax.set_ylabel("fairlead tension (kN)")
            ax.set_title(f"{depth} chain, heave {name}")
            ax.legend()
            fig.tight_layout()
            Path(args.plot).mkdir(parents=True, exist_ok=True)
            tag = "moordyn" if args.moordyn else args.solver
            fig.savefig(Path(args.plot) / f"chain_{depth}_{name}_{tag}.png", dpi=90)
            plt.close(fig)


if __name__ == "__main__":
    main()
