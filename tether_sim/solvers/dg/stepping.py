"""The DG solver's time stepping: advance_to, step, the one-call node tick, ends and drains.

A mixin of :class:`~tether_sim.solvers.dg.solver.DGCableSolver` (which owns the arrays, the
workspace ``ws`` and the parameters); every interval is one compiled call: ``tick.dg_tick`` for
advance_to / step, ``tick.node_tick`` for tick (targets + substeps + outputs + drain).
"""

import math

import numpy as np

from tether_sim.errors import SolverDivergedError, UnstableTimeStepError
from tether_sim.physics.boundary import END_NAMES
from tether_sim.solvers.base import LOAD_F, LOAD_M, LOAD_T, TickOutput, end_index
from tether_sim.solvers.dg import layout as Y
from tether_sim.solvers.dg.damping_layout import MODE_EXPLICIT
from tether_sim.solvers.dg.inputs import motion_floats
from tether_sim.solvers.dg.stepper import STATUS_DIVERGED
from tether_sim.solvers.dg.tick import BAD_INPUT, TG_P, TG_SET, TG_V, dg_tick, drain_now, evaluate_now, node_tick, outputs_now
from tether_sim.solvers.dg.timestep import config_stable_dt

# the end-load columns are those of TickOutput.loads, so that tick() returns a view of endf
assert (Y.E_F, Y.E_T, Y.E_M) == (LOAD_F, LOAD_T, LOAD_M)


class SteppingMixin:
    """Time step, end inputs, stepping and the drain of the DG solver (module docstring)."""

    # ------------------------------------------------------------------ time step
    def stable_time_step(self, h=None) -> float:
        """Automatic substep = dg.cfl x the stability limit of docs/dg_solver.md (element sizes h)."""
        return config_stable_dt(self.config, self.h if h is None else h, self.law.max_slope(),
                                self._damp.mode != MODE_EXPLICIT)

    def _substep(self):
        return self.fixed_dt if self.fixed_dt > 0 else self._dt_rule

    # ------------------------------------------------------------------ ends
    def set_end_motion(self, end, position, velocity) -> None:
        """Target position/velocity of a prescribed end at the target time of the next advance_to."""
        e = end_index(end)
        if self.ends[e].position != "motion":
            raise ValueError(f"set_end_motion: the {end} end is {self.kinds[e]!r}, not 'prescribed'")
        vals = motion_floats(position, velocity)
        if not all(map(math.isfinite, vals)):
            raise ValueError(f"set_end_motion: non-finite position or velocity for the {end} end")
        tg = self.ws.target[e]  # element-wise stores: cheaper than numpy converting a tuple
        tg[TG_P], tg[TG_P + 1], tg[TG_P + 2] = vals[0:3]
        tg[TG_V], tg[TG_V + 1], tg[TG_V + 2] = vals[3:6]
        tg[TG_SET] = 1.0

    def set_end_load(self, end, force, moment=(0.0, 0.0, 0.0)) -> None:
        """Point force (and moment) applied on a force end (held until changed)."""
        e = end_index(end)
        if self.ends[e].load != "applied":
            raise ValueError(f"set_end_load: the {end} end is {self.kinds[e]!r}, not 'force'")
        f = np.asarray(force, float).reshape(3)
        m = np.asarray(moment, float).reshape(3)
        if not (np.all(np.isfinite(f)) and np.all(np.isfinite(m))):
            raise ValueError(f"set_end_load: non-finite load for the {end} end")
        self.bc[e, Y.B_F:Y.B_F + 3] = f
        self.bc[e, Y.B_M:Y.B_M + 3] = m
        self._outputs_valid = False

    # ------------------------------------------------------------------ stepping
    def _run(self, nsteps, dt, t_end):
        """One compiled call (tick.dg_tick): driven ends, nsteps substeps of dt, end bookkeeping and,
        when outputs are being read, their evaluation at t_end."""
        ws = self.ws
        self._outputs_valid = False
        winch = self._winch_moving()
        status = dg_tick(ws.F, ws.I, ws.spec, self.time, t_end, nsteps, dt, self._want_outputs)
        if status == STATUS_DIVERGED:
            self._raise_diverged(dt)
        self.time = t_end
        if winch:
            self._winch_sync()
        self._outputs_valid = self._want_outputs
        return nsteps

    def _raise_diverged(self, dt):
        done = int(self._out[0])
        raise SolverDivergedError(
            f"DG state became non-finite at t = {self.time + (done + 1) * dt:.6g} s "
            f"(substep {dt:.3g} s); restore a snapshot and reduce dg.cfl or check the inputs")

    def _substeps_to(self, t, what):
        """(substeps, their size) for an interval to time t, equal and stable (advance_to's rule)."""
        if not math.isfinite(t) or t < self.time - 1e-12:
            raise ValueError(f"{what}: target time {t} is before the current time {self.time}")
        span = t - self.time
        if span <= 0.0:
            return 0, 0.0
        step = (self._winch_substep(span) if self.winch_enabled else None) or self._substep()
        n = max(1, math.ceil(span / step * (1.0 - 1e-12)))
        return n, span / n

    def advance_to(self, t) -> int:
        """Advance to time t in equal stable substeps (compiled loop); returns the substep count."""
        t = float(t)
        n, dt = self._substeps_to(t, "advance_to")
        return self._run(n, dt, t) if n else 0

    def tick(self, t, ship=None, vehicle=None, drain=True) -> TickOutput:
        """One node tick in one compiled call (tick.node_tick): the targets of the driven ends given as
        (position, velocity), advance_to(t), the drain of the end tensions and the end loads; the
        result's arrays are views, valid until the next call (base.py's contract)."""
        t = float(t)
        tin, mask = self._tick_in, 0
        for e, motion in ((0, ship), (1, vehicle)):
            if motion is not None:
                if self.ends[e].position != "motion":
                    raise ValueError(f"tick: the {END_NAMES[e]} end is {self.kinds[e]!r}, not 'prescribed'")
                try:
                    tin[e, 0:3] = motion[0]
                    tin[e, 3:6] = motion[1]
                except (ValueError, TypeError, IndexError) as exc:
                    raise ValueError(f"tick: the {END_NAMES[e]} end's motion must be (position, velocity), "
                                     f"3 numbers each: {exc}") from None
                mask |= 1 << e
        n, dt = self._substeps_to(t, "tick")
        if n == 0:  # nothing to step: the composition (targets kept for the next interval)
            for e, name in enumerate(END_NAMES):
                if mask >> e & 1:
                    self.set_end_motion(name, tin[e, 0:3], tin[e, 3:6])
            count = self._drain_count() if drain else 0
            self._evaluate_outputs()
            return TickOutput(count, self.ws.drain, self._endf, 0)
        ws = self.ws
        self._outputs_valid = False
        winch = self._winch_moving()
        r = node_tick(ws.F, ws.I, ws.spec, tin, mask, self.time, t, n, dt, drain)
        if r <= BAD_INPUT:
            raise ValueError(f"tick: non-finite position or velocity for the {END_NAMES[BAD_INPUT - r]} end")
        if r < 0:
            self._raise_diverged(dt)
        self.time = t
        if winch:
            self._winch_sync()
        self._want_outputs = self._outputs_valid = True
        return TickOutput(r, ws.drain, self._endf, n)

    def step(self, dt) -> None:
        """One substep of size dt (UnstableTimeStepError above the stability limit)."""
        limit = self._dt_rule / self.config.dg.cfl
        if self._winch_moving() and dt > 0:
            limit = min(limit, self._winch_limit(float(dt)))
        if dt <= 0 or dt > limit:
            raise UnstableTimeStepError(f"step: dt = {dt:g} s outside (0, {limit:g}] s (stability limit)")
        self._run(1, float(dt), self.time + float(dt))

    # ------------------------------------------------------------------ outputs
    def _evaluate(self):
        """A full right-hand-side evaluation at the current state (dU, endf, work arrays)."""
        self._outputs_valid = False
        evaluate_now(self.ws.F, self.ws.I, self.ws.spec, self.time)

    def _evaluate_outputs(self):
        """What the outputs (state(), end_forces(), body_state()) read of a right-hand-side evaluation
        at the current state (end loads, modal work channels; sampling.evaluate_outputs). Done once
        per state: by the tick itself once outputs have been asked for (a node asking for all three
        per tick pays for one evaluation, inside the tick's compiled call), else here."""
        self._want_outputs = True
        if not self._outputs_valid:
            outputs_now(self.ws.F, self.ws.I, self.ws.spec, self.time)
            self._outputs_valid = True

    def drain_end_tensions(self):
        """(t, T_ship, T_vehicle) at the start of every substep since the last call (newest cap kept)."""
        t, ship, vehicle = self.ws.drain[:, :self._drain_count()].copy()  # one copy; rows are views of it
        return t, ship, vehicle

    def _drain_count(self):
        return drain_now(self.ws.F, self.ws.I, self.ws.spec)

