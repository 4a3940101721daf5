"""DGCableSolver: the high-order DG / nested-LDG cable solver of Palm & Eskilsson 2020.

Implements :class:`tether_sim.solvers.base.TetherSolver`. The state is the modal expansion of
u = [q, v] per element (``layout.py``); positions are r(s) = r_a + int_{s_a}^{s} q ds from an
anchor end s_a (the ship end unless only the vehicle end is held), whose position r_a follows the
boundary flux velocity v_hat / gamma0 in the same Runge-Kutta stages and is set exactly to the
prescribed position of a held end after every substep. Because the DG update conserves
int q ds up to the boundary fluxes, r(L) - r(0) follows v_hat(L) - v_hat(0) to round-off.

The solver is a thin driver: every array lives in the workspace ``ws`` (workspace.py, one slot per
array: ``ws.U``, ``ws.prm``, ``ws.endf`` ...), the work is done by functions of the workspace
(stepping.py: stepping and drains; outputs.py: sampled state, end loads, bodies; winch_driver.py:
the winch) and the compiled calls behind them (tick.py). The driver itself keeps the configuration,
the mesh (N, P, L, s_edges), the clock and whether the output evaluation is current.
"""

import math
import time as wallclock

import numpy as np

from tether_sim.errors import UnstableTimeStepError
from tether_sim.numerics.operators import element_operators, project_function
from tether_sim.physics.bodies import BODY_STATE_SIZE, initial_body_state, pack_body_params, submerged_weight
from tether_sim.physics.boundary import END_NAMES
from tether_sim.physics.constitutive import TensionLaw
from tether_sim.physics.end_conditions import end_kind, held_in_place
from tether_sim.physics.hydrodynamics import added_mass_per_length, current_table
from tether_sim.physics.statics import solve_static
from tether_sim.solvers.base import BodyPose, TickOutput, end_index
from tether_sim.solvers.dg import layout as Y
from tether_sim.solvers.dg import outputs, stepping, winch_driver
from tether_sim.solvers.dg.damping_layout import MODE_AXIAL, MODE_EXPLICIT, MODE_GENERAL, MODE_RKL2
from tether_sim.solvers.dg.equilibrium import polish_equilibrium
from tether_sim.solvers.dg.implicit_damping import DampingWork
from tether_sim.solvers.dg.parameters import end_data, parameters, with_waves
from tether_sim.solvers.dg.soa import TMP_HEAD, soa_scratch_size
from tether_sim.solvers.dg.tick import EN_P, EN_V, NOT_PLAIN, TG_SET, ship_tick
from tether_sim.solvers.dg.timestep import bending_multirate_steps, config_stable_dt
from tether_sim.solvers.dg.workspace import Workspace
from tether_sim.solvers.work import mesh_sizes
from tether_sim.solvers.config import SPLIT_DAMPING

# The relaxation runs in compiled calls of this much wall time (the first of RELAX_FIRST_CHUNK substeps,
# to measure): a signal (Ctrl-C) is handled by Python between two calls, so a long initial.relax_time
# stops within about this; the substeps are those of one advance_to (same size, same times).
RELAX_CHUNK_WALL = 0.2  # s
RELAX_FIRST_CHUNK = 200

# np.ndarray once: a module attribute of numpy is a slow look-up (tens of ns), and tick() asks twice per call
_NDARRAY = np.ndarray

# the implicit damping's arrays in the workspace: slot -> attribute of DampingWork
_DAMPING_SLOTS = dict(idp="idp", dprm="dprm", blk="blk", bvec="bvec", wp="wp", wd="wd", band="band", vec="vec",
                      dtmp="tmp", dwood="wood", fdamp="fdamp")


class DGCableSolver:
    """Discontinuous Galerkin cable solver [PE2020 Sec. 2-3]; see docs/dg_solver.md."""

    name = "dg"

    def __init__(self, config):
        self.config = config
        cab, env, opt = config.cable, config.environment, config.dg
        self.kinds = (config.ship_end.kind, config.vehicle_end.kind)
        self.ends = tuple(end_kind(k, f"{e}.kind") for e, k in zip(("ship_end", "vehicle_end"), self.kinds))
        self.law = TensionLaw(cab)
        self.N, self.P = int(opt.n_elements), int(opt.order)
        self.L = float(cab.length)
        h = self._element_sizes(opt)
        self.s_edges = np.concatenate(([0.0], np.cumsum(h)))
        self.ops = element_operators(self.P, int(opt.quad_points) or None)
        cz, cx, cy = current_table(env)
        prm, iprm = parameters(cab, env, opt, self.law, (self.N, self.P, self.ops.vandermonde.shape[0]), self.kinds,
                                cz.size)
        self.winch_end, hw = winch_driver.setup(config, self.ends, self.kinds, prm, iprm, h, self.L)
        self.winch_enabled = self.winch_end is not None
        prm = with_waves(config, cab, env, prm, iprm)
        self._damp, prm_step, iprm_step = self._damping(cab, env, opt, h, prm, iprm)
        N, nm, nq = self.N, self.P + 1, self.ops.vandermonde.shape[0]
        o = self.ops
        bp = pack_body_params(config.body, env)
        ends = np.zeros((2, 6))
        ends[0, 0:3], ends[1, 0:3] = config.ship_end.position, config.vehicle_end.position
        cap = int(opt.tension_buffer)
        arrays = dict(
            U=np.zeros((N, nm, 6)), ra=np.zeros(3), prm_step=prm_step, iprm_step=iprm_step, h=h,
            V=o.vandermonde, Pj=o.projection, D=o.derivative, Lf=o.lift, Tr=o.trace, Iq=o.integral,
            tab_eps=self.law.tab_eps, tab_T=self.law.tab_T, cz=cz, cx=cx, cy=cy,
            bc=end_data(config, self.ends), vbc=np.zeros((2, 6)),
            wq=np.zeros((N, nq, Y.NWQ)), wm=np.zeros((N, nm, Y.NWM)), trc=np.zeros((N, 2, Y.NTR)),
            fl=np.zeros((N + 1, Y.NFL)), rs=np.zeros((N, 3)),
            tmp=np.zeros(TMP_HEAD + soa_scratch_size(N, nm, nq)),  # + scratch of soa.py
            dU=np.zeros((N, nm, 6)), dra=np.zeros(3), endf=np.zeros((2, Y.N_ENDF)),
            bs=np.zeros((2, BODY_STATE_SIZE)), bp=np.stack([bp, bp]), dbs=np.zeros((2, BODY_STATE_SIZE)),
            bs0=np.zeros((2, BODY_STATE_SIZE)), U0=np.zeros((N, nm, 6)), ra0=np.zeros(3),
            buf=np.zeros((cap, 3)), cnt=np.zeros(1, dtype=np.int64), out=np.zeros(2),
            hw=hw, prm=prm, iprm=iprm, ends=ends, target=np.zeros((2, 7)), no_fdamp=np.zeros((2, 4)),
            drained=np.zeros(1, dtype=np.int64), drain=np.zeros((3, cap)), fresh=np.zeros(2, dtype=np.int64),
            snap=np.zeros(N * nm * 6 + prm.size + 2 * Y.N_BC + 2 * 6 + N), snap_i=np.zeros(iprm.size, dtype=np.int64),
            bmr=np.zeros(stepping.records_size(N * nm * 6)),
        )
        arrays.update({slot: getattr(self._damp, a) for slot, a in _DAMPING_SLOTS.items()})
        self.ws = Workspace(arrays)
        for slot, a in _DAMPING_SLOTS.items():  # the damping's arrays become views of the workspace
            setattr(self._damp, a, getattr(self.ws, slot))
        self._tick = stepping.TickInputs(self.ends, self.kinds)  # tick(): the driven ends' targets, node_tick's tin
        self._ship_tick = self.ends[0].position == "motion" and not self.winch_enabled  # tick() may take ship_tick
        # the last result of tick()'s common case: the same (count, substeps) next time is the same tuple (its arrays
        # are the workspace's views), returned again instead of a new one
        self._ship_out = tuple.__new__(TickOutput, (-1, self.ws.drain, self.ws.endf, -1))
        self._plans = {}  # sampling plans (outputs.plan)
        self._outputs_valid = False  # the output work arrays hold the evaluation at the current state
        self._want_outputs = False  # outputs were asked for: the tick evaluates them (tick.py)
        self.time = 0.0
        self.q_penalty_form = "tension" if opt.q_penalty_jump == "tension" else "strain"
        self.equilibrium_iterations = 0  # Newton iterations of the discrete static equilibrium (-1: failed)
        self._dt_rule = self.stable_time_step()
        self.fixed_dt = float(opt.fixed_time_step)
        if self.fixed_dt > 0.0 and self.fixed_dt > self._dt_rule / opt.cfl:
            raise UnstableTimeStepError(
                f"dg.fixed_time_step = {self.fixed_dt:g} s exceeds the stability limit "
                f"{self._dt_rule / opt.cfl:g} s (cfl = 1; automatic step with dg.cfl = {opt.cfl:g} "
                f"would be {self._dt_rule:g} s): reduce it, or use fewer elements / a lower order")
        self._set_bending_multirate()
        self._set_initial_state(config)

    # ------------------------------------------------------------------ set-up
    def _element_sizes(self, opt):
        wts = np.asarray(opt.element_lengths, float)
        if wts.size and (wts.size != self.N or np.any(wts <= 0)):
            raise ValueError(f"dg.element_lengths: need {self.N} positive weights (dg.n_elements), got {wts.size}")
        return mesh_sizes(self.L, self.N, wts)

    def _damping(self, cab, env, opt, h, prm, iprm):
        """(DampingWork, prm_step, iprm_step). dg.damping = implicit: the stepper gets prm/iprm without
        the damping terms (E of the splitting) and the implicit damping work arrays; outputs keep the
        full prm/iprm."""
        mode = MODE_EXPLICIT
        if opt.damping in SPLIT_DAMPING and (cab.damping > 0.0 or cab.bending_damping > 0.0):
            mode = MODE_GENERAL if cab.bending_damping > 0.0 else MODE_AXIAL
            if opt.damping == "rkl2":
                if cab.bending_damping > 0.0:  # a fourth-order term: its stages would grow as h^-2
                    raise ValueError("dg.damping rkl2 steps the axial damping only; with cable.bending_damping > 0 "
                                     "use dg.damping implicit")
                mode = MODE_RKL2
        mt, mn = added_mass_per_length(cab, env)
        damp = DampingWork(mode, self.ops, h, self.kinds, cab, cab.gamma0, mt, mn, opt.beta, self.law.code,
                           (iprm[Y.I_KIND0], iprm[Y.I_KIND1]), max(prm[Y.P_LAMBDA_BC], prm[Y.P_LAMBDA_FLOOR]),
                           opt.damping_substeps, opt.damping_correction)
        prm_step, iprm_step = prm.copy(), iprm.copy()
        if mode != MODE_EXPLICIT:
            iprm_step[Y.I_AXDAMP] = iprm_step[Y.I_BENDDAMP] = 0
            iprm_step[Y.I_BENDING] = int(cab.EI > 0.0 or cab.torque != 0.0)
        return damp, prm_step, iprm_step

    def _set_bending_multirate(self):
        """iprm[I_BMR_K] (both parameter sets; the outputs never extrapolate): the nested LDG every K substeps
        (timestep.bending_multirate_steps); 1 when dg.bending_multirate is off or with a winch (h changes)."""
        cab = self.config.cable
        k = 1
        if self.config.dg.bending_multirate and not self.winch_enabled:
            k = bending_multirate_steps(self.ws.h, self.P, cab.gamma0, cab.EI, cab.bending_damping, cab.torque,
                                        self._substep())
        self.bending_multirate_k = k
        self.ws.iprm[Y.I_BMR_K] = self.ws.iprm_step[Y.I_BMR_K] = k

    def _set_initial_state(self, config):
        ws = self.ws
        kind = config.initial.kind
        shape = None
        body_load = np.array([0.0, 0.0, -submerged_weight(config.body, config.environment)])
        if kind == "static":
            try:
                body = [k.position == "body" for k in self.ends]
                shape = solve_static(config, vehicle_load=body_load if body[1] else None,
                                     ship_load=body_load if body[0] else None)
            except RuntimeError:
                shape = None  # fall back to dynamic relaxation from the straight line
        if shape is not None:
            tangent = shape.tangent
            end_pos = shape.position(np.array([0.0, self.L]))
        else:
            for e in range(2):
                if self.ends[e].position == "body":
                    ws.ends[e, EN_P:EN_P + 3] = (initial_body_state(config.body)[0:3]
                                                 + np.asarray(config.body.attachment, float))
            A, B = ws.ends[:, EN_P:EN_P + 3]
            q = (B - A) / self.L
            tangent = (lambda s, q=q: np.repeat(q[None, :], np.atleast_1d(s).size, axis=0))
            end_pos = np.array([A, B])
        for e in range(self.N):
            ws.U[e, :, 0:3] = project_function(self.P, tangent, self.s_edges[e], self.s_edges[e + 1])
        ws.U[:, :, 3:6] = 0.0
        ws.ra[:] = end_pos[ws.iprm[Y.I_ANCHOR]]
        for e in range(2):
            if self.ends[e].position in ("cable", "body"):
                ws.ends[e, EN_P:EN_P + 3] = end_pos[e]
            if self.ends[e].position == "body":
                ws.bs[e] = initial_body_state(config.body, attachment_world=end_pos[e])
        if shape is not None and self.config.dg.q_penalty_jump == "auto":
            self._choose_q_penalty(shape)
        if shape is not None and all(held_in_place(k) for k in self.kinds):
            self.equilibrium_iterations = polish_equilibrium(self, end_pos[1] - end_pos[0])
        self.start_warning = self._start_mismatch(shape) if shape is not None else ""
        relax = config.initial.relax_time
        if kind == "relax" or (kind == "static" and shape is None):
            relax = relax if relax > 0 else self._default_relax_time()
        if relax > 0:
            self.relax(relax)

    def _start_mismatch(self, shape) -> str:
        """A sentence when the mesh cannot hold the static shape, else "": the projected state's tension
        exceeds the shape's by more than half its largest tension (and 1 N) somewhere. A slack cable whose
        static shape has a kink (a light tether in a current, its slack streaming past an end and doubling
        back) projects onto too few elements with kN spikes that no relaxation removes."""
        s = np.linspace(0.0, self.L, 8 * self.N * (self.P + 1) + 1)
        want = self._want_outputs
        dg, ref = self.state(s).tension, shape.tension(s)
        self._want_outputs = want  # a check at the start, not a reader of outputs: the ticks need not evaluate them
        k = int(np.argmax(dg - ref))
        if dg[k] - ref[k] <= max(0.5 * float(np.max(ref)), 1.0):
            return ""
        return (f"the mesh (N = {self.N}, P = {self.P}) cannot hold the static shape: its starting tension is "
                f"{dg[k]:.4g} N at s = {s[k]:.1f} m where the static shape has {ref[k]:.4g} N (largest "
                f"{float(np.max(ref)):.4g} N; a kink in a slack cable?): refine dg.n_elements")

    def _relax_in_chunks(self, t):
        """advance_to(t) in compiled calls of about RELAX_CHUNK_WALL s each (a signal is handled between
        them); the same substeps as one advance_to: n of span / n, the chunk ends at t0 + k dt."""
        n, dt = self._substeps_to(t, "relax")
        t0, done, chunk = self.time, 0, RELAX_FIRST_CHUNK
        while done < n:
            m = min(chunk, n - done)
            wall = wallclock.perf_counter()
            done += m
            self._run(m, dt, t if done == n else t0 + done * dt)
            spent = wallclock.perf_counter() - wall
            chunk = max(1, min(8 * m, int(m * RELAX_CHUNK_WALL / max(spent, 1e-9))))

    def _choose_q_penalty(self, shape):
        """dg.q_penalty_jump auto: the tension-jump penalty when max dT/deps / min T of the static
        state exceeds dg.q_penalty_auto_ratio (docs/dg_solver.md, "q-equation penalty")."""
        t_min = float(np.min(shape.tension(np.linspace(0.0, self.L, 201))))
        ratio = self.law.max_slope() / max(t_min, 1e-300)
        self.q_penalty_form = "tension" if ratio > self.config.dg.q_penalty_auto_ratio else "strain"
        if self.q_penalty_form == "tension":
            for p in (self.ws.prm, self.ws.prm_step):
                p[Y.P_QPENT], p[Y.P_QPEN] = self.config.dg.q_penalty, 0.0

    def set_shape(self, tangent, velocity=None, origin=None):
        """Replace the state: q = tangent(s) (n, 3) = dr/ds and cable velocity velocity(s) (n, 3) (m/s),
        both L2-projected on the modes; origin (3,) = r(0) (default: the current r(0))."""
        ws = self.ws
        r0 = self.positions_at(np.array([0.0]))[0] if origin is None else np.asarray(origin, float)
        g0 = self.config.cable.gamma0
        for e in range(self.N):
            a, b = self.s_edges[e], self.s_edges[e + 1]
            ws.U[e, :, 0:3] = project_function(self.P, tangent, a, b)
            ws.U[e, :, 3:6] = 0.0 if velocity is None else g0 * project_function(self.P, velocity, a, b)
        if ws.iprm[Y.I_ANCHOR] == 0:
            ws.ra[:] = r0
        else:
            ws.ra[:] = r0 + np.sum(ws.h[:, None] * ws.U[:, 0, 0:3], axis=0)

    def _default_relax_time(self):
        """Ten decay times of the automatic relaxation damping (or 5 pendulum periods)."""
        if self.config.initial.relax_damping > 0 or self.config.cable.EI > 0:
            return 20.0 / self.relax_rate()
        return 5.0 * 2.0 * math.pi * math.sqrt(self.L / max(self.config.environment.g, 1e-3))

    def relax_rate(self):
        """Automatic relaxation damping: twice the lowest of the pendulum and cantilever frequencies
        (near-critical for the slowest mode), or initial.relax_damping when set."""
        if self.config.initial.relax_damping > 0:
            return float(self.config.initial.relax_damping)
        cab = self.config.cable
        rates = []
        if self.config.environment.g > 0:
            rates.append(math.sqrt(self.config.environment.g / self.L))
        if cab.EI > 0:
            rates.append((1.875 / self.L) ** 2 * math.sqrt(cab.EI / cab.gamma0))
        return 2.0 * (min(rates) if rates else 1.0 / self._default_relax_time())

    def relax(self, duration):
        """Dynamic relaxation: run with the ends held and linear momentum damping; the clock is reset.

        The momentum is kept (not zeroed): at a discrete DG equilibrium v balances the
        Lax-Friedrichs penalty on the small jumps of q, and zeroing it would leave a spurious
        strain rate (and damping tension zeta * deps/dt) at restart."""
        ws = self.ws
        ws.prm[Y.P_RELAX] = self.relax_rate()
        t0 = self.time
        saved = ws.ends.copy()
        try:
            self._relax_in_chunks(t0 + duration)
        finally:
            ws.prm[Y.P_RELAX] = 0.0
        self.time = t0
        ws.bs[:, 7:13] = 0.0  # bodies start at rest (their velocity was damped anyway)
        for e in range(2):
            if self.ends[e].kinematic:
                ws.ends[e] = saved[e]
        self._outputs_valid = False
        self.drain_end_tensions()

    def snapshot(self):
        ws = self.ws
        return dict(time=self.time, U=ws.U.copy(), ra=ws.ra.copy(), bc=ws.bc.copy(), bodies=ws.bs.copy(),
                    end_pos=[p.copy() for p in ws.ends[:, EN_P:EN_P + 3]],
                    end_vel=[v.copy() for v in ws.ends[:, EN_V:EN_V + 3]], **stepping.records(ws),
                    **winch_driver.snapshot(ws, self.winch_enabled))

    def restore(self, snap) -> None:
        ws = self.ws
        self.time = snap["time"]
        ws.U[...] = snap["U"]
        ws.ra[:] = snap["ra"]
        ws.bc[...] = snap["bc"]
        ws.bs[...] = snap["bodies"]
        ws.ends[:, EN_P:EN_P + 3] = np.asarray(snap["end_pos"], float)
        ws.ends[:, EN_V:EN_V + 3] = np.asarray(snap["end_vel"], float)
        ws.target[:, TG_SET] = 0.0
        stepping.put_records(ws, snap)
        if winch_driver.restore(ws, snap):
            self._winch_sync()
        self._outputs_valid = False

    # ------------------------------------------------------------------ time step and ends (stepping.py)
    def stable_time_step(self, h=None) -> float:
        """Automatic substep = dg.cfl x the stability limit of docs/dg_solver.md (element sizes h)."""
        return config_stable_dt(self.config, self.ws.h if h is None else h, self.law.max_slope(),
                                self._damp.mode != MODE_EXPLICIT)

    def _substep(self):
        return self.fixed_dt if self.fixed_dt > 0 else self._dt_rule

    def set_end_motion(self, end, position, velocity) -> None:
        """Target position/velocity of a prescribed end at the target time of the next advance_to."""
        e = end_index(end)
        if self.ends[e].position != "motion":
            raise ValueError(f"set_end_motion: the {end} end is {self.kinds[e]!r}, not 'prescribed'")
        stepping.set_target(self.ws, e, end, position, velocity)

    def set_end_load(self, end, force, moment=(0.0, 0.0, 0.0)) -> None:
        """Point force (and moment) applied on a force end (held until changed)."""
        e = end_index(end)
        if self.ends[e].load != "applied":
            raise ValueError(f"set_end_load: the {end} end is {self.kinds[e]!r}, not 'force'")
        stepping.set_load(self.ws, e, end, force, moment)
        self._outputs_valid = False

    def _substeps_to(self, t, what):
        """(substeps, their size) for an interval to time t, equal and stable (advance_to's rule)."""
        span = stepping.span_to(self.time, t, what)
        if span <= 0.0:
            return 0, 0.0
        return stepping.substeps(span, (self._winch_substep(span) if self.winch_enabled else None) or self._substep())

    def _run(self, nsteps, dt, t_end):
        """One compiled call: driven ends, nsteps substeps of dt, end bookkeeping and, when outputs are
        being read, their evaluation at t_end (stepping.run)."""
        self._outputs_valid = False
        winch = self._winch_moving()
        stepping.run(self.ws, self.time, t_end, nsteps, dt, self._want_outputs)
        self.time = t_end
        if winch:
            self._winch_sync()
        self._outputs_valid = self._want_outputs
        return nsteps

    def advance_to(self, t) -> int:
        """Advance to time t in equal stable substeps (compiled loop); returns the substep count."""
        t = float(t)
        n, dt = self._substeps_to(t, "advance_to")
        return self._run(n, dt, t) if n else 0

    def tick(self, t, ship=None, vehicle=None, drain=True) -> TickOutput:
        """One node tick in one compiled call (tick.node_tick): the targets of the driven ends given as
        (position, velocity), advance_to(t), the drain of the end tensions and the end loads; the
        result's arrays are views, valid until the next call (base.py's contract). The common tick -- the
        ship end's motion as two arrays, no winch -- is tick.ship_tick, which reads them itself and takes
        the substeps of the rule; anything else (or what it declines) goes the general way."""
        t = float(t)
        if self._ship_tick and vehicle is None and ship is not None:  # the common node tick: ship_tick
            try:
                p, v = ship
            except (TypeError, ValueError):
                p = v = None  # (the general path says what is wrong)
            if type(p) is _NDARRAY and type(v) is _NDARRAY:
                ws, t0 = self.ws, self.time
                r, n = ship_tick(ws.F, ws.I, ws.spec, p, v, t0, t, self.fixed_dt if self.fixed_dt > 0 else self._dt_rule,
                                 drain)
                if r >= 0:
                    self.time = t
                    self._want_outputs = self._outputs_valid = True
                    out = self._ship_out
                    if out[0] != r or out[3] != n:  # (a tuple subclass made costs ~0.1-0.3 us; TickOutput's own __new__ more)
                        out = self._ship_out = tuple.__new__(TickOutput, (r, ws.drain, ws.endf, n))
                    return out
                if r != NOT_PLAIN:
                    self._outputs_valid = False
                    raise stepping.diverged(ws, t0, (t - t0) / n)
        ws, tin = self.ws, self._tick.tin
        mask = self._tick.read(ship, vehicle)
        span = t - self.time  # (_substeps_to's span and substeps; its checks when the span is not plainly > 0)
        n, dt = (stepping.substeps(span, self._substep()) if 0.0 < span < math.inf and not self.winch_enabled
                 else self._substeps_to(t, "tick"))
        if n == 0:  # nothing to step: the composition (targets kept for the next interval)
            for e in range(2):
                if mask >> e & 1:
                    stepping.set_target(ws, e, END_NAMES[e], tin[e, 0:3], tin[e, 3:6])
            count = stepping.drain_count(ws) if drain else 0
            self._evaluate_outputs()
            return TickOutput(count, ws.drain, ws.endf, 0)
        self._outputs_valid, winch = False, self.winch_enabled and self._winch_moving()
        r = stepping.run_tick(ws, tin, mask, self.time, t, n, dt, drain)
        self.time = t
        if winch:
            self._winch_sync()
        self._want_outputs = self._outputs_valid = True
        return tuple.__new__(TickOutput, (r, ws.drain, ws.endf, n))  # (TickOutput's own __new__ is a Python call)

    def step(self, dt) -> None:
        """One substep of size dt (UnstableTimeStepError above the stability limit)."""
        limit = self._dt_rule / self.config.dg.cfl
        if self._winch_moving() and dt > 0:
            limit = min(limit, self._winch_limit(float(dt)))
        if dt <= 0 or dt > limit:
            raise UnstableTimeStepError(f"step: dt = {dt:g} s outside (0, {limit:g}] s (stability limit)")
        self._run(1, float(dt), self.time + float(dt))

    def drain_end_tensions(self):
        """(t, T_ship, T_vehicle) at the start of every substep since the last call (newest cap kept)."""
        return stepping.drain(self.ws)

    # ------------------------------------------------------------------ outputs (outputs.py)
    def _evaluate(self):
        """A full right-hand-side evaluation at the current state (dU, endf, work arrays)."""
        self._outputs_valid = False
        stepping.evaluate(self.ws, self.time)

    def _evaluate_outputs(self):
        """What the outputs (state(), end_forces(), body_state()) read of a right-hand-side evaluation
        at the current state (end loads, modal work channels; sampling.evaluate_outputs). Done once
        per state: by the tick itself once outputs have been asked for (a node asking for all three
        per tick pays for one evaluation, inside the tick's compiled call), else here."""
        self._want_outputs = True
        if not self._outputs_valid:
            stepping.evaluate_outputs(self.ws, self.time)
            self._outputs_valid = True

    def positions_at(self, arc_lengths):
        """r(s) (n, 3) from the anchor and int q ds."""
        return outputs.positions_at(self.ws, self.P, self.s_edges, self.L, arc_lengths)

    def state(self, arc_lengths=None):
        """Position, velocity, strain, tension, curvature and bending moment at arc lengths s
        (one compiled sampling kernel, sampling.py)."""
        self._evaluate_outputs()
        plan = outputs.plan(self._plans, arc_lengths, self.s_edges, self.ws.h, self.P, self.L,
                            self.config.node.output_points, self.ops.points)
        return outputs.sampled_state(self.ws, plan, self.law, self.config.cable.gamma0, self.time, self._substep())

    def end_forces(self):
        """Force (and moment) BY the cable ON each end: -n T_hat at the boundary fluxes."""
        self._evaluate_outputs()
        return outputs.end_forces(self.ws)

    def end_tension(self, end):
        """Axial tension at end 'ship' or 'vehicle' (end_forces()'s, without building them: the winch asks every tick)."""
        self._evaluate_outputs()
        return float(self.ws.endf[end_index(end), Y.E_T])

    def end_kinematics(self, arc_lengths):
        """What the snap guard's relative end speed reads (base.relative_end_speed): the cable's
        (positions, velocities) (n, 3) at ``arc_lengths`` and, per end, the body's (position, velocity,
        angular velocity) or None: the numbers of state() and body_state(), without the rest of the
        sampled state or the bodies' accelerations (a look-ahead asks every tick)."""
        self._evaluate_outputs()
        plan = outputs.plan(self._plans, arc_lengths, self.s_edges, self.ws.h, self.P, self.L,
                            self.config.node.output_points, self.ops.points)
        pos, vel = outputs.sampled_kinematics(self.ws, plan, self.law, self.config.cable.gamma0)
        return pos, vel, self.end_bodies()

    def end_bodies(self):
        """Per end, the body's (position, velocity, angular velocity) or None (end_kinematics' third item)."""
        return tuple((b[0:3], b[7:10], b[10:13]) if kind.position == "body" else None
                     for b, kind in zip(self.ws.bs, self.ends))

    def body_state(self, end):
        """State of the rigid body at a "body" end (None for other kinds)."""
        e = end_index(end)
        if self.ends[e].position != "body":
            return None
        self._evaluate_outputs()
        return outputs.body_state(self.ws, e)

    def body_pose(self, end):
        """(position, orientation) of the rigid body at a "body" end, body_state()'s two arrays without its
        velocities and acceleration (the node's outputs read no more); None for other kinds."""
        e = end_index(end)
        if self.ends[e].position != "body":
            return None
        self._evaluate_outputs()
        b = self.ws.bs[e]
        return BodyPose(b[0:3].copy(), b[3:7].copy())

    # ------------------------------------------------------------------ winch (winch_driver.py)
    @property
    def unstretched_length(self) -> float:
        """L(t): unstretched length of cable in the domain (m)."""
        return float(self.ws.prm[Y.P_WL])

    @property
    def pay_out_rate(self) -> float:
        """dL/dt reached at the current time (m/s)."""
        return float(self.ws.prm[Y.P_WR0])

    def set_pay_out_rate(self, rate: float) -> None:
        """Rate dL/dt (m/s, > 0 pays out) reached by a linear ramp over the next advance_to, then held."""
        winch_driver.set_rate(self.ws, self.winch_enabled, rate)

    def _winch_moving(self) -> bool:
        return winch_driver.moving(self.ws, self.winch_enabled)

    def _winch_limit(self, span):
        return winch_driver.limit(self.ws, self.winch_enabled, span, self.P, self.config.dg.cfl, self.stable_time_step)

    def _winch_substep(self, span):
        return winch_driver.substep(self.ws, self.winch_enabled, span, self.P, self.config.dg.cfl, self.fixed_dt,
                                    self.stable_time_step)

    def _winch_sync(self):
        """After a moving interval: length, element edges, sampling plans and time step follow L."""
        self.L = float(self.ws.prm[Y.P_WL])
        self.s_edges = np.concatenate(([0.0], np.cumsum(self.ws.h)))
        self._plans.clear()
        self._dt_rule = self.stable_time_step()
