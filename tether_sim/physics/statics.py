"""Static equilibrium of an elastic cable under its submerged weight (initial states of both solvers).

The internal force T(s) (the force the part beyond s exerts on [0, s]) satisfies dT/ds = w z_hat
with w the submerged weight per unstretched metre [PE2020 Eq. 14], so T(s) = T0 + w s z_hat,
and dr/ds = (1 + eps(|T|)) T / |T|. For the linear and bilinear laws eps = |T| / EA and r(s)
has the closed form of the elastic catenary (H = |T_h|, V = T_z):

    r_h(s) = e_h [ (H / w)(asinh(V(s)/H) - asinh(V0/H)) + H s / EA ]
    r_z(s) = (sqrt(H^2 + V(s)^2) - sqrt(H^2 + V0^2)) / w + (V0 s + w s^2 / 2) / EA

Solved cases: two fixed points (Newton on T0), a cable hanging from one end with a point load at
the other (a cage's submerged weight, a force end, or nothing), and a cable partly lying on a
frictionless seabed (touchdown point and horizontal tension, the lying part sunk by w / (K_g d)).
With ``environment.free_surface`` and the ship (s = 0) end above z = 0, the part above the still-water
surface weighs w_air = g (gamma0 - rho_air A) per metre: the shape is two elastic catenaries joined at
the crossing arc s_c (z(s_c) = 0) with T continuous there, T(s) = T0 + (w_air min(s, s_c) +
w max(s - s_c, 0)) z_hat.
With a current, or when Newton fails, ``solve_static`` finishes with the lumped-mass dynamic
relaxation of ``physics/relaxation.py`` (current drag included). Bending stiffness is ignored.
Tabulated laws use numerical quadrature of the same integrals.
"""

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from tether_sim.physics.constitutive import TensionLaw
from tether_sim.physics.end_conditions import KINDS, TABLE
from tether_sim.physics.hydrodynamics import air_weight_per_length, net_weight_per_length
from tether_sim.physics.relaxation import relax_cable

# a relaxed shape is an initial state when its largest nodal force imbalance is below this fraction of the
# loads it carries (relax_cable iterates towards 1e-9, which a light cable in a current may not reach
# within its iteration limit; the dynamic solvers settle the rest)
ACCEPTED_RESIDUAL = 1e-6
KINEMATIC_KINDS = tuple(k.name for k in TABLE if k.kinematic and k.position != "body")  # held in place


@dataclass
class StaticSolution:
    """A static shape; ``position(s)`` and ``tension(s)`` evaluate it at unstretched arc lengths."""

    length: float
    T0: np.ndarray  # (3,) internal force at s = 0 (the force by the cable on the s = 0 end)
    w: float  # submerged weight per metre (N/m)
    law: TensionLaw
    origin: np.ndarray  # (3,) r(0)
    touchdown: float = -1.0  # arc length where the cable meets the seabed (-1: no contact)
    liftoff: float = -1.0  # arc length where it leaves the seabed again toward s = L (-1: it lies to s = L)
    seabed_z: float = 0.0
    sink: float = 0.0
    method: str = "catenary"
    w_air: float = 0.0  # weight per metre in air (free surface)
    crossing: float = 0.0  # arc length where the cable enters the water (free surface; 0: all wet)

    def force_at(self, s):
        """Internal force vector T(s), (n, 3)."""
        s = np.atleast_1d(np.asarray(s, float))
        T = np.repeat(self.T0[None, :], s.size, axis=0)
        if self.crossing > 0.0:
            T[:, 2] += self.w_air * np.minimum(s, self.crossing) + self.w * np.maximum(s - self.crossing, 0.0)
            return T
        T[:, 2] += self.w * np.minimum(s, self.touchdown if self.touchdown >= 0 else np.inf)
        if self.touchdown >= 0 and self.liftoff >= 0:
            T[:, 2] += self.w * np.maximum(s - self.liftoff, 0.0)
        return T

    def tension(self, s):
        """Axial tension |T(s)| (N)."""
        return np.linalg.norm(self.force_at(s), axis=1)

    def tangent(self, s):
        """dr/ds = (1 + eps) T / |T| (n, 3) (straight down where |T| = 0)."""
        T = self.force_at(s)
        n = np.linalg.norm(T, axis=1)
        eps = np.array([self.law.strain_at(x) for x in n])
        d = np.where(n[:, None] > 0, T / np.where(n > 0, n, 1.0)[:, None], np.array([0.0, 0.0, -1.0]))
        return (1.0 + eps)[:, None] * d

    def position(self, s):
        """r(s) (n, 3)."""
        s = np.atleast_1d(np.asarray(s, float))
        if self.crossing > 0.0:
            return self.origin + _integral_split(self.T0, self.w_air, self.w, self.law, s, self.crossing)
        if self.touchdown < 0:
            return self.origin + _integral(self.T0, self.w, self.law, s)
        sh = np.minimum(s, self.touchdown)
        r = self.origin + _integral(self.T0, self.w, self.law, sh)
        lying = s > self.touchdown
        if np.any(lying):
            Ttd = self.force_at([self.touchdown])[0]
            H = np.linalg.norm(Ttd)
            d = Ttd / H if H > 0 else np.array([1.0, 0.0, 0.0])
            end = self.liftoff if self.liftoff >= 0 else self.length
            r[lying] += np.outer(np.minimum(s[lying], end) - self.touchdown, d * (1.0 + self.law.strain_at(H)))
            rising = s > end
            if np.any(rising):  # the hanging part from the lift-off point up to s = L
                r[rising] += _integral(Ttd, self.w, self.law, s[rising] - end)
        return r


def _integral(T0, w, law, s):
    """r(s) - r(0) of the hanging catenary with T(s) = T0 + w s z_hat (see module docstring)."""
    s = np.atleast_1d(np.asarray(s, float))
    Th = np.array([T0[0], T0[1], 0.0])
    H = float(np.linalg.norm(Th))
    eh = Th / H if H > 0 else np.zeros(3)
    V0 = float(T0[2])
    # closed form unless it would cancel catastrophically (weight tiny against the tension)
    if law.code == 2 or abs(w) * (s.max() if s.size else 0.0) < 1e-4 * max(H + abs(V0), 1e-300):
        return _integral_numeric(T0, w, law, s)
    V = V0 + w * s
    EA = law.EA
    if H > 1e-12 * max(abs(V0), abs(w) * s.max(), 1e-300):
        xh = (H / w) * (np.arcsinh(V / H) - math.asinh(V0 / H)) + H * s / EA
        z = (np.hypot(H, V) - math.hypot(H, V0)) / w + (V0 * s + 0.5 * w * s**2) / EA
    else:  # vertical: dz/ds = sign(V) (1 + |V| / EA)
        xh = np.zeros_like(s)
        geo = np.where(V * V0 > 0, np.sign(V0) * s, (np.abs(V) - abs(V0)) / w)
        z = geo + (V0 * s + 0.5 * w * s**2) / EA
    return xh[:, None] * eh[None, :] + z[:, None] * np.array([0.0, 0.0, 1.0])[None, :]


def _integral_split(T0, w_air, w, law, s, sc):
    """r(s) - r(0) with weight w_air on [0, sc] (in air) and w beyond (in water)."""
    s = np.atleast_1d(np.asarray(s, float))
    out = np.empty((s.size, 3))
    top = s <= sc
    if np.any(top):
        out[top] = _integral(T0, w_air, law, s[top])
    if not np.all(top):
        rc = _integral(T0, w_air, law, np.array([sc]))[0]
        Tc = np.array([T0[0], T0[1], T0[2] + w_air * sc])
        out[~top] = rc + _integral(Tc, w, law, s[~top] - sc)
    return out


def surface_crossing(T0, w_air, law, length, z0, n=200):
    """Arc length where a cable starting at height z0 > 0 (in air, weight w_air) first reaches the
    still-water surface z = 0; 0 if z0 <= 0, length if it stays in air."""
    if z0 <= 0.0:
        return 0.0
    grid = np.linspace(0.0, length, n + 1)
    z = z0 + _integral(T0, w_air, law, grid)[:, 2]
    below = np.nonzero(z <= 0.0)[0]
    if below.size == 0:
        return float(length)
    k = int(below[0])
    a, b = grid[k - 1], grid[k]
    for _ in range(100):  # bisection on the monotone stretch [a, b]
        m = 0.5 * (a + b)
        if z0 + _integral(T0, w_air, law, np.array([m]))[0, 2] > 0.0:
            a = m
        else:
            b = m
        if b - a < 1e-13 * max(length, 1.0):
            break
    return 0.5 * (a + b)


def _end_point(T0, w, law, length, fs, z0):
    """r(L) - r(0); fs = w_air (free surface on) or None."""
    if fs is None:
        return _integral(T0, w, law, np.array([length]))[0]
    sc = surface_crossing(T0, fs, law, length, z0)
    return _integral_split(T0, fs, w, law, np.array([length]), sc)[0] if sc > 0.0 else \
        _integral(T0, w, law, np.array([length]))[0]


def _integral_numeric(T0, w, law, s, n=4000):
    """Same integral by composite Gauss quadrature (tabulated laws, weightless cables)."""
    smax = float(np.max(s)) if s.size else 0.0
    edges = np.linspace(0.0, max(smax, 1e-12), n + 1)
    x, wq = np.polynomial.legendre.leggauss(4)
    out = np.zeros((s.size, 3))
    for idx, si in enumerate(s):
        k = np.searchsorted(edges, si, side="right") - 1
        acc = np.zeros(3)
        segs = list(zip(edges[:k], edges[1:k + 1])) + [(edges[min(k, n)], si)]
        a = np.array([p[0] for p in segs])
        b = np.array([p[1] for p in segs])
        pts = (a[:, None] + (x[None, :] + 1.0) * (b - a)[:, None] / 2.0).ravel()
        T = np.repeat(T0[None, :], pts.size, axis=0)
        T[:, 2] += w * pts
        nT = np.linalg.norm(T, axis=1)
        eps = np.array([law.strain_at(v) for v in nT])
        d = np.where(nT[:, None] > 0, T / np.where(nT > 0, nT, 1.0)[:, None], np.array([0.0, 0.0, -1.0]))
        f = (1.0 + eps)[:, None] * d
        wts = (np.repeat(((b - a) / 2.0)[:, None], 4, axis=1) * wq[None, :]).ravel()
        acc = (f * wts[:, None]).sum(axis=0)
        out[idx] = acc
    return out


def catenary_between(A, B, length, w, law, *, seabed_z=None, sink=0.0, tol=1e-11, max_iter=100, w_air=None):
    """Elastic catenary from A (s = 0) to B (s = L) under weight w; touchdown if seabed_z is given.
    w_air (free surface): weight per metre of the part above z = 0 (A in air, B in water).

    Raises RuntimeError when Newton does not converge (callers fall back to dynamic relaxation).
    """
    A = np.asarray(A, float)
    B = np.asarray(B, float)
    d = B - A
    dh = float(np.hypot(d[0], d[1]))
    eh = np.array([d[0], d[1], 0.0]) / dh if dh > 0 else np.array([1.0, 0.0, 0.0])
    chord = float(np.linalg.norm(d))
    scale = max(abs(w) * length, law.EA * 1e-6, 1e-9)

    def T0_of(x):
        return np.array([x[0] * eh[0], x[0] * eh[1], x[1]])

    def resid(x):
        r = _end_point(T0_of(x), w, law, length, w_air, A[2])
        return np.array([np.dot(r, eh) - dh, r[2] - d[2]])

    # initial guess: Irvine/Peyrot for slack chords, taut straight line otherwise
    if chord >= length:
        T = law.EA * (chord / length - 1.0) + 0.5 * abs(w) * length
        x = np.array([T * dh / max(chord, 1e-300), T * d[2] / max(chord, 1e-300) - 0.5 * w * length])
    else:
        lam = math.sqrt(max(3.0 * (length**2 - d[2] ** 2) / max(dh, 1e-6 * length) ** 2 - 3.0, 1e-6)) if dh > 0 else 1e3
        H = abs(w) * dh / (2.0 * lam)
        V = -0.5 * w * (length - d[2] / math.tanh(lam)) if lam < 50 else -0.5 * w * length
        x = np.array([max(H, 1e-6 * scale), V])
    if dh == 0.0:
        x[0] = 0.0
    for _ in range(max_iter):
        f = resid(x)
        if np.max(np.abs(f)) < tol * max(length, 1.0):
            break
        J = np.empty((2, 2))
        for k in range(2):
            dx = np.zeros(2)
            dx[k] = 1e-7 * max(abs(x[k]), scale * 1e-3)
            J[:, k] = (resid(x + dx) - resid(x - dx)) / (2.0 * dx[k])
        if dh == 0.0:
            step = np.array([0.0, f[1] / J[1, 1]])
        else:
            step = np.linalg.solve(J, f)
        alpha = 1.0
        while alpha > 1e-4:
            xn = x - alpha * step
            if (dh == 0.0 or xn[0] > 0.0) and np.linalg.norm(resid(xn)) < np.linalg.norm(f):
                break
            alpha *= 0.5
        x = xn
    else:
        raise RuntimeError("static catenary: Newton did not converge")
    if np.max(np.abs(resid(x))) > 1e-6 * max(length, 1.0):
        raise RuntimeError("static catenary: Newton did not converge")
    sol = _with_surface(StaticSolution(length, T0_of(x), w, law, A.copy()), w_air)
    if sol.crossing > 0.0:
        return sol  # touchdown with a surface crossing: not in closed form (solve_static relaxes it)
    if seabed_z is not None and w > 0 and _lowest_z(sol) < seabed_z - sink - 1e-9 * length:
        return _touchdown(A, B, length, w, law, seabed_z, sink, eh, dh)  # the free catenary dips into the seabed
    return sol


def _lowest_z(sol):
    s = np.linspace(0.0, sol.length, 2001)
    return float(sol.position(s)[:, 2].min())


def _hanging_length(H, h, w, law, eh):
    """Arc length of a hanging part that drops h from its upper end to a horizontal touchdown (vertical
    force 0 there) under the horizontal force H; the drop grows with the length, so a bracketed root."""
    if h <= 0.0:
        return 0.0

    def drop(sh):
        return -_integral(np.array([H * eh[0], H * eh[1], -w * sh]), w, law, np.array([sh]))[0, 2]

    return brentq(lambda sh: drop(sh) - h, 0.0, h + H / w + 1e-12 * h, xtol=1e-14 * h, rtol=1e-15)


def _touchdown(A, B, length, w, law, zg, sink, eh, dh):
    """A cable lying on a frictionless seabed (z = zg - sink) between two hanging parts, one from each end.

    Either end may be on the seabed (its hanging part has length 0: an anchor at s = 0 or at s = L; an end
    at the seabed's surface z = zg counts as on it, the lying part below it by the sink), or
    both above it (the middle lies). On the seabed the tension is horizontal and equal to H, so each
    hanging part is an elastic catenary from its end down to a horizontal touchdown, of a length sh(H)
    fixed by its drop; H solves the span:
        x_A(H) + x_B(H) + (L - sh_A(H) - sh_B(H)) (1 + eps(H)) = horizontal distance from A to B,
    whose left side grows with H (flatter parts, less cable lost to the drops): a bracketed root."""
    zt, tol = zg - sink, 1e-9 * length
    if min(A[2], B[2]) < zt - tol:
        raise RuntimeError("static catenary: an end is below the seabed")
    # an end on the seabed's surface (an anchor at the mudline) lies: the sink is the contact spring's, of
    # the lying part, and does not lift the end's neighbourhood
    hA, hB = (0.0 if X[2] <= zg + tol else float(X[2] - zt) for X in (A, B))

    def parts(H):
        shA, shB = _hanging_length(H, hA, w, law, eh), _hanging_length(H, hB, w, law, -eh)
        xA = _integral(np.array([H * eh[0], H * eh[1], -w * shA]), w, law, np.array([shA]))[0] @ eh if shA else 0.0
        xB = _integral(np.array([H * eh[0], H * eh[1], -w * shB]), w, law, np.array([shB]))[0] @ eh if shB else 0.0
        return shA, shB, xA + xB + (length - shA - shB) * (1.0 + law.strain_at(H))

    H_lo = 1e-9 * w * length
    if parts(H_lo)[2] > dh:
        raise RuntimeError("static catenary: more cable than the span on the seabed (slack; no unique shape)")
    H_hi = w * length
    shA, shB, span = parts(H_hi)
    while shA + shB < length and span < dh:
        H_hi *= 2.0
        shA, shB, span = parts(H_hi)
    if shA + shB > length:  # the lying part vanishes before the span is reached: H_hi at that point
        H_hi = brentq(lambda H: sum(parts(H)[:2]) - length, H_lo, H_hi, xtol=1e-14 * H_hi, rtol=1e-15)
        if parts(H_hi)[2] < dh:
            raise RuntimeError("static catenary with touchdown: the cable cannot reach the span lying")
    H = brentq(lambda H: parts(H)[2] - dh, H_lo, H_hi, xtol=1e-15 * H_hi, rtol=1e-15)
    shA, shB, _ = parts(H)
    T0 = np.array([H * eh[0], H * eh[1], -w * shA])
    sol = StaticSolution(length, T0, w, law, np.asarray(A, float).copy(), touchdown=float(shA),
                         liftoff=float(length - shB) if shB > 0 else -1.0, seabed_z=zg, sink=sink,
                         method="catenary+seabed")
    gap = sol.position([length])[0] - B
    if max(abs(gap[0]), abs(gap[1]), abs(gap[2]) - (sink if hB == 0.0 else 0.0)) > 1e-6 * max(length, 1.0):
        raise RuntimeError("static catenary with touchdown: the shape does not close on the s = L end")
    return sol


def _with_surface(sol, w_air):
    """Attach the free-surface split (air above z = 0 from s = 0 to the crossing) to a solution."""
    if w_air is not None:
        sol.w_air = float(w_air)
        sol.crossing = surface_crossing(sol.T0, w_air, sol.law, sol.length, float(sol.origin[2]))
    return sol


def hanging_from(A, length, w, law, end_load, at_start=True, w_air=None):
    """Cable hanging from the fixed point A with a point load end_load (3,) on its other end.

    at_start=True: A is the s = 0 end and the load acts on s = L (T(L) = load);
    otherwise A is the s = L end and the load acts on s = 0 (T(0) = -load).
    w_air (free surface, at_start only): weight per metre above z = 0; the crossing arc s_c solves
    z(s_c) = 0 with T0 = load - (w_air s_c + w (L - s_c)) z_hat (fixed point on s_c).
    """
    load = np.asarray(end_load, float)
    if at_start and w_air is not None and A[2] > 0.0:
        sc = 0.0
        for _ in range(200):  # s_c -> T0 -> crossing of that shape: a contraction (T0 depends on s_c weakly)
            T0 = load - np.array([0.0, 0.0, w_air * sc + w * (length - sc)])
            sn = surface_crossing(T0, w_air, law, length, float(A[2]))
            if abs(sn - sc) <= 1e-12 * max(length, 1.0):
                sc = sn
                break
            sc = sn
        T0 = load - np.array([0.0, 0.0, w_air * sc + w * (length - sc)])
        sol = StaticSolution(length, T0, w, law, np.asarray(A, float).copy(), method="hanging", w_air=w_air)
        sol.crossing = surface_crossing(T0, w_air, law, length, float(A[2]))
        return sol
    if at_start:
        T0 = load - np.array([0.0, 0.0, w * length])
        return StaticSolution(length, T0, w, law, np.asarray(A, float).copy(), method="hanging")
    T0 = -load
    rL = _integral(T0, w, law, np.array([length]))[0]
    return StaticSolution(length, T0, w, law, np.asarray(A, float) - rL, method="hanging")


def solve_static(config, vehicle_load=None, ship_load=None):
    """Static shape for a SimConfig's ends (see module docstring); vehicle_load / ship_load (3,) override
    the point load on a non-kinematic end (e.g. a body's submerged weight, (0, 0, -W)).
    Raises RuntimeError if unsolvable."""
    cable, env = config.cable, config.environment
    law = TensionLaw(cable)
    w = net_weight_per_length(cable, env)
    L = cable.length
    ks, kv = config.ship_end.kind, config.vehicle_end.kind
    A = np.asarray(config.ship_end.position, float)
    B = np.asarray(config.vehicle_end.position, float)
    seabed = env.seabed_z if env.seabed else None
    sink = w / (env.seabed_stiffness * cable.diameter) if env.seabed and env.seabed_stiffness > 0 else 0.0
    loads = np.zeros((2, 3))
    if KINDS[ks].load == "applied":
        loads[0] = config.ship_end.force
    if KINDS[kv].load == "applied":
        loads[1] = config.vehicle_end.force
    if ship_load is not None:
        loads[0] = ship_load
    if vehicle_load is not None:
        loads[1] = vehicle_load
    held = (ks in KINEMATIC_KINDS, kv in KINEMATIC_KINDS)
    w_air = _surface_weight(config, A, B)
    if held[0] and held[1]:
        try:
            sol = catenary_between(A, B, L, w, law, seabed_z=seabed, sink=sink, w_air=w_air)
        except RuntimeError:
            sol = None
    elif held[0]:
        sol = hanging_from(A, L, w, law, loads[1], at_start=True, w_air=w_air)
    elif held[1]:
        sol = hanging_from(B, L, w, law, loads[0], at_start=False)
    else:
        raise RuntimeError("static equilibrium needs at least one end held in place")
    if sol is not None and len(env.current_z) == 0 and not (sol.crossing > 0.0 and env.seabed):
        return sol
    # dynamic relaxation: no catenary solution, or a current to balance (the catenary ignores it)
    n = 101
    s = np.linspace(0.0, L, n)
    initial = sol.position(s) if sol is not None else None
    start = initial[0] if initial is not None else A
    end = initial[-1] if initial is not None else B
    wn = w
    if w_air is not None and initial is not None:  # free surface: per-node weight from the first guess
        wn = np.where(initial[:, 2] > 0.0, w_air, w)
    shape = relax_cable(start, end, L, law, wn, held=held, loads=loads, n_nodes=n, initial=initial, env=env, cable=cable)
    if not (shape.converged or shape.residual <= ACCEPTED_RESIDUAL * shape.scale):
        raise RuntimeError(f"static shape: dynamic relaxation did not converge (residual {shape.residual:.3g} N "
                           f"against loads of {shape.scale:.3g} N)")
    return shape


def _surface_weight(config, A, B):
    """Weight per metre in air when the free surface is on and the ship end is above z = 0 (else None).

    The static state uses the sharp interface z = 0 (still water): the dynamic solvers' wetted fraction
    is odd about the surface, so a straight cable crossing its band carries the same wetted length."""
    env = config.environment
    if not env.free_surface:
        return None
    if B[2] > 0.0 and A[2] <= 0.0:
        raise RuntimeError("free surface: the static solve handles a cable entering the water from the "
                           "s = 0 (ship) end; here the s = L end is above z = 0")
    if A[2] <= 0.0:
        return None
    return air_weight_per_length(config.cable, env)
