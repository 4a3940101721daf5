"""Hybrid solver cost, analytic band Jacobian vs the forward-difference twin, on config/ropos_L200_hybrid.yaml
(ROPOS L = 200 m, cage simulated, dt = 0.01 s, adaptive zoning, slack and snap every 5 s), in one process.

Both runs are driven the same way (fairlead commanded every 0.01 s from the config's orbit) and timed with
thread CPU time; the ratio is the figure to quote on a shared machine. Also prints the largest
difference of the end tensions and of the final state between the two, and the time up to which they
agree to 1e-6.

    PYTHONPATH=. python benchmarks/bench_hybrid_jacobian.py [--duration 30]
"""

import argparse
import os
import time
from dataclasses import replace

import numpy as np

from tether_sim.io.params import load_config
from tether_sim.physics.motion import build_motion
from tether_sim.solvers.factory import build_solver


def run(cfg, duration, motion):
    s = build_solver(replace(cfg, hybrid=replace(cfg.hybrid)))
    s.drain_end_tensions()
    c0 = time.thread_time()
    k = 0
    while k < int(round(duration / 0.01)):
        k += 1
        p, v = motion.at(0.01 * k)[:2]
        s.set_end_motion("ship", p, v)
        s.advance_to(0.01 * k)
    cpu = time.thread_time() - c0
    t, a, b = s.drain_end_tensions()
    return {"t": t, "ship": a, "vehicle": b, "cpu": cpu, "stats": dict(s.stats), "state": s.state()}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--config", default="config/ropos_L200_hybrid.yaml")
    ap.add_argument("--duration", type=float, default=30.0)
    args = ap.parse_args()
    base = load_config(args.config)
    motion = build_motion(base.motion, np.asarray(base.ship_end.position, dtype=float))
    res = {}
    for jac in ("analytic", "finite_difference"):
        cfg = replace(base, hybrid=replace(base.hybrid, jacobian=jac))
        run(cfg, 0.05, motion)  # compile / load the kernels outside the timing
        r = res[jac] = run(cfg, args.duration, motion)
        st = r["stats"]
        print(f"{jac}: {r['cpu']:.2f} s thread CPU for {args.duration:g} s -> {r['cpu'] / args.duration:.4f} s/s, "
              f"real-time factor {args.duration / r['cpu']:.1f}; {st['steps']} steps, "
              f"{st['newton_iterations'] / st['steps']:.2f} Newton it./step, {st.get('jacobians', 0) / st['steps']:.2f} "
              f"Jacobians/step, halvings {st['halvings']}, failure re-zonings {st.get('failure_rezonings', 0)}", flush=True)
    a, f = res["analytic"], res["finite_difference"]
    n = min(a["t"].size, f["t"].size)
    scale = max(np.abs(f["ship"]).max(), 1.0)
    d = np.abs(a["ship"][:n] - f["ship"][:n]) / scale
    dv = np.abs(a["vehicle"][:n] - f["vehicle"][:n]) / max(np.abs(f["vehicle"]).max(), 1.0)
    bad = np.nonzero(np.maximum(d, dv) > 1e-6)[0]
    t_agree = a["t"][bad[0]] if bad.size else a["t"][n - 1]
    upto = a["t"][:n] < t_agree
    print(f"speed-up (same process, thread CPU): {f['cpu'] / a['cpu']:.2f}x")
    print(f"end tensions: agree to {max(d[upto].max(initial=0.0), dv[upto].max(initial=0.0)):.1e} (relative to the "
          f"largest) up to t = {t_agree:.2f} s; largest difference over the whole run {max(d.max(), dv.max()):.2e}")
    sa, sf = a["state"], f["state"]
    print(f"final state: position {np.abs(sa.position - sf.position).max():.3g} m, tension "
          f"{np.abs(sa.tension - sf.tension).max() / np.abs(sf.tension).max():.2e} relative")
    print(f"load: {os.getloadavg()}")


if __name__ == "__main__":
    main()
