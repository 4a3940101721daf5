"""What the TMS excursion tether's end pulses are made of: its end traces at every coupling step.

config/ropos_tms.yaml under the soak's drive (the ship heaving 0.5 m at 0.1 Hz from rest, the vehicle
held; benchmarks/excursion_rattle.py), the network's coupling step set to ``--coupling-step``
(default 0.5 ms, about two of the excursion tether's substeps) so that the state is read between
substeps. After each coupling step the excursion tether's right-hand side is evaluated once at its
state and, at each end, read: the trace strain eps+ = |q+| - 1, the speed w at which the end pulls away
from the cable along the trace tangent ((gamma0 v_BC - v+) / gamma0 along -i at s = 0, +i at s = L),
the transverse part of that velocity difference, the axial trace of the tension T+ (the end value of
the projected tension), the boundary flux's axial part T_hat (the end tension the line reports) and
the wave speed lambda the flux uses. Prints, per end, the steps whose T_hat exceeds ``--level``
(default 150 N), the medians of those quantities there and at quiet steps (T_hat < 30 N), and the
split of T_hat into T+ and the upwind term lambda gamma0 w (docs/dg_solver.md, "The slack end's flux").

Usage: PYTHONPATH=. python benchmarks/probes/excursion_end_probe.py [--duration 30] [--coupling-step 0.0005]
       [--params config/ropos_tms.yaml] [--level 150] [--save rows.npy]
"""

import argparse
import dataclasses
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from benchmarks.bench_tms import Heave  # noqa: E402
from tether_sim.network.params import load_network_files  # noqa: E402
from tether_sim.ros.network_driver import NetworkDriver  # noqa: E402
from tether_sim.solvers.dg import layout as Y  # noqa: E402
from tether_sim.solvers.dg import stepping  # noqa: E402
from tether_sim.solvers.dg.layout import P_LAMBDA_BC  # noqa: E402

COLUMNS = ("t", "eps", "w", "w_transverse", "T_trace", "T_hat", "lambda")


def end_row(ws, g0, end):
    """(eps+, w, |transverse|, T+ . i, T_hat . i, lambda) at one end after a full right-hand-side evaluation."""
    N = ws.U.shape[0]
    e, side = (0, 0) if end == 0 else (N - 1, 1)
    q = ws.trc[e, side, Y.T_Q:Y.T_Q + 3]
    nq = float(np.linalg.norm(q))
    i = q / nq
    dv = (g0 * ws.vbc[end, 3:6] - ws.trc[e, side, Y.T_V:Y.T_V + 3]) / g0
    w = (-1.0 if end == 0 else 1.0) * float(dv @ i)
    wt = float(np.linalg.norm(dv - (dv @ i) * i))
    lam = max(float(ws.trc[e, side, Y.T_LAM]), float(ws.prm_step[P_LAMBDA_BC]))
    return [nq - 1.0, w, wt, float(ws.trc[e, side, Y.T_TV:Y.T_TV + 3] @ i), float(ws.endf[end, Y.E_T]), lam]


def run(params, duration, coupling_step):
    spec, cfg = load_network_files([params])
    sources = {n: Heave(p.position, 0.5 if n == "ship" else 0.0) for n, p in spec.points.items()
               if p.kind == "prescribed"}
    d = NetworkDriver(spec, cfg.node, sources=sources)
    d.start(0.0)
    d.net.spec = dataclasses.replace(d.net.spec, coupling_step=coupling_step)
    line = d.net.lines["excursion"]
    g0 = float(spec.lines["excursion"].config.cable.gamma0)
    rows = []
    inner = line.tick

    def tick(t, ship=None, vehicle=None, drain=True):
        out = inner(t, ship=ship, vehicle=vehicle, drain=drain)
        stepping.evaluate(line.ws, line.time)  # the traces and fluxes at the state reached
        rows.append([line.time] + end_row(line.ws, g0, 0) + end_row(line.ws, g0, 1))
        return out
    line.tick = tick
    c0 = time.process_time()
    now = 0.0
    while now < duration - 1e-9:
        now += 1.0 / cfg.node.output_rate
        if d.tick(now).error:
            break
    return np.array(rows), time.process_time() - c0, g0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=30.0)
    ap.add_argument("--coupling-step", type=float, default=0.0005)
    ap.add_argument("--params", default=str(Path(__file__).resolve().parents[2] / "config" / "ropos_tms.yaml"))
    ap.add_argument("--level", type=float, default=150.0)
    ap.add_argument("--save", help="the rows (t, then per end eps, w, w_transverse, T_trace, T_hat, lambda) as .npy")
    args = ap.parse_args(argv)
    print(f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load {os.getloadavg()[0]:.1f}; {args.params}, "
          f"{args.duration:g} s, coupling step {args.coupling_step:g} s")
    a, cpu, g0 = run(args.params, args.duration, args.coupling_step)
    print(f"{len(a)} coupling steps, {cpu:.1f} CPU s")
    if args.save:
        np.save(args.save, a)
    for end, name in enumerate(("cage end (s = 0)", "vehicle end (s = L)")):
        eps, w, wt, tt, th, lam = (a[:, 1 + 6 * end + k] for k in range(6))
        big, quiet = th > args.level, th < 30.0
        print(f"{name}: largest T_hat {th.max():.0f} N; {big.sum()} steps above {args.level:g} N")
        if big.any():
            up = lam[big] * g0 * w[big]
            print(f"  there: eps+ median {np.median(eps[big]):.4f} (slack in {100 * np.mean(eps[big] < 0):.0f} %), "
                  f"pull w median {np.median(w[big]):.4f} m/s, transverse {np.median(wt[big]):.4f} m/s; "
                  f"T_hat = T+ + lambda gamma0 w: T+ median {np.median(tt[big]):.0f} N, upwind term median "
                  f"{np.median(up):.0f} N (largest residual {np.max(np.abs(tt[big] + up - th[big])):.2g} N)")
        print(f"  quiet (T_hat < 30 N): eps+ median {np.median(eps[quiet]):.4f}, |w| median "
              f"{np.median(np.abs(w[quiet])):.5f} m/s, transverse {np.median(wt[quiet]):.5f} m/s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
