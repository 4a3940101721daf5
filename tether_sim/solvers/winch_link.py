"""The winch between the driver and the solver (imports no ROS; shared by the node, the offline runner and line networks).

:func:`wrap_factory` is the driver's one hook: with ``winch.enabled`` every solver the driver builds
comes wrapped in a :class:`WinchedSolver`, which before each ``advance_to`` / ``step`` runs the winch
controller (:class:`tether_sim.physics.winch.Winch`) on the drum-side tension of the current state
and hands the rate to the solver (``set_pay_out_rate``: the solver ramps to it linearly over the
interval), then reads the length back (``unstretched_length``: the solver is the truth). Everything
else is delegated, so the driver, its snapshots (the winch's state travels with the solver's) and
its recoveries see one solver.

:class:`WinchLink` lives as long as the driver, across solver rebuilds: it keeps the winch, the
schedule (``winch.schedule_*``, times from the start of the run), the commands waiting for the next
interval (topic) and the record of applied commands (for the MCAP). A rebuilt solver (static restart
after a divergence) starts at the winch's current length, not at ``cable.length``. While held
(:meth:`WinchLink.hold`: a rebuilt network settling before its clock restarts) the drum stands still
and the winch's clock stops; :meth:`WinchLink.release` carries its clock on from there.
"""

from dataclasses import replace

import numpy as np

from tether_sim.errors import ConfigError
from tether_sim.physics.hydrodynamics import net_weight_per_length
from tether_sim.physics.winch import Schedule, Winch, command_problem, static_end_tensions

END_TENSION = {"ship": "ship_tension", "vehicle": "vehicle_tension"}


class WinchLink:
    """Winch controller + schedule + command queue of one run."""

    def __init__(self, config):
        self.config = config
        self.winch = Winch(config.winch, config.cable.length)
        self.schedule = Schedule(config.winch)
        self.queue = []  # (mode, setpoint, source) waiting for the next interval
        self.applied = []  # (run time s, mode, setpoint, source): drained by the outputs
        self.offset = 0.0  # run time at solver time 0 (moves when the solver is rebuilt)
        self.held = False  # the drum stands still and the run time stops (hold / release)

    @property
    def length(self) -> float:
        return self.winch.length

    def request(self, mode, setpoint, source="topic"):
        """Queue a command for the next interval; returns the reason it is refused, or None. A topic
        command ends the schedule (the operator has taken over)."""
        problem = command_problem(self.winch.cfg, mode, setpoint)
        if problem is None:
            self.queue.append((mode, float(setpoint), source))
            if source == "topic":
                self.schedule.next = len(self.schedule.entries)
        return problem

    def drain_applied(self) -> list:
        out, self.applied = self.applied, []
        return out

    def build(self, factory, config):
        """A solver for ``config`` (length: the winch's current one), wrapped."""
        if self.winch.time > 0.0 or self.winch.length != config.cable.length:
            config = replace(config, cable=replace(config.cable, length=self.winch.length))
        solver = factory(config)
        missing = [a for a in ("set_pay_out_rate", "unstretched_length") if not hasattr(solver, a)]
        if missing:
            raise ConfigError(f"winch.enabled: the {getattr(solver, 'name', config.solver)} solver cannot change its "
                              f"length during a run (it has no {', '.join(missing)}); set winch.enabled false")
        self.offset = self.winch.time - float(solver.time)
        self.winch.speed = 0.0  # a (re)built solver starts at rest, and so does its drum
        return WinchedSolver(solver, self)

    def hold(self):
        """Stand the drum still and stop the run time (commands wait) until :meth:`release`."""
        self.held = True

    def release(self, solver):
        """End a hold: the run time goes on from where it stopped, at ``solver``'s time now."""
        self.held = False
        self.offset = self.winch.time - float(solver.time)

    def before(self, solver, t_end):
        """Run the controller over [solver.time, t_end]: schedule, queued commands, rate to the solver."""
        dt = t_end - solver.time
        if dt <= 0.0:
            return
        if self.held:
            solver.set_pay_out_rate(0.0)
            return
        run_time = self.offset + solver.time
        for _, mode, setpoint in self.schedule.due(run_time):
            self.queue.append((mode, setpoint, "schedule"))
        for mode, setpoint, source in self.queue:
            if self.winch.command(mode, setpoint) is None:
                self.applied.append((run_time, mode, setpoint, source))
        self.queue.clear()
        end = self.config.winch.end
        quick = getattr(solver, "end_tension", None)  # (DG: the same number without the force vectors' copies)
        tension = quick(end) if quick is not None else getattr(solver.end_forces(), END_TENSION[end])
        solver.set_pay_out_rate(self.winch.step(dt, tension))

    def after(self, solver):
        if self.held:
            return
        self.winch.observe_length(solver.unstretched_length)
        self.winch.time = self.offset + solver.time


class WinchedSolver:
    """A solver with the winch applied before every interval (module docstring); delegates the rest."""

    def __init__(self, solver, link: WinchLink):
        self.inner = solver
        self.winch_link = link

    def __getattr__(self, name):
        return getattr(self.inner, name)

    def advance_to(self, t):
        self.winch_link.before(self.inner, t)
        k = self.inner.advance_to(t)
        self.winch_link.after(self.inner)
        return k

    def tick(self, t, ship=None, vehicle=None, drain=True):
        for end, motion in (("ship", ship), ("vehicle", vehicle)):  # the winch sees the tick's targets
            if motion is not None:
                self.inner.set_end_motion(end, *motion)
        self.winch_link.before(self.inner, t)
        out = self.inner.tick(t, drain=drain)
        self.winch_link.after(self.inner)
        return out

    def step(self, dt):
        self.winch_link.before(self.inner, self.inner.time + dt)
        self.inner.step(dt)
        self.winch_link.after(self.inner)

    def snapshot(self):
        link = self.winch_link
        return (self.inner.snapshot(), link.winch.snapshot(), link.schedule.next, link.offset)

    def restore(self, snap):
        inner, winch, schedule_next, offset = snap
        self.inner.restore(inner)
        link = self.winch_link
        link.winch.restore(winch)
        link.schedule.next, link.offset = schedule_next, offset


class LengthReference:
    """The snap detector's reference (static) end tensions as the winch changes the length
    (physics.winch.static_end_tensions from the static state the solver was built in)."""

    def __init__(self, solver, config):
        f = solver.end_forces()
        self.forces = np.array([f.ship_force, f.vehicle_force], float)
        z = solver.state(np.array([0.0, solver.unstretched_length])).position[:, 2]
        self.upper = 0 if z[0] >= z[1] else 1  # the end that carries the weight of the added cable
        self.weight = net_weight_per_length(config.cable, config.environment)
        self.length0 = float(solver.unstretched_length)

    def tensions(self, length: float) -> tuple:
        """(ship, vehicle) reference tensions at unstretched length ``length`` (m)."""
        return static_end_tensions(self.forces, self.upper, self.weight, float(length) - self.length0)


def length_reference(solver, config):
    """A :class:`LengthReference` for a solver built with the winch on, else None."""
    return LengthReference(solver, config) if config.winch.enabled else None


def wrap_factory(config, factory):
    """The driver's hook: ``factory`` itself without a winch, else one building WinchedSolvers."""
    if not config.winch.enabled:
        return factory
    link = WinchLink(config)

    def build(cfg):
        return link.build(factory, cfg)

    build.winch_link = link
    return build


def link_of(driver):
    """The WinchLink of a driver's run, or None (no winch)."""
    return getattr(driver.solver_factory, "winch_link", None)
