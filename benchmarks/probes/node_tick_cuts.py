"""The node tick's cut parts, old way against new way, interleaved in one process (thread CPU per call, min over
--repeat blocks of --calls calls each), with the numbers each way checked equal bit for bit:

- a body end's pose for the outputs: ``solver.body_state(end)`` (position, orientation, velocities and the
  acceleration under the end load and the current) against ``solver.body_pose(end)`` (position and orientation,
  what the outputs read), on the live file's solver after --warm s of its fairlead circle;
- the RAO ship's command (config/ropos_forecast.yaml): ``motion.at(t)`` (position, velocity, acceleration)
  against ``motion.position_velocity(t)``, the first two.

Usage: PYTHONPATH=. python benchmarks/probes/node_tick_cuts.py [--params config/ropos_L200.yaml]
       [--calls 2000] [--repeat 15] [--warm 20]
"""

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))


def best(fn, calls, repeat, out):
    for _ in range(repeat):
        c = time.thread_time()
        for _ in range(calls):
            fn()
        out.append((time.thread_time() - c) / calls)


def pair(name, old, new, calls, repeat):
    a, b = [], []
    for _ in range(repeat):  # interleaved block by block
        best(old, calls, 1, a)
        best(new, calls, 1, b)
    print(f"{name:58s} old {min(a) * 1e6:7.2f} us, new {min(b) * 1e6:7.2f} us, old - new {(min(a) - min(b)) * 1e6:6.2f} us",
          flush=True)


def main(argv=None):
    from tether_sim.io.params import load_config
    from tether_sim.physics.motion import build_motion
    from tether_sim.physics.waves import wave_components
    from tether_sim.solvers.factory import build_solver

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--params", default="config/ropos_L200.yaml")
    ap.add_argument("--forecast", default="config/ropos_forecast.yaml")
    ap.add_argument("--calls", type=int, default=2000)
    ap.add_argument("--repeat", type=int, default=15)
    ap.add_argument("--warm", type=float, default=20.0)
    args = ap.parse_args(argv)
    print(f"node_tick_cuts, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load average "
          f"{os.getloadavg()[0]:.2f}, {args.params}", flush=True)
    cfg = load_config(args.params)
    solver = build_solver(cfg)
    motion = build_motion(cfg.motion, cfg.ship_end.position)
    t = 0.0
    while t < args.warm - 1e-9:
        t += 0.02
        p, v, _ = motion.at(t)
        solver.set_end_motion("ship", p, v)
        solver.advance_to(t)
        solver.drain_end_tensions()
    full, pose = solver.body_state("vehicle"), solver.body_pose("vehicle")
    assert full.position.tobytes() == pose.position.tobytes() and full.orientation.tobytes() == pose.orientation.tobytes()
    pair("vehicle body for the outputs: body_state / body_pose", lambda: solver.body_state("vehicle"),
         lambda: solver.body_pose("vehicle"), args.calls, args.repeat)

    fcfg = load_config(args.forecast)
    rao = build_motion(fcfg.motion, fcfg.ship_end.position, wave_components(fcfg))
    full, pv = rao.at(37.3), rao.position_velocity(37.3)
    assert full[0].tobytes() == pv[0].tobytes() and full[1].tobytes() == pv[1].tobytes()
    pair("RAO ship command: at / position_velocity", lambda: rao.at(37.3), lambda: rao.position_velocity(37.3),
         args.calls, args.repeat)


if __name__ == "__main__":
    main()
