"""The MuJoCo vehicle on the TMS network's excursion tether, in the loop.

    .venv/bin/python benchmarks/studies/vehicle_on_tms.py [--seconds 30] [--out 5]

config/ropos_tms.yaml (ship, 1730 m tether, the ROPOS cage, a 30 m excursion tether to the vehicle) and
tether-sim-vehicle's BlueROV2 Heavy in one process in simulated time (tether_sim.ros.closed_loop, the
network's node, node.input_delay 0). The vehicle starts at the file's vehicle point and is told to move
``--out`` m further from the cage along x. Printed every 5 s: the vehicle's position, the excursion
tether's force on it (mean and largest over the interval) and the wall time taken.
"""

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

ATTACH = np.array([-0.2, 0.0, 0.0])  # node.vehicle_attachment of the file (vehicle frame)
VEHICLE = np.array([20.0, 0.0, -1751.0])  # the file's vehicle point


def main(argv=None) -> int:
    from tether_sim.ros.closed_loop import ClosedLoop

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seconds", type=float, default=30.0)
    ap.add_argument("--out", type=float, default=5.0, help="m further from the cage along x")
    args = ap.parse_args(argv)
    start = VEHICLE - ATTACH
    wall = time.perf_counter()
    loop = ClosedLoop(tuple(start), tuple(start + [args.out, 0.0, 0.0]), params_file=ROOT / "config" / "ropos_tms.yaml",
                      **{"node.input_delay": 0.0})
    print(f"start-up {time.perf_counter() - wall:.1f} s of wall time")
    print("| t (s) | vehicle position (m) | excursion tether force on the vehicle: mean / largest (N) | wall (s) |")
    print("|---|---|---|---|")
    try:
        for _ in range(int(round(args.seconds / 5.0))):
            wall = time.perf_counter()
            loop.run(5.0)
            f = np.linalg.norm([x[2][:3] for x in loop.trace[-250:]], axis=1)
            print(f"| {loop.sim.time:.1f} | {", ".join(f"{v:.2f}" for v in loop.sim.position)} | {f.mean():.1f} / "
                  f"{f.max():.1f} | {time.perf_counter() - wall:.1f} |", flush=True)
            if loop.vehicle.failed:
                print("the vehicle simulation went unstable")
                return 1
    finally:
        loop.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
