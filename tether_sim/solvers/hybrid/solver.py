"""Hybrid rod-catenary tether solver [GP]: catenary elements where tension dominates, Kirchhoff rod
elements where it does not, joined by spherical joints; implicit generalized-alpha in time, box
scheme in arc length, the whole discretised step solved by Newton with a sparse LU.

See docs/hybrid_solver.md for the method, the choices made and the measured iteration counts.
"""

import copy
import math

import numpy as np

from tether_sim.errors import ConfigError, SolverDivergedError
from tether_sim.numerics.gen_alpha import gen_alpha_coefficients
from tether_sim.numerics.interp import interp_columns
from tether_sim.numerics.rotations import rotate_frame
from tether_sim.physics.bodies import body_acceleration, pack_body_params, submerged_weight
from tether_sim.physics.end_conditions import end_kind
from tether_sim.physics.waves import wave_components
from tether_sim.solvers.base import BodyState, EndForces, SolverState, compose_tick, end_index
from tether_sim.solvers.hybrid import zoning
from tether_sim.solvers.hybrid.chain import build_chain, rod_blocks
from tether_sim.solvers.hybrid.initial import InitialStateMixin
from tether_sim.solvers.hybrid.newton import MAX_TURN, NewtonMixin, _NewtonFailure
from tether_sim.solvers.hybrid.newton_band import (FAIL_ITERATIONS, FAIL_RESIDUAL, FAIL_SINGULAR, FAIL_UPDATE,
                                                   newton_band)
from tether_sim.solvers.hybrid.kernels import elastic_strain, pack_parameters
from tether_sim.solvers.hybrid.layout import (CAT_EPS, CAT_T, CAT_TAN, CAT_V, HP_AF, HP_AM, HP_GAM, HP_TIME, ROD_EPS,
                                              ROD_F, ROD_KAPPA, ROD_V)
from tether_sim.solvers.hybrid.rod import frame_at
from tether_sim.solvers.hybrid.state_io import (EndMotion, close_rod_shapes, convert_state, end_target, frames_along,
                                                node_profile, shape_along)
from tether_sim.solvers.hybrid.winch import HybridWinchMixin

MAX_HALVINGS = 6
CLOSURE_LIMIT = 0.01  # largest gap between a line's shape and where its end is held (driven, body), per metre of line (_check_closure)
MAX_BOOST = 256.0
_EYE = np.eye(3)  # largest factor on the rod switching tension after failed Newton solves


FAILURES = {FAIL_RESIDUAL: "non-finite residual", FAIL_SINGULAR: "singular Jacobian",
            FAIL_UPDATE: "non-finite Newton update", FAIL_ITERATIONS: "no convergence"}


class HybridRodCatenarySolver(InitialStateMixin, NewtonMixin, HybridWinchMixin):
    """TetherSolver of Goyal & Perkins (see tether_sim.solvers.base for the interface contract)."""

    name = "hybrid"

    def __init__(self, config):
        self.config = config
        cab, env, opt = config.cable, config.environment, config.hybrid
        self.opt = opt
        self.length = cab.length
        self.n_seg = opt.n_segments
        self.s_grid = np.linspace(0.0, cab.length, self.n_seg + 1)
        self.ds = cab.length / self.n_seg
        if cab.EI <= 0.0 and opt.zoning in ("all_rod", "fixed"):
            raise ConfigError(f"hybrid.zoning={opt.zoning!r} needs rod elements, but cable.EI = 0")
        self.EI = cab.EI
        self.ck = 1.0 / cab.EA if cab.EA > 0.0 else 0.0  # compliance c_k [GP Eq. 1]
        self.GJ = cab.GIp if cab.GIp > 0.0 else cab.EI  # torsion needs a stiffness; default GJ = EI
        self.inertia_b = cab.gamma0 * cab.area / (4.0 * math.pi)  # rho_c * pi r^4 / 4 with pi r^2 = A
        self.inertia_t = 2.0 * self.inertia_b
        if opt.rotary_inertia_bend > 0.0:
            self.inertia_b = opt.rotary_inertia_bend
        if opt.rotary_inertia_torsion > 0.0:
            self.inertia_t = opt.rotary_inertia_torsion
        self.cz = np.asarray(env.current_z, dtype=float)
        self.cx = np.asarray(env.current_x, dtype=float)
        self.cy = np.asarray(env.current_y, dtype=float)
        self.net_weight = abs(cab.gamma0 - env.fluid_density * cab.area) * env.g
        self.waves = wave_components(config)  # on from t = 0 (the initial relaxation is in still water)
        self.ends = (config.ship_end, config.vehicle_end)
        self.end_kinds = tuple(end_kind(e.kind, f"{n}.kind") for n, e in zip(("ship_end", "vehicle_end"), self.ends))
        body = [k.position == "body" for k in self.end_kinds]
        body_weight = submerged_weight(config.body, env) if any(body) else 0.0
        self.compression_width = 1e-3 * max(self.net_weight * cab.length + body_weight, 1e-9)
        self.body_params = tuple(pack_body_params(config.body, env) if b else None for b in body)
        holds = (opt.hold_direction_ship, opt.hold_direction_vehicle)
        # an end's frame is held at a clamped row, and at a force end with hybrid.hold_direction_* (the GP
        # benchmark's right end); a body's end, prescribed and fixed ends are moment free
        self.end_held = tuple(k.direction == "held" or (not k.kinematic and hold)
                              for k, hold in zip(self.end_kinds, holds))
        self.free_ends = [k.load == "zero" or (k.load == "applied" and not np.any(e.force))
                          for k, e in zip(self.end_kinds, self.ends)]
        self.end_motion = [EndMotion(np.asarray(e.position, dtype=float)) for e in self.ends]
        self.end_load = [(np.asarray(e.force, dtype=float), np.asarray(e.moment, dtype=float)) for e in self.ends]
        self.time = 0.0
        self._last_zoning = -np.inf
        self.stats = {"steps": 0, "newton_iterations": 0, "max_iterations": 0, "halvings": 0, "rezonings": 0}
        self._record = ([], [], [])
        self._setup_winch(config)  # winch.py: segments added and removed at the winch end
        self._init_state()

    # ------------------------------------------------------------------ set-up
    def _set_chain(self):
        self._profile_cache = None
        self.chain = build_chain(self.zones, self.s_grid, self.end_kinds, self.end_held, self.free_ends,
                                 self.body_params)
        n = self.chain.nnz_max
        self._coo = (np.empty(n, dtype=np.int64), np.empty(n, dtype=np.int64), np.empty(n))

    # ------------------------------------------------------------------ interface
    def set_end_motion(self, end, position, velocity):
        self.end_motion[end_index(end)].set_target(np.asarray(position, dtype=float), np.asarray(velocity, dtype=float))

    def set_end_load(self, end, force, moment=(0.0, 0.0, 0.0)):
        self.end_load[end_index(end)] = (np.asarray(force, dtype=float), np.asarray(moment, dtype=float))

    def stable_time_step(self):
        return self.opt.time_step

    def step(self, dt):
        self._winch_begin(self.time, self.time + float(dt))
        self._step_with_retry(float(dt))
        self._winch_finish(self.time)

    def advance_to(self, t):
        t = float(t)
        for m in self.end_motion:
            m.begin(self.time, t)
        self._winch_begin(self.time, t)
        n = 0
        dt = self.opt.time_step
        while self.time < t - 1e-12 * max(1.0, abs(t)):
            h = min(dt, t - self.time)
            if t - self.time - h < 1e-3 * dt:
                h = t - self.time
            self._step_with_retry(h)
            n += 1
        self.time = max(self.time, t)
        for m in self.end_motion:
            m.finish(t)
        self._winch_finish(self.time)
        return n

    def state(self, arc_lengths=None):
        if arc_lengths is None:
            arc_lengths = np.linspace(0.0, self.length, self.config.node.output_points)
        s = np.asarray(arc_lengths, dtype=float)
        prof = self._profile()
        v = np.empty((s.size, 12))
        interp_columns(s, prof["s"], self._state_columns(prof), v)
        if self.winch_end is None:
            elem = np.clip((s / self.ds).astype(int), 0, self.n_seg - 1)
        else:  # the grid is not uniform with a winch
            elem = np.clip(np.searchsorted(self.s_grid, s, side="right") - 1, 0, self.n_seg - 1)
        extra = {"zone": self.zones[elem].astype(np.int64), "shear": v[:, 6], "torsion_moment": v[:, 7],
                 "newton": dict(self.stats)}
        return SolverState(time=self.time, arc_length=s, position=v[:, 0:3], velocity=v[:, 3:6], tension=v[:, 8],
                           strain=v[:, 9], curvature=v[:, 10], bending_moment=v[:, 11], time_step=self.opt.time_step,
                           extra=extra)

    @staticmethod
    def _state_columns(prof):
        """The profile's fields state() interpolates, as the columns of one array: position (3), velocity (3), shear,
        torsion, tension, strain, curvature, moment. Made once per profile (a tick's state() calls share it)."""
        cols = prof.get("state_columns")
        if cols is not None:
            return cols
        K = prof["s"].size
        cols = np.empty((K, 12))
        cols[:, 0:3] = prof["position"]
        cols[:, 3:6] = prof["velocity"]
        for k, name in enumerate(("shear", "torsion", "tension", "strain", "curvature", "moment")):
            cols[:, 6 + k] = prof[name]
        prof["state_columns"] = cols
        return cols

    def _profile(self):
        """node_profile of the current state, evaluated once per state: a node's tick reads it through state(), end_forces()
        and body_state() five times. Valid while the state's arrays are the same objects at the same time and no step,
        restore or re-zoning has invalidated it (each sets _profile_cache to None)."""
        key = (self.Y, self.Lf, self.positions, self.chain)
        cached = self._profile_cache
        if cached is not None and cached[1] == self.time and all(a is b for a, b in zip(cached[0], key)):
            return cached[2]
        prof = node_profile(self)
        self._profile_cache = (key, self.time, prof)
        return prof

    def end_forces(self):
        prof = self._profile()
        f = prof["force"]
        q = prof["moment_vec"]
        return EndForces(ship_force=f[0].copy(), vehicle_force=-f[-1], ship_moment=q[0].copy(), vehicle_moment=-q[-1],
                         ship_tension=float(prof["tension"][0]), vehicle_tension=float(prof["tension"][-1]))

    def body_state(self, end):
        e = end_index(end)
        x = self.body_x[e]
        if x is None:
            return None
        acc = np.empty(3)
        F = self.end_forces()
        force = F.ship_force if e == 0 else F.vehicle_force
        uc = np.zeros(3)
        if self.cz.size:
            uc[0] = np.interp(x[2], self.cz, self.cx)
            uc[1] = np.interp(x[2], self.cz, self.cy)
        body_acceleration(x, self.body_params[e], np.asarray(force, dtype=float), uc, acc)
        return BodyState(position=x[0:3].copy(), orientation=x[3:7].copy(), velocity=x[7:10].copy(),
                         angular_velocity=x[10:13].copy(), acceleration=acc)

    def drain_end_tensions(self):
        t, a, b = (np.asarray(x, dtype=float) for x in self._record)
        self._record = ([], [], [])
        return t, a, b

    def tick(self, t, ship=None, vehicle=None, drain=True):
        """One node tick (base.py's contract) as the composition of the calls above."""
        return compose_tick(self, t, ship, vehicle, drain)

    def snapshot(self):
        return copy.deepcopy({"Y": self.Y, "Yt": self.Yt, "Lf": self.Lf, "zones": self.zones, "time": self.time,
                              "positions": self.positions, "rdot": self.rdot, "motion": self.end_motion,
                              "load": self.end_load, "stats": self.stats, "body_x": self.body_x,
                              "body_xd": self.body_xd, "last_zoning": self._last_zoning, **self._winch_snapshot()}) | {
            "factorisation": self._factorisation_snapshot()}

    def restore(self, snap):
        kept = snap.get("factorisation")
        snap = copy.deepcopy({k: v for k, v in snap.items() if k != "factorisation"})
        self.Y, self.Yt, self.Lf, self.zones = snap["Y"], snap["Yt"], snap["Lf"], snap["zones"]
        self.time, self.positions, self.rdot = snap["time"], snap["positions"], snap["rdot"]
        self.end_motion, self.end_load, self.stats = snap["motion"], snap["load"], snap["stats"]
        self.body_x, self.body_xd = snap["body_x"], snap["body_xd"]
        self._last_zoning = snap.get("last_zoning", -np.inf)
        self._winch_restore(snap)
        self._set_chain()
        self._record = ([], [], [])
        self._factorisation_restore(kept)

    def _factorisation_snapshot(self):
        """The factorisation the next step would start with (hybrid.reuse_factorisation), so that a restored run
        takes the same Newton path as the run it was taken from: (step key without the chain, band LU arrays, the
        Python twin's factorisation), or None. The twin's SuperLU object is shared, not copied (it is only read)."""
        key = self._lu_key
        if key is None or key[0] is not self.chain:
            return None
        band = None if self._band is None else (self._band.copy(), *(a.copy() for a in self._lu))
        return key[1:], band, self._fd_lu

    def _factorisation_restore(self, kept):
        """The factorisation of a snapshot (_factorisation_snapshot) for the chain restore() just built."""
        self._lu_key, self._fd_lu = None, None
        if kept is not None:
            key, band, self._fd_lu = kept
            self._lu_key = (self.chain, *key)
            if band is not None:
                self._band, self._lu = band[0].copy(), tuple(a.copy() for a in band[1:])

    # ------------------------------------------------------------------ stepping
    _rho = None
    _band = None
    _lu = None
    _lu_key = None  # (chain, dt, rho_inf, relaxing) of the last step's factorisation (_factorisation_kept)
    _pcache = (None, None)
    _profile_cache = None

    def _parameters(self, dt):
        rho = self.opt.rho_inf if self._rho is None else self._rho
        key = (dt, rho, self._rho is None)
        if self._pcache[0] != key:  # packed once per (step, rho_inf, relaxing); the kernels only read it
            self._pcache = (key, self._pack_parameters(dt, rho, waves=self._rho is None))
        P = self._pcache[1]
        P[HP_TIME] = self.time  # the wave field's clock (t_n of the step; kernels.wave_state)
        return P

    def _pack_parameters(self, dt, rho, waves=True):
        am, af, g = gen_alpha_coefficients(rho)
        return pack_parameters(self.config.cable, self.config.environment, dt, am, af, g, self.EI, self.GJ,
                               self.inertia_b, self.inertia_t, self.opt.compression_softening, self.compression_width,
                               segment=self.ds, waves=self.waves if waves else None)

    def _step_with_retry(self, dt):
        pieces = [dt]
        level = 0
        boost = 4.0
        while pieces:
            h = pieces.pop(0)
            self._winch_prepare(h)  # split or merge at the winch end for the length at time + h
            snap = (self.Y.copy(), self.Yt.copy(), self.Lf.copy())
            try:
                self._step(h)
            except _NewtonFailure as exc:
                self.Y, self.Yt, self.Lf = snap
                # a catenary losing its tension is ill-conditioned [GP Sec. 5]: widen the rod zones first,
                # with switching tensions 4, 16, 64, 256 x T_on on repeated failures, then halve the step
                while boost <= MAX_BOOST and self.opt.zoning == "adaptive" and self.EI > 0.0:
                    changed = self._rezone(boost=boost)
                    boost *= 4.0
                    if changed:
                        break
                else:
                    changed = False
                if changed:
                    self.stats["failure_rezonings"] = self.stats.get("failure_rezonings", 0) + 1
                    pieces.insert(0, h)
                    continue
                level += 1
                self.stats["halvings"] += 1
                if level > MAX_HALVINGS:
                    raise SolverDivergedError(f"hybrid solver: Newton failed at t = {self.time:.6g} s "
                                              f"even with dt = {h:.3g} s ({exc})") from None
                pieces = [0.5 * h, 0.5 * h] + pieces

    def _velocity_end(self, e):
        """A kinematic end that is not a body's: its velocity is v_BC (prescribed motion, or 0)."""
        return self.end_kinds[e].kinematic and self.end_kinds[e].position != "body"

    def _update_end_groups(self, t_new):
        ch = self.chain
        K = ch.grid.size
        for e, node in ((0, 0), (1, K - 1)):
            g = ch.end_group[e]
            sign = -1.0 if e == 0 else 1.0  # internal force f(0) = -F_applied, f(L) = +F_applied
            rod = ch.kind[node] == zoning.ROD
            if self._velocity_end(e):
                v = self.end_motion[e].velocity_at(t_new) if self.end_kinds[e].position == "motion" else np.zeros(3)
                ch.gpar[g, 1:4] = v if rod else 0.0
                if not rod:
                    ch.gpar[g, 0:3] = v
            else:
                F, M = self.end_load[e]
                if rod:
                    ch.gpar[g, 1:4] = sign * F
                    ch.gpar[g, 4:7] = sign * M
                elif self.free_ends[e]:
                    t = self.Y[node, CAT_TAN:CAT_TAN + 3]
                    from tether_sim.solvers.hybrid.catenary import tangent_normals
                    p1, p2 = tangent_normals(t)
                    ch.gpar[g, 0:3], ch.gpar[g, 3:6] = p1, p2
                    ch.gpar[g, 6] = max(self.net_weight * self.length, 1e-12)
                else:
                    ch.gpar[g, 0:3] = sign * F

    def _step(self, dt):
        ch = self.chain
        P = self._parameters(dt)
        t_new = self.time + dt
        if self.winch_end is not None:  # the winch element's length at t_{n+1}
            self._winch_set_length(t_new)
        self._update_end_groups(t_new)
        K = ch.grid.size
        bodies = [e for e in (0, 1) if ch.body_node[e] >= 0]
        bodies.sort(key=lambda e: ch.body_node[e])
        nb = len(bodies)
        # body nodes follow the cable nodes in every node array
        rn = np.zeros((K + nb, 6))
        rn[:K, 0:3] = self.positions
        rn[:K, 3:6] = self.rdot
        Yn = np.empty((K + nb, self.Y.shape[1]))
        Ytn = np.empty_like(Yn)
        Ln = np.empty((K + nb, 3, 3))
        Yn[:K], Ytn[:K], Ln[:K], Ln[K:] = self.Y, self.Yt, self.Lf, _EYE
        for i, e in enumerate(bodies):
            Yn[K + i], Ytn[K + i] = self.body_x[e], self.body_xd[e]
        Y = Yn.copy()  # predictor: the state at t_n (robust after abrupt starts)
        cat = ch.kind != zoning.ROD
        Y[:K][cat, 4:7] /= np.linalg.norm(Y[:K][cat, 4:7], axis=1)[:, None]
        n = ch.n_unknowns
        scale = self._unknown_scales(Yn)
        tangent_unknowns = getattr(ch, "tangent_unknowns", None)
        if tangent_unknowns is None:
            kind_ext = np.concatenate([ch.kind, np.full(nb, 2)])
            tangent_unknowns = ch.tangent_unknowns = (ch.idx_slot >= 4) & (ch.idx_slot < 7) & (
                kind_ext[ch.idx_node] == zoning.CATENARY)
        if self.opt.jacobian == "analytic":
            it = self._newton_compiled(Y, Yn, Ytn, Ln, rn, P, scale, tangent_unknowns)
        else:
            it = self._newton_python(Y, Yn, Ytn, Ln, rn, P, scale, tangent_unknowns, n, bodies)
        for e in bodies:
            x = Y[ch.body_node[e]].copy()
            self.body_xd[e] = ((x - self.body_x[e]) / dt - (1.0 - P[HP_GAM]) * self.body_xd[e]) / P[HP_GAM]
            x[3:7] /= np.linalg.norm(x[3:7])
            self.body_x[e] = x
        self._commit(np.ascontiguousarray(Y[:K]), dt, P, it)

    def _newton_compiled(self, Y, Yn, Ytn, Ln, rn, P, scale, tangent_unknowns):
        """Newton iterations with the analytic band Jacobian, compiled (newton_band.py). With
        hybrid.reuse_factorisation the factorised iteration matrix of the last step is kept for the next one while the
        chain and the step's parameters (step size, rho_inf) are the same (_kept_factorisation)."""
        ch = self.chain
        kl, ku = ch.kl, ch.ku
        n = ch.n_unknowns
        if self._band is None or self._band.shape != (2 * kl + ku + 1, n):
            self._band = np.zeros((2 * kl + ku + 1, n))
            self._lu = (np.empty(n, dtype=np.int64), np.ones(n), np.zeros(1, dtype=np.int64))
        ipiv, rs, held = self._lu
        if not self._factorisation_kept():
            held[0] = 0
        counts = np.zeros(3, dtype=np.int64)
        groups = (ch.gkind, ch.ga, ch.gb, ch.grow, ch.gpar, ch.noff, ch.nslot, ch.idx_node, ch.idx_slot)
        it = newton_band(groups, kl, ku, ch.low, ch.last, tangent_unknowns, scale, Y, Yn, Ytn, Ln, rn, ch.s, P, self.cz, self.cx,
                         self.cy, self.opt.max_newton_iterations, self.opt.newton_tolerance, MAX_TURN, self._band,
                         ipiv, rs, held, counts)
        st = self.stats
        st["jacobians"] = st.get("jacobians", 0) + int(counts[0])
        if counts[1]:
            st["line_search_exhausted"] = st.get("line_search_exhausted", 0) + int(counts[1])
        if counts[2]:
            st["kept_factorisation_failures"] = st.get("kept_factorisation_failures", 0) + int(counts[2])
        if it < 0:
            raise _NewtonFailure(FAILURES[it])
        return it

    def _factorisation_kept(self):
        """hybrid.reuse_factorisation: may the step being solved start with the factorisation of the last one? Yes if
        it was made for this chain (the same zones, joints and ends) and the same step size and rho_inf. Step sizes
        equal to 1e-9 relative count as the same: advance_to's steps to a tick's time differ in the last bits, and
        the iteration matrix changes by as much (it is an approximation anyway; the converged step does not depend
        on it). Records this step's key for the next."""
        dt, rho, relaxing = self._pcache[0]
        key, self._lu_key = self._lu_key, (self.chain, dt, rho, relaxing)
        return (self.opt.reuse_factorisation and key is not None and key[0] is self.chain and key[2:] == (rho, relaxing)
                and abs(key[1] - dt) <= 1e-9 * dt)

    def _commit(self, Y, dt, P, iterations):
        self._profile_cache = None
        ch = self.chain
        g = P[HP_GAM]
        v_old = self._world_velocities()
        self.Yt = ((Y - self.Y) / dt - (1.0 - g) * self.Yt) / g
        blocks = rod_blocks(ch)
        if self.opt.frames_from_curvature:  # only each block's anchor keeps its frame advanced in time
            advanced = [last if self._anchored_at_last(first, last) else first for first, last in blocks]
        else:
            advanced = np.nonzero(ch.kind == zoning.ROD)[0]
        for c in advanced:
            out = np.empty((3, 3))
            frame_at(Y[c], self.Y[c], self.Lf[c], dt, out)
            self.Lf[c] = out
        self.Y = Y
        if self.opt.frames_from_curvature:
            self._integrate_frames(blocks)
        self.time += dt
        # node positions: generalized-alpha variables of dr/dt = v (their rate r' collocated: r'_am = v_af)
        am, af = P[HP_AM], P[HP_AF]
        v_af = (1.0 - af) * v_old + af * self._world_velocities()
        rdot = (v_af - (1.0 - am) * self.rdot) / am
        self.positions = self.positions + dt * ((1.0 - g) * self.rdot + g * rdot)
        self.rdot = rdot
        K = ch.grid.size
        driven = [None, None]
        for e, node in ((0, 0), (1, K - 1)):  # kinematic ends sit exactly where they are driven
            if self.end_kinds[e].position == "motion":
                driven[e] = self.positions[node] = self.end_motion[e].position_at(self.time)
            elif self.end_kinds[e].position == "fixed":
                driven[e] = self.positions[node] = self.ends[e].position
        for first, last in blocks:  # rod shape by integrating its tangents from the block start
            if first > 0 and ch.grid[first] == ch.grid[first - 1]:
                self.positions[first] = self.positions[first - 1]  # starts at the joint's catenary node
            if last > first:
                self.positions[first + 1:last + 1] = shape_along(self.positions[first], self.Lf[first:last + 1],
                                                                 self.Y[first:last + 1, ROD_EPS],
                                                                 np.diff(ch.s[first:last + 1]))[1:]
        relax_closes = self._relaxation_recloses()
        if relax_closes:  # judged on the shape the next step starts from, after the re-closing below
            self._note_relaxation_drift(driven[1])
        else:
            self._check_closures(driven[1])
        st = self.stats
        st["steps"] += 1
        st["newton_iterations"] += iterations
        st["max_iterations"] = max(st["max_iterations"], iterations)
        K = ch.grid.size
        self._record[0].append(self.time)
        self._record[1].append(self._node_tension(0))
        self._record[2].append(self._node_tension(K - 1))
        # zones re-evaluated at most every zoning_interval of simulated time: each rod<->catenary
        # conversion perturbs the state a little, and at small steps (dt <= 0.002 s in the L = 200 m
        # slack case) converting every step let those perturbations build up to failure
        due = self.time - self._last_zoning >= self.opt.zoning_interval - 1e-9 * max(dt, 1e-12)
        if self.opt.zoning == "adaptive" and self.EI > 0.0 and (due or self._rho is not None):
            self._last_zoning = self.time
            self._rezone()
        if relax_closes:
            self._check_closures(driven[1])

    def _relaxation_recloses(self):
        """True in a step of the damped initial relaxation (rho_inf = 0, ``relax_time_step``) of an adaptive line whose
        rod shapes are re-closed on their ends: the zones are evaluated after every such step and each rod block closed
        again (close_rod_shapes). The relaxation is a pseudo-time path to the rest shape (its velocities are zeroed and
        its clock reset at the end) in steps 500x the dynamic ones, over which a relaxing rod's rate-form positions
        drift decimetres off its held end within one step; only the re-closed shape is carried on, so the closure check
        judges that one there. In dynamics the check looks before the re-closing (the published shape)."""
        o = self.opt
        return (self._rho is not None and o.zoning == "adaptive" and self.EI > 0.0 and o.close_rod_shapes == "evaluation"
                and o.frames_from_curvature)

    def _note_relaxation_drift(self, driven_far):
        """The within-step drift of a relaxing rod shape off its held far end before the re-closing:
        stats["relax_step_gap"], the largest over the relaxation (m)."""
        K = self.chain.grid.size
        gaps = [float(np.linalg.norm(self.positions[K - 1] - driven_far))] if (
            driven_far is not None and self.chain.kind[K - 1] == zoning.ROD) else []
        gaps += [float(np.linalg.norm(self.positions[node] - end_target(self, e)))
                 for e, node in ((0, 0), (1, K - 1)) if self.end_kinds[e].position == "body"]
        if gaps:
            self.stats["relax_step_gap"] = max(self.stats.get("relax_step_gap", 0.0), max(gaps))

    def _check_closures(self, driven_far):
        """The closure checks of a step (_check_closure): a rod zone ending at a driven or fixed far end, a line's end
        on a body."""
        K = self.chain.grid.size
        if driven_far is not None and self.chain.kind[K - 1] == zoning.ROD:
            self._check_closure(driven_far)
        for e, node in ((0, 0), (1, K - 1)):  # a line's end on a body is where the body's attachment point is
            if self.end_kinds[e].position == "body":
                self._check_closure(end_target(self, e), node, body=True)

    def _check_closure(self, target, node=-1, body=False):
        """A line must end where its end is held: a rod block ending at a kinematic far end where that end is driven,
        a line's end on a body (rod or catenary) at the body's attachment point. A rod block's shape is the integral of
        its tangents from the block start, and the kinematic or body condition holds its end's velocity only, so a
        shape that does not close there is not this line's; a catenary end on a body keeps the gap a rod zone left
        when it turned catenary. The gap (largest so far in stats["closure_gap"], m; the last one at a body end in
        stats["body_gap"]), measured after each step before the zones are re-evaluated (after, in a relaxation step that
        re-closes the rod shapes: _relaxation_recloses), is the integration error of
        the tangents (centimetres on the cross-check network's all-rod excursion tether) unless re-zoning conversions
        have broken the shape (docs/hybrid_solver.md, "Zoning"); beyond CLOSURE_LIMIT of the line's length the run
        stops with a clear error rather than go on with a line that ends elsewhere."""
        node = node % self.chain.grid.size
        gap = float(np.linalg.norm(self.positions[node] - target))
        st = self.stats
        st["closure_gap"] = max(st.get("closure_gap", 0.0), gap)
        if body:
            st["body_gap"] = gap
        where = "the body's attachment point it is joined to" if body else "where its far end is driven"
        length = float(self.s_grid[-1] - self.s_grid[0])
        if gap > CLOSURE_LIMIT * length:
            shape = "rod zone's shape" if self.chain.kind[node] == zoning.ROD else "line's shape"
            raise SolverDivergedError(
                f"hybrid solver: at t = {self.time:.6g} s the {shape} ends {gap:.3g} m from {where} "
                f"({100.0 * gap / length:.3g} % of the line's {length:g} m; limit {100.0 * CLOSURE_LIMIT:g} %): "
                f"re-zoning conversions broke the shape (hybrid.zoning: all_rod keeps it closed; docs/hybrid_solver.md, "
                f"\"Zoning\")")

    def _anchored_at_last(self, first, last):
        """A rod block's frames are re-derived from its last node when that node is a held vehicle end (and the
        block does not also start at a held ship end), else from its first (_integrate_frames)."""
        return last == self.chain.grid.size - 1 and self.end_held[1] and not (first == 0 and self.end_held[0])

    def _integrate_frames(self, blocks=None):
        """Re-derive the frames of each rod block from kappa, L_b = exp(-kappa~ ds) L_a, starting at an
        anchor whose frame was advanced in time [GP Eq. 15-18]: a held end if the block has one, else the
        block's first node. Keeps frames and curvature consistent (no drift of the incremental update).
        From the first node: state_io.frames_along (compiled, the same arithmetic as the loop below)."""
        ch = self.chain
        out = np.empty((3, 3))
        for first, last in rod_blocks(ch) if blocks is None else blocks:
            if not self._anchored_at_last(first, last):
                if last > first:
                    self.Lf[first + 1:last + 1] = frames_along(self.Lf[first], self.Y[first:last + 1, ROD_KAPPA:ROD_KAPPA + 3],
                                                               np.diff(ch.s[first:last + 1]))[1:]
                continue
            for c in range(last - 1, first - 1, -1):
                nb = c + 1
                kap = 0.5 * (self.Y[c, ROD_KAPPA:ROD_KAPPA + 3] + self.Y[nb, ROD_KAPPA:ROD_KAPPA + 3]) * abs(ch.s[c] - ch.s[nb])
                rotate_frame(self.Lf[nb], -kap, out)
                self.Lf[c] = out

    def _strain(self, T):
        """Static strain carrying tension T (inverse of the law at deps/dt = 0)."""
        return float(elastic_strain(float(T), self._parameters(self.opt.time_step)))

    def _node_strain(self, c):
        return float(self.Y[c, ROD_EPS if self.chain.kind[c] == zoning.ROD else CAT_EPS])

    def _world_velocities(self):
        v = self.Y[:, CAT_V:CAT_V + 3].copy()
        rod = self.chain.kind == zoning.ROD
        if rod.any():
            v[rod] = np.einsum("kji,kj->ki", self.Lf[rod], self.Y[rod, ROD_V:ROD_V + 3])
        return v

    def _node_tension(self, c):
        return float(self.Y[c, ROD_F] if self.chain.kind[c] == zoning.ROD else self.Y[c, CAT_T])

    def _rezone(self, boost=1.0):
        """Re-evaluate the zones (after each step; with boost > 1 after a failed step); True if changed."""
        ch = self.chain
        ends = getattr(ch, "grid_ends", None)
        if ends is None:
            ends = ch.grid_ends = zoning.grid_ends(ch.grid)
        if boost == 1.0 and self._quiet is not None and self._quiet[0] is ch:
            raw = self._raw_zones(ends)
            if raw is not None and np.array_equal(raw, self._quiet[2]) and self._quiet[1] == self._end_rod_elements():
                return self._zones_kept()
        T_elem, kappa, shear = self._element_criteria(ends)
        new = self._classify(T_elem, self.zones, boost, kappa, shear)
        if boost > 1.0:
            new = np.maximum(new, self.zones)  # only add rod elements
        if np.array_equal(new, self.zones):
            if boost == 1.0:
                raw = self._raw_zones(ends)
                self._quiet = None if raw is None else (ch, self._end_rod_elements(), raw)
            return self._zones_kept()

        self.Y, self.Yt, self.Lf, self.positions, self.rdot = convert_state(self, new)
        self.zones = new
        self._set_chain()
        self.stats["rezonings"] += 1
        return True

    def _element_criteria(self, ends):
        """(T_elem, kappa, shear) per element: the lower tension of each element's nodes (at a joint: the lower of
        both sides), so that no catenary node is left slack; and the bending the line carries: a rod element bent or
        sheared more than its weight does it stays rod until the tension dominates (zoning.py)."""
        ch = self.chain
        T_node = np.where(ch.kind == zoning.ROD, self.Y[:, ROD_F], self.Y[:, CAT_T])
        T_grid = np.minimum(T_node[ends[0]], T_node[ends[1]])
        T_elem = np.minimum(T_grid[1:], T_grid[:-1])
        kappa, shear = zoning.element_bending(ch.kind, self.Y, ch.grid, ch.s, self.zones.size, ends)
        return T_elem, kappa, shear

    # (chain, end rod elements, zone_criterion's raw zones) of the last full zone evaluation that changed nothing
    _quiet = None

    def _raw_zones(self, ends):
        """The zones by the criterion alone (zoning.zone_criterion), or None where it leaves the decision to classify.
        A zone evaluation whose raw zones equal those of an evaluation of the same chain that changed nothing changes
        nothing either: classify's clean-up is a function of the raw zones (and of min_zone_elements and the held
        end rods). So the full evaluation (~70 us of numpy at 50 elements) runs only when a zone can change."""
        o = self.opt
        raw = np.empty(self.zones.size, dtype=self.zones.dtype)
        ch = self.chain
        if zoning.zone_criterion(ch.kind, self.Y, ch.grid, ch.s, ends[0], ends[1], self.zones, self.EI,
                                 max(self.net_weight, 1e-12), o.chi_on, o.chi_off, raw):
            return raw
        return None

    def _zones_kept(self):
        """A zone evaluation without a change: the rod shapes back onto their ends (state_io.close_rod_blocks)."""
        if self.opt.close_rod_shapes == "evaluation" and (self.chain.kind == zoning.ROD).any():
            self._profile_cache = None
            close_rod_shapes(self)
        return False
