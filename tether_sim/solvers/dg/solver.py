"""DGCableSolver: the high-order DG / nested-LDG cable solver of Palm & Eskilsson 2020.

Implements :class:`tether_sim.solvers.base.TetherSolver`. The state is the modal expansion of
u = [q, v] per element (``layout.py``); positions are r(s) = r_a + int_{s_a}^{s} q ds from an
anchor end s_a (the ship end unless only the vehicle end is held), whose position r_a follows the
boundary flux velocity v_hat / gamma0 in the same Runge-Kutta stages and is set exactly to the
prescribed position of a held end after every substep. Because the DG update conserves
int q ds up to the boundary fluxes, r(L) - r(0) follows v_hat(L) - v_hat(0) to round-off.
"""

import math
import time as wallclock

import numpy as np

from tether_sim.errors import UnstableTimeStepError
from tether_sim.numerics.operators import element_operators, project_function
from tether_sim.physics.bodies import BODY_STATE_SIZE, initial_body_state, pack_body_params, submerged_weight
from tether_sim.physics.constitutive import TensionLaw, cap_stiffness
from tether_sim.physics.end_conditions import KIND_CODES, anchor_end, end_kind, held_in_place
from tether_sim.physics.hydrodynamics import (
    added_mass_per_length, air_weight_per_length, current_table, net_weight_per_length,
)
from tether_sim.physics.statics import solve_static
from tether_sim.physics.waves import wave_components
from tether_sim.solvers.dg import layout as Y
from tether_sim.solvers.dg.damping_layout import MODE_AXIAL, MODE_EXPLICIT, MODE_GENERAL
from tether_sim.solvers.dg.equilibrium import polish_equilibrium
from tether_sim.solvers.dg.implicit_damping import DampingWork
from tether_sim.solvers.dg.outputs import OutputsMixin
from tether_sim.solvers.dg.soa import TMP_HEAD, soa_scratch_size
from tether_sim.solvers.dg.stepping import SteppingMixin
from tether_sim.solvers.dg.tick import TG_SET
from tether_sim.solvers.dg.winch_driver import WinchMixin
from tether_sim.solvers.dg.workspace import Workspace
from tether_sim.solvers.work import mesh_sizes

# The relaxation runs in compiled calls of this much wall time (the first of RELAX_FIRST_CHUNK substeps,
# to measure): a signal (Ctrl-C) is handled by Python between two calls, so a long initial.relax_time
# stops within about this; the substeps are those of one advance_to (same size, same times).
RELAX_CHUNK_WALL = 0.2  # s
RELAX_FIRST_CHUNK = 200


class DGCableSolver(SteppingMixin, OutputsMixin, WinchMixin):
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
        self.h = self._element_sizes(opt)
        self.s_edges = np.concatenate(([0.0], np.cumsum(self.h)))
        self.ops = element_operators(self.P, int(opt.quad_points) or None)
        o = self.ops
        self.V, self.Pj, self.D, self.Lf, self.Tr, self.Iq = o.vandermonde, o.projection, o.derivative, o.lift, o.trace, o.integral
        self.cz, self.cx, self.cy = current_table(env)
        self.prm, self.iprm = self._parameters(cab, env, opt)
        self._setup_winch(config)  # winch_driver.py (a moving end of the domain, winch.py)
        self.prm = self._with_waves(config, cab, env, self.prm, self.iprm)
        self.bc = np.zeros((2, Y.N_BC))
        for e, ec in enumerate((config.ship_end, config.vehicle_end)):
            self.bc[e, Y.B_P0:Y.B_P0 + 3] = ec.position
            self.bc[e, Y.B_P1:Y.B_P1 + 3] = ec.position
            self.bc[e, Y.B_F:Y.B_F + 3] = ec.force
            self.bc[e, Y.B_M:Y.B_M + 3] = ec.moment
            d = np.asarray(ec.direction, float)
            nd = np.linalg.norm(d)
            if self.ends[e].direction == "held" and nd == 0.0:
                raise ValueError(f"{('ship_end', 'vehicle_end')[e]}.direction: must be a nonzero vector")
            self.bc[e, Y.B_DIR:Y.B_DIR + 3] = d / nd if nd > 0 else d
        N, nm, nq = self.N, self.P + 1, self.V.shape[0]
        self.U = np.zeros((N, nm, 6))
        self.ra = np.zeros(3)
        self._U0, self._ra0, self._dU, self._dra = np.zeros_like(self.U), np.zeros(3), np.zeros_like(self.U), np.zeros(3)
        self._wq = np.zeros((N, nq, Y.NWQ))
        self._wm = np.zeros((N, nm, Y.NWM))
        self._tr = np.zeros((N, 2, Y.NTR))
        self._fl = np.zeros((N + 1, Y.NFL))
        self._rs = np.zeros((N, 3))
        self._tmp = np.zeros(TMP_HEAD + soa_scratch_size(N, nm, nq))  # + scratch of soa.py
        self._vbc = np.zeros((2, 6))
        self._endf = np.zeros((2, Y.N_ENDF))
        self._buf = np.zeros((int(opt.tension_buffer), 3))
        self._cnt = np.zeros(1, dtype=np.int64)
        self._out = np.zeros(2)
        self._tick_in = np.zeros((2, 6))  # tick(): targets of the driven ends, tick.node_tick's tin
        self._plans = {}
        self._outputs_valid = False  # the output work arrays hold the evaluation at the current state
        self._want_outputs = False  # outputs were asked for: the tick evaluates them (tick.py)
        self._bs = np.zeros((2, BODY_STATE_SIZE))
        self._bs0 = np.zeros((2, BODY_STATE_SIZE))
        self._dbs = np.zeros((2, BODY_STATE_SIZE))
        bp = pack_body_params(config.body, env)
        self._bp = np.ascontiguousarray(np.stack([bp, bp]))
        self._setup_damping(cab, env, opt)
        self._build_workspace(config)
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
        self._set_initial_state(config)

    # ------------------------------------------------------------------ set-up
    def _element_sizes(self, opt):
        wts = np.asarray(opt.element_lengths, float)
        if wts.size and (wts.size != self.N or np.any(wts <= 0)):
            raise ValueError(f"dg.element_lengths: need {self.N} positive weights (dg.n_elements), got {wts.size}")
        return mesh_sizes(self.L, self.N, wts)

    def _parameters(self, cab, env, opt):
        prm = np.zeros(Y.N_PRM)
        prm[Y.P_GAMMA0] = cab.gamma0
        prm[Y.P_EA] = cab.EA
        prm[Y.P_ZETA] = cab.damping
        mt, mn = added_mass_per_length(cab, env)
        prm[Y.P_MT], prm[Y.P_MN] = mt, mn
        prm[Y.P_FBZ] = -net_weight_per_length(cab, env)
        prm[Y.P_HALF_RHO_D] = 0.5 * env.fluid_density * cab.diameter
        prm[Y.P_CDT], prm[Y.P_CDN] = cab.Cdt, cab.Cdn
        prm[Y.P_ZG] = env.seabed_z
        kd = env.seabed_stiffness * cab.diameter
        prm[Y.P_KD] = kd
        prm[Y.P_CCRIT] = 2.0 * math.sqrt(kd * cab.gamma0)
        prm[Y.P_SBZETA] = env.seabed_damping
        prm[Y.P_MU] = env.seabed_friction
        prm[Y.P_VMU] = env.seabed_friction_speed
        prm[Y.P_EI] = cab.EI
        prm[Y.P_EIC] = cap_stiffness(cab)
        prm[Y.P_ZETAB] = cab.bending_damping
        prm[Y.P_BETA] = opt.beta
        prm[Y.P_TORQUE] = cab.torque
        prm[Y.P_LAMBDA_FLOOR] = opt.lambda_floor
        prm[Y.P_LAMBDA_BC] = math.sqrt(self.law.max_slope() / cab.gamma0)
        prm[Y.P_QPEN] = opt.q_penalty if opt.q_penalty_jump != "tension" else 0.0  # auto: _choose_q_penalty
        prm[Y.P_QPENT] = opt.q_penalty if opt.q_penalty_jump == "tension" else 0.0
        prm[Y.P_FBZ_AIR] = -air_weight_per_length(cab, env)
        prm[Y.P_HALF_RHO_D_AIR] = 0.5 * env.air_density * cab.diameter
        prm[Y.P_CDT_AIR], prm[Y.P_CDN_AIR] = env.air_Cdt, env.air_Cdn
        prm[Y.P_SURF_B] = 0.5 * env.surface_smoothing
        ip = np.zeros(Y.N_IPRM, dtype=np.int64)
        ip[Y.I_N], ip[Y.I_P], ip[Y.I_Q] = self.N, self.P, self.V.shape[0]
        ip[Y.I_LAW] = self.law.code
        ip[Y.I_SEABED] = int(env.seabed)
        ip[Y.I_CURRENT] = int(self.cz.size > 0)
        ip[Y.I_BENDING] = int(cab.EI > 0.0 or cab.bending_damping > 0.0 or cab.torque != 0.0)
        ip[Y.I_BENDDAMP] = int(cab.bending_damping > 0.0)
        ip[Y.I_AXDAMP] = int(cab.damping > 0.0 or cab.bending_damping > 0.0)
        ip[Y.I_KIND0], ip[Y.I_KIND1] = KIND_CODES[self.kinds[0]], KIND_CODES[self.kinds[1]]
        ip[Y.I_ANCHOR] = anchor_end(self.kinds)
        ip[Y.I_SURFACE] = int(env.free_surface)
        ip[Y.I_NEEDPOS] = int(env.seabed or self.cz.size > 0 or env.free_surface)
        return prm, ip

    def _with_waves(self, config, cab, env, prm, ip):
        """prm with the wave components appended (layout.py), the Froude-Krylov mass and the depth
        below which the wave kinematics are negligible (< 1e-4 of their surface value: skipped)."""
        comps = wave_components(config)
        n = int(np.asarray(comps.amp).size)
        ip[Y.I_NWAVE] = n
        prm[Y.P_RHO_AH] = env.fluid_density * cab.area  # Froude-Krylov on the displaced volume (docs/waves.md)
        prm[Y.P_WAVE_DEPTH] = float(comps.depth)
        prm[Y.P_WAVE_STRETCH] = float(comps.stretch)
        prm[Y.P_WAVE_ZCUT] = math.inf
        if n == 0:
            return prm
        ip[Y.I_NEEDPOS] = 1
        amp = np.abs(np.asarray(comps.amp, float))
        kmin = float(np.min(np.asarray(comps.k, float)))
        zcut = -float(amp.sum()) - math.log(1e4) / kmin if kmin > 0.0 else -math.inf
        if math.isfinite(comps.depth) and kmin * comps.depth < math.log(1e4):
            zcut = -math.inf  # shallow for its longest component: the kinematics reach the bottom
        prm[Y.P_WAVE_ZCUT] = zcut
        tail = [np.asarray(getattr(comps, f), float) for f in ("amp", "omega", "k", "cos_dir", "sin_dir", "phase")]
        return np.ascontiguousarray(np.concatenate([prm] + tail))

    def _setup_damping(self, cab, env, opt):
        """dg.damping = implicit: the stepper gets prm/iprm without the damping terms (E of the
        splitting) and the implicit damping work arrays; outputs keep the full prm/iprm."""
        mode = MODE_EXPLICIT
        if opt.damping == "implicit" and (cab.damping > 0.0 or cab.bending_damping > 0.0):
            mode = MODE_GENERAL if cab.bending_damping > 0.0 else MODE_AXIAL
        mt, mn = added_mass_per_length(cab, env)
        self._damp = DampingWork(mode, self.ops, self.h, self.kinds, cab, cab.gamma0, mt, mn, opt.beta,
                                 self.law.code, (self.iprm[Y.I_KIND0], self.iprm[Y.I_KIND1]),
                                 max(self.prm[Y.P_LAMBDA_BC], self.prm[Y.P_LAMBDA_FLOOR]))
        self._prm_step, self._iprm_step = self.prm.copy(), self.iprm.copy()
        if mode != MODE_EXPLICIT:
            self._iprm_step[Y.I_AXDAMP] = self._iprm_step[Y.I_BENDDAMP] = 0
            self._iprm_step[Y.I_BENDING] = int(cab.EI > 0.0 or cab.torque != 0.0)
        self._no_fdamp = np.zeros((2, 4))

    def _build_workspace(self, config):
        """Move every array of the compiled code into the arenas of workspace.py (the attributes
        become views of them) so that one call with three array arguments runs a tick."""
        dw = self._damp
        ends = np.zeros((2, 6))
        ends[0, 0:3], ends[1, 0:3] = config.ship_end.position, config.vehicle_end.position
        own = dict(U="U", ra="ra", prm_step="_prm_step", iprm_step="_iprm_step", h="h", V="V", Pj="Pj", D="D",
                   Lf="Lf", Tr="Tr", Iq="Iq", cz="cz", cx="cx", cy="cy", bc="bc", vbc="_vbc", wq="_wq", wm="_wm",
                   trc="_tr", fl="_fl", rs="_rs", tmp="_tmp", dU="_dU", dra="_dra", endf="_endf", bs="_bs",
                   bp="_bp", dbs="_dbs", bs0="_bs0", U0="_U0", ra0="_ra0", buf="_buf", cnt="_cnt", out="_out",
                   prm="prm", iprm="iprm", no_fdamp="_no_fdamp", hw="_hw")
        damp = dict(idp="idp", dprm="dprm", blk="blk", bvec="bvec", wp="wp", wd="wd", band="band", vec="vec",
                    dtmp="tmp", fdamp="fdamp")
        arrays = {slot: getattr(self, a) for slot, a in own.items()}
        arrays.update({slot: getattr(dw, a) for slot, a in damp.items()})
        arrays.update(tab_eps=self.law.tab_eps, tab_T=self.law.tab_T, ends=ends, target=np.zeros((2, 7)),
                      drained=np.zeros(1, dtype=np.int64), drain=np.zeros((3, self._buf.shape[0])),
                      fresh=np.zeros(2, dtype=np.int64),
                      snap=np.zeros(self.U.size + self.prm.size + self.bc.size + self._vbc.size + self.h.size),
                      snap_i=np.zeros(self.iprm.size, dtype=np.int64))
        self.ws = ws = Workspace(arrays)
        for slot, a in own.items():
            setattr(self, a, getattr(ws, slot))
        for slot, a in damp.items():
            setattr(dw, a, getattr(ws, slot))

    @property
    def _end_pos(self):
        """(2, 3) view: position of each end at the solver time (driven ends; start of the others)."""
        return self.ws.ends[:, 0:3]

    @_end_pos.setter
    def _end_pos(self, value):
        self.ws.ends[:, 0:3] = np.asarray(value, float)

    @property
    def _end_vel(self):
        """(2, 3) view: velocity of each driven end at the solver time."""
        return self.ws.ends[:, 3:6]

    @_end_vel.setter
    def _end_vel(self, value):
        self.ws.ends[:, 3:6] = np.asarray(value, float)

    def _set_initial_state(self, config):
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
            tangent, origin = shape.tangent, shape.position(np.array([0.0]))[0]
            end_pos = shape.position(np.array([0.0, self.L]))
        else:
            for e in range(2):
                if self.ends[e].position == "body":
                    self._end_pos[e] = initial_body_state(config.body)[0:3] + np.asarray(config.body.attachment, float)
            A, B = self._end_pos
            q = (B - A) / self.L
            tangent = (lambda s, q=q: np.repeat(q[None, :], np.atleast_1d(s).size, axis=0))
            origin, end_pos = A, np.array([A, B])
        for e in range(self.N):
            self.U[e, :, 0:3] = project_function(self.P, tangent, self.s_edges[e], self.s_edges[e + 1])
        self.U[:, :, 3:6] = 0.0
        a = self.iprm[Y.I_ANCHOR]
        self.ra[:] = end_pos[a]
        for e in range(2):
            if self.ends[e].position in ("cable", "body"):
                self._end_pos[e] = end_pos[e].copy()
            if self.ends[e].position == "body":
                self._bs[e] = initial_body_state(config.body, attachment_world=end_pos[e])
        if shape is not None and self.config.dg.q_penalty_jump == "auto":
            self._choose_q_penalty(shape)
        if shape is not None and all(held_in_place(k) for k in self.kinds):
            self.equilibrium_iterations = polish_equilibrium(self, end_pos[1] - end_pos[0])
        relax = config.initial.relax_time
        if kind == "relax" or (kind == "static" and shape is None):
            relax = relax if relax > 0 else self._default_relax_time()
        if relax > 0:
            self.relax(relax)

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
            for p in (self.prm, self._prm_step):
                p[Y.P_QPENT], p[Y.P_QPEN] = self.config.dg.q_penalty, 0.0

    def set_shape(self, tangent, velocity=None, origin=None):
        """Replace the state: q = tangent(s) (n, 3) = dr/ds and cable velocity velocity(s) (n, 3) (m/s),
        both L2-projected on the modes; origin (3,) = r(0) (default: the current r(0))."""
        r0 = self.positions_at(np.array([0.0]))[0] if origin is None else np.asarray(origin, float)
        g0 = self.config.cable.gamma0
        for e in range(self.N):
            a, b = self.s_edges[e], self.s_edges[e + 1]
            self.U[e, :, 0:3] = project_function(self.P, tangent, a, b)
            self.U[e, :, 3:6] = 0.0 if velocity is None else g0 * project_function(self.P, velocity, a, b)
        if self.iprm[Y.I_ANCHOR] == 0:
            self.ra[:] = r0
        else:
            self.ra[:] = r0 + np.sum(self.h[:, None] * self.U[:, 0, 0:3], axis=0)

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
        self.prm[Y.P_RELAX] = self.relax_rate()
        t0 = self.time
        saved = self.ws.ends.copy()
        try:
            self._relax_in_chunks(t0 + duration)
        finally:
            self.prm[Y.P_RELAX] = 0.0
        self.time = t0
        self._bs[:, 7:13] = 0.0  # bodies start at rest (their velocity was damped anyway)
        for e in range(2):
            if self.ends[e].kinematic:
                self.ws.ends[e] = saved[e]
        self._outputs_valid = False
        self.drain_end_tensions()

    def snapshot(self):
        return dict(time=self.time, U=self.U.copy(), ra=self.ra.copy(), bc=self.bc.copy(), bodies=self._bs.copy(),
                    end_pos=[p.copy() for p in self._end_pos], end_vel=[v.copy() for v in self._end_vel],
                    **self._winch_snapshot())

    def restore(self, snap) -> None:
        self.time = snap["time"]
        self.U[...] = snap["U"]
        self.ra[:] = snap["ra"]
        self.bc[...] = snap["bc"]
        self._bs[...] = snap["bodies"]
        self._end_pos = snap["end_pos"]
        self._end_vel = snap["end_vel"]
        self.ws.target[:, TG_SET] = 0.0
        self._winch_restore(snap)
        self._outputs_valid = False
