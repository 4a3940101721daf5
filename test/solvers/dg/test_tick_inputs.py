"""set_end_motion's conversion of its inputs (inputs.motion_floats): the plain-float fast path for flat
sequences of three gives exactly numpy's values, and every other shape goes through numpy's
conversion with its errors (nothing accepted that the numpy-only version rejected)."""

import numpy as np
import pytest

from tether_sim.solvers.dg.inputs import motion_floats

P = (1.5, -2.25, 3.0e3)
V = (0.1, 0.2, -0.3)
EXPECTED = P + V


@pytest.mark.parametrize("conv", [tuple, list, np.array,
                                  lambda x: np.array(x).reshape(3, 1), lambda x: np.array(x).reshape(1, 3),
                                  lambda x: [np.float64(v) for v in x], lambda x: np.array(x, dtype=object)])
def test_same_values_as_numpy(conv):
    got = motion_floats(conv(P), conv(V))
    ref = tuple(np.array(conv(P), dtype=float).reshape(3).tolist() + np.array(conv(V), dtype=float).reshape(3).tolist())
    assert got == ref
    assert got == EXPECTED
    assert all(type(x) is float for x in got)


@pytest.mark.parametrize("bad", [(1.0, 2.0), (1.0, 2.0, 3.0, 4.0), "abc", [[1.0, 2.0], [3.0, 4.0]], None])
def test_wrong_inputs_raise_like_numpy(bad):
    with pytest.raises((TypeError, ValueError)):
        motion_floats(bad, V)
