"""The ROPOS tether-cage system [PE2020 Sec. 6, Table 3, App. A; Driscoll et al.].

Configurations, the closed-form static check, one dynamic run through the solver interface
(with streaming snap detection on every substep) and the snap-front lag measurement. The
Section 6.2 study and the Appendix A mesh study are in :mod:`tether_sim.scenarios.ropos_study`.
"""

import time
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from tether_sim.io.params import load_config
from tether_sim.physics.bodies import submerged_weight
from tether_sim.physics.boundary import END_NAMES
from tether_sim.physics.motion import build_motion
from tether_sim.physics.snap import NumericalSnapWarning, SlackStarted, SnapDetector, SnapEvent, snap_guard
from tether_sim.solvers.base import relative_end_speed, shortest_element
from tether_sim.solvers.factory import build_solver

CONFIG_DIR = Path(__file__).resolve().parents[2] / "config"
LENGTHS = (200.0, 500.0, 975.0, 1730.0)  # m [PE2020 Eq. 47]
ALPHAS = (0.0, 1.0, 10.0, 100.0)  # EI = alpha * EI* [PE2020 Eq. 48]
FREQUENCIES = (0.10, 0.20, 0.25)  # Hz [PE2020 Sec. 6.2]
EI_STAR = 2.62e3  # N m^2, solid section of d = 0.03 m with EA = 45.5 MN [PE2020 Sec. 6.2]


def ropos_config(length=1730.0, alpha=0.0, frequency=0.2, amplitude=2.0, n_elements=None, order=None,
                 periods=12.0, solver=None, cfl=None, **sections):
    """SimConfig of ``config/ropos_L<length>_paper.yaml`` (the paper's N = 20, P = 4) with the study's
    alpha, f, a and mesh.

    ``periods`` sets the duration (12 periods: the paper's Figure 6 looks at period 8.65) and the
    fairlead ramp is one period. ``sections`` replace whole sections (e.g. ``snap=SnapConfig(...)``).
    """
    path = CONFIG_DIR / f"ropos_L{int(length)}_paper.yaml"
    if path.is_file():
        cfg = load_config(path)
    else:  # another depth: the L = 1730 m file with the length (and the cage position) changed
        base = load_config(CONFIG_DIR / "ropos_L1730_paper.yaml")
        cfg = replace(base, cable=replace(base.cable, length=float(length)),
                      vehicle_end=replace(base.vehicle_end, position=(0.0, 0.0, -float(length))),
                      body=replace(base.body, initial_position=(0.0, 0.0, -float(length) - base.body.attachment[2])))
    cfg = replace(cfg, cable=replace(cfg.cable, EI=float(alpha) * EI_STAR),
                  motion=replace(cfg.motion, kind="circle", amplitude=float(amplitude), frequency=float(frequency),
                                 ramp_time=1.0 / float(frequency) if frequency > 0 else 0.0),
                  duration=float(periods) / float(frequency) if frequency > 0 else cfg.duration)
    dg = replace(cfg.dg, n_elements=int(n_elements or cfg.dg.n_elements), order=int(order or cfg.dg.order),
                 cfl=float(cfl or cfg.dg.cfl))
    cfg = replace(cfg, dg=dg, **sections)
    return replace(cfg, solver=solver) if solver else cfg


def static_end_tensions(config):
    """Closed-form static tensions (ship, vehicle) of the vertical tether with the cage (N).

    Vehicle end: the cage's submerged weight m g (1 - rho_f / rho_cg). Ship end: that plus the
    tether's submerged weight gamma0 g (1 - rho_f / rho) L (44 kN at L = 1730 m, PE2020 Sec. 6.1).
    """
    env, cable = config.environment, config.cable
    cage = submerged_weight(config.body, env)
    tether = cable.gamma0 * env.g * (1.0 - env.fluid_density / cable.density) * cable.length
    return cage + tether, cage


def point_load_config(config):
    """The same tether with the cage replaced by its submerged weight as a point load (Table 1 'force')."""
    _, cage = static_end_tensions(config)
    return replace(config, vehicle_end=replace(config.vehicle_end, kind="force", force=(0.0, 0.0, -cage)))


@dataclass
class CaseResult:
    """One dynamic run: end tensions (binned maxima at ``sample_rate``), cage motion, snap events."""

    length: float
    alpha: float
    frequency: float
    n_elements: int
    order: int
    static: tuple  # solver's initial (ship, vehicle) tensions, N
    t: np.ndarray = field(default_factory=lambda: np.zeros(0))
    ship_tension: np.ndarray = field(default_factory=lambda: np.zeros(0))
    vehicle_tension: np.ndarray = field(default_factory=lambda: np.zeros(0))
    t_out: np.ndarray = field(default_factory=lambda: np.zeros(0))
    cage_acceleration: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    ship_acceleration: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    events: list = field(default_factory=list)
    substeps: int = 0
    wall_time: float = 0.0
    error: str = ""
    raw: tuple = ()  # (t (k,), tensions (k, 2)) of every substep when run with keep_raw

    def snaps(self, location=None):
        return [e for e in self.events if isinstance(e, SnapEvent) and location in (None, e.location)]

    def slacks(self, location=None):
        return [e for e in self.events if isinstance(e, SlackStarted) and location in (None, e.location)]

    def numerical(self, location=None):
        """Re-tensionings the snap guard rejected (NumericalSnapWarning; not snaps)."""
        return [e for e in self.events if isinstance(e, NumericalSnapWarning) and location in (None, e.location)]


def _bin_index(t, rate):
    """Index of the 1/rate-wide time bin of each t (bins [k, k+1)/rate; float noise absorbed)."""
    return np.floor(np.asarray(t) * rate + 1e-9).astype(np.int64)


def _binned_max(t, y, rate):
    """Maxima of y (k, m) over the 1/rate-wide time bins the samples fall in (bin centre times)."""
    if t.size == 0:
        return np.zeros(0), np.zeros((0, y.shape[1]))
    uniq, first = np.unique(_bin_index(t, rate), return_index=True)
    return (uniq + 0.5) / rate, np.maximum.reduceat(y, first, axis=0)


def run_case(config, output_rate=200.0, sample_rate=1000.0, keep_raw=False, t_end=None):
    """Run ``config`` through its solver; the ship end follows the motion generator.

    Every substep's end tensions go to a :class:`SnapDetector` (static references = the solver's
    initial tensions); tensions are stored as maxima over 1/sample_rate bins, cage acceleration
    at ``output_rate``. ``keep_raw`` additionally stores the substep series in ``result.raw``.
    """
    start = time.perf_counter()
    solver = build_solver(config)
    forces = solver.end_forces()
    static = (float(forces.ship_tension), float(forces.vehicle_tension))
    result = CaseResult(config.cable.length, config.cable.EI / EI_STAR, config.motion.frequency,
                        config.dg.n_elements, config.dg.order, static)
    ship_origin = np.asarray(config.ship_end.position, dtype=float)
    motion = build_motion(config.motion, ship_origin)
    element = shortest_element(solver, config)
    detector = SnapDetector(config.snap, list(END_NAMES), list(static), [0.0, config.cable.length],
                            snap_guard(config, element))
    solver.drain_end_tensions()
    t_end = config.duration if t_end is None else t_end
    n_out = int(round(t_end * output_rate))
    t_out = np.arange(1, n_out + 1) / output_rate
    acc = np.full((n_out, 3), np.nan)
    ship_acc = np.zeros((n_out, 3))
    chunks_t, chunks_T, raw = [], [], []
    try:
        for k, t in enumerate(t_out):
            pos, vel, a_ship = motion.at(t)
            if config.ship_end.kind == "prescribed":
                solver.set_end_motion("ship", pos, vel)
            result.substeps += solver.advance_to(t)
            ts, T0, T1 = solver.drain_end_tensions()
            ts = np.asarray(ts, dtype=float)
            tens = np.column_stack([T0, T1]).astype(float)
            body = solver.body_state("vehicle")
            result.events += detector.update(ts, tens, relative_end_speed(solver, config.cable.length))
            if keep_raw:
                raw.append((ts, tens))
            chunks_t.append(ts)
            chunks_T.append(tens)
            if body is not None:
                acc[k] = body.acceleration
            ship_acc[k] = a_ship
            if len(chunks_t) >= 64 or k == n_out - 1:
                # Bin whole 1/sample_rate bins only; the last (maybe incomplete) bin waits for more samples.
                ts_all, T_all = np.concatenate(chunks_t), np.concatenate(chunks_T)
                bins = _bin_index(ts_all, sample_rate)
                keep = bins == bins[-1] if k < n_out - 1 else np.zeros(ts_all.size, dtype=bool)
                bt, bT = _binned_max(ts_all[~keep], T_all[~keep], sample_rate)
                result.t = np.r_[result.t, bt]
                result.ship_tension = np.r_[result.ship_tension, bT[:, 0]]
                result.vehicle_tension = np.r_[result.vehicle_tension, bT[:, 1]]
                chunks_t, chunks_T = [ts_all[keep]], [T_all[keep]]
    except Exception as exc:  # a diverged case is reported in the study table, not fatal
        result.error = f"{type(exc).__name__}: {exc}"
    result.events += detector.flush()
    result.t_out, result.cage_acceleration, result.ship_acceleration = t_out, acc, ship_acc
    if keep_raw and raw:
        result.raw = (np.concatenate([r[0] for r in raw]), np.concatenate([r[1] for r in raw]))
    result.wall_time = time.perf_counter() - start
    return result


def front_arrival_time(t, tension, t_from, t_to):
    """Time of the steepest rise of ``tension`` within [t_from, t_to] (parabolic refinement)."""
    sel = np.nonzero((t >= t_from) & (t <= t_to))[0]
    if sel.size < 3:
        raise ValueError(f"no samples in [{t_from}, {t_to}] s to locate a front")
    dT = np.gradient(tension[sel], t[sel])
    i = int(np.argmax(dT))
    if 0 < i < sel.size - 1:
        y0, y1, y2 = dT[i - 1], dT[i], dT[i + 1]
        den = y0 - 2 * y1 + y2
        shift = 0.5 * (y0 - y2) / den if den != 0 else 0.0
        h = t[sel[i + 1]] - t[sel[i]]
        return float(t[sel[i]] + np.clip(shift, -1, 1) * h)
    return float(t[sel[i]])


def snap_lag(t, ship_tension, vehicle_tension, snap, wave_time):
    """Lag (s) between the steepest rise of a cage snap and of its arrival at the ship.

    The cage front is searched in [slack end - 0.05 s, peak]; the ship front within
    [cage front + 0.5 L/c, cage front + 1.5 L/c], with L/c = ``wave_time``.
    """
    exit_time = snap.slack_start + snap.slack_duration
    t_cage = front_arrival_time(t, vehicle_tension, exit_time - 0.05, snap.time + 1e-9)
    t_ship = front_arrival_time(t, ship_tension, t_cage + 0.5 * wave_time, t_cage + 1.5 * wave_time)
    return t_ship - t_cage
