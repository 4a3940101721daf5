"""Tension-strain laws T(eps, deps/dt) and their slope dT/deps [PE2020 Sec. 2.5, Eq. 22].

Law codes used by the kernels: ``LAW_BILINEAR`` (Eq. 22, no compression: T = 0 when eps <= 0,
and the total T = EA eps + zeta deps/dt is clipped at 0 so that a slackening cable never pushes),
``LAW_LINEAR`` (T = EA eps + zeta deps/dt for any sign), ``LAW_TABLE`` (synthetic ropes: a
piecewise-linear elastic tension through (table_strain, table_tension) starting at (0, 0),
extrapolated with the last slope, zero in compression, plus zeta deps/dt, clipped at 0).
"""

import numpy as np

from tether_sim.numerics.jit import jit

LAW_BILINEAR = 0
LAW_LINEAR = 1
LAW_TABLE = 2
LAW_CODES = {"bilinear": LAW_BILINEAR, "linear": LAW_LINEAR, "table": LAW_TABLE}


@jit
def chord_floor(law):
    """Stretch below which a chord is not compressed material but a cable wavy below the mesh scale: 1 for
    the laws without compression (bilinear, table), 0 for the linear law, whose compression is real
    (the bending tangent of solvers/dg/ldg.py)."""
    return 0.0 if law == LAW_LINEAR else 1.0


@jit
def elastic_tension(law, eps, EA, tab_eps, tab_T):
    """Elastic part of the tension at strain eps (N)."""
    if law == LAW_LINEAR:
        return EA * eps
    if eps <= 0.0:
        return 0.0
    if law == LAW_BILINEAR:
        return EA * eps
    n = tab_eps.shape[0]
    for k in range(1, n):
        if eps <= tab_eps[k]:
            a = (eps - tab_eps[k - 1]) / (tab_eps[k] - tab_eps[k - 1])
            return tab_T[k - 1] + a * (tab_T[k] - tab_T[k - 1])
    slope = (tab_T[n - 1] - tab_T[n - 2]) / (tab_eps[n - 1] - tab_eps[n - 2])
    return tab_T[n - 1] + slope * (eps - tab_eps[n - 1])


@jit
def tension_slope(law, eps, EA, tab_eps, tab_T):
    """dT/deps of the elastic part (N); sets the local wave speed lambda [PE2020 Eq. 25]."""
    if law == LAW_LINEAR:
        return EA
    if eps < 0.0:
        return 0.0
    if law == LAW_BILINEAR:
        return EA
    n = tab_eps.shape[0]
    for k in range(1, n):
        if eps <= tab_eps[k]:
            return (tab_T[k] - tab_T[k - 1]) / (tab_eps[k] - tab_eps[k - 1])
    return (tab_T[n - 1] - tab_T[n - 2]) / (tab_eps[n - 1] - tab_eps[n - 2])


@jit
def axial_tension(law, eps, eps_rate, EA, zeta, tab_eps, tab_T):
    """T(eps, deps/dt) [PE2020 Eq. 22] (visco-elastic; see module docstring per law)."""
    if law == LAW_LINEAR:
        return EA * eps + zeta * eps_rate
    if eps <= 0.0:
        return 0.0
    t = elastic_tension(law, eps, EA, tab_eps, tab_T) + zeta * eps_rate
    return t if t > 0.0 else 0.0


class TensionLaw:
    """Python-side view of a cable's law (validation, statics, max slope for the time step)."""

    def __init__(self, cable):
        if cable.material not in LAW_CODES:
            raise ValueError(f"cable.material: unknown law {cable.material!r}")
        self.code = LAW_CODES[cable.material]
        self.EA = float(cable.EA)
        self.zeta = float(cable.damping)
        if self.code == LAW_TABLE:
            e = np.asarray(cable.table_strain, dtype=float)
            t = np.asarray(cable.table_tension, dtype=float)
            if e.size < 2 or e.size != t.size:
                raise ValueError("cable.table_strain / cable.table_tension: need >= 2 points of equal count")
            if e[0] != 0.0 or t[0] != 0.0:
                raise ValueError("cable.table_strain / cable.table_tension: the table must start at (0, 0)")
            if np.any(np.diff(e) <= 0.0) or np.any(np.diff(t) < 0.0):
                raise ValueError("cable.table_strain must increase and cable.table_tension must not decrease")
            self.tab_eps, self.tab_T = np.ascontiguousarray(e), np.ascontiguousarray(t)
        else:
            self.tab_eps, self.tab_T = np.zeros(2), np.zeros(2)

    def tension(self, eps, eps_rate=0.0):
        """T(eps, deps/dt), vectorised."""
        e = np.atleast_1d(np.asarray(eps, float))
        r = np.broadcast_to(np.asarray(eps_rate, float), e.shape)
        return np.array([axial_tension(self.code, a, b, self.EA, self.zeta, self.tab_eps, self.tab_T)
                         for a, b in zip(e, r)])

    def slope(self, eps):
        """dT/deps (elastic), vectorised."""
        e = np.atleast_1d(np.asarray(eps, float))
        return np.array([tension_slope(self.code, a, self.EA, self.tab_eps, self.tab_T) for a in e])

    def max_slope(self) -> float:
        """Largest dT/deps the law can reach (sets the largest wave speed)."""
        if self.code == LAW_TABLE:
            return float(np.max(np.diff(self.tab_T) / np.diff(self.tab_eps)))
        return self.EA

    def strain_at(self, tension: float) -> float:
        """Elastic strain carrying a static tension (>= 0); inverse of the elastic law."""
        if tension <= 0.0:
            return 0.0
        if self.code != LAW_TABLE:
            return tension / self.EA
        e, t = self.tab_eps, self.tab_T
        if tension <= t[-1]:
            return float(np.interp(tension, t, e))
        return float(e[-1] + (tension - t[-1]) / ((t[-1] - t[-2]) / (e[-1] - e[-2])))
