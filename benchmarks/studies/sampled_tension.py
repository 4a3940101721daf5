"""The DG state's sampled tension against what the scheme uses (docs/dg_solver.md, "Sampled tension").

Three cases, each printed as a table row per mesh:

- taut: the inclined elastic catenary of test/solvers/dg/test_catenary_statics.py (L = 100 m, EA 20 kN,
  17 N/m in water, ends 80 m across and 30 m down) against its closed form: the largest error of
  state().tension over 401 points (the interfaces among them) over the largest tension, and the end
  samples' errors;
- slack: a 30 m line (EA 2 MN, the TMS file's excursion tether mesh N = 3, P = 3 and a finer one) with
  one end fixed 22 m from the other, which a prescribed motion sweeps 9 m to and fro at 0.5 Hz for
  3 s (slack, jerked taut), 121 points: per tick the largest |state end sample - end load tension|,
  the largest state tension against the largest end tension, and the largest excursion of a sample
  beyond the range of the values the scheme used in and next to its element (the law at its Gauss
  points and at the Gauss points beside its interfaces, the end load at an end element);
- snap: the slack-snap cycles of test/solvers/dg/test_slack_snap.py (10 m, EA 1e5 N, bilinear, zeta = 0;
  every 2 ms for 1 s, 201 points): the lowest state tension, the largest excursion beyond the
  element's range and the largest tension.

With ``--network N:P`` (and ``--times``), instead: the slack excursion tether of the MoorDyn cross-check
(benchmarks/studies/network_vs_moordyn.py, its DG network with the excursion tether on N:P), every 50 Hz
tick to the last time, 401 points: the state's end samples against the end loads and its largest
interior value at each time, and the largest excursion beyond the element's scheme values so far.

Run it on another checkout (``--root``) to see its numbers with the same cases.

Usage: PYTHONPATH=. python benchmarks/studies/sampled_tension.py [--root PATH] [--meshes 10:4 4:3 3:2]
       [--slack-meshes 3:3 10:4] [--snap-meshes 10:4] [--network 10:4 [--times 3.6 8.32 9.4]]
"""

import argparse
import sys
from pathlib import Path

import numpy as np


def meshes(text):
    return [tuple(int(x) for x in m.split(":")) for m in text]


def excursion(solver, s, T):
    """Largest amount by which a sample leaves the range of the values the scheme used in and next to its
    element: the law at its Gauss points (strain and strain rate of the last evaluation), at the Gauss
    points beside its interior interfaces and, at an end element, the end load's axial tension."""
    from tether_sim.physics.constitutive import axial_tension, compression_cap
    from tether_sim.solvers.dg import layout as Y

    ws, law = solver.ws, solver.law
    N, nq = ws.wq.shape[:2]
    G = np.array([[axial_tension(law.code, ws.wq[e, j, Y.W_L] - 1.0, ws.wq[e, j, Y.W_EDOT], law.EA, law.zeta,
                                 law.tab_eps, law.tab_T, compression_cap(law.code, ws.prm[Y.P_EIC], solver.P, ws.h[e]))
                   for j in range(nq)] for e in range(N)])
    lo, hi = G.min(axis=1), G.max(axis=1)
    lo[:-1], hi[:-1] = np.minimum(lo[:-1], G[1:, 0]), np.maximum(hi[:-1], G[1:, 0])
    lo[1:], hi[1:] = np.minimum(lo[1:], G[:-1, -1]), np.maximum(hi[1:], G[:-1, -1])
    ef = solver.end_forces()
    lo[0], hi[0] = min(lo[0], ef.ship_tension), max(hi[0], ef.ship_tension)
    lo[-1], hi[-1] = min(lo[-1], ef.vehicle_tension), max(hi[-1], ef.vehicle_tension)
    e = np.clip(np.searchsorted(solver.s_edges, s, side="right") - 1, 0, N - 1)
    return float(max(0.0, np.max(T - hi[e]), np.max(lo[e] - T)))


def network_case(mesh, times):
    """The cross-check's excursion tether (module docstring)."""
    from benchmarks import ropos_case as rc
    from benchmarks.studies import network_vs_moordyn as nm
    from tether_sim.network.solver import NetworkSolver
    from tether_sim.network.spec import parse_network

    net = NetworkSolver(parse_network(nm.network_tree("dg", 0.005, exc_dg=mesh)))
    veh = nm.vehicle_position()
    exc = net.line("excursion")
    arc = np.linspace(0.0, exc.config.cable.length, 401)
    print(f"excursion tether N = {mesh[0]}, P = {mesh[1]} | time s | state ends N | end loads N | "
          "interior max N | max excursion so far N")
    k, worst = 0, 0.0
    while times:
        k += 1
        t = 0.02 * k
        p, v = rc.fairlead_motion(t)
        net.set_point_motion("ship", p, v)
        net.set_point_motion("vehicle", veh, np.zeros(3))
        net.tick(t)
        st, ef = exc.state(arc), exc.end_forces()
        worst = max(worst, excursion(exc, arc, st.tension))
        if abs(t - times[0]) < 1e-9:
            times.pop(0)
            print(f" | {t:.2f} | {st.tension[0]:.4g}, {st.tension[-1]:.4g} | {ef.ship_tension:.4g}, "
                  f"{ef.vehicle_tension:.4g} | {st.tension[1:-1].max():.4g} | {worst:.3g}", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--root", default=str(Path(__file__).resolve().parents[2]), help="the checkout whose solver runs")
    ap.add_argument("--meshes", nargs="+", default=["10:4", "4:3", "3:2"])
    ap.add_argument("--slack-meshes", nargs="+", default=["3:3", "10:4"])
    ap.add_argument("--snap-meshes", nargs="+", default=["10:4"])
    ap.add_argument("--network", default=None, help="N:P of the cross-check's excursion tether (the network case only)")
    ap.add_argument("--times", nargs="+", type=float, default=[3.6, 8.32, 9.4])
    a = ap.parse_args()
    sys.path.insert(0, a.root)
    sys.path.insert(0, str(Path(a.root) / "test" / "solvers" / "dg"))
    if a.network:
        network_case(meshes([a.network])[0], sorted(a.times))
        return
    from tether_sim.scenarios import harness
    from tether_sim.scenarios import references as ref
    from test_catenary_statics import EA, L, W, catenary_flat

    print("taut catenary | max |T - T_cat| / max T_cat | ship end | vehicle end (relative errors)")
    xyz = (80.0, 0.0, -30.0)
    cat = ref.elastic_catenary(L, EA, W, xyz[0], xyz[2])
    s = np.linspace(0.0, L, 401)
    T_ref = cat.tension(s)
    for n, p in meshes(a.meshes):
        _cfg, solver = harness.make_solver(catenary_flat(xyz, **{"dg.n_elements": n, "dg.order": p}))
        T = solver.state(s).tension
        print(f"N = {n}, P = {p} | {np.max(np.abs(T - T_ref)) / np.max(T_ref):.2e} | "
              f"{abs(T[0] / T_ref[0] - 1):.2e} | {abs(T[-1] / T_ref[-1] - 1):.2e}")

    print("slack line | max |state end - end load tension| N | max state tension N | max end tension N | "
          "max excursion beyond the element's scheme values N")
    for n, p in meshes(a.slack_meshes):
        flat = {"solver": "dg", "dg.resolution": "manual", "dg.n_elements": n, "dg.order": p, "cable.length": 30.0,
                "cable.EA": 2.0e6, "cable.gamma0": 1.59, "cable.density": 2000.0, "cable.diameter": 0.045,
                "cable.EI": 0.0, "cable.damping": 2000.0, "cable.material": "bilinear", "environment.g": 9.81,
                "environment.fluid_density": 1025.0, "ship_end.kind": "prescribed",
                "ship_end.position": [0.0, 0.0, 0.0], "vehicle_end.kind": "fixed",
                "vehicle_end.position": [22.0, 0.0, 0.0], "initial.kind": "static"}
        _cfg, solver = harness.make_solver(flat)
        arc = np.linspace(0.0, 30.0, 121)
        d = big = ends = out = 0.0
        for k in range(1, 151):
            t = 0.02 * k
            x, vx = -9.0 * np.sin(np.pi * t), -9.0 * np.pi * np.cos(np.pi * t)
            solver.tick(t, ship=(np.array([x, 0.0, 0.0]), np.array([vx, 0.0, 0.0])))
            st, ef = solver.state(arc), solver.end_forces()
            d = max(d, abs(st.tension[0] - ef.ship_tension), abs(st.tension[-1] - ef.vehicle_tension))
            big = max(big, float(st.tension.max()))
            ends = max(ends, ef.ship_tension, ef.vehicle_tension)
            out = max(out, excursion(solver, arc, st.tension))
        print(f"N = {n}, P = {p} | {d:.4g} | {big:.4g} | {ends:.4g} | {out:.4g}")

    print("snap cycles | min state tension N | max excursion beyond the element's scheme values N | max state tension N")
    from test_slack_snap import L as SL, flat as snap_flat
    for n, p in meshes(a.snap_meshes):
        eps0 = 1e-3
        amp, freq = 3 * eps0 * SL, 3.0
        _cfg, solver = harness.make_solver(snap_flat(SL * (1 + eps0), n_elements=n, order=p))
        arc = np.linspace(0.0, SL, 201)
        low = out = big = 0.0
        for t in np.arange(0.002, 1.0, 0.002):
            solver.set_end_motion("ship", np.array([amp * np.sin(2 * np.pi * freq * t), 0.0, 0.0]),
                                  np.array([2 * np.pi * freq * amp * np.cos(2 * np.pi * freq * t), 0.0, 0.0]))
            solver.advance_to(float(t))
            T = solver.state(arc).tension
            low, big = min(low, float(T.min())), max(big, float(T.max()))
            out = max(out, excursion(solver, arc, T))
        print(f"N = {n}, P = {p} | {low:.4g} | {out:.4g} | {big:.4g}")


if __name__ == "__main__":
    main()
