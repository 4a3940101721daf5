"""Static shape by dynamic relaxation of a lumped-mass cable (fallback of ``statics``, both solvers).

The cable is cut into n - 1 segments of unstretched length ds; node forces are the segment
tensions T(eps) of the cable's law [PE2020 Eq. 22, zeta = 0], the submerged weight [Eq. 14], the
steady current drag on a cable at rest [Eq. 17 with nu = 0], the seabed spring [Eq. 15, no damping]
and point loads at the ends. Held ends stay put. The fictitious dynamics (unit time step, masses
from the stiffness so that it is stable) uses kinetic damping: all velocities are zeroed whenever
the kinetic energy passes a peak. Converged when every free node's force is below
``tol * (|w| L + |loads| + 1)``.
"""

import math

import numpy as np

from tether_sim.numerics.jit import jit_alloc
from tether_sim.physics.constitutive import axial_tension
from tether_sim.physics.hydrodynamics import current_at, morison_drag


@jit_alloc
def _node_forces(r, ds, law, EA, tab_eps, tab_T, fext, hrd, Cdt, Cdn, cz, cx, cy, seabed, zg, Kd, F):
    n = r.shape[0]
    uc = np.zeros(3)
    for i in range(n):
        for c in range(3):
            F[i, c] = fext[i, c]
    for k in range(n - 1):
        d0 = r[k + 1, 0] - r[k, 0]
        d1 = r[k + 1, 1] - r[k, 1]
        d2 = r[k + 1, 2] - r[k, 2]
        ln = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
        if ln <= 0.0:
            continue
        l = ln / ds[k]
        T = axial_tension(law, l - 1.0, 0.0, EA, 0.0, tab_eps, tab_T, 0.0)  # (statics: no bending)
        t0, t1, t2 = d0 / ln, d1 / ln, d2 / ln
        F[k, 0] += T * t0
        F[k, 1] += T * t1
        F[k, 2] += T * t2
        F[k + 1, 0] -= T * t0
        F[k + 1, 1] -= T * t1
        F[k + 1, 2] -= T * t2
        if cz.shape[0] > 0 and hrd > 0.0:
            current_at(0.5 * (r[k, 2] + r[k + 1, 2]), cz, cx, cy, uc)
            fx, fy, fz = morison_drag(t0, t1, t2, l, uc[0], uc[1], uc[2], hrd, Cdt, Cdn)
            for c, f in ((0, fx), (1, fy), (2, fz)):
                F[k, c] += 0.5 * ds[k] * f
                F[k + 1, c] += 0.5 * ds[k] * f
    if seabed:
        for i in range(n):
            delta = zg - r[i, 2]
            if delta > 0.0:
                trib = 0.5 * ((ds[i - 1] if i > 0 else 0.0) + (ds[i] if i < n - 1 else 0.0))
                F[i, 2] += Kd * delta * trib


@jit_alloc
def _relax(r, held, ds, law, EA, kmax, tab_eps, tab_T, fext, hrd, Cdt, Cdn, cz, cx, cy, seabed, zg, Kd,
           max_iter, ftol, F, v, m):
    n = r.shape[0]
    for i in range(n):
        kk = 0.0
        if i > 0:
            kk += kmax / ds[i - 1]
        if i < n - 1:
            kk += kmax / ds[i]
        if seabed:
            kk += Kd * 0.5 * ((ds[i - 1] if i > 0 else 0.0) + (ds[i] if i < n - 1 else 0.0))
        m[i] = kk  # unit time step: m > k_max / 2 is the explicit stability bound, margin 2
    ke_prev = 0.0
    res = 0.0
    for it in range(max_iter):
        _node_forces(r, ds, law, EA, tab_eps, tab_T, fext, hrd, Cdt, Cdn, cz, cx, cy, seabed, zg, Kd, F)
        res = 0.0
        ke = 0.0
        for i in range(n):
            if held[i]:
                continue
            for c in range(3):
                res = max(res, abs(F[i, c]))
                v[i, c] += F[i, c] / m[i]
                ke += m[i] * v[i, c] * v[i, c]
        if res < ftol:
            return it, res
        if ke < ke_prev:
            for i in range(n):
                for c in range(3):
                    v[i, c] = 0.0
            ke = 0.0
        ke_prev = ke
        for i in range(n):
            if not held[i]:
                for c in range(3):
                    r[i, c] += v[i, c]
    return max_iter, res


class DiscreteShape:
    """Node positions of a relaxed cable; same evaluation methods as ``statics.StaticSolution``."""

    def __init__(self, s, r, law, converged, residual, iterations, scale=1.0):
        self.s, self.r, self.law = s, r, law
        self.length = float(s[-1])
        self.converged, self.residual, self.iterations = converged, residual, iterations
        self.scale = scale  # N: the loads the cable carries (weight, end loads, current drag)
        self.method = "dynamic relaxation"
        # direction from the finite-difference gradient, stretch from the segments: the gradient's length
        # at a curved end (one-sided, second order) is not the stretch (a 40 m light tether read 281 N at
        # an end whose last segment carried 0.2 N)
        self._dr = np.stack([np.gradient(r[:, c], s, edge_order=2) for c in range(3)], axis=1)
        self._mid = 0.5 * (s[1:] + s[:-1])
        self._eps = np.linalg.norm(np.diff(r, axis=0), axis=1) / np.diff(s) - 1.0

    def strain(self, s):
        """Axial strain (n,): the segments' own, linear between their midpoints (constant beyond)."""
        return np.interp(np.atleast_1d(np.asarray(s, float)), self._mid, self._eps)

    def position(self, s):
        s = np.atleast_1d(np.asarray(s, float))
        return np.stack([np.interp(s, self.s, self.r[:, c]) for c in range(3)], axis=1)

    def tangent(self, s):
        """dr/ds (n, 3): the gradient's direction with the segments' stretch 1 + eps."""
        s = np.atleast_1d(np.asarray(s, float))
        d = np.stack([np.interp(s, self.s, self._dr[:, c]) for c in range(3)], axis=1)
        return d / np.linalg.norm(d, axis=1)[:, None] * (1.0 + self.strain(s))[:, None]

    def tension(self, s):
        return self.law.tension(self.strain(s))


def relax_cable(start, end, length, law, w, held=(True, False), loads=None, n_nodes=101, initial=None,
                env=None, cable=None, tol=1e-9, max_iter=2_000_000):
    """Relax a cable from s = 0 at ``start`` to s = L at ``end`` (held ends stay; others move).

    ``loads`` (2, 3): point loads on the two end nodes (ignored on held ends); ``initial`` (n, 3):
    starting node positions (default: the straight line); ``env``/``cable`` enable current drag and
    the seabed. Returns a :class:`DiscreteShape` (``converged`` tells whether tol was met).
    """
    s = np.linspace(0.0, length, n_nodes)
    ds = np.diff(s)
    if initial is None:
        r = np.asarray(start, float)[None, :] + (s / length)[:, None] * (np.asarray(end, float) - np.asarray(start, float))[None, :]
    else:
        r = np.array(initial, float)
    fext = np.zeros((n_nodes, 3))
    trib = np.zeros(n_nodes)
    trib[:-1] += 0.5 * ds
    trib[1:] += 0.5 * ds
    fext[:, 2] = -w * trib
    loads = np.zeros((2, 3)) if loads is None else np.asarray(loads, float)
    fext[0] += loads[0]
    fext[-1] += loads[1]
    hold = np.zeros(n_nodes, dtype=np.bool_)
    hold[0], hold[-1] = held
    hrd, Cdt, Cdn, Kd, zg, seabed = 0.0, 0.0, 0.0, 0.0, 0.0, False
    cz = cx = cy = np.zeros(0)
    if env is not None and cable is not None:
        from tether_sim.physics.hydrodynamics import current_table
        cz, cx, cy = current_table(env)
        hrd, Cdt, Cdn = 0.5 * env.fluid_density * cable.diameter, cable.Cdt, cable.Cdn
        if env.seabed:
            seabed, zg, Kd = True, env.seabed_z, env.seabed_stiffness * cable.diameter
    F, v, m = np.zeros_like(r), np.zeros_like(r), np.zeros(n_nodes)
    scale = float(np.max(np.abs(w))) * length + float(np.abs(loads).sum()) + 1.0  # w: scalar or per node
    it, res = _relax(r, hold, ds, law.code, law.EA, law.max_slope(), law.tab_eps, law.tab_T, fext, hrd, Cdt, Cdn,
                     cz, cx, cy, seabed, zg, Kd, max_iter, tol * scale, F, v, m)
    # the loads include the current's drag (normal drag of the fastest current over the whole length)
    u = max([float(np.max(np.abs(c))) for c in (cx, cy) if len(c)] + [0.0])
    return DiscreteShape(s, r, law, res < tol * scale, res, it, scale=scale + hrd * Cdn * u * u * length)
