"""Twin test: the compiled many-column interpolation (numerics.interp.interp_columns) against np.interp per column,
bit for bit, on grids with repeated values (a hybrid chain's joint nodes share an arc length), points on grid values,
outside the grid and NaN, and columns with signed zeros, infinities and NaN (numpy's fall-backs).

Marked ``jit_off``: `make test` also runs it with NUMBA_DISABLE_JIT=1 (the kernel as plain Python)."""

import numpy as np
import pytest

from tether_sim.numerics.interp import interp_columns

pytestmark = pytest.mark.jit_off


def _check(x, xp, F):
    out = np.full((x.size, F.shape[1]), 7.0)
    interp_columns(x, xp, F, out)
    for k in range(F.shape[1]):
        want = np.interp(x, xp, F[:, k])
        assert out[:, k].tobytes() == want.tobytes(), (k, out[:, k], want)


@pytest.mark.parametrize("seed", range(6))
def test_random_columns_bit_for_bit(seed):
    rng = np.random.default_rng(seed)
    K = int(rng.integers(2, 60))
    xp = np.sort(rng.uniform(0.0, 200.0, K))
    dup = rng.integers(0, K - 1, size=3)
    xp[dup + 1] = xp[dup]  # repeated grid values
    xp = np.sort(xp)
    F = rng.normal(size=(K, 12)) * 10.0 ** rng.integers(-3, 6, size=12)
    x = np.concatenate([np.linspace(xp[0], xp[-1], 50), xp, rng.uniform(-20.0, 220.0, 40), [xp[0] - 1, xp[-1] + 1]])
    _check(x, xp, F)
    _check(rng.permutation(x), xp, F)  # any order of points


def test_special_values():
    xp = np.array([0.0, 1.0, 1.0, 2.0, 3.0, 4.0, 5.0])
    F = np.array([[-0.0, 0.0, np.inf, np.nan, 1.0, -np.inf],
                  [0.0, -0.0, np.inf, 1.0, np.inf, 2.0],
                  [-0.0, 3.0, 1.0, 2.0, np.inf, np.inf],
                  [0.0, -0.0, -np.inf, np.nan, 5.0, np.inf],
                  [-0.0, -0.0, -np.inf, 0.0, np.nan, 1.0],
                  [1e308, -1e308, 2.0, 0.0, 1.0, 1.0],
                  [-1e308, 1e308, 3.0, 0.0, 1.0, 1.0]])
    x = np.array([-1.0, 0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.25, 4.0, 4.5, 5.0, 6.0, np.nan, -0.0])
    with np.errstate(all="ignore"):
        _check(x, xp, F)
    _check(x, np.array([2.0]), F[:1])  # a one-point grid
    _check(x, xp[:2], F[:2])

