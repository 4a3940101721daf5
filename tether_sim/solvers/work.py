"""What one simulated second of a configuration costs, estimated at load time (nothing is built).

Every key can sit inside its documented range and still make a run that never ends: the DG solver
steps explicitly with the substep of dg/timestep.py, which falls as 1/h for the axial waves and as
1/h^2 (1/h^4) for material damping and bending (bending damping), so ``dg.n_elements: 2000`` on the
ROPOS tether with its axial damping asks for a 1.3e-8 s substep, 2.3e7 substeps for 0.3 s. The
hybrid solver does one implicit step of ``hybrid.n_segments`` segments every ``hybrid.time_step``.

The counts are machine-independent (element-mode updates, segment-steps per simulated second); the
CPU time per count was measured on the 2-core reference machine on 2026-11-27 (load average 7,
``nice -n 10``; the commands in docs/parameters.md):

- DG, ROPOS L = 200 m: 0.33-0.55 us of CPU per element-mode per SSP-RK3 substep
  (N = 20, P = 4: 0.55; N = 200, P = 2: 0.42; N = 2000, P = 2: 0.33);
- DG with ``dg.damping: implicit`` (measured 2026-11-27, load ~13, ``bench_work_estimate.py``): the
  axial damping solve (no bending damping) 0.88-0.95 us per element-mode per substep (ROPOS 200 m,
  N = 20 and 40, P = 4); with bending damping (the general block solve) 34 us (Koh's swinging cable,
  N = 20, P = 4): 75 times an explicit update, so its cheaper substep is not a cheaper run there;
- hybrid, ROPOS L = 200 m: 9.5-19 us per segment per implicit step (50-800 segments).

With a winch (``winch.enabled``) the length changes during the run: the DG elements scale with it, so
the estimate is taken at the shortest length the winch can reach (``winch.min_length``, with its
transport speed ``winch.max_speed``), and the hybrid solver adds segments as it pays out, so there at
the longest (``winch.max_length``).

``check_work`` refuses (ConfigError) a configuration whose estimate exceeds ``work_limit`` CPU
seconds per simulated second, naming the keys that set the substep and the limit, and a
``dg.fixed_time_step`` above the stability limit (the solver's own check, made at load).
"""

import math
from dataclasses import dataclass, replace

import numpy as np

from tether_sim.errors import ConfigError
from tether_sim.solvers.config import SPLIT_DAMPING

DG_UPDATE_CPU = 0.45e-6  # CPU s per element-mode per substep (the upper half of the measured 0.33-0.55 us)
DG_IMPLICIT_AXIAL_CPU = 0.95e-6  # the same with the implicit axial damping solve (measured 0.88-0.95 us)
DG_IMPLICIT_GENERAL_CPU = 35e-6  # the same with the implicit bending-damping (general) solve (measured 34 us)
HYBRID_SEGMENT_CPU = 15e-6  # CPU s per segment per implicit step (measured 9.5-19 us)

# the terms of the DG substep rule (dg/timestep.py) and the keys that set each
_DG_TERMS = {
    "waves": ("axial waves", ("cable.EA", "cable.gamma0", "dg.lambda_floor"), "a lower axial stiffness"),
    "damping": ("axial material damping", ("cable.damping",), "dg.damping: implicit, or less cable.damping"),
    "bending": ("bending waves", ("cable.EI",), "less cable.EI"),
    "bending_damping": ("bending damping", ("cable.bending_damping",),
                        "dg.damping: implicit, or less cable.bending_damping"),
    "seabed": ("seabed contact", ("environment.seabed_stiffness",), "a softer seabed"),
}


@dataclass(frozen=True)
class Work:
    """The estimate: ``substep`` (s), ``count`` (unknown updates per simulated second: element-modes
    x substeps for dg, segments x steps for hybrid), ``cpu`` (CPU s per simulated second on the
    reference machine) and the sentence that says what sets them."""

    substep: float
    count: float
    cpu: float
    cause: str


def mesh_sizes(length, n_elements, weights=()) -> np.ndarray:
    """The DG element lengths (m) of a cable of ``length``: the relative ``weights`` (dg.element_lengths,
    one per element) scaled to it, or ``n_elements`` equal ones when there are none."""
    if len(weights) == 0:
        return np.full(int(n_elements), float(length) / int(n_elements))
    w = np.asarray(weights, float)
    return np.ascontiguousarray(w / w.sum() * float(length))


def element_sizes(config) -> np.ndarray:
    """The DG element lengths (m) of ``config`` (:func:`mesh_sizes` of its cable and dg keys)."""
    return mesh_sizes(config.cable.length, config.dg.n_elements, config.dg.element_lengths)


def winch_range(config) -> tuple:
    """(shortest, longest) unstretched length the run can reach, m: ``winch.min_length`` and
    ``winch.max_length`` with a winch (a command on the winch topic may ask for either at any time; the
    winch never passes them), else the configured length twice."""
    L, w = float(config.cable.length), config.winch
    if not w.enabled:
        return L, L
    return min(float(w.min_length), L), max(float(w.max_length), L)


def dg_work(config) -> Work:
    """The DG estimate, with the substep of the solver's own rule (``stable_time_step``); with a winch,
    at the shortest length it can haul in to (:func:`dg_winch_work`), where the elements are shortest."""
    work = dg_work_at_length(config)
    shortest = winch_range(config)[0]
    if shortest < float(config.cable.length):
        hauled = dg_winch_work(config, shortest)
        if hauled.cpu > work.cpu:
            return hauled
    return work


def dg_winch_work(config, length) -> Work:
    """The DG estimate with the cable hauled in to ``length``: the elements scale with the length (h_e =
    w_e L(t), docs/dg_solver.md "Winch") and the winch's transport at ``winch.max_speed`` adds to the
    wave speed, as in the solver's own rule while the winch moves (dg/winch_driver.py ``limit``)."""
    from tether_sim.solvers.dg.timestep import _A, _coef

    cab, opt, w = config.cable, config.dg, config.winch
    scaled = replace(config, cable=replace(cab, length=float(length)), dg=replace(opt, fixed_time_step=0.0))
    at = dg_work_at_length(scaled)
    h, P = element_sizes(scaled), int(opt.order)
    limit = 1.0 / (opt.cfl / at.substep + _coef(_A, P, 2) * float(w.max_speed) / float(np.min(h)))
    if opt.fixed_time_step > 0.0:
        if opt.fixed_time_step > limit:  # the solver's own check while the winch moves (UnstableTimeStepError)
            raise ConfigError(f"dg.fixed_time_step = {opt.fixed_time_step:g} s exceeds the stability limit {limit:.3g} s "
                              f"of the cable hauled in to winch.min_length = {float(length):g} m (elements down to "
                              f"{float(np.min(h)):.3g} m): reduce it, or raise winch.min_length")
        substep = float(opt.fixed_time_step)
    else:
        substep = opt.cfl * limit
    count = h.size * (P + 1) / substep
    cause = (f"{at.cause.split(': the substep')[0]} hauled in to winch.min_length = {float(length):g} m (of "
             f"cable.length = {float(cab.length):g} m; winch.max_speed = {float(w.max_speed):g} m/s): the substep there "
             f"is {substep:.3g} s (remedies: a longer winch.min_length, fewer elements or a lower order)")
    return Work(substep, count, count * dg_update_cpu(config), cause)


def dg_work_at_length(config) -> Work:
    """The DG estimate at the configured length (``stable_time_step`` of the solver as built)."""
    from tether_sim.physics.constitutive import TensionLaw
    from tether_sim.solvers.dg.timestep import config_stable_dt, stable_dt

    cab, env, opt = config.cable, config.environment, config.dg
    h, P = element_sizes(config), int(opt.order)
    slope = TensionLaw(cab).max_slope()
    implicit = opt.damping in SPLIT_DAMPING
    kd = env.seabed_stiffness * cab.diameter if env.seabed else 0.0
    rule = config_stable_dt(config, h, slope, implicit)
    dofs = h.size * (P + 1)
    mesh = f"dg.n_elements = {h.size}, dg.order = {P} (elements down to {float(np.min(h)):.3g} m)"
    if opt.fixed_time_step > 0.0:
        if opt.fixed_time_step > rule / opt.cfl:  # the solver's own check (UnstableTimeStepError), at load
            raise ConfigError(f"dg.fixed_time_step = {opt.fixed_time_step:g} s exceeds the stability limit "
                              f"{rule / opt.cfl:.3g} s of {mesh} (cfl = 1; the automatic substep with dg.cfl = "
                              f"{opt.cfl:g} would be {rule:.3g} s): reduce it, or use fewer elements / a lower order")
        substep, cause = float(opt.fixed_time_step), f"dg.fixed_time_step = {opt.fixed_time_step:g} s on {mesh}"
    else:
        one = {  # each term of the rule alone (the others zero): the largest rate names the cause
            "waves": stable_dt(h, P, slope, cab.gamma0, 0.0, 0.0, 0.0, opt.lambda_floor),
            "damping": stable_dt(h, P, 0.0, cab.gamma0, 0.0 if implicit else cab.damping, 0.0, 0.0),
            "bending": stable_dt(h, P, 0.0, cab.gamma0, 0.0, cab.EI, 0.0),
            "bending_damping": stable_dt(h, P, 0.0, cab.gamma0, 0.0, 0.0, 0.0 if implicit else cab.bending_damping),
            "seabed": stable_dt(h, P, 0.0, cab.gamma0, 0.0, 0.0, 0.0, 0.0, kd, env.seabed_damping) if kd > 0 else 1.0,
        }
        term = min(one, key=one.get)
        what, keys, remedy = _DG_TERMS[term]
        values = ", ".join(f"{k} = {_value(config, k):g}" for k in keys)
        substep = rule
        cause = (f"{mesh} with {values}: the substep of the stability rule is {substep:.3g} s, set by the "
                 f"{what} (remedies: fewer elements or a lower order, {remedy})")
    count = dofs / substep
    return Work(substep, count, count * dg_update_cpu(config), cause)


def dg_update_cpu(config) -> float:
    """CPU s per element-mode per substep of the DG solver with ``config``'s damping (the solver's own
    choice of the implicit damping mode, dg/solver.py ``_damping``)."""
    cab = config.cable
    if config.dg.damping not in SPLIT_DAMPING or not (cab.damping > 0.0 or cab.bending_damping > 0.0):
        return DG_UPDATE_CPU
    return DG_IMPLICIT_GENERAL_CPU if cab.bending_damping > 0.0 else DG_IMPLICIT_AXIAL_CPU


def hybrid_work(config) -> Work:
    """One implicit step of every segment per ``hybrid.time_step``. With a winch the segments keep their
    length (one is added per cable.length / hybrid.n_segments paid out, hybrid/winch.py), so the count
    is that of the longest length the winch can pay out to."""
    opt = config.hybrid
    n0 = int(opt.n_segments)
    length, longest = float(config.cable.length), winch_range(config)[1]
    n = n0 + max(0, math.ceil((longest - length) / (length / n0) - 1e-9))
    count = n / float(opt.time_step)
    cause = f"hybrid.n_segments = {n0} with hybrid.time_step = {opt.time_step:g} s"
    if n > n0:
        cause += (f", {n} segments when the winch has paid out to winch.max_length = {longest:g} m "
                  "(remedies: a shorter winch.max_length, fewer segments, a longer time step)")
    else:
        cause += " (remedies: fewer segments, a longer time step)"
    return Work(float(opt.time_step), count, count * HYBRID_SEGMENT_CPU, cause)


def estimate(config) -> Work:
    return hybrid_work(config) if config.solver == "hybrid" else dg_work(config)


def check_work(config, where: str = "parameters") -> None:
    """ConfigError when one simulated second would cost more than ``work_limit`` CPU seconds."""
    try:
        work = estimate(config)
    except ConfigError as exc:
        raise ConfigError(f"{where}: {exc}") from exc
    limit = float(config.work_limit)
    if limit <= 0.0:
        return
    if not math.isfinite(work.cpu) or work.cpu > limit:
        unit = "element-mode updates" if config.solver != "hybrid" else "segment-steps"
        raise ConfigError(
            f"{where}: {work.cause}; {work.count:.3g} {unit} per simulated second, about {work.cpu:.3g} CPU s per "
            f"simulated second on the reference machine, above the limit work_limit = {limit:g} s "
            "(work_limit: 0 lifts it)")


def _value(config, dotted: str) -> float:
    obj = config
    for part in dotted.split("."):
        obj = getattr(obj, part)
    return float(obj)


# What a whole run (tether-sim-offline, a study case) costs besides the solver's substeps: each output
# tick (messages, /tf, the snap detector, the MCAP write; for the hybrid solver also its Python per step
# and its state profile, which the per-segment figure above does not carry) and the start (the numba
# cache, the static solve). Measured with tether-sim-offline on the 2-core reference machine, 2026-11-27, load 13-14
# (CPU time of the process from the start of the solver to the file's close; commands in docs/node.md
# "Offline runner"): start 1.0-1.24 s; DG 0.65-0.88 ms per tick (ropos_L200, ropos_L1730, 20 s);
# hybrid 10.7-12.4 ms per tick all in (ropos_L1730_hybrid, ropos_L200_hybrid, 10 s).
TICK_CPU = {"dg": 0.8e-3, "hybrid": 9e-3}  # CPU s per output tick
START_CPU = 1.1  # CPU s


def run_estimate(config, duration: float) -> tuple:
    """(CPU seconds, one line) that a run of ``duration`` simulated seconds with outputs at
    node.output_rate (tether-sim-offline, a study case) is expected to take on the reference machine,
    before it starts: :func:`estimate` (with a winch: at its worst reachable length) plus the outputs'
    and the start's share."""
    work = estimate(config)
    n_ticks = max(1, int(round(duration * config.node.output_rate)))
    solver, outputs = work.cpu * duration, n_ticks * TICK_CPU.get(config.solver, TICK_CPU["dg"])
    total = START_CPU + solver + outputs
    return total, (f"{duration:.6g} s simulated, {n_ticks} output ticks: expected to take about {span(total)} of "
                   f"CPU on an idle core (solver ~{span(solver)}, outputs ~{span(outputs)}; the solver's "
                   f"substep {work.substep:.3g} s{' at the shortest length the winch can reach' if config.winch.enabled else ''}); "
                   "longer on a busy machine")


def span(seconds: float) -> str:
    """A CPU time as people read it: 42 s, 5.3 min, 2.1 h."""
    if seconds < 120.0:
        return f"{seconds:.2g} s" if seconds < 10.0 else f"{seconds:.0f} s"
    return f"{seconds / 60.0:.2g} min" if seconds < 7200.0 else f"{seconds / 3600.0:.2g} h"
