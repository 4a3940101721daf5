"""Full ring-beam convergence study [PE2020 Sec. 4.1, Eq. 34-36, Fig. 1] for docs/verification.md.

Static ring (end moment 1 N m) for P = 1..5 on three meshes N0, 2 N0, 4 N0 each
(ring_beam.TABLE_MESHES): the discrete fixed point du/dt = 0 by Newton's method; prints the Eq. 34
position errors, the curvature errors and their Eq. 36 rates as a markdown table with the paper's
expected rates (P + 1 for P = 1 and even P, P for odd P > 1), writes docs/figures/ring_beam.png
(like the paper's Fig. 1, transient snapshots inset), and with --flutter the growth rate of the
in-plane flutter of the linearised operator per mesh, with and without the relaxation damping.
With --relax-check, dynamic relaxation (axial damping RELAX_ZETA) on meshes that did not settle
without it, against the Newton fixed point. Minutes of CPU: not part of pytest.

    PYTHONPATH=. python benchmarks/studies/ring_beam_convergence.py [--flutter] [--relax-check] [--no-figure]
"""

import argparse
import time

import numpy as np

from tether_sim.scenarios import harness, ring_beam
from tether_sim.scenarios.ring_beam_analysis import discrete_equilibrium, linearised_spectrum


def flutter_table(meshes=((8, 2), (16, 2), (32, 2), (64, 2), (8, 3), (16, 3), (32, 3), (8, 4), (16, 4), (16, 5))):
    print("\n| N | P | max Re in-plane (1/s) | at Im (rad/s) | + relax 0.06 | + relax 0.06, zeta = 2 N s | max Re out-of-plane |")
    print("|---|---|---|---|---|---|---|")
    for n, p in meshes:
        row = []
        for zeta, relax in ((0.0, 0.0), (0.0, ring_beam.RELAX_DAMPING), (ring_beam.RELAX_ZETA, ring_beam.RELAX_DAMPING)):
            _, solver = ring_beam.ring_solver(n, p, {"cable.damping": zeta})
            discrete_equilibrium(solver)
            w_in, w_out = linearised_spectrum(solver, relax)
            k = np.argmax(w_in.real)
            row.append((w_in[k], w_out.real.max()))
        (w0, o0), (w1, _), (w2, _) = row
        print(f"| {n} | {p} | {w0.real:+.3f} | {abs(w0.imag):.1f} | {w1.real:+.3f} | {w2.real:+.3f} | {o0:+.3f} |", flush=True)


def relax_check(cases=((32, 2), (16, 3))):
    print("\n| N | P | Eq. 34 error, relaxation (zeta = 2 N s, 800 s) | Newton fixed point | wall (s) |")
    print("|---|---|---|---|---|")
    for n, p in cases:
        wall = time.perf_counter()
        e_relax = ring_beam.static_error(n, p, method="relax")
        wall = time.perf_counter() - wall
        e_newton = ring_beam.static_error(n, p)
        print(f"| {n} | {p} | {e_relax:.4e} | {e_newton:.4e} | {wall:.0f} |", flush=True)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--flutter", action="store_true")
    parser.add_argument("--relax-check", action="store_true")
    parser.add_argument("--no-figure", action="store_true")
    args = parser.parse_args(argv)
    wall = time.perf_counter()
    table = ring_beam.convergence_table()
    print(ring_beam.format_table(table))
    print(f"\n(table: wall {time.perf_counter() - wall:.0f} s)", flush=True)
    if not args.no_figure:
        tr = ring_beam.run_transient(n_elements=8, order=4, t_end=600.0)
        tr.update(N=8, P=4)
        print(f"transient N = 8, P = 4: Eq. 34 error at t = 600 s {tr['error']:.3e} (wall {tr['wall']:.0f} s)")
        path = harness.figure_dir() / "ring_beam.png"
        ring_beam.plot(tr, table, path)
        print(f"figure: {path}")
    if args.flutter:
        flutter_table()
    if args.relax_check:
        relax_check()


if __name__ == "__main__":
    main()
