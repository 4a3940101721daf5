"""Station keeping in a current: the thrust against a hand estimate of the tether's drag.

    .venv/bin/python benchmarks/studies/vehicle_tether_drag.py [--current 0.4] [--length 80] [--seconds 60]

The MuJoCo BlueROV2 Heavy of tether-sim-vehicle holds station straight below the tether's fixed upper
end (config/light_tether_vehicle.yaml: 7.6 mm, Cdn 1), the chord 2 % shorter than the tether, in a
uniform current U along +x that acts on the vehicle and on the tether. The tether is attached at the
vehicle's centre of gravity: at the file's rear attachment (0.2 m behind it) the ~70 N the bowed tether
pulls up with needs a pitch moment the four vertical thrusters cannot add to the heave they give (the
rear pair saturates) and the vehicle is dragged off station, so the thrust would not be the steady one.
The station keeper is stiffer than tether-sim-vehicle's default (1.5 rad/s against 0.6): with the
default the vehicle drifts ~2 m while its integral builds up, which changes the chord by more than the
tether's slack, and the loop takes minutes to settle. Both nodes run in one process in
simulated time (tether_sim.ros.closed_loop), node.input_delay 0.

Hand estimate. The tether is nearly taut and nearly vertical, so the current is normal to it and loads
it with q = rho Cdn d U^2 / 2 per metre (PE2020 Eq. 17), bowing it into a parabola of sag f across the
chord c (slack L - c = 8 f^2 / (3 c)). The normal component of the flow at slope x' = dx/dz is
U / sqrt(1 + x'^2), so the horizontal load per metre of height is q / (1 + x'^2); the vehicle end takes
the share that balances the moments about the upper end, H = int_0^c q z / (1 + x'(z)^2) dz / c, which
for a straight tether is q c / 2 (the mean of 1 / (1 + x'^2) over the parabola is 1 - 16 f^2 / (3 c^2)).
The station-keeping thrust along x is then the vehicle's own drag in the current (its linear and
quadratic damping at the relative speed U, model.py) plus H.

Printed: the hand estimate of H, the tether force on the vehicle along x (mean over the last 10 s),
the thrust along x, and the thrust less the vehicle's own drag against H.
"""

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

TOP = np.array([0.0, 0.0, -2.0])
ATTACH = np.array([0.0, 0.0, 0.0])  # node.vehicle_attachment here: at the centre of gravity (module doc)
SLACK = 0.02  # (L - c) / L
KEEPER_OMEGA = 1.5  # rad/s: a stiffer station keeper than the default 0.6 (module doc)
RHO, CDN, DIAMETER = 1025.0, 1.0, 0.0076  # the file's fluid, the default Cdn, the file's tether


def hand_estimate(U, length, chord, n=2001):
    """(H (N), q (N/m), sag f (m)): the vehicle end's share of the tether's horizontal drag (module doc)."""
    q = 0.5 * RHO * CDN * DIAMETER * U**2
    f = np.sqrt(3.0 * chord * (length - chord) / 8.0)
    z = np.linspace(0.0, chord, n)
    slope = 4.0 * f * (chord - 2.0 * z) / chord**2
    h = q / (1.0 + slope**2)
    return float(np.trapezoid(h * z, z) / chord), q, float(f)


def vehicle_drag(model, U):
    """The vehicle's own drag along x at rest in a current U along x (N): its linear and quadratic damping."""
    return model.linear_damping[0] * U + model.quadratic_damping[0] * U * abs(U)


def run(U, length, seconds, average=10.0, verbose=False):
    from tether_sim.ros.closed_loop import ClosedLoop
    from tether_sim.vehicle.model import BLUEROV2_HEAVY
    from tether_sim.vehicle.sim import StationKeeper

    chord = (1.0 - SLACK) * length
    station = TOP + np.array([0.0, 0.0, -chord]) - ATTACH  # the attachment straight below the top
    extra = {"cable.length": float(length), "ship_end.position": tuple(TOP),
             "vehicle_end.position": tuple(station + ATTACH), "environment.current_z": (-1000.0, 0.0),
             "environment.current_x": (float(U), float(U)), "environment.current_y": (0.0, 0.0),
             "cable.damping": 200.0, "node.vehicle_attachment": tuple(ATTACH)}
    loop = ClosedLoop(tuple(station), tuple(station), params_file=ROOT / "config" / "light_tether_vehicle.yaml",
                      current=(U, 0.0, 0.0), keeper=StationKeeper(BLUEROV2_HEAVY, omega=KEEPER_OMEGA), **extra)
    thrust = []
    try:
        for _ in range(int(round(seconds))):
            loop.run(1.0)
            R = loop.sim.rotation()
            thrust.append((loop.sim.time, R @ (loop.sim.B @ loop.vehicle.thrust)[:3]))
            if loop.vehicle.failed:
                raise RuntimeError("the vehicle simulation went unstable")
            if verbose and len(thrust) % 10 == 0:
                f = loop.sim.rotation() @ loop.vehicle.applied[:3]
                print(f"  t {loop.sim.time:6.1f} s: position - station {np.array2string(loop.sim.position - station, precision=3)} m, "
                      f"tether force {np.array2string(f, precision=2)} N, thrust {np.array2string(thrust[-1][1], precision=2)} N",
                      flush=True)
        t_end = loop.trace[-1][0]
        late = [x for x in loop.trace if x[0] >= t_end - average]
        R = loop.sim.rotation()
        tether_x = float(np.mean([(R @ x[2][:3])[0] for x in late]))
        thrust_x = float(np.mean([f[0] for t, f in thrust if t >= t_end - average]))
        offset = loop.sim.position - station
    finally:
        loop.close()
    H, q, f = hand_estimate(U, length, chord)
    own = vehicle_drag(BLUEROV2_HEAVY, U)
    return {"U": U, "length": length, "H": H, "q": q, "sag": f, "tether_x": tether_x, "thrust_x": thrust_x,
            "own_drag": own, "offset": offset}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--current", type=float, nargs="+", default=[0.4])
    ap.add_argument("--length", type=float, default=80.0)
    ap.add_argument("--seconds", type=float, default=60.0)
    ap.add_argument("--verbose", action="store_true", help="print the vehicle's offset, the tether force and the thrust every 10 s")
    args = ap.parse_args(argv)
    print("| U (m/s) | hand estimate H (N) | tether force on the vehicle, x (N) | thrust against the current (N) | vehicle's own drag (N) "
          "| thrust - own drag (N) | against H | station error x, y, z (m) |")
    print("|---|---|---|---|---|---|---|---|")
    for U in args.current:
        r = run(U, args.length, args.seconds, verbose=args.verbose)
        net = -r["thrust_x"] - r["own_drag"]  # the thrust holds against the current: along -x
        print(f"| {U:g} | {r['H']:.2f} | {r['tether_x']:.2f} | {-r['thrust_x']:.2f} | {r['own_drag']:.2f} | {net:.2f} "
              f"| {100 * (net / r['H'] - 1):+.1f} % | {np.array2string(r['offset'], precision=3)} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
