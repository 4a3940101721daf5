"""Drive any TetherSolver the way the node does: a fixed output rate, set_end_motion + advance_to.

Only the public interface is used (``build_solver(SimConfig)``, ``set_end_motion``,
``advance_to``, ``drain_end_tensions``) so the figures measure what the node will see.
"""

import os
import time

import numpy as np

from tether_sim.solvers.factory import build_solver


def run(config, duration, rate=50.0, motion=None, end="ship", t_warm=0.0):
    """Run ``config`` for ``duration`` simulated seconds at ``rate`` ticks per second.

    ``motion(t) -> (position, velocity)`` drives the prescribed ``end`` (None: the end is left
    as configured). Returns a dict: ``t``/``ship``/``vehicle`` end tensions at every substep,
    ``tick_wall`` (wall s per tick, array), ``wall``/``cpu`` (summed over ticks; the thread CPU
    time is the robust cost on a shared machine), ``build_wall`` (construction incl. static solve and,
    on a cold cache, JIT compilation), ``substeps``, ``wall`` (sum of ticks).
    """
    w0 = time.perf_counter()
    solver = build_solver(config)
    build_wall = time.perf_counter() - w0
    n_ticks = int(round(duration * rate))
    tick_wall = np.empty(n_ticks)
    tick_cpu = np.empty(n_ticks)
    ts, ship, veh = [], [], []
    substeps = 0
    t0 = solver.time
    solver.drain_end_tensions()
    for k in range(n_ticks):
        t1 = t0 + (k + 1) / rate
        w, c = time.perf_counter(), time.thread_time()
        if motion is not None:
            pos, vel = motion(t1)
            solver.set_end_motion(end, pos, vel)
        substeps += solver.advance_to(t1)
        tt, ts_ship, ts_veh = solver.drain_end_tensions()
        tick_wall[k] = time.perf_counter() - w
        tick_cpu[k] = time.thread_time() - c
        ts.append(np.asarray(tt, dtype=float))
        ship.append(np.asarray(ts_ship, dtype=float))
        veh.append(np.asarray(ts_veh, dtype=float))
    t = np.concatenate(ts) if ts else np.empty(0)
    return {
        "t": t, "ship": np.concatenate(ship) if ship else t, "vehicle": np.concatenate(veh) if veh else t,
        "tick_wall": tick_wall, "wall": float(tick_wall.sum()), "cpu": float(tick_cpu.sum()),
        "build_wall": build_wall,
        "substeps": int(substeps), "duration": float(duration), "rate": float(rate),
        "time_step": float(solver.stable_time_step()), "solver": solver,
    }


def resample(t, values, grid):
    """Linear interpolation of a substep record onto a uniform grid (for like-for-like peaks)."""
    return np.interp(grid, t, values)


def summary(res):
    """One-line figures of a run: real-time factor, substeps per simulated s, tick statistics."""
    ticks_ms = 1e3 * res["tick_wall"]
    return {
        "rtf": res["duration"] / res["wall"],
        "rtf_cpu": res["duration"] / res["cpu"],
        "substeps_per_s": res["substeps"] / res["duration"],
        "us_per_substep": 1e6 * res["wall"] / max(res["substeps"], 1),
        "tick_median_ms": float(np.median(ticks_ms)),
        "tick_p99_ms": float(np.percentile(ticks_ms, 99)),
        "tick_max_ms": float(ticks_ms.max()),
        "build_wall": res["build_wall"],
        "time_step": res["time_step"],
        "load": os.getloadavg()[0],
    }
