"""The DG solver's time stepping as functions of the workspace: end inputs, one compiled call per
interval, evaluations and the drain.

Each function takes the workspace ``ws`` (workspace.py; its slots are the solver's arrays) and the
plain numbers it needs; :class:`~tether_sim.solvers.dg.solver.DGCableSolver` keeps the clock and
the flags and calls these. Every interval is one compiled call: ``tick.dg_tick`` for advance_to /
step, ``tick.node_tick`` for tick (targets + substeps + outputs + drain). No compiled code here.
"""

import math

import numpy as np

from tether_sim.errors import SolverDivergedError
from tether_sim.physics.bodies import BODY_STATE_SIZE
from tether_sim.physics.boundary import END_NAMES
from tether_sim.solvers.base import LOAD_F, LOAD_M, LOAD_T
from tether_sim.solvers.dg import layout as Y
from tether_sim.solvers.dg.inputs import motion_floats
from tether_sim.solvers.dg.stepper import BMR_STATE, STATUS_DIVERGED
from tether_sim.solvers.dg.tick import (
    BAD_INPUT, TG_P, TG_SET, TG_V, dg_tick, drain_now, evaluate_now, node_tick, outputs_now,
)

# the end-load columns are those of TickOutput.loads, so that tick() returns a view of endf
assert (Y.E_F, Y.E_T, Y.E_M) == (LOAD_F, LOAD_T, LOAD_M)


# ---------------------------------------------------------------------- ends
def set_target(ws, e, end, position, velocity):
    """Target (position, velocity) of the driven end e at the target time of the next interval."""
    vals = motion_floats(position, velocity)
    if not all(map(math.isfinite, vals)):
        raise ValueError(f"set_end_motion: non-finite position or velocity for the {end} end")
    tg = ws.target[e]  # element-wise stores: cheaper than numpy converting a tuple
    tg[TG_P], tg[TG_P + 1], tg[TG_P + 2] = vals[0:3]
    tg[TG_V], tg[TG_V + 1], tg[TG_V + 2] = vals[3:6]
    tg[TG_SET] = 1.0


def set_load(ws, e, end, force, moment):
    """Point force and moment held on the force end e (end data B_F, B_M)."""
    f = np.asarray(force, float).reshape(3)
    m = np.asarray(moment, float).reshape(3)
    if not (np.all(np.isfinite(f)) and np.all(np.isfinite(m))):
        raise ValueError(f"set_end_load: non-finite load for the {end} end")
    ws.bc[e, Y.B_F:Y.B_F + 3] = f
    ws.bc[e, Y.B_M:Y.B_M + 3] = m


class TickInputs:
    """tick()'s end inputs: tin (2, 6), node_tick's input, filled through views of its four rows made once
    (a view's [...] store is a third of the cost of tin[e, 0:3] = ..., which makes the view each time)."""

    __slots__ = ("tin", "_rows", "_driven", "_kinds")

    def __init__(self, ends, kinds):
        self.tin = np.zeros((2, 6))
        self._rows = (self.tin[0, 0:3], self.tin[0, 3:6], self.tin[1, 0:3], self.tin[1, 3:6])
        self._driven = tuple(end.position == "motion" for end in ends)  # only a prescribed end takes a motion
        self._kinds = kinds

    def read(self, ship, vehicle):
        """tin[e] = (position, velocity) of each end given; returns the bit mask of the ends given."""
        mask = 0
        if ship is not None:
            self._put(0, ship)
            mask = 1
        if vehicle is not None:
            self._put(1, vehicle)
            mask |= 2
        return mask

    def _put(self, e, motion):
        if not self._driven[e]:
            raise ValueError(f"tick: the {END_NAMES[e]} end is {self._kinds[e]!r}, not 'prescribed'")
        try:
            self._rows[2 * e][...] = motion[0]
            self._rows[2 * e + 1][...] = motion[1]
        except (ValueError, TypeError, IndexError) as exc:
            raise ValueError(f"tick: the {END_NAMES[e]} end's motion must be (position, velocity), "
                             f"3 numbers each: {exc}") from None


# ---------------------------------------------------------------------- bending multirate records
def records_size(nu):
    """Length of the slot bmr for a state of nu numbers (stepper.BMR_STATE + U, r_a, two body states)."""
    return BMR_STATE + nu + 3 + 2 * BODY_STATE_SIZE


def records(ws):
    """The bending multirate's carried records, for snapshot(): bookkeeping (bmr) and the T_s records."""
    return dict(bmr=ws.bmr.copy(), bmr_records=ws.wq[:, :, Y.W_TSH:Y.W_TSH + 9].copy())


def put_records(ws, snap):
    """restore(): the records of the snapshot's state, or none (a snapshot without them)."""
    if "bmr" in snap:
        ws.bmr[:] = snap["bmr"]
        ws.wq[:, :, Y.W_TSH:Y.W_TSH + 9] = snap["bmr_records"]
    else:
        ws.bmr[:] = 0.0


# ---------------------------------------------------------------------- stepping
def span_to(t0, t, what):
    """The interval t - t0 (<= 0: nothing to step; more than round-off before t0 is refused; what: the caller)."""
    if not math.isfinite(t) or t < t0 - 1e-12:
        raise ValueError(f"{what}: target time {t} is before the current time {t0}")
    return t - t0


def substeps(span, step):
    """(substeps, their size) over a span > 0: equal, none longer than step (advance_to's rule)."""
    n = max(1, math.ceil(span / step * (1.0 - 1e-12)))
    return n, span / n


def run(ws, t0, t_end, nsteps, dt, outputs):
    """One compiled call (tick.dg_tick): driven ends, nsteps substeps of dt from t0, end bookkeeping
    and, with outputs, their evaluation at t_end. Raises SolverDivergedError when the state diverged."""
    if dg_tick(ws.F, ws.I, ws.spec, t0, t_end, nsteps, dt, outputs) == STATUS_DIVERGED:
        raise diverged(ws, t0, dt)


def run_tick(ws, tin, mask, t0, t, nsteps, dt, drain):
    """One node tick in one compiled call (tick.node_tick); returns the number of drained samples."""
    r = node_tick(ws.F, ws.I, ws.spec, tin, mask, t0, t, nsteps, dt, drain)
    if r <= BAD_INPUT:
        raise ValueError(f"tick: non-finite position or velocity for the {END_NAMES[BAD_INPUT - r]} end")
    if r < 0:
        raise diverged(ws, t0, dt)
    return r


def diverged(ws, t0, dt):
    """The error of a stepper stopped at a non-finite state (out[0]: substeps done)."""
    done = int(ws.out[0])
    return SolverDivergedError(
        f"DG state became non-finite at t = {t0 + (done + 1) * dt:.6g} s "
        f"(substep {dt:.3g} s); restore a snapshot and reduce dg.cfl or check the inputs")


# ---------------------------------------------------------------------- evaluations and the drain
def evaluate(ws, t):
    """A full right-hand-side evaluation at time t (dU, endf, the work arrays)."""
    evaluate_now(ws.F, ws.I, ws.spec, t)


def evaluate_outputs(ws, t):
    """The evaluation the outputs read at time t (end loads, modal work channels)."""
    outputs_now(ws.F, ws.I, ws.spec, t)


def drain_count(ws):
    """The ring entries since the last drain copied into the drain slot; returns their number."""
    return drain_now(ws.F, ws.I, ws.spec)


def drain(ws):
    """(t, T_ship, T_vehicle) at the start of every substep since the last drain (newest cap kept)."""
    t, ship, vehicle = ws.drain[:, :drain_count(ws)].copy()  # one copy; rows are views of it
    return t, ship, vehicle
