"""The DG workspace: ``SLOTS`` is the only list of the compiled code's arrays (workspace.py).

``bind`` (generated from ``SLOTS``) must return, at position ``X_<NAME>``, the view of slot
``<NAME>`` -- the same memory, shape and dtype as ``ws.<name>``. Checked on the source ``bind`` is
made of (plain Python) and on the compiled ``bind`` (each slot filled with its own marker, summed in
compiled code); a bind whose order disagrees with ``SLOTS`` (two same-rank slots swapped) is shown
to fail the check.
"""

import numpy as np
import pytest
from numba import literal_unroll, njit

from tether_sim.config import SimConfig
from tether_sim.physics.boundary import EndCondition
from tether_sim.physics.cable import CableProperties
from tether_sim.physics.environment import Environment
from tether_sim.solvers.config import DGOptions, InitialState
from tether_sim.solvers.dg import workspace as W
from tether_sim.solvers.dg.solver import _DAMPING_SLOTS, DGCableSolver

pytestmark = pytest.mark.jit_off


def _solver(vehicle, EI=0.0, damping="explicit"):
    """A 60 m cable in water from a prescribed ship end, vehicle end of kind ``vehicle`` (N = 3, P = 3)."""
    cab = CableProperties(length=60.0, EA=2e5, gamma0=3.0, diameter=0.03, density=7000.0, EI=EI, damping=300.0,
                          Cdn=1.2, Cdt=0.05, Cmn=1.0, Cmt=0.3)
    cfg = SimConfig(cable=cab, environment=Environment(g=9.81, fluid_density=1025.0),
                    ship_end=EndCondition(kind="prescribed", position=(0, 0, 0)),
                    vehicle_end=EndCondition(kind=vehicle, position=(20.0, 0, -50.0)),
                    dg=DGOptions(n_elements=3, order=3, damping=damping), initial=InitialState(kind="straight"))
    return DGCableSolver(cfg)


@pytest.fixture(scope="module")
def ws():
    return _solver("body", EI=5.0, damping="implicit").ws


def _plain_bind(slots):
    """bind made of the source generated for ``slots``, with the plain-Python view functions."""
    fs = (getattr(W, f"_f{r}") for r in (1, 2, 3, 5))
    ns = {f.__name__: getattr(f, "py_func", f) for f in fs}  # (plain functions already with the JIT off)
    exec(W._bind_source(slots), ns)
    return ns["bind"]


def mismatches(A, ws):
    """Slots whose view in A is not ws.<name> (memory, shape, dtype)."""
    bad = []
    for k, (name, _, _, _) in enumerate(W.SLOTS):
        a, b = A[k], getattr(ws, name)
        same = (a.shape == b.shape and a.dtype == b.dtype
                and a.__array_interface__["data"][0] == b.__array_interface__["data"][0])
        if not same:
            bad.append(name)
    return bad


def test_slot_constants_are_the_positions_in_SLOTS():
    assert len({n for n, _, _, _ in W.SLOTS}) == W.N_SLOTS
    for k, (name, _, _, _) in enumerate(W.SLOTS):
        assert getattr(W, "X_" + name.upper()) == k


def test_bind_returns_every_slot_at_its_index(ws):
    A = _plain_bind(W.SLOTS)(ws.F, ws.I, ws.spec)
    assert len(A) == W.N_SLOTS
    assert mismatches(A, ws) == []
    assert mismatches(W.views(ws), ws) == []


def test_a_swap_of_two_same_rank_slots_is_caught(ws):
    """bind generated with "U" and "dU" (both rank 3, same shape) swapped: the check names both."""
    slots = list(W.SLOTS)
    i, j = W.X_U, W.X_DU
    assert slots[i][1:3] == slots[j][1:3] and ws.U.shape == ws.dU.shape
    slots[i], slots[j] = slots[j], slots[i]
    order = {name: k for k, (name, _, _, _) in enumerate(W.SLOTS)}
    spec = ws.spec[[order[name] for name, _, _, _ in slots]]  # the spec rows follow the swapped table
    A = _plain_bind(slots)(ws.F, ws.I, spec)
    assert mismatches(A, ws) == ["U", "dU"]


# not cached on disk: numba keys a cache on this file alone, and bind changes with SLOTS in workspace.py
@njit(cache=False, _nrt=False)
def _marker_sums(F, I, S, out):
    k = 0
    for a in literal_unroll(W.bind(F, I, S)):
        out[k] = a.sum()
        k += 1


def test_compiled_bind_reads_each_slot_by_its_name(ws):
    """Every slot filled with its own marker k + 1; the compiled bind's view k sums to (k + 1) x size."""
    F, I = ws.F.copy(), ws.I.copy()  # laid out by ws.spec
    for k, (name, arena, rank, _) in enumerate(W.SLOTS):
        o, shape = int(ws.spec[k, 0]), tuple(int(d) for d in ws.spec[k, 2:2 + rank])
        view = (F if arena == "f" else I)[o:o + int(np.prod(shape))].reshape(shape)
        view[...] = k + 1
    out = np.zeros(W.N_SLOTS)
    _marker_sums(F, I, ws.spec, out)
    want = [(k + 1) * getattr(ws, name).size for k, (name, _, _, _) in enumerate(W.SLOTS)]
    assert out.tolist() == want


def test_the_arrays_have_one_name():
    """The driver keeps no second name for an array of the compiled code: no attribute of the solver
    is a view into the arenas (a slot is read as ws.<name>), and the implicit damping's arrays are
    the workspace's views."""
    s = _solver("free", damping="implicit")
    assert isinstance(s, DGCableSolver)
    for name, value in vars(s).items():
        if isinstance(value, np.ndarray):
            assert not (np.shares_memory(value, s.ws.F) or np.shares_memory(value, s.ws.I)), name
    for slot, attr in _DAMPING_SLOTS.items():
        assert np.shares_memory(getattr(s._damp, attr), getattr(s.ws, slot)), slot
