"""Compile (or load from numba's on-disk cache) the solver kernels ahead of time.

``python -m tether_sim.warm`` is the warm-up stage of ``tools/setup_env.sh``: it builds each solver
variant the shipped configurations use, takes two substeps and calls every output the node and the
offline runner use (state at the output points, end forces, body states, substep end tensions and
the snap detector), one *kernel group* at a time with its progress printed. A line-network file
(config/ropos_tms.yaml) is run as its node runs it (:func:`exercise_network`): the network statics,
the settling, coupling steps with the bodies' compiled kicks, each line's winch paying out, every
line's state at the output points and its snap detector. numba compiles each
kernel on its first call and caches the machine code next to the source (``__pycache__/*.nbi``,
``*.nbc``); the cache is keyed on the source files, so the set-up reruns this stage whenever a
source file of ``tether_sim`` changes (a warm run takes a few seconds: every kernel is a cache
load).

:func:`run_interruptibly` is what the node uses at start-up: it runs the warm-up in a worker thread
while the calling (main) thread waits, says what it is doing when the work takes longer than a
cache load, and returns at once when asked to stop (SIGINT/SIGTERM), so a node started with a cold
cache can be stopped while it compiles.

No ROS here: nothing imports rclpy or a message package (the line-network group drives
``tether_sim.ros.network_driver``, which imports neither; test/test_layering.py).
"""

from __future__ import annotations

import argparse
import os
import sys
import threading
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
# (name, parameter file): one per solver variant with kernels of its own. The node and `make run`
# use the first; the others are the bending (LDG), implicit-damping and hybrid code paths that the
# scenarios, the test suite and the other shipped configurations reach, and the line network.
# test/test_warm_coverage.py fails when a shipped configuration's start compiles a kernel these leave out.
GROUPS = (
    ("DG solver with a cage (make run, the ROPOS live configurations)", "config/ropos_validation.yaml"),
    ("DG solver with bending (LDG) and clamped/force ends", "config/cantilever.yaml"),
    ("DG solver with implicit damping", "config/koh_swinging_cable.yaml"),
    ("hybrid rod-catenary solver", "config/ropos_L200_hybrid.yaml"),
    ("hybrid rod with bending and torsion (frames along the rod)", "config/goyal_perkins.yaml"),
    ("dynamic-relaxation statics (the ROV demo)", "config/rov_demo.yaml"),
    ("line network: main tether and excursion tether on the cage, bodies, winches (the TMS file)",
     "config/ropos_tms.yaml"),
)
# what a cold start costs, measured (docs/node.md "Stepping policy"): said to the user while waiting
COLD_COMPILE_NOTE = ("about 1.5 min on an idle 2-core machine, ~10 min at load 10; "
                     "`make setup` (tools/setup_env.sh) does this ahead of time")


class Interrupted(Exception):
    """The warm-up was asked to stop before it finished."""


_workers = set()  # warm-up threads still running


def exit_if_compiling(code: int = 0) -> None:
    """Leave the process at once (``os._exit``) when an abandoned warm-up thread is still compiling.

    An orderly interpreter exit waits for it to let go (~2.2 s measured at load 10, while
    ``os._exit`` took 0.2 s); nothing is lost: numba writes a cache file only when a compile
    finishes, and the caller has nothing else open. A no-op when no warm-up is running."""
    if any(t.is_alive() for t in _workers):
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(code)


def exercise(config, solver_factory=None) -> None:
    """Build the solver of ``config``, take two substeps and call every output a tick uses."""
    from tether_sim.physics.boundary import END_NAMES
    from tether_sim.physics.snap import SnapDetector
    from tether_sim.solvers.factory import build_solver

    solver = (solver_factory or build_solver)(config)
    ends = END_NAMES
    for end in ends:
        cond = getattr(config, f"{end}_end")
        if cond.kind == "prescribed":
            solver.set_end_motion(end, cond.position, (0.0, 0.0, 0.0))
    solver.advance_to(solver.time + 2.0 * solver.stable_time_step())
    if config.ship_end.kind == "prescribed":  # the interface's one-call tick with the ship's motion (a forecast
        # member's tick, ForecastRunner; the network's lines): its compiled path is another kernel than advance_to's
        solver.tick(solver.time + 2.0 * solver.stable_time_step(),
                    ship=(np.asarray(config.ship_end.position, dtype=np.float64), np.zeros(3)))
    solver.state(np.linspace(0.0, config.cable.length, config.node.output_points))
    forces = solver.end_forces()
    for end in ends:
        solver.body_state(end)
    times, t_ship, t_vehicle = solver.drain_end_tensions()
    static = [max(abs(float(forces.ship_tension)), 1.0), max(abs(float(forces.vehicle_tension)), 1.0)]
    detector = SnapDetector(config.snap, list(ends), static, [0.0, config.cable.length])
    detector.update(np.asarray(times, float), np.column_stack([t_ship, t_vehicle]))
    from tether_sim.numerics.colour_map import tension_rgba

    tension_rgba(np.zeros(2), 1.0, np.empty((2, 4)))  # the marker's colours (the node's outputs)


def exercise_network(path, ticks: int = 4) -> None:
    """Run the line-network file ``path`` as the network node and the offline runner do: the
    driver's start (statics, settling, detectors), ``ticks`` output periods with every winch paying
    out from the second on (a command's first tick must not compile), each body's motion for the
    outputs (NetworkSolver.body_motion), each line's state at the
    output points (a read-only array, as the outputs pass it: numba compiles read-only arrays
    separately)."""
    from tether_sim.network.params import load_network_files
    from tether_sim.ros.network_driver import NetworkDriver

    spec, cfg = load_network_files([path])
    node = cfg.node
    driver = NetworkDriver(spec, node)
    driver.start(0.0)
    now, period = 0.0, 1.0 / node.output_rate
    for k in range(ticks):
        if k == 1:
            for line, link in driver.net.winches.items():
                driver.net.command_winch(line, "speed", 0.5 * link.config.winch.max_speed, "topic")
        now += period
        report = driver.tick(now)
        if report.error:
            raise RuntimeError(f"{path}: {report.error}")
    for name in driver.net.bodies:  # the outputs' body motion (its compiled loads and accelerations)
        driver.net.body_motion(name)
    for line, solver in driver.net.lines.items():
        length = float(getattr(solver, "unstretched_length", spec.lines[line].config.cable.length))
        at = np.linspace(0.0, length, node.output_points)
        at.flags.writeable = False
        solver.state(at)


def warm_group(params, root: Path = REPO) -> None:
    """Exercise one group's parameter file (a line network or a single line)."""
    from tether_sim.io.params import load_config
    from tether_sim.network.params import file_is_network

    path = root / params
    if file_is_network(path):
        exercise_network(path)
    else:
        exercise(load_config(path))


def warm_groups(groups=GROUPS, root: Path = REPO, out=print) -> float:
    """Run :func:`exercise` for each group, printing progress; returns the total wall time."""
    t_all = time.perf_counter()
    for k, (name, params) in enumerate(groups, 1):
        t0 = time.perf_counter()
        out(f"[warm-up {k}/{len(groups)}] {name} ({params}) ...")
        warm_group(params, root)
        out(f"[warm-up {k}/{len(groups)}] done in {time.perf_counter() - t0:.1f} s")
    return time.perf_counter() - t_all


def compiled_count() -> int:
    """Kernels numba has compiled in this process because its cache had no entry for them (cache
    misses of every numba dispatcher in the loaded tether_sim modules; 0 when all came from the
    cache or the JIT is off)."""
    from numba.core.dispatcher import Dispatcher

    total = 0
    for name, module in sys.modules.copy().items():  # copy(): atomic while other threads import
        if not name.startswith("tether_sim.") or module is None:
            continue
        for value in list(vars(module).values()):
            if isinstance(value, Dispatcher):
                total += sum(value.stats.cache_misses.values())
    return total


def run_interruptibly(work, *, log, should_stop, what: str, quiet_for: float = 3.0,
                      every: float = 30.0, poll: float = 0.1, compiled=compiled_count):
    """Run ``work()`` in a daemon thread; the caller's thread waits for it, polling ``should_stop()``.

    Once ``quiet_for`` s have passed and numba has compiled a kernel (``compiled()`` > 0: a cold
    cache), ``log`` says so and how long a cold compile takes, then every ``every`` s how far it
    is; a slow start without compiling (a loaded machine) is noted every ``every`` s. Raises
    :class:`Interrupted` as soon as ``should_stop()`` is true (the daemon thread is abandoned: the
    caller then exits, see :func:`exit_if_compiling`), re-raises an exception of ``work``, returns
    its result. A signal handler of the main thread (Python's or rclpy's) runs while this thread
    waits, because the compiling thread releases the GIL in LLVM and at every switch interval.
    """
    result, done = {}, threading.Event()

    def target():
        try:
            result["value"] = work()
        except BaseException as exc:  # noqa: BLE001 - handed to the waiting thread
            result["error"] = exc
        finally:
            done.set()
            _workers.discard(threading.current_thread())

    t0 = time.monotonic()
    worker = threading.Thread(target=target, name="tether-sim-warm-up", daemon=True)
    _workers.add(worker)
    worker.start()
    told, next_note = False, t0 + every
    while not done.wait(poll):
        if should_stop():
            raise Interrupted(f"stopped while {what}")
        now = time.monotonic()
        if not told and now - t0 >= quiet_for and compiled() > 0:
            log(f"{what}: compiling the numba kernels (the cache is cold: first start after an install "
                f"or a source change; {COLD_COMPILE_NOTE}). Ctrl-C stops.")
            told, next_note = True, now + every
        elif now >= next_note:
            n = compiled()
            log(f"{what}: still compiling ({n} kernels so far, {now - t0:.0f} s)" if n else
                f"{what}: still warming up after {now - t0:.0f} s (loading the numba cache, static "
                f"solve; a loaded machine)")
            next_note = now + every
    if "error" in result:
        raise result["error"]
    return result.get("value")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m tether_sim.warm", description=__doc__.split("\n")[0])
    ap.add_argument("--list", action="store_true", help="list the kernel groups and exit")
    ap.add_argument("--groups", type=int, nargs="*", default=None,
                    help="numbers (1-based) of the groups to warm (default: all)")
    args = ap.parse_args(argv)
    if args.list:
        for k, (name, params) in enumerate(GROUPS, 1):
            print(f"{k}. {name} ({params})")
        return 0
    groups = GROUPS if not args.groups else [GROUPS[k - 1] for k in args.groups]
    try:
        took = warm_groups(groups)
    except KeyboardInterrupt:
        print("[warm-up] interrupted", file=sys.stderr)
        return 130
    print(f"[warm-up] {len(groups)} kernel group(s) ready in {took:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
