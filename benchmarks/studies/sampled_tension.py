"""The DG state's sampled tension against what the scheme applies (docs/dg_solver.md, "Sampled tension").

Two cases, each printed as a table row per mesh:

- taut: the inclined elastic catenary of test/solvers/dg/test_catenary_statics.py (L = 100 m, EA 20 kN,
  17 N/m in water, ends 80 m across and 30 m down) against its closed form: the largest error of
  state().tension over 401 points (the interfaces among them) over the largest tension, and the end
  samples' errors;
- slack: a 30 m line (EA 2 MN, the TMS file's excursion tether mesh N = 3, P = 3 and a finer one) with
  one end fixed 22 m from the other, which a prescribed motion draws from rest to 30.2 m apart and back at 0.5 Hz for
  3 s (slack, jerked taut): per tick the largest |state end sample - end load tension| and the
  largest state tension against the largest end tension.

Run it on another checkout (``--root``) to see its numbers with the same cases.

Usage: PYTHONPATH=. python benchmarks/studies/sampled_tension.py [--root PATH] [--meshes 10:4 4:3 3:2]
       [--slack-meshes 3:3 10:4]
"""

import argparse
import sys
from pathlib import Path

import numpy as np


def meshes(text):
    return [tuple(int(x) for x in m.split(":")) for m in text]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--root", default=str(Path(__file__).resolve().parents[2]), help="the checkout whose solver runs")
    ap.add_argument("--meshes", nargs="+", default=["10:4", "4:3", "3:2"])
    ap.add_argument("--slack-meshes", nargs="+", default=["3:3", "10:4"])
    a = ap.parse_args()
    sys.path.insert(0, a.root)
    sys.path.insert(0, str(Path(a.root) / "test" / "solvers" / "dg"))
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

    print("slack line | max |state end - end load tension| N | max state tension N | max end tension N")
    for n, p in meshes(a.slack_meshes):
        flat = {"solver": "dg", "dg.resolution": "manual", "dg.n_elements": n, "dg.order": p, "cable.length": 30.0,
                "cable.EA": 2.0e6, "cable.gamma0": 1.59, "cable.density": 2000.0, "cable.diameter": 0.045,
                "cable.EI": 0.0, "cable.damping": 2000.0, "cable.material": "bilinear", "environment.g": 9.81,
                "environment.fluid_density": 1025.0, "ship_end.kind": "prescribed",
                "ship_end.position": [0.0, 0.0, 0.0], "vehicle_end.kind": "fixed",
                "vehicle_end.position": [22.0, 0.0, 0.0], "initial.kind": "static"}
        _cfg, solver = harness.make_solver(flat)
        arc = np.linspace(0.0, 30.0, 41)
        d = big = ends = 0.0
        for k in range(1, 151):
            t = 0.02 * k
            x, vx = -4.1 * (1.0 - np.cos(np.pi * t)), -4.1 * np.pi * np.sin(np.pi * t)
            solver.tick(t, ship=(np.array([x, 0.0, 0.0]), np.array([vx, 0.0, 0.0])))
            st, ef = solver.state(arc), solver.end_forces()
            d = max(d, abs(st.tension[0] - ef.ship_tension), abs(st.tension[-1] - ef.vehicle_tension))
            big = max(big, float(st.tension.max()))
            ends = max(ends, ef.ship_tension, ef.vehicle_tension)
        print(f"N = {n}, P = {p} | {d:.4g} | {big:.4g} | {ends:.4g}")


if __name__ == "__main__":
    main()
