"""Winch of the hybrid solver: segments added and removed at the winch end.

API (the one the DG solver agreed with physics/winch.py and ros/winch_link.py):

- ``set_pay_out_rate(rate)``: dL/dt (m/s, > 0 pays out) reached by a linear ramp from the current
  rate over the next ``advance_to`` (or ``step``) interval, then held;
- ``unstretched_length``: L(t), the unstretched length in the domain (m);
- ``pay_out_rate``: the rate reached at the current time (m/s).

Method (docs/winch.md, "The hybrid winch"). The chain node at the winch end is the sheave: a
spatial point that moves with the end (prescribed, fixed or clamped). The element next to it (the
"winch element") holds the cable between the sheave and the first material node; its unstretched
length h_w follows L(t) = sum of the other element lengths + h_w, so the implicit step at t_{n+1}
uses h_w(t_{n+1}) in its box equations (every cell equation uses its own s_b - s_a). Before a
step whose h_w(t_{n+1}) would exceed 1.5 h0 (h0 = cable.length / hybrid.n_segments), a node is
inserted at h0 from the winch element's material end (the winch element keeps h_w - h0 >= 0.5 h0);
before one whose h_w(t_{n+1}) would fall below 0.5 h0, the winch element's material node is removed
(the winch element absorbs its neighbour). Both act on the state at t_n, so a retried step sees a
consistent state. Mass (gamma0 times the sum of the element lengths) is gamma0 L by construction; the
lumped momentum sum_j m_j v_j (m_j = gamma0 (h_{j-1} + h_j)/2) is conserved to round-off by both
(split: linear interpolation of the velocity; merge: the velocity of the surviving neighbour below).
"""

import math

import numpy as np

from tether_sim.errors import ConfigError
from tether_sim.numerics.rotations import rotate_frame
from tether_sim.physics.boundary import END_NAMES
from tether_sim.solvers.hybrid import zoning
from tether_sim.solvers.hybrid.layout import CAT_EPS, CAT_TAN, CAT_V, ROD_EPS, ROD_F, ROD_KAPPA, ROD_OMEGA, ROD_V
from tether_sim.solvers.hybrid.state_io import convert_state

DEFECT_TIME = 1.0  # s over which the geometric defect of a split or merge is phased out (_winch_defect)
SPLIT = 1.5  # split the winch element when it would exceed SPLIT h0
MERGE = 0.5  # merge it with its neighbour when it would fall below MERGE h0
_ROD_VECTORS = tuple(slice(c, c + 3) for c in (ROD_V, ROD_OMEGA, ROD_KAPPA, ROD_F))  # body-frame vectors


class HybridWinchMixin:
    """set_pay_out_rate, unstretched_length, pay_out_rate and the winch element's bookkeeping."""

    winch_end = None  # 0: ship, 1: vehicle, None: no winch (the solver's fixed-length path, untouched)

    def _setup_winch(self, config):
        """After the end modes, before the initial state."""
        w = getattr(config, "winch", None)
        if not getattr(w, "enabled", False):
            return
        end = getattr(w, "end", "ship")
        if end not in END_NAMES:
            raise ConfigError(f"winch.end: {end!r} is not one of {', '.join(END_NAMES)}")
        e = END_NAMES.index(end)
        if e == 1:
            raise ConfigError(
                "winch.end = vehicle: not supported by the hybrid solver. The winch element is shorter than its "
                "neighbour for half of each h0 of pay-out, and next to a low-tension end (a tether-management "
                "system's usual case) a short end cell makes the box scheme unstable at hybrid.time_step 0.01-0.02 s "
                "(measured on a 686 N sagging span, also at rate 0; docs/winch.md 'The hybrid winch'); use "
                "solver: dg for a winch at the vehicle end")
        name = ("ship_end", "vehicle_end")[e]
        if self.end_kinds[e].position == "body":
            raise ConfigError(f"winch.end = {end}: {name}.kind is body; the hybrid solver's winch keeps the sheave on "
                              "a prescribed, fixed or clamped end (a rigid body at the winch end is not implemented "
                              "in the hybrid solver; use solver: dg for a winch on a body)")
        if not self._velocity_end(e):
            raise ConfigError(f"winch.end = {end}: {name}.kind is {self.ends[e].kind!r}, a force end; the winch "
                              "needs a kinematic end (prescribed, fixed or clamped) whose point is the sheave")
        self.winch_end = e
        self._h0 = self.ds
        self._wl = float(self.length)  # L at self.time
        self._wrate = 0.0  # rate reached at self.time
        self._wtarget = 0.0  # rate at the end of the next interval
        self._win = (0.0, 0.0, self._wl, 0.0, 0.0)  # current interval: t0, t1, L(t0), rate(t0), rate(t1)
        self._wdef = (0.0, 0.0)  # geometric defect of the last split/merge: (time, length), see _winch_defect

    # ------------------------------------------------------------------ API
    @property
    def unstretched_length(self) -> float:
        """L(t): unstretched length of cable in the domain (m)."""
        return float(self.s_grid[-1] - self.s_grid[0]) if self.winch_end is not None else float(self.length)

    @property
    def pay_out_rate(self) -> float:
        """dL/dt reached at the current time (m/s)."""
        return self._wrate if self.winch_end is not None else 0.0

    def set_pay_out_rate(self, rate: float) -> None:
        """Rate dL/dt (m/s, > 0 pays out) reached by a linear ramp over the next advance_to, then held."""
        if self.winch_end is None:
            raise ConfigError("set_pay_out_rate: this hybrid solver has no winch (winch.enabled is false)")
        r = float(rate)
        if not math.isfinite(r):
            raise ValueError(f"set_pay_out_rate: non-finite rate {rate!r}")
        self._wtarget = r

    # ------------------------------------------------------------------ the rate ramp
    def _winch_begin(self, t0, t1):
        if self.winch_end is not None:
            self._win = (float(t0), float(t1), self._wl, self._wrate, self._wtarget)

    def _winch_finish(self, t):
        if self.winch_end is not None:
            self._wl = self._winch_length_at(t)
            self._wrate = self._wtarget = self._winch_rate_at(t)
            self._win = (float(t), float(t), self._wl, self._wrate, self._wrate)
            self._winch_set_length(t)

    def _winch_rate_at(self, t):
        t0, t1, _, r0, r1 = self._win
        if t1 <= t0:
            return r1
        return r0 + (r1 - r0) * min(max((t - t0) / (t1 - t0), 0.0), 1.0)

    def _winch_length_at(self, t):
        """L(t) of the interval's ramp: the trapezoid (r0 + r1) (t1 - t0) / 2 at its end, held rate after."""
        t0, t1, L0, r0, r1 = self._win
        tau = t - t0
        span = max(t1 - t0, 0.0)
        if tau <= span and span > 0.0:
            return L0 + r0 * tau + 0.5 * (r1 - r0) * tau * tau / span
        return L0 + 0.5 * (r0 + r1) * span + r1 * (tau - span)

    # ------------------------------------------------------------------ geometry
    def _winch_element_length(self):
        g = self.s_grid
        return float(g[1] - g[0]) if self.winch_end == 0 else float(g[-1] - g[-2])

    def _winch_set_length(self, t):
        """Element lengths at time t: the winch element takes up the change of L (the hot path: O(K)); the
        box equations see it with the decaying geometric defect of the last split or merge added."""
        L = self._winch_length_at(t)
        if self.winch_end == 0:
            self.s_grid[1:] += L - self.s_grid[-1]
        else:
            self.s_grid[-1] = self.s_grid[0] + L
        if self._winch_element_length() <= 0.0:
            raise ConfigError(f"winch: the winch element's length {self._winch_element_length():.3g} m is not positive "
                              f"at L = {L:.6g} m (haul-in past the end of the cable; keep winch.min_length above "
                              f"one segment, {self._h0:.3g} m)")
        self.length = float(L)
        s = self.chain.s
        s[:] = self.s_grid[self.chain.grid]
        t0, d0 = self._wdef
        if d0 != 0.0:
            d = d0 * max(0.0, 1.0 - (t - t0) / DEFECT_TIME)
            if self.winch_end == 0:
                s[1:] += d
            else:
                s[-1] += d

    def _winch_prepare(self, h):
        """Before a step of length h: split or merge at the winch end for the length at t + h."""
        if self.winch_end is None:
            return
        self._winch_set_length(self.time)  # the geometry at t_n (a failed step left that of its t_{n+1})
        dL = self._winch_length_at(self.time + h) - self._winch_length_at(self.time)
        for _ in range(self.s_grid.size + 2):
            hw = self._winch_element_length() + dL
            if hw > SPLIT * self._h0 and self._winch_element_length() > self._h0:
                self._winch_split()
            elif hw < MERGE * self._h0 and self.n_seg > 1:
                self._winch_merge()
            else:
                return

    # ------------------------------------------------------------------ topology
    def _winch_nodes(self):
        """Chain indices (sheave a, material end b) of the winch element, and the grid index of b."""
        K = self.chain.grid.size
        if self.winch_end == 0:
            return 0, 1, 1
        return K - 1, K - 2, self.n_seg - 1

    def _winch_split(self):
        """Insert a node h0 from the winch element's material end, on the current shape (state at t_n)."""
        a, b, jb = self._winch_nodes()
        h = self._winch_element_length()
        f = (h - self._h0) / h  # fraction of the way from the sheave a to b
        Y, Yt, Lf, pos, rdot = self._interpolated_node(a, b, f, h, *self._sheave_material_motion())
        ins = b if self.winch_end == 0 else a  # chain index of the new node (between a and b)
        s_new = self.s_grid[jb] - self._h0 if self.winch_end == 0 else self.s_grid[jb] + self._h0
        elem = 0 if self.winch_end == 0 else self.n_seg - 1
        self.zones = np.insert(self.zones, elem, self.zones[elem])
        self.s_grid = np.insert(self.s_grid, jb if self.winch_end == 0 else jb + 1, s_new)
        self.Y = np.insert(self.Y, ins, Y, axis=0)
        self.Yt = np.insert(self.Yt, ins, Yt, axis=0)
        self.Lf = np.insert(self.Lf, ins, Lf, axis=0)
        self.positions = np.insert(self.positions, ins, pos, axis=0)
        self.rdot = np.insert(self.rdot, ins, rdot, axis=0)
        self.n_seg += 1
        self._set_chain()
        self._winch_defect()
        self.stats["winch_splits"] = self.stats.get("winch_splits", 0) + 1

    def _sheave_tangent(self):
        a = 0 if self.winch_end == 0 else self.chain.grid.size - 1
        if self.chain.kind[a] == zoning.ROD:
            return self.Lf[a][0].copy()
        return self.Y[a, CAT_TAN:CAT_TAN + 3] / np.linalg.norm(self.Y[a, CAT_TAN:CAT_TAN + 3])

    def _sheave_material_motion(self):
        """World velocity and acceleration of the material at the sheave: the sheave's plus the pay-out
        rate along the tangent (out of the sheave into the domain: +t at the ship end, -t at the vehicle end)."""
        a = 0 if self.winch_end == 0 else self.chain.grid.size - 1
        sign = 1.0 if self.winch_end == 0 else -1.0
        t = self._sheave_tangent()
        t0, t1, _, r0, r1 = self._win
        slope = (r1 - r0) / (t1 - t0) if t0 <= self.time < t1 else 0.0
        acc = self.Yt[a, CAT_V:CAT_V + 3].copy()  # = ROD_V
        if self.chain.kind[a] == zoning.ROD:  # body-frame rate of the body-frame velocity: world, to first order
            acc = self.Lf[a].T @ acc
        u = self._world_velocities()[a] + sign * self._winch_rate_at(self.time) * t
        return u, acc + sign * slope * t

    def _interpolated_node(self, a, b, f, h, ua, uda):
        """Node at the fraction f from chain node a to chain node b (same kind, one element of length h
        apart): world vectors interpolated linearly, the velocity and its rate from the material's at the
        sheave a (ua, uda; so the lumped momentum of the material is kept), tangent normalised; frame and
        position by the box scheme's trapezoid from b (the shape reconstruct_positions integrates), so the
        new material cell is consistent and the winch cell carries the defect (_winch_defect)."""
        Ya, Yb = self.Y[a], self.Y[b]
        Y = (1.0 - f) * Ya + f * Yb
        Yt = (1.0 - f) * self.Yt[a] + f * self.Yt[b]
        hb = -(1.0 - f) * h if self.winch_end == 0 else (1.0 - f) * h  # signed arc length from b to the new node
        if self.chain.kind[a] == zoning.ROD:
            La, Lb = self.Lf[a], self.Lf[b]
            L = np.empty((3, 3))
            rotate_frame(Lb, (0.5 * (Yb[ROD_KAPPA:ROD_KAPPA + 3] + Y[ROD_KAPPA:ROD_KAPPA + 3])) * hb, L)
            for sl in _ROD_VECTORS:  # body-frame vectors: interpolate in world components
                wa, wta = (ua, uda) if sl.start == ROD_V else (La.T @ Ya[sl], La.T @ self.Yt[a, sl])
                Y[sl] = L @ ((1.0 - f) * wa + f * (Lb.T @ Yb[sl]))
                Yt[sl] = L @ ((1.0 - f) * wta + f * (Lb.T @ self.Yt[b, sl]))
            qb, q = (1.0 + Yb[ROD_EPS]) * Lb[0], (1.0 + Y[ROD_EPS]) * L[0]
        else:
            L = self.Lf[a].copy()  # a catenary node's frame is only the reference of a later conversion
            Y[CAT_V:CAT_V + 3] = (1.0 - f) * ua + f * Yb[CAT_V:CAT_V + 3]
            Yt[CAT_V:CAT_V + 3] = (1.0 - f) * uda + f * self.Yt[b, CAT_V:CAT_V + 3]
            Y[CAT_TAN:CAT_TAN + 3] /= np.linalg.norm(Y[CAT_TAN:CAT_TAN + 3])
            qb = (1.0 + Yb[CAT_EPS]) * Yb[CAT_TAN:CAT_TAN + 3] / np.linalg.norm(Yb[CAT_TAN:CAT_TAN + 3])
            q = (1.0 + Y[CAT_EPS]) * Y[CAT_TAN:CAT_TAN + 3]
        pos = self.positions[b] + 0.5 * hb * (qb + q)
        rdot = (1.0 - f) * (self.rdot[a] + ua - self._world_velocities()[a]) + f * self.rdot[b]  # material rate at a
        return Y, Yt, L, pos, rdot

    def _winch_merge(self):
        """Remove the winch element's material node: the winch element absorbs its neighbour. The surviving
        neighbour's velocity keeps the lumped momentum (the sheave's lumped mass grows at the material velocity
        there)."""
        n = self.n_seg
        w, nb = (0, 1) if self.winch_end == 0 else (n - 1, n - 2)  # winch element and its neighbour
        if self.zones[w] != self.zones[nb]:  # one model for the merged element (a held end keeps its rod)
            keep = self.zones[w] if self.end_kinds[self.winch_end].direction == "held" else self.zones[nb]
            new = self.zones.copy()
            new[[w, nb]] = keep
            self.Y, self.Yt, self.Lf, self.positions, self.rdot = convert_state(self, new)
            self.zones = new
            self._set_chain()
        K = self.chain.grid.size
        a, m, b = (0, 1, 2) if self.winch_end == 0 else (K - 1, K - 2, K - 3)
        g = self.s_grid
        jm = 1 if self.winch_end == 0 else n - 1  # grid index of the removed node
        step = 1 if self.winch_end == 0 else -1
        hw, hn = abs(g[jm] - g[jm - step]), abs(g[jm + step] - g[jm])
        jn = jm + 2 * step
        hx = abs(g[jn] - g[jm + step]) if 0 <= jn < g.size else 0.0  # element beyond b (none at the far end)
        v = self._world_velocities()
        v[a] = self._sheave_material_motion()[0]
        if b != K - 1 - a:  # b is not the far end node (whose velocity is the far end's condition)
            vb = ((hw + hn) * v[m] + (hn + hx) * v[b] - hn * v[a]) / (hw + hn + hx)
            for c in np.nonzero(self.chain.grid == self.chain.grid[b])[0]:  # both nodes of a joint
                self.Y[c, CAT_V:CAT_V + 3] = self.Lf[c] @ vb if self.chain.kind[c] == zoning.ROD else vb
        self.zones = np.delete(self.zones, w)
        self.s_grid = np.delete(self.s_grid, jm)
        self.Y, self.Yt, self.Lf = (np.delete(x, m, axis=0) for x in (self.Y, self.Yt, self.Lf))
        self.positions, self.rdot = np.delete(self.positions, m, axis=0), np.delete(self.rdot, m, axis=0)
        self.n_seg -= 1
        self._set_chain()
        self._winch_defect()
        self.stats["winch_merges"] = self.stats.get("winch_merges", 0) + 1

    def _winch_defect(self):
        """Geometric defect of the new winch cell after a split or merge, and its decay.

        The box scheme's cell chord is the trapezoid h (q_a + q_b)/2 of q = (1 + eps) t; on a curved
        cable splitting a cell (or merging two) changes that sum by O(h theta^2 / 16) (theta: the turn
        of the tangent across the cell) -- with EA = 45 MN and theta = 0.15 rad a 3 mm, i.e. kN, jump.
        Instead the box equations of the winch cell see its length plus the defect d that makes its
        chord consistent again (along the chord, where the defect lies), and d decays linearly to 0 over
        DEFECT_TIME: a slow extra pay-out of d / DEFECT_TIME (mm/s). The bookkeeping (L, mass) is
        untouched."""
        K = self.chain.grid.size
        i, j = (0, 1) if self.winch_end == 0 else (K - 2, K - 1)
        p = 0.5 * (self._node_q(i) + self._node_q(j))
        chord = self.positions[j] - self.positions[i]
        h = self.s_grid[self.chain.grid[j]] - self.s_grid[self.chain.grid[i]]
        self._wdef = (self.time, float(chord @ p / (p @ p) - h))
        self._winch_set_length(self.time)

    def _node_q(self, c):
        """(1 + eps) t at chain node c."""
        if self.chain.kind[c] == zoning.ROD:
            return (1.0 + self.Y[c, ROD_EPS]) * self.Lf[c][0]
        t = self.Y[c, CAT_TAN:CAT_TAN + 3]
        return (1.0 + self.Y[c, CAT_EPS]) * t / np.linalg.norm(t)

    def _winch_snapshot(self):
        if self.winch_end is None:
            return {}
        return {"winch": (self.s_grid.copy(), self.n_seg, self.length, self._wl, self._wrate, self._wtarget, self._win,
                          self._wdef)}

    def _winch_restore(self, snap):
        if "winch" not in snap:
            return
        s_grid, self.n_seg, self.length, self._wl, self._wrate, self._wtarget, self._win, self._wdef = snap["winch"]
        self.s_grid = s_grid.copy()

    def cell_lengths(self):
        """Unstretched element lengths (m): h0 each without a winch (bit-identical to the fixed grid)."""
        if self.winch_end is None:
            return np.full(self.n_seg, self.ds)
        return np.diff(self.s_grid)
