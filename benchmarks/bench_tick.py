"""Cost per substep and per node tick of the DG solver, optionally against a baseline tree in the
same process (thread CPU, best of --repeat).

For each case (L, N, P = 4, alpha; ROPOS tether + cage body, circular fairlead) the solver is run to
t = 2 s at 50 Hz, then from that state:

- substep: one advance_to over ``--steps`` substeps (the compiled loop; the per-call work amortised);
- tick: a node tick at 50 Hz, i.e. set_end_motion + advance_to(t + 0.02) + drain_end_tensions +
  state() at 41 points + end_forces() + body_state(), averaged over 25 ticks;
- overhead: tick - substeps per tick x substep, the cost per tick that is not substeps (end motion,
  call, bookkeeping, the output evaluation and sampling, Python).

``--baseline DIR`` loads another checkout's ``tether_sim`` (e.g. a worktree of main) under the name
``tether_sim_base`` (a copy in a temporary directory with the imports renamed, kept per content of the
checkout's sources, so a changed checkout is copied again) and times it in the same process,
interleaved block by block (base, new, then new, base), so that the ratio does not depend on the
machine's load.

``--hybrid``: the hybrid solver's node tick instead (ROPOS L = 200 m); ``--solver-tick FILE``: the same for
the solver of FILE (solver.tick + state() per 50 Hz tick, the call a coupled program makes; solver_ticks).

Usage: PYTHONPATH=. python benchmarks/bench_tick.py [--baseline /path/to/main] [--steps 2000] [--hybrid | --solver-tick FILE]
"""

import argparse
import hashlib
import importlib
import os
import re
import shutil
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

CASES = ((200.0, 2, 0.0), (200.0, 2, 1.0), (1730.0, 3, 0.0), (1730.0, 3, 1.0), (1730.0, 20, 0.0), (1730.0, 20, 1.0))


def load_baseline(root, with_ros=False):
    """(tether_sim package, ropos_case module) of another checkout, renamed to tether_sim_base
    (``with_ros``: its tether_sim.ros too, for the node)."""
    key = _source_digest(root, with_ros)
    tmp = Path(tempfile.gettempdir()) / f"tether_sim_base_{key}"  # kept per content: its numba cache survives runs
    if not (tmp / "ropos_case_base.py").exists():
        _copy_renamed(root, tmp, with_ros)
    sys.path.insert(0, str(tmp))
    return importlib.import_module("tether_sim_base.solvers.factory"), importlib.import_module("ropos_case_base")


def _source_digest(root, with_ros=False):
    """A digest of the checkout's sources that the copy holds (tether_sim/, its ros/ when asked, ropos_case.py):
    the copy is made again whenever the other checkout changes, never taken stale from an earlier run."""
    root = Path(root)
    h = hashlib.sha1(b"+ros" if with_ros else b"")
    files = sorted(p for p in (root / "tether_sim").rglob("*.py")
                   if "__pycache__" not in p.parts and (with_ros or "ros" not in p.relative_to(root).parts[1:2]))
    for path in files + [root / "benchmarks" / "ropos_case.py"]:
        h.update(str(path.relative_to(root)).encode())
        h.update(path.read_bytes())
    return h.hexdigest()[:12]


def _copy_renamed(root, tmp, with_ros=False):
    shutil.rmtree(tmp, ignore_errors=True)
    shutil.copytree(Path(root) / "tether_sim", tmp / "tether_sim_base",
                    ignore=shutil.ignore_patterns("__pycache__", *(() if with_ros else ("ros",))))
    shutil.copy(Path(root) / "benchmarks" / "ropos_case.py", tmp / "ropos_case_base.py")
    for path in list((tmp / "tether_sim_base").rglob("*.py")) + [tmp / "ropos_case_base.py"]:
        text = path.read_text()
        path.write_text(re.sub(r"\btether_sim(?=\.|\s+import)", "tether_sim_base", text))


def best_of(fn, repeat):
    best = np.inf
    for _ in range(repeat):
        c = time.thread_time()
        fn()
        best = min(best, time.thread_time() - c)
    return best


def prepared(factory, rc, length, n, alpha, t_warm=2.0):
    sol = factory.build_solver(rc.ropos_config(length, alpha=alpha, n_elements=n, order=4))
    for k in range(int(t_warm * 50)):
        t1 = (k + 1) / 50.0
        sol.set_end_motion("ship", *rc.fairlead_motion(t1))
        sol.advance_to(t1)
    sol.drain_end_tensions()
    return sol


def timed_blocks(sol, rc, steps, ticks=25):
    """(substep block, tick block, substeps per tick, reset) of a prepared solver: two callables that
    each restore the same state and do the same work every call, the substeps a tick takes, and a
    callable that puts the solver back in that state."""
    snap = sol.snapshot()
    dt = sol._substep()
    t1 = sol.time + steps * dt
    target = rc.fairlead_motion(t1)
    t0 = sol.time
    motions = [rc.fairlead_motion(t0 + (k + 1) / 50.0) for k in range(ticks)]
    counts = []

    def substeps():
        sol.restore(snap)
        sol.set_end_motion("ship", *target)
        sol.advance_to(t1)
        sol.drain_end_tensions()

    def run_ticks():
        sol.restore(snap)
        for k in range(ticks):
            sol.set_end_motion("ship", *motions[k])
            counts.append(sol.advance_to(t0 + (k + 1) / 50.0))
            sol.drain_end_tensions()
            sol.state()
            sol.end_forces()
            sol.body_state("vehicle")

    def reset():
        sol.restore(snap)
        sol.drain_end_tensions()

    run_ticks()
    nsub = float(np.mean(counts))
    reset()
    return substeps, run_ticks, nsub, reset


def measure_trees(sols, steps, repeat, ticks=25):
    """{tree: (us per substep, us per tick, substeps per tick)} for prepared solvers {tree: (sol, rc)}.
    The trees take turns within every repeat (base, new, then new, base on the next), so a change of
    the machine's load during the run falls on both alike; best of ``repeat`` per tree."""
    blocks = {name: timed_blocks(sol, rc, steps, ticks) for name, (sol, rc) in sols.items()}
    best = {name: [np.inf, np.inf] for name in sols}
    order = list(sols)
    for r in range(repeat):
        for which in (0, 1):  # 0: substep blocks, 1: tick blocks
            for name in (order if r % 2 == 0 else order[::-1]):
                c = time.thread_time()
                blocks[name][which]()
                best[name][which] = min(best[name][which], time.thread_time() - c)
    for block in blocks.values():
        block[3]()
    return {name: (1e6 * best[name][0] / steps, 1e6 * best[name][1] / ticks, blocks[name][2]) for name in sols}


def split(sol, rc, repeat, n=200):
    """us per call of each part of a node tick (this tree only): the public calls, and the compiled
    entries they make (tick.dg_tick for advance_to, sampling.sample_state for state()), so that
    "Python" = call - compiled entry."""
    from tether_sim.solvers.dg.tick import dg_tick
    sol.state()  # a node reads outputs: from now on the tick evaluates them (tick.dg_tick)
    snap = sol.snapshot()
    t0, dt = sol.time, sol._substep()
    motion = rc.fairlead_motion(t0 + dt)
    ws = sol.ws

    def calls(fn):
        def run():
            for _ in range(n):
                fn()
        return 1e6 * best_of(run, repeat) / n

    def one_substep():  # advance_to over one substep from the same state
        sol.restore(snap)
        sol.set_end_motion("ship", *motion)
        sol.advance_to(t0 + dt)

    def restore_only():
        sol.restore(snap)
        sol.set_end_motion("ship", *motion)

    def compiled_tick():
        sol.restore(snap)
        sol.set_end_motion("ship", *motion)
        dg_tick(ws.F, ws.I, ws.spec, t0, t0 + dt, 1, dt, True)

    out = {"set_end_motion": calls(lambda: sol.set_end_motion("ship", *motion))}
    base = calls(restore_only)
    out["advance_to (1 substep)"] = calls(one_substep) - base
    out["dg_tick (same work)"] = calls(compiled_tick) - base
    sol.restore(snap)
    sol.advance_to(t0 + dt)
    out["drain_end_tensions"] = calls(sol.drain_end_tensions)
    out["state()"] = calls(sol.state)
    out["end_forces()"] = calls(sol.end_forces)
    out["body_state()"] = calls(lambda: sol.body_state("vehicle"))
    sol.restore(snap)
    return out


def solver_ticks(trees, repeat, config_file, ticks=25, t_warm=1.0):
    """us per node tick of the solver of ``config_file`` (its ship end on a 0.5 m circle, solver.tick +
    state() at 50 Hz as a node calls them), per tree: blocks of ``ticks`` ticks
    taken in turn from each tree, best of ``repeat`` (the trees' states stay the same when their
    results are bit-identical, so each block does the same work in both)."""
    root = Path(__file__).resolve().parents[1]
    sols = {}
    for name, fac, mod in trees:
        params = importlib.import_module(fac.__name__.rsplit(".", 2)[0] + ".io.params")
        sol = fac.build_solver(params.load_config(root / config_file))
        sols[name] = [sol, np.asarray(sol.config.ship_end.position, float)]

    def block(name, n):
        sol, p0 = sols[name]
        for _ in range(n):
            t = sol.time + 0.02
            pos = p0 + 0.5 * np.array((np.cos(t) - 1.0, np.sin(t), 0.0))
            sol.tick(t, ship=(pos, 0.5 * np.array((-np.sin(t), np.cos(t), 0.0))), drain=True)
            sol.state()

    best = {name: np.inf for name in sols}
    for name in sols:
        block(name, int(t_warm * 50))
    for _ in range(repeat):
        for name in sols:
            c = time.thread_time()
            block(name, ticks)
            best[name] = min(best[name], (time.thread_time() - c) / ticks)
    return {name: 1e6 * v for name, v in best.items()}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--baseline", help="root of another checkout to time in the same process")
    ap.add_argument("--steps", type=int, default=2000)
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--cases", default="all", help="comma-separated indices into CASES, or all")
    ap.add_argument("--split", action="store_true", help="also time each call of a tick (this tree)")
    ap.add_argument("--hybrid", action="store_true", help="time the hybrid solver's node tick instead (solver_ticks on "
                    "config/ropos_L200_hybrid.yaml)")
    ap.add_argument("--solver-tick", metavar="FILE", help="time solver.tick + state() of FILE's solver instead (solver_ticks)")
    args = ap.parse_args(argv)
    from benchmarks import ropos_case as rc
    from tether_sim.solvers import factory
    trees = [("new", factory, rc)]
    if args.baseline:
        trees.insert(0, ("base",) + load_baseline(args.baseline))
    if args.hybrid or args.solver_tick:
        config_file = args.solver_tick or "config/ropos_L200_hybrid.yaml"
        us = solver_ticks(trees, args.repeat, config_file)
        print(f"bench_tick {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load "
              f"{os.getloadavg()[0]:.1f}; thread CPU, best of {args.repeat} blocks of 25 ticks; {config_file}: "
              + ", ".join(f"{name} {v:.0f} us/tick" for name, v in us.items())
              + (f"; new/base {us['new'] / us['base']:.3f}" if "base" in us else ""), flush=True)
        return
    cases = CASES if args.cases == "all" else [CASES[int(k)] for k in args.cases.split(",")]
    print(f"bench_tick {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load {os.getloadavg()[0]:.1f}; "
          f"thread CPU, best of {args.repeat}; P = 4, cage body, 50 Hz ticks", flush=True)
    for length, n, alpha in cases:
        sols = {name: (prepared(fac, mod, length, n, alpha), mod) for name, fac, mod in trees}
        row = measure_trees(sols, args.steps, args.repeat)
        line = f"  L={length:6.0f} N={n:2d} alpha={alpha:g}:"
        for name, (sub, tick, nsub) in row.items():
            line += f" | {name}: substep {sub:6.2f} us, tick {tick:7.1f} us ({nsub:.1f} substeps), " \
                    f"overhead {tick - nsub * sub:6.1f} us"
        if "base" in row:
            b, w = row["base"], row["new"]
            line += f" | new/base substep {w[0] / b[0]:.3f}, tick {w[1] / b[1]:.3f}"
        print(line, flush=True)
        if args.split:
            parts = split(prepared(factory, rc, length, n, alpha), rc, args.repeat)
            print("    per call (new): " + ", ".join(f"{k} {v:.1f} us" for k, v in parts.items()), flush=True)


if __name__ == "__main__":
    main()
