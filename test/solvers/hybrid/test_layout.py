"""The hybrid solver's column tables (solvers/hybrid/layout.py): each named column of P holds what its row
says, and the node-state columns are the ones the zone conversions read and write."""

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from tether_sim.io.params import load_config
from tether_sim.numerics.rotations import frame_with_tangent
from tether_sim.solvers import columns
from tether_sim.solvers.hybrid import layout
from tether_sim.solvers.hybrid.kernels import pack_parameters
from tether_sim.solvers.hybrid.layout import (CAT_EPS, CAT_SLOTS, CAT_T, CAT_TAN, CAT_V, HP_AF, HP_AM, HP_AREA, HP_B0,
                                              HP_CDN, HP_CDT, HP_CK, HP_CMN, HP_CMT, HP_D, HP_DT, HP_EA, HP_G, HP_GAM,
                                              HP_I0, HP_M, HP_RHOF, HP_SIZE, HP_ZETA, N_SLOTS, ROD_EPS, ROD_F, ROD_SLOTS,
                                              ROD_V)
from tether_sim.solvers.hybrid.zoning import cat_to_rod, rod_to_cat

ROOT = Path(__file__).resolve().parents[3]


@pytest.mark.parametrize("array", ["P (hybrid)", "Y catenary node", "Y rod node"])
def test_tables_are_contiguous_and_named_once(array):
    cols = columns.TABLES[array]
    offsets = [c.offset for c in cols]
    assert offsets == list(np.cumsum([0] + [c.width for c in cols[:-1]]))
    assert all(getattr(layout, c.name) == c.offset for c in cols)
    assert len({c.name for c in cols}) == len(cols)
    assert max(CAT_SLOTS, ROD_SLOTS) <= N_SLOTS


def test_each_parameter_column_holds_its_quantity():
    """Every argument of pack_parameters gets a distinct value, so two swapped columns would fail."""
    cfg = load_config(ROOT / "config" / "ropos_L200_hybrid.yaml")
    cable = replace(cfg.cable, damping=123.0)
    env = cfg.environment
    P = pack_parameters(cable, env, 0.011, 0.7, 0.6, 0.61, 2620.0, 1310.0, 0.013, 0.026)
    assert P.shape == (HP_SIZE,)
    expected = {HP_M: cable.gamma0, HP_CK: 1.0 / cable.EA, HP_G: env.g, HP_RHOF: env.fluid_density,
                HP_AREA: cable.area, HP_D: cable.diameter, HP_CDN: cable.Cdn, HP_CDT: cable.Cdt, HP_CMN: cable.Cmn,
                HP_CMT: cable.Cmt, HP_DT: 0.011, HP_AM: 0.7, HP_AF: 0.6, HP_GAM: 0.61, HP_EA: cable.EA,
                HP_ZETA: 123.0}
    for col, value in expected.items():
        assert P[col] == value
    assert tuple(P[HP_B0:HP_B0 + 3]) == (1310.0, 2620.0, 2620.0)  # (torsion, bend, bend)
    assert tuple(P[HP_I0:HP_I0 + 3]) == (0.026, 0.013, 0.013)


def test_zone_conversion_round_trip_by_name():
    """A catenary node (v, T, t, eps) converted to a rod node in a frame with axis 0 = t carries T in
    f[0], eps in ROD_EPS, v in body components; converted back it is the same node."""
    t = np.array([0.6, 0.0, -0.8])
    Yc = np.zeros(N_SLOTS)
    Yc[CAT_V:CAT_V + 3] = (0.3, -0.2, 0.1)
    Yc[CAT_T] = 5000.0
    Yc[CAT_TAN:CAT_TAN + 3] = t
    Yc[CAT_EPS] = 1e-3
    L = frame_with_tangent(t)
    Yr, Ytr = cat_to_rod(Yc, np.zeros(N_SLOTS), L)
    assert Yr[ROD_F] == pytest.approx(5000.0, rel=1e-14)
    assert Yr[ROD_EPS] == 1e-3
    np.testing.assert_allclose(L.T @ Yr[ROD_V:ROD_V + 3], Yc[CAT_V:CAT_V + 3], rtol=0, atol=1e-15)
    Yback, _ = rod_to_cat(Yr, Ytr, L)
    np.testing.assert_allclose(Yback[:CAT_SLOTS], Yc[:CAT_SLOTS], rtol=1e-14, atol=1e-15)
