"""Tension-strain laws T(eps, deps/dt) and their slope dT/deps [PE2020 Sec. 2.5, Eq. 22].

Law codes used by the kernels: ``LAW_BILINEAR`` (Eq. 22, no compression: T = 0 when eps <= 0,
and the total T = EA eps + zeta deps/dt is clipped at 0 so that a slackening cable never pushes),
``LAW_LINEAR`` (T = EA eps + zeta deps/dt for any sign), ``LAW_TABLE`` (synthetic ropes: a
piecewise-linear elastic tension through (table_strain, table_tension) starting at (0, 0),
extrapolated with the last slope, zero in compression, plus zeta deps/dt, clipped at 0).

**Compression up to the mesh's buckling load** (``cable.compression: buckling``; ``pc`` below, N; solvers/dg:
``compression_cap``, with the EI of :func:`cap_stiffness`). The default, ``cable.compression: none``, is Eq. 22
as printed with or without bending (pc = 0): the material of a slack cable shortens freely, and bending acts on
the curvature of the line only, as in MoorDyn; docs/dg_solver.md "Slack with bending" compares the two. The
"no compression" of Eq. 22 is the law of a perfectly flexible cable, which buckles under any push. A
cable with bending stiffness EI carries a push elastically until it buckles: a wave of the centreline
of wavenumber k buckles at its Euler load EI k^2, and to shorten the chord by a fraction d with such
a wave costs the bending energy EI k^2 d per metre, i.e. a compression EI k^2. A solver with bending
computes the buckling of the wavelengths its mesh resolves itself; the law stands for the shorter,
unresolved ones. So for the laws without compression, with a cap pc >= 0:

    T_el = k0 eps for 0 > eps > eps_y = -pc / k0 (k0 = EA, table: its first slope): the material is
    strained, T = max(T_el + zeta deps/dt, -pc);
    T = T_el = -pc l / l_y below (l = 1 + eps, l_y = 1 + eps_y): buckled below the mesh scale, the chord
    shortens at the Euler load of the shortest resolved wave, and the push fades with the chord so that
    the force vector T q / l = -pc q / l_y is continuous (Lipschitz) through a fold, where q / l flips.

pc = 0 (no bending, EI = 0) is Eq. 22 exactly, bit for bit; as the mesh is refined pc grows and the
law tends to the linear rod (compression carried, buckling resolved), and as EI -> 0 to Eq. 22.
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
def _first_slope(law, EA, tab_eps, tab_T):
    """dT/deps at eps = 0+ (the stiffness of the first strain, used in capped compression)."""
    if law == LAW_TABLE:
        return (tab_T[1] - tab_T[0]) / (tab_eps[1] - tab_eps[0])
    return EA


@jit
def buckled(law, eps, EA, tab_eps, tab_T, pc):
    """True where a law without compression is buckled below the mesh scale (k0 eps <= -pc, module
    docstring); always for eps <= 0 without a cap (pc = 0), never for the linear law."""
    if law == LAW_LINEAR or eps > 0.0:
        return False
    return _first_slope(law, EA, tab_eps, tab_T) * eps <= -pc


@jit
def elastic_tension(law, eps, EA, tab_eps, tab_T, pc):
    """Elastic part of the tension at strain eps (N); pc: compression cap (module docstring)."""
    if law == LAW_LINEAR:
        return EA * eps
    if eps <= 0.0:
        if pc <= 0.0:
            return 0.0
        k0 = _first_slope(law, EA, tab_eps, tab_T)
        t = k0 * eps
        if t > -pc:
            return t
        return -pc * (1.0 + eps) / (1.0 - pc / k0)  # buckled: fades with the chord (pc < k0 here)
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
def tension_slope(law, eps, EA, tab_eps, tab_T, pc):
    """dT/deps of the elastic part (N); sets the local wave speed lambda [PE2020 Eq. 25]."""
    if law == LAW_LINEAR:
        return EA
    if eps < 0.0:  # capped compression: k0 while strained; 0 where buckled (the fading push is no wave)
        k0 = _first_slope(law, EA, tab_eps, tab_T)
        return k0 if pc > 0.0 and k0 * eps > -pc else 0.0
    if law == LAW_BILINEAR:
        return EA
    n = tab_eps.shape[0]
    for k in range(1, n):
        if eps <= tab_eps[k]:
            return (tab_T[k] - tab_T[k - 1]) / (tab_eps[k] - tab_eps[k - 1])
    return (tab_T[n - 1] - tab_T[n - 2]) / (tab_eps[n - 1] - tab_eps[n - 2])


@jit
def axial_tension(law, eps, eps_rate, EA, zeta, tab_eps, tab_T, pc):
    """T(eps, deps/dt) [PE2020 Eq. 22] (visco-elastic; see module docstring per law and for pc)."""
    if law == LAW_LINEAR:
        return EA * eps + zeta * eps_rate
    if pc > 0.0:
        tel = elastic_tension(law, eps, EA, tab_eps, tab_T, pc)
        if buckled(law, eps, EA, tab_eps, tab_T, pc):
            return tel  # no material strain rate where buckled below the mesh scale
        t = tel + zeta * eps_rate
        return t if t > -pc else -pc
    if eps <= 0.0:
        return 0.0
    t = elastic_tension(law, eps, EA, tab_eps, tab_T, 0.0) + zeta * eps_rate
    return t if t > 0.0 else 0.0


@jit
def compression_cap(law, EI, P, h):
    """The cap pc of the laws without compression on an element of length h with order P (N): the Euler
    load EI k^2 of the shortest wave the element resolves, k = pi P / h (wavelength 2 h / P, two nodes
    per wave); 0 for the linear law and without bending (module docstring)."""
    if law == LAW_LINEAR or EI <= 0.0:
        return 0.0
    k = 3.141592653589793 * P / h
    return EI * k * k


def cap_stiffness(cable):
    """EI of the compression cap (N m^2): the cable's EI with ``cable.compression: buckling``, 0 with ``none``
    (Eq. 22 as printed: a slack cable pushes nothing, with or without bending)."""
    return float(cable.EI) if cable.compression == "buckling" else 0.0


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

    def tension(self, eps, eps_rate=0.0, pc=0.0):
        """T(eps, deps/dt), vectorised; pc: the compression cap (module docstring)."""
        e = np.atleast_1d(np.asarray(eps, float))
        r = np.broadcast_to(np.asarray(eps_rate, float), e.shape)
        return np.array([axial_tension(self.code, a, b, self.EA, self.zeta, self.tab_eps, self.tab_T, pc)
                         for a, b in zip(e, r)])

    def slope(self, eps, pc=0.0):
        """dT/deps (elastic), vectorised."""
        e = np.atleast_1d(np.asarray(eps, float))
        return np.array([tension_slope(self.code, a, self.EA, self.tab_eps, self.tab_T, pc) for a in e])

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
