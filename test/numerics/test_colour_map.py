"""The marker's compiled tension colour map (tether_sim/numerics/colour_map.py) against the numpy
statement of the map, value for value, over tensions that visit every branch: slack, the clip at
both ends, the midpoint (d = 0 exactly), infinities and NaN, and a scale <= 0.

Marked ``jit_off``: `make test` runs it a second time with NUMBA_DISABLE_JIT=1 (the loop as plain Python).
"""

import numpy as np
import pytest

from tether_sim.numerics.colour_map import tension_rgba

pytestmark = pytest.mark.jit_off


def numpy_map(tension, scale):
    """d = 2 T / scale - 1 clipped to [-1, 1] (-1 for scale <= 0); (max(d, 0), 1 - |d|, max(-d, 0), 1)."""
    tension = np.asarray(tension, float)
    d = np.clip(tension / scale * 2.0 - 1.0, -1.0, 1.0) if scale > 0 else np.full(tension.shape, -1.0)
    return np.column_stack([np.maximum(d, 0.0), 1.0 - np.abs(d), np.maximum(-d, 0.0), np.ones_like(d)])


def compiled_map(tension, scale):
    tension = np.ascontiguousarray(tension, dtype=float)
    out = np.full((tension.size, 4), -7.0)
    tension_rgba(tension, float(scale), out)
    return out


EDGES = [-1e6, -5.0, -0.0, 0.0, 1e-300, 25.0, 50.0, 75.0, 99.99999999999999, 100.0, 100.00000000000001, 500.0,
         np.inf, -np.inf, np.nan]


@pytest.mark.parametrize("scale", [100.0, 3.7, 1e-300, 0.0, -2.0])
def test_compiled_colour_map_is_the_numpy_map(scale):
    rng = np.random.default_rng(7)
    tension = np.concatenate([EDGES, rng.uniform(-0.5, 1.5, 200) * max(scale, 1.0)])
    got, want = compiled_map(tension, scale), numpy_map(tension, scale)
    np.testing.assert_array_equal(got, want)  # equal values, NaN where NaN (a zero's sign aside)
    finite = np.isfinite(want) & (want != 0.0)
    assert (got[finite].view(np.int64) == want[finite].view(np.int64)).all()  # bit for bit


def test_colour_map_ends_and_midpoint():
    """Blue at and below zero tension, pure green at half the scale, red at and above the scale."""
    c = compiled_map([-3.0, 0.0, 50.0, 100.0, 250.0], 100.0)
    np.testing.assert_array_equal(c, [[0, 0, 1, 1], [0, 0, 1, 1], [0, 1, 0, 1], [1, 0, 0, 1], [1, 0, 0, 1]])
