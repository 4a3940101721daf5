"""The Table 1 module: the rows say what PE2020 Table 1 says, and every consumer reads them."""

import numpy as np
import pytest

from tether_sim.physics import end_conditions as ec
from tether_sim.physics.boundary import END_KINDS
from tether_sim.physics.statics import KINEMATIC_KINDS


def test_rows_follow_pe2020_table_1():
    # velocity (kinematic) ends: moving pin, pinned joint, clamp, rigid-body connection
    assert {k.name for k in ec.TABLE if k.kinematic} == {"prescribed", "fixed", "clamped", "body"}
    # force ends: T_hat = n F_BC (zero for a free end), v_hat = v+
    assert {k.name: k.load for k in ec.TABLE if not k.kinematic} == {"free": "zero", "force": "applied"}
    # only the clamp holds i (i_hat = i_BC, i-dot_hat = 0) and takes M*_hat from the interior
    assert [k.name for k in ec.TABLE if k.direction == "held"] == ["clamped"]
    assert {k.name: k.moment for k in ec.TABLE} == {"prescribed": "zero", "fixed": "zero", "free": "zero",
                                                    "force": "applied", "clamped": "interior", "body": "zero"}
    assert {k.name: k.position for k in ec.TABLE} == {"prescribed": "motion", "fixed": "fixed", "free": "cable",
                                                      "force": "cable", "clamped": "fixed", "body": "body"}


def test_flag_arrays_and_codes_are_the_table():
    for k in ec.TABLE:
        assert ec.KIND_CODES[k.name] == k.code
        assert bool(ec.is_kinematic(k.code)) == k.kinematic
        assert bool(ec.has_body(k.code)) == (k.position == "body")
        assert bool(ec.is_driven(k.code)) == (k.position == "motion")
        assert bool(ec.holds_direction(k.code)) == (k.direction == "held")
        assert ec.moment_rule(k.code) == {"zero": ec.M_ZERO, "applied": ec.M_APPLIED, "interior": ec.M_INTERIOR}[k.moment]
    assert END_KINDS == ec.END_KINDS
    assert set(KINEMATIC_KINDS) == {"prescribed", "fixed", "clamped"}  # the statics anchor these (a body is a load)


def test_anchor_and_unknown_kind():
    assert ec.anchor_end(("prescribed", "body")) == 0
    assert ec.anchor_end(("free", "body")) == 1  # only the vehicle end is held: integrate from s = L
    assert ec.anchor_end(("free", "force")) == 0
    with pytest.raises(ValueError, match="ship_end.kind: unknown end kind 'pinned'"):
        ec.end_kind("pinned", "ship_end.kind")


@pytest.mark.parametrize("kinds, hold, held, ends", [
    (("prescribed", "body"), False, (False, False), ("CAT_VEL", "CAT_BODY")),
    (("fixed", "clamped"), False, (False, True), ("CAT_VEL", "ROD_END_CLAMPED")),
    (("fixed", "free"), False, (False, False), ("CAT_VEL", "CAT_FREE")),
    (("fixed", "free"), True, (False, True), ("CAT_VEL", "ROD_END_FORCE_HELD")),
    (("fixed", "prescribed"), True, (False, False), ("CAT_VEL", "CAT_VEL")),  # hold_direction: force ends only
])
def test_hybrid_end_conditions_come_from_the_table(kinds, hold, held, ends):
    """The hybrid solver's end equations follow each end's Table 1 row: a body's end is tied to the body
    node, a kinematic end is a velocity end, a free end a tension-free one; a held frame (clamped row, or
    a force end with hybrid.hold_direction_*) puts a rod at the end with omega = 0."""
    from tether_sim.config import SimConfig
    from tether_sim.physics.boundary import EndCondition
    from tether_sim.physics.cable import CableProperties
    from tether_sim.solvers.config import HybridOptions, InitialState
    from tether_sim.solvers.hybrid import assembly, rod
    from tether_sim.solvers.hybrid.solver import HybridRodCatenarySolver

    cfg = SimConfig(solver="hybrid", cable=CableProperties(length=20.0, EI=1.0),
                    ship_end=EndCondition(kind=kinds[0], position=(0, 0, 0)),
                    vehicle_end=EndCondition(kind=kinds[1], position=(0, 0, -19.9), direction=(0, 0, -1)),
                    hybrid=HybridOptions(n_segments=10, hold_direction_vehicle=hold),
                    initial=InitialState(kind="straight"))
    s = HybridRodCatenarySolver(cfg)
    assert s.end_held == held
    ch = s.chain
    for e in range(2):
        g = ch.end_group[e]
        k = int(ch.gkind[g])
        name = next(n for n in ("CAT_VEL", "CAT_FREE", "CAT_FORCE", "CAT_BODY", "ROD_BODY", "ROD_END")
                    if getattr(assembly, n) == k)
        if name == "ROD_END":
            name = next(n for n in ("ROD_END_PINNED", "ROD_END_CLAMPED", "ROD_END_FORCE", "ROD_END_FORCE_HELD")
                        if getattr(rod, n) == ch.gpar[g, 0])
        assert name == ends[e]
    assert s.free_ends == [False, kinds[1] == "free"]
    assert np.all(np.isfinite(s.positions))
