"""solver.tick's common case against its previous form, A/B on two solvers of the 1730 m live file in one process.

The previous form (``previous_tick`` below) looked numpy's ndarray up twice per call and made a new TickOutput
every tick; solver.tick looks it up once and returns its last result again when the count and substeps repeat.
Both call the same compiled ship_tick, on two solvers ticked to the same times, interleaved; min over the
blocks of thread CPU per tick; at the end the two solvers' arenas must be equal bit for bit.

Usage: PYTHONPATH=. python benchmarks/probes/tick_result_ab.py [blocks, default 15] [ticks per block, default 1000]
"""

import math
import os
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from tether_sim.io.params import load_config  # noqa: E402
from tether_sim.solvers.factory import build_solver  # noqa: E402
from tether_sim.solvers.base import TickOutput  # noqa: E402
from tether_sim.solvers.dg.tick import ship_tick  # noqa: E402


def previous_tick(self, t, ship=None, vehicle=None, drain=True):
    """solver.tick's common case as it was (the general path left out)."""
    t = float(t)
    if self._ship_tick and vehicle is None and ship is not None:
        try:
            p, v = ship
        except (TypeError, ValueError):
            p = v = None
        if type(p) is np.ndarray and type(v) is np.ndarray:
            ws, t0 = self.ws, self.time
            r, n = ship_tick(ws.F, ws.I, ws.spec, p, v, t0, t, self.fixed_dt if self.fixed_dt > 0 else self._dt_rule,
                             drain)
            if r >= 0:
                self.time = t
                self._want_outputs = self._outputs_valid = True
                return tuple.__new__(TickOutput, (r, ws.drain, ws.endf, n))
    raise RuntimeError("not the common case")


def motion(t):
    return 0.5*np.array((math.cos(t)-1, math.sin(t), 0.)), 0.5*np.array((-math.sin(t), math.cos(t), 0.))


cfg = load_config(ROOT / "config" / "ropos_L1730.yaml")
sa, sb = build_solver(cfg), build_solver(cfg)
for s in (sa, sb):
    t = 0.0
    for k in range(50):
        t += 0.02; s.tick(t, ship=motion(t))
calls = int(sys.argv[2]) if len(sys.argv) > 2 else 1000


def run(s, new):
    t0 = s.time
    ts = [t0 + 0.02 * (i + 1) for i in range(calls)]
    ms = [motion(x) for x in ts]
    c = time.thread_time()
    if new:
        for x, m in zip(ts, ms): s.tick(x, ship=m)
    else:
        for x, m in zip(ts, ms): previous_tick(s, x, ship=m)
    return (time.thread_time() - c) / calls


best = {True: 1e9, False: 1e9}
for r in range(int(sys.argv[1]) if len(sys.argv) > 1 else 15):
    for new in ((True, False) if r % 2 else (False, True)):
        best[new] = min(best[new], run(sa if new else sb, new))
# identical results
print("arenas equal:", np.array_equal(sa.ws.F, sb.ws.F) and np.array_equal(sa.ws.I, sb.ws.I), sa.time == sb.time)
print(f"previous {best[False]*1e6:.3f} us, solver.tick {best[True]*1e6:.3f} us per tick, previous / solver.tick "
      f"{best[False]/best[True]:.4f}, difference {1e6*(best[False]-best[True]):.3f} us; load {os.getloadavg()[0]:.1f}")
