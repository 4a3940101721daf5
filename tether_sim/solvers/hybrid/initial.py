"""Initial state of the hybrid solver: zones, straight/arc shape, tensions, damped relaxation.

Mixed into HybridRodCatenarySolver (uses its attributes: config, opt, s_grid, end_kinds, end_held, ...).
"""

import math

import numpy as np

from tether_sim.numerics.rotations import frame_with_tangent
from tether_sim.physics.bodies import initial_body_state, submerged_weight
from tether_sim.physics.statics import solve_static
from tether_sim.solvers.hybrid import zoning
from tether_sim.solvers.hybrid.layout import CAT_EPS, CAT_T, CAT_TAN, CAT_V, N_SLOTS, ROD_OMEGA
from tether_sim.solvers.hybrid.state_io import convert_state, reconstruct_positions


class InitialStateMixin:
    """Set-up methods of the hybrid solver (see docs/hybrid_solver.md, 'End conditions')."""

    def _initial_zones(self, tension):
        opt = self.opt
        n = self.n_seg
        if opt.zoning == "all_rod":
            return np.full(n, zoning.ROD)
        if opt.zoning == "all_catenary" or self.EI <= 0.0:
            return np.full(n, zoning.CATENARY)
        if opt.zoning == "fixed":
            centres = 0.5 * (self.s_grid[1:] + self.s_grid[:-1])
            return np.where(centres < opt.joint_arc_length, zoning.CATENARY, zoning.ROD)
        return self._classify(tension, np.full(n, zoning.CATENARY))

    def _end_rod_elements(self):
        out = []
        for held in self.end_held:
            out.append(max(1, int(math.ceil(self.opt.end_rod_length / self.ds))) if held else 0)
        return tuple(out)

    def _classify(self, T_elem, previous, boost=1.0, kappa_elem=None, shear_elem=None):
        o = self.opt
        f = boost ** -1.5  # T_on scales as chi_on^(-2/3): boost multiplies the switching tensions
        return zoning.classify(T_elem, previous, self.EI, max(self.net_weight, 1e-12), o.chi_on * f, o.chi_off * f,
                               o.min_zone_elements, self._end_rod_elements(), kappa_elem, shear_elem)

    def _init_state(self):
        cfg = self.config
        p0 = np.asarray(self.ends[0].position, dtype=float)
        p1 = np.asarray(self.ends[1].position, dtype=float)
        chord = p1 - p0
        dist = float(np.linalg.norm(chord))
        d = chord / dist if dist > 1e-12 else np.array([0.0, 0.0, -1.0])
        tangents, T_grid = self._static_shape() if cfg.initial.kind == "static" else (None, None)
        if tangents is None:
            tangents, T_grid = self._initial_shape(d, dist)
        target = self._initial_zones(0.5 * (T_grid[1:] + T_grid[:-1]))
        self.zones = np.full(self.n_seg, zoning.CATENARY)  # built as catenary, then converted
        self._set_chain()
        K = self.chain.grid.size
        self.Y = np.zeros((K, N_SLOTS))
        self.Yt = np.zeros((K, N_SLOTS))
        self.Y[:, CAT_T] = T_grid
        self.Y[:, CAT_TAN:CAT_TAN + 3] = tangents
        self.Y[:, CAT_EPS] = [self._strain(T) for T in T_grid]
        self.Lf = np.stack([frame_with_tangent(t) for t in tangents])
        self.r0 = p0.copy()
        self.positions = reconstruct_positions(self)
        self.rdot = np.zeros_like(self.positions)
        if np.any(target == zoning.ROD):
            self.Y, self.Yt, self.Lf, self.positions, self.rdot = convert_state(self, target)
            self.zones = target
            self._set_chain()
            K = self.chain.grid.size
        self.body_x = [None, None]
        self.body_xd = [None, None]
        for e, node in ((0, 0), (1, K - 1)):
            if self.body_params[e] is not None:
                self.body_x[e] = initial_body_state(self.config.body, attachment_world=self.positions[node])
                self.body_xd[e] = np.zeros(13)
        for e, node in ((0, 0), (1, K - 1)):  # a held end starts with its prescribed tangent
            if self.end_held[e] and self.chain.kind[node] == zoning.ROD:
                self.Lf[node] = frame_with_tangent(self.ends[e].direction, self.Lf[node])
        kind = cfg.initial.kind
        relax = cfg.initial.relax_time if kind == "relax" else (self.opt.static_relax_time if kind == "static" else 0.0)
        if relax > 0.0:
            self._relax(relax)

    def _static_shape(self):
        """Tangents and tensions on the grid from the static catenary (physics/statics.py: elastic, with a
        seabed touchdown) when both ends are held in place, else (None, None). The circular arc of
        _initial_shape knows no seabed: a chain from a fairlead to an anchor on the bottom started as an arc
        lies metres into the seabed, and its contact and friction forces stop the relaxation's Newton."""
        if not (self._velocity_end(0) and self._velocity_end(1)):
            return None, None
        try:
            shape = solve_static(self.config)
        except RuntimeError:
            return None, None
        t = np.asarray(shape.tangent(self.s_grid), dtype=float)
        t /= np.linalg.norm(t, axis=1)[:, None]
        return t, np.maximum(np.asarray(shape.tension(self.s_grid), dtype=float), 1e-3 * self.net_weight * self.length)

    def _initial_shape(self, d, dist):
        """Tangents and tensions on the grid: straight (stretched) if the chord is >= L, else a circular
        arc of length L through both ends sagging along gravity (tension w R)."""
        if dist >= self.length or not self._velocity_end(1):
            return np.repeat(d[None], self.n_seg + 1, axis=0), self._straight_tension(d, dist)
        # sag direction: gravity minus its component along the chord, g - (g.d) d with g = -e_z (until 2026-11-23 the
        # sign was wrong, so a sloping chord got an arc that missed its far end by metres)
        sag = np.array([0.0, 0.0, -1.0]) + d[2] * d
        sag = sag / np.linalg.norm(sag) if np.linalg.norm(sag) > 1e-9 else np.array([1.0, 0.0, 0.0])
        floor = 1e-3 * self.net_weight * self.length
        T = floor
        for _ in range(50):  # arc of stretched length L (1 + eps(T)) with T = w R (fixed point)
            stretched = self.length * (1.0 + self._strain(T))
            theta = self._discrete_arc_angle(self._arc_angle(dist / stretched), stretched, dist)
            T = max(self.net_weight * stretched / (2.0 * theta), floor)
        stretched = self.length * (1.0 + self._strain(T))  # the shape for the final T (closes exactly)
        theta = self._discrete_arc_angle(theta, stretched, dist)
        phi = theta * (1.0 - 2.0 * self.s_grid / self.length)
        tangents = np.cos(phi)[:, None] * d[None] + np.sin(phi)[:, None] * sag[None]
        return tangents, np.full(self.n_seg + 1, T)

    def _discrete_arc_angle(self, theta, stretched, dist):
        """Half angle for which the trapezoid sum of the grid tangents (as reconstruct_positions integrates
        them) spans the chord exactly: the continuous arc misses it by O(ds^2) (2.4 mm on a 316 m chord
        with 5.4 m cells), which a stiff cable turns into kN of spurious tension in the end cell."""
        x = 1.0 - 2.0 * self.s_grid / self.length  # phi = theta x along the arc
        w = np.full(x.size, stretched / self.n_seg)
        w[[0, -1]] *= 0.5

        def chord(th):
            return float(np.dot(w, np.cos(th * x)))

        for _ in range(30):  # Newton on chord(theta) = dist (monotone decreasing for theta < pi)
            f = chord(theta) - dist
            if abs(f) <= 1e-13 * dist:
                break
            theta = min(max(theta + f / float(np.dot(w, x * np.sin(theta * x))), 1e-6), math.pi - 1e-6)
        return theta

    @staticmethod
    def _arc_angle(ratio):
        """Half angle theta of a circular arc with chord/arc = sin(theta)/theta = ratio."""
        theta = 1.0
        for _ in range(60):
            f = math.sin(theta) / theta - ratio
            df = (theta * math.cos(theta) - math.sin(theta)) / theta**2
            theta = min(max(theta - f / df, 1e-6), math.pi - 1e-6)
        return theta

    def _straight_tension(self, d, dist):
        """Tension along the initial straight line: tangential equilibrium dT/ds = w_z d_z [GP Eq. 3]
        from an end whose tension is known (force/free), else from the chord strain; kept > 0."""
        w = self.net_weight if self.config.cable.gamma0 > self.config.environment.fluid_density * \
            self.config.cable.area else -self.net_weight
        Tlin = w * d[2] * self.s_grid  # T(s) - T(0) for F = -w z
        force_end = [not k.kinematic for k in self.end_kinds]
        if self.end_kinds[1].position == "body":
            weight = submerged_weight(self.config.body, self.config.environment)
            T = weight * max(-d[2], 0.0) + Tlin - Tlin[-1]
        elif force_end[1]:
            T = float(np.dot(self.end_load[1][0], d)) + Tlin - Tlin[-1]
        elif force_end[0]:
            T = -float(np.dot(self.end_load[0][0], d)) + Tlin
        else:
            T_strain = self.config.cable.EA * max(dist / self.length - 1.0, 0.0)
            T = Tlin - Tlin.min() + T_strain
        return np.maximum(T, 1e-3 * self.net_weight * self.length)

    def _relax(self, duration):
        """Damped dynamic relaxation with rho_inf = 0 (maximum numerical dissipation), then rest at t = 0."""
        self._rho = 0.0
        t_end = self.time + duration
        step = self.opt.relax_time_step if self.opt.relax_time_step > 0.0 else self.opt.time_step
        while self.time < t_end - 1e-12:
            self._step_with_retry(min(step, t_end - self.time))
        self._rho = None
        self.stats["relax_final_speed"] = float(np.abs(self._world_velocities()).max())
        self.Y[:, CAT_V:CAT_V + 3] = 0.0  # = ROD_V
        self.Y[self.chain.kind == zoning.ROD, ROD_OMEGA:ROD_OMEGA + 3] = 0.0
        self.Yt[:] = 0.0
        self.rdot[:] = 0.0
        for e in range(2):
            if self.body_x[e] is not None:
                self.body_x[e][7:13] = 0.0
                self.body_xd[e][:] = 0.0
        self.time = 0.0
        self._last_zoning = -np.inf
        self._record = ([], [], [])
        for m in self.end_motion:
            m.reset_time(0.0)
