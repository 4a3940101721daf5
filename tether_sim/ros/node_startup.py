"""What the node does once before its first tick: compile (or load from the numba cache) every
compiled path the ticks use, and refuse a solver too slow for the wall clock (docs/node.md, "Stepping policy": start-up and its speed check).
Functions of the node (:class:`tether_sim.ros.sim_node.TetherSimNode`), which calls them in its constructor.
"""

import math
import time

import numpy as np

from tether_sim.errors import ConfigError
from tether_sim.physics.snap import SnapDetector
from tether_sim.ros import convert
from tether_sim.ros.driver import END_NAMES


def warm_up(node, solver_factory):
    """Build a throw-away solver, take two substeps and call every output the ticks use (state
    at the output points, end forces, body states, substep tensions, the snap detector) before
    any publisher exists, so JIT compiling (or loading the numba cache) happens now, not in the
    first ticks, and a configuration the solver cannot build fails at start-up; a recorder or
    test waiting for our topics waits for this too."""
    t0 = time.perf_counter()
    solver = solver_factory(node.config)
    for end in END_NAMES:
        cond = getattr(node.config, f"{end}_end")
        if cond.kind == "prescribed":
            solver.set_end_motion(end, cond.position, (0.0, 0.0, 0.0))
    solver.advance_to(solver.time + 2.0 * solver.stable_time_step())
    solver.state(np.linspace(0.0, node.config.cable.length, node.config.node.output_points))
    forces = solver.end_forces()
    for end in END_NAMES:
        solver.body_state(end)
    times, t_ship, t_vehicle = solver.drain_end_tensions()
    static = [max(abs(float(forces.ship_tension)), 1.0), max(abs(float(forces.vehicle_tension)), 1.0)]
    detector = SnapDetector(node.config.snap, list(END_NAMES), static, [0.0, node.config.cable.length])
    detector.update(np.asarray(times, float), np.column_stack([t_ship, t_vehicle]))
    convert.tension_colours(np.zeros(2), 1.0)  # the marker's colour loop (compiled)
    node.get_logger().info(f"{node.config.solver} solver warmed up in {time.perf_counter() - t0:.1f} s")
    check_speed(node, solver)


def check_speed(node, solver):
    """Time the warmed-up solver in this thread's CPU time (the machine's load does not enter)
    and, on the wall clock, refuse to start a solver that cannot keep up with it within
    ``node.tick_budget`` (docs/node.md): such a node never follows its input, it only
    re-synchronises. ``node.require_real_time: false`` starts it anyway."""
    rtf = solver_speed(solver)
    cfg = node.config.node
    needed = 1.0 / cfg.tick_budget
    node.get_logger().info(f"solver speed: {rtf:.3g} x real time per CPU second (the node needs {needed:.3g} x "
                           "on the wall clock: node.tick_budget)")
    if rtf >= needed or node.get_parameter("use_sim_time").value or not cfg.require_real_time:
        return
    raise ConfigError(f"the solver runs at {rtf:.3g} x real time per CPU second on this machine, the node needs "
                      f"{needed:.3g} x (1 / node.tick_budget) to follow the clock: it would only fall behind and "
                      f"re-synchronise. {coarser_mesh_hint(node.config, rtf / needed)}; or start it anyway with "
                      "-p node.require_real_time:=false (late outputs, marked degraded)")


def solver_speed(solver, cpu_s: float = 0.25, max_sim_s: float = 2.0) -> float:
    """Simulated seconds per CPU second of ``solver`` (this thread's CPU time), from batches of
    substeps until ``cpu_s`` of CPU or ``max_sim_s`` of simulated time have passed."""
    dt = solver.stable_time_step()
    t_sim0, cpu0 = solver.time, time.thread_time()
    while True:
        solver.advance_to(solver.time + 10.0 * dt)
        cpu, sim = time.thread_time() - cpu0, solver.time - t_sim0
        if cpu >= cpu_s or sim >= max_sim_s:
            return sim / max(cpu, 1e-9)


def coarser_mesh_hint(config, speed_ratio: float) -> str:
    """The mesh that would keep up, from the measured speed over the needed one (< 1). DG: a
    substep's work grows with N and the stable substep shrinks as 1/N, so the speed goes as 1/N^2;
    hybrid: fixed time step, work about linear in the segments."""
    if config.solver == "dg":
        n = config.dg.n_elements
        keep = max(1, int(n * math.sqrt(speed_ratio)))
        return (f"A coarser mesh keeps up: about -p dg.resolution:=manual -p dg.n_elements:={keep} (now {n}, "
                f"order {config.dg.order})")
    n = config.hybrid.n_segments
    return f"A coarser mesh keeps up: about -p hybrid.n_segments:={max(1, int(n * speed_ratio))} (now {n})"
