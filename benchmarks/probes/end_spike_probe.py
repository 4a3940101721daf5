"""One-substep tension spikes at the cage end, substep by substep (docs/snap_guard.md, "One-substep end spikes in
strongly forced slack"): the ROPOS tether with the cage at L m (config/ropos_L500_paper.yaml shortened), the circular
fairlead orbit of the Sec. 6.2 kind, run on the tether-sim-offline path (snap detector and guard included) up to
T + 0.05 s; between T - 4 ms and T + 2 ms every interval of the driver is cut into single substeps (the fairlead
motion on the driver's own cubic Hermite), and after each the cage end is printed: end tension E_T, the axial part
of the projected tension's trace and of the upwind term c gamma0 (v_BC - v+), the end element's outermost Gauss
point (strain, strain rate, tension), the cable end trace's and the cage attachment's vertical velocity.

    PYTHONPATH=. python benchmarks/probes/end_spike_probe.py T [--L 300] [--f 0.3] [--alpha 3] [--N 20] [--a 2.5]
"""
import argparse
import math
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
from tether_sim.io.params import load_config  # noqa: E402
from tether_sim.ros.offline import run_offline  # noqa: E402
from tether_sim.solvers.dg import layout as Y  # noqa: E402
from tether_sim.solvers.factory import build_solver  # noqa: E402

EI_STAR = 2620.0  # N m^2 [PE2020 Sec. 6.2]


def hermite(p0, v0, p1, v1, H, x):
    """Position and velocity on the cubic Hermite segment of length H at the fraction x."""
    h00, h10, h01, h11 = 2 * x**3 - 3 * x**2 + 1, (x**3 - 2 * x**2 + x) * H, -2 * x**3 + 3 * x**2, (x**3 - x**2) * H
    d00, d10, d11 = (6 * x**2 - 6 * x) / H, 3 * x**2 - 4 * x + 1, 3 * x**2 - 2 * x
    return h00 * p0 + h10 * v0 + h01 * p1 + h11 * v1, d00 * p0 + d10 * v0 - d00 * p1 + d11 * v1


def cage_line(s, cfg):
    """One printed line: the cage end of the state just stepped to."""
    ws, g0 = s.ws, cfg.cable.gamma0
    s._evaluate_outputs()
    e = ws.trc.shape[0] - 1
    q = ws.trc[e, 1, Y.T_Q:Y.T_Q + 3]
    i = q / np.linalg.norm(q)
    vtr = ws.trc[e, 1, Y.T_V:Y.T_V + 3] / g0
    vbc = ws.vbc[1, 3:6]
    lam = max(ws.trc[e, 1, Y.T_LAM], ws.prm[Y.P_LAMBDA_BC])
    up = lam * g0 * (vbc - vtr) @ i
    w = ws.wq[e, -1]
    return (f"{s.time:.6f} E_T {ws.endf[1, Y.E_T]:9.0f} | trace T {ws.trc[e, 1, Y.T_TV:Y.T_TV + 3] @ i:9.0f} "
            f"upwind {up:8.0f} (lambda trace {ws.trc[e, 1, Y.T_LAM]:.0f}, used {lam:.0f}) | outer Gauss point eps "
            f"{w[Y.W_L] - 1:+.2e} deps/dt {w[Y.W_EDOT]:6.3f} T {np.linalg.norm(w[Y.W_TV:Y.W_TV + 3]):9.0f} | "
            f"v_z end trace {vtr[2]:7.3f} cage {vbc[2]:7.3f}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("T", type=float, help="time of the event (s)")
    ap.add_argument("--L", type=float, default=300.0)
    ap.add_argument("--f", type=float, default=0.3)
    ap.add_argument("--alpha", type=float, default=3.0)
    ap.add_argument("--N", type=int, default=20)
    ap.add_argument("--a", type=float, default=2.5, help="orbit radius (m)")
    args = ap.parse_args()
    cfg = load_config(ROOT / "config" / "ropos_L500_paper.yaml", {
        "cable.length": args.L, "vehicle_end.position": [0.0, 0.0, -args.L],
        "body.initial_position": [0.0, 0.0, -args.L - 2.1], "cable.EI": args.alpha * EI_STAR,
        "motion.kind": "circle", "motion.amplitude": args.a, "motion.frequency": args.f,
        "motion.ramp_time": 1.0 / args.f, "duration": args.T + 0.05, "dg.n_elements": args.N})
    window = (args.T - 0.004, args.T + 0.002)

    def factory(config):
        s = build_solver(config)
        advance, set_motion = s.advance_to, s.set_end_motion
        ship = {"prev": None, "cur": None}

        def set_end_motion(end, position, velocity):
            if end == "ship":
                ship["cur"] = (np.array(position, float), np.array(velocity, float))
            set_motion(end, position, velocity)

        def advance_to(t):
            t0, k = s.time, 0
            if ship["prev"] is not None and t > window[0] and t0 < window[1]:
                H = t - t0
                n = max(1, math.ceil(H / s._substep() * (1 - 1e-12)))
                for j in range(1, n + 1):
                    set_motion("ship", *hermite(*ship["prev"], *ship["cur"], H, j / n))
                    k += advance(t0 + H * j / n)
                    print(cage_line(s, cfg), flush=True)
            else:
                k = advance(t)
            ship["prev"] = ship["cur"]
            return k

        s.advance_to, s.set_end_motion = advance_to, set_end_motion
        return s

    summary = run_offline(cfg, None, progress=False, solver_factory=factory)
    for ev in summary["events"]:
        print(type(ev).__name__, getattr(ev, "location", ""), getattr(ev, "time", ""), getattr(ev, "peak", ""))


if __name__ == "__main__":
    main()
