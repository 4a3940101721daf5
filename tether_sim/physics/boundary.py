"""End conditions of the cable: the rows of [PE2020 Table 1].

Each end (``ship`` at s = 0, ``vehicle`` at s = L) has one kind:

=============  ====================================================================
``prescribed``  moving pinned end driven by a pose topic or motion generator (v_BC)
``fixed``       pinned joint at a fixed point (v = 0, no moment)
``free``        free cable end (T = 0, no moment)
``force``       point force and moment (T_BC, M_BC)
``clamped``     fixed clamped end with prescribed tangent direction (v = 0, i_BC)
``body``        rigid-body connection at point P (v_RB^(P)); the body is simulated
=============  ====================================================================
"""

from dataclasses import dataclass

from tether_sim.physics.end_conditions import END_KINDS
from tether_sim.spec import param

END_NAMES = ("ship", "vehicle")
# the kinds and what each imposes: physics/end_conditions.py (one table, used by every solver)


@dataclass(frozen=True)
class EndCondition:
    """Boundary condition of one cable end (world frame, ENU)."""

    kind: str = param("prescribed", doc="end condition, a row of PE2020 Table 1", choices=END_KINDS)
    position: tuple = param((0.0, 0.0, 0.0), unit="m", doc="initial (or fixed) position of the end, world frame")
    direction: tuple = param((0.0, 0.0, -1.0), doc="cable tangent dr/ds held at a clamped end (unit vector)")
    force: tuple = param((0.0, 0.0, 0.0), unit="N", doc="applied point force on the cable end (kind=force)")
    moment: tuple = param((0.0, 0.0, 0.0), unit="N m", doc="applied point moment on the cable end (kind=force)")
