"""The stepper's divergence check (stepper._finite_state) decides as the sum it replaces.

After every substep the stepper stops with STATUS_DIVERGED when s = sum |U| + sum |body states|, summed in
that order, is not finite. _finite_state decides that without the sum's chain of additions when every value is
below 1e300 in magnitude, and falls back to the sum otherwise; its answer must be the sum's for every input:
ordinary states, a NaN or an infinity anywhere, and finite values so large that the sum overflows (or does
not). Marked ``jit_off``: also run with the kernels as Python.
"""

import math

import numpy as np
import pytest

from tether_sim.solvers.dg.stepper import _finite_state

pytestmark = pytest.mark.jit_off


def summed(Uf, bs):
    """The check as written before: the plain sum in U's order, then the body states'."""
    s = 0.0
    for x in Uf:
        s += abs(x)
    for row in bs:
        for x in row:
            s += abs(x)
    return math.isfinite(s)


def cases():
    rng = np.random.default_rng(7)
    base_u, base_b = rng.normal(scale=50.0, size=108), rng.normal(size=(2, 13))
    yield "ordinary", base_u, base_b
    yield "zeros", np.zeros(108), np.zeros((2, 13))
    for where in (0, 53, 107):
        for bad in (math.nan, math.inf, -math.inf):
            u = base_u.copy()
            u[where] = bad
            yield f"U[{where}] = {bad}", u, base_b
    for bad in (math.nan, -math.inf):
        b = base_b.copy()
        b[1, 12] = bad
        yield f"body {bad}", base_u, b
    u = base_u.copy()
    u[10] = u[90] = 1.7e308  # finite values whose sum overflows: diverged
    yield "sum overflows", u, base_b
    u = base_u.copy()
    u[10] = -3e301  # above the bound, the sum finite: not diverged
    b = base_b.copy()
    b[0, 0] = 5e305
    yield "huge, sum finite", u, b
    u = np.full(108, 1e300)  # at the bound: the sum (1.08e302) is finite
    yield "at the bound", u, base_b
    yield "subnormal", np.full(108, 5e-324), base_b


@pytest.mark.parametrize("name, Uf, bs", list(cases()), ids=[c[0] for c in cases()])
def test_finite_state_is_the_sums_answer(name, Uf, bs):
    assert _finite_state(Uf, bs) == summed(Uf, bs)
