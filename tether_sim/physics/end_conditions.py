"""The end conditions of the cable [PE2020 Table 1], in one table used by every solver.

Each end (ship at s = 0, outward normal n = -1; vehicle at s = L, n = +1) has one kind. A row of
``TABLE`` says everything a solver decides from the kind:

- ``kinematic``: the end's velocity is given (v_hat = v_BC) and the tension flux comes from the
  interior (T_hat = T+, upwinded in the DG solver); otherwise the end takes a force
  (T_hat = n F_BC) and its velocity follows the cable (v_hat = v+).
- ``position``: where the end's position and velocity come from: ``"motion"`` (set_end_motion
  targets, a cubic Hermite segment between them), ``"fixed"`` (EndCondition.position, at rest),
  ``"body"`` (the attachment point P of the simulated rigid body) or ``"cable"`` (wherever the
  cable puts it).
- ``load``: ``"applied"`` (F_BC, M_BC from EndCondition.force/moment or set_end_load), ``"zero"``
  (a free end: F_BC = 0, M_BC = 0) or ``"none"`` (kinematic ends).
- ``direction``: ``"held"`` (clamped: i_hat = i_BC, i_hat-dot = 0, M*_hat = M*+ from the interior)
  or ``"free"`` (i_hat = i+, i_hat-dot = i-dot+).
- ``moment``: M*_hat at the end: ``"zero"`` (pinned and free ends: moment free), ``"applied"``
  (n M_BC) or ``"interior"`` (M*+, clamped).

What each kind means for the DG unknowns q = dr/ds, v = gamma0 dr/dt, i = q/|q| and
M* = M/|q|^2 is in the ``q``, ``v``, ``i``, ``m`` text columns (docs/dg_solver.md prints them).
The compiled kernels read the same table through the flag arrays below, indexed by the code.
"""

from dataclasses import dataclass

import numpy as np

from tether_sim.numerics.jit import jit


@dataclass(frozen=True)
class EndKind:
    """One row of PE2020 Table 1 (module docstring)."""

    name: str
    code: int
    kinematic: bool
    position: str
    load: str
    direction: str
    moment: str
    q: str
    v: str
    i: str
    m: str


TABLE = (
    EndKind("prescribed", 0, True, "motion", "none", "free", "zero",
            "T_hat = T(q+) + upwind", "v_BC (Hermite)", "i+", "0 (moving pin)"),
    EndKind("fixed", 1, True, "fixed", "none", "free", "zero",
            "T_hat = T(q+) + upwind", "0", "i+", "0 (pinned joint)"),
    EndKind("free", 2, False, "cable", "zero", "free", "zero",
            "T_hat = 0", "v+", "i+", "0"),
    EndKind("force", 3, False, "cable", "applied", "free", "applied",
            "T_hat = n F_BC", "v+", "i+", "n M_BC"),
    EndKind("clamped", 4, True, "fixed", "none", "held", "interior",
            "T_hat = T(q+) + upwind", "0", "i_BC (i-dot 0)", "M*+"),
    EndKind("body", 5, True, "body", "none", "free", "zero",
            "T_hat = T(q+) + upwind", "v_RB at P", "i+", "0"),
)
KINDS = {k.name: k for k in TABLE}
END_KINDS = tuple(k.name for k in TABLE)
KIND_CODES = {k.name: k.code for k in TABLE}
assert [k.code for k in TABLE] == list(range(len(TABLE)))

# M*_hat rules
M_ZERO, M_APPLIED, M_INTERIOR = 0, 1, 2
_MOMENT_CODES = {"zero": M_ZERO, "applied": M_APPLIED, "interior": M_INTERIOR}

# flag arrays for the compiled kernels (numba freezes module-level arrays as constants)
KINEMATIC = np.array([k.kinematic for k in TABLE])
HAS_BODY = np.array([k.position == "body" for k in TABLE])
DRIVEN = np.array([k.position == "motion" for k in TABLE])
HOLDS_DIRECTION = np.array([k.direction == "held" for k in TABLE])
MOMENT_RULE = np.array([_MOMENT_CODES[k.moment] for k in TABLE], dtype=np.int64)


def end_kind(name, where="end.kind"):
    """The row of an end kind by name (ValueError naming the field for an unknown kind)."""
    try:
        return KINDS[name]
    except KeyError:
        raise ValueError(f"{where}: unknown end kind {name!r} (one of {', '.join(END_KINDS)})") from None


def held_in_place(name):
    """Kinematic and not a simulated body: the end sits at a given point (statics anchors it)."""
    k = end_kind(name)
    return k.kinematic and k.position != "body"


def anchor_end(names):
    """End from which positions are integrated: the ship end unless only the vehicle end is kinematic."""
    a, b = (end_kind(n) for n in names)
    return 1 if (not a.kinematic and b.kinematic) else 0


# ------------------------------------------------------------------- compiled look-ups (by code)
@jit
def is_kinematic(code):
    """v_hat = v_BC (prescribed, fixed, clamped, body); else T_hat = n F_BC (free, force)."""
    return KINEMATIC[code]


@jit
def has_body(code):
    """The end is the attachment point P of a simulated rigid body."""
    return HAS_BODY[code]


@jit
def holds_direction(code):
    """i_hat = i_BC, i_hat-dot = 0 and M*_hat = M*+ (clamped)."""
    return HOLDS_DIRECTION[code]


@jit
def is_driven(code):
    """Position and velocity from set_end_motion targets (Hermite segment)."""
    return DRIVEN[code]


@jit
def moment_rule(code):
    """M*_hat rule: M_ZERO, M_APPLIED (n M_BC) or M_INTERIOR (M*+)."""
    return MOMENT_RULE[code]
