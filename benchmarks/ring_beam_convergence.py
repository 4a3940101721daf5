"""Full ring-beam convergence study [PE2020 Sec. 4.1, Eq. 34-36, Fig. 1] for docs/verification.md.

Static ring (end moment 1 N m, dynamic relaxation) for P = 1..5 on three meshes N0, 2 N0, 4 N0;
prints the Eq. 34 errors and the Eq. 36 rates as a markdown table, with the paper's expected
rates (P + 1 for P = 1 and even P, P for odd P > 1). Minutes of CPU: not part of pytest.

    PYTHONPATH=. python benchmarks/ring_beam_convergence.py [--meshes 4 8 16] [--orders 1 2 3 4 5]
"""

import argparse
import time

from tether_sim.scenarios import ring_beam


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--meshes", type=int, nargs="+", default=[4, 8, 16])
    parser.add_argument("--orders", type=int, nargs="+", default=[1, 2, 3, 4, 5])
    parser.add_argument("--relax-time", type=float, default=ring_beam.RELAX_TIME)
    args = parser.parse_args(argv)
    wall = time.perf_counter()
    errors, rates = ring_beam.convergence_table(tuple(args.orders), tuple(args.meshes), relax_time=args.relax_time)
    print(ring_beam.format_table(args.orders, args.meshes, errors, rates))
    print(f"\n(wall {time.perf_counter() - wall:.0f} s)")


if __name__ == "__main__":
    main()
