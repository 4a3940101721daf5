"""The element loops at fixed sizes (kernels.SIZED): tension_scalar_<nm>_<nq> and momentum_rate_<nm>_<nq> are
the generic kernels with the modes per element and the Gauss points made constants, and must give the
generic kernels' bits on every branch they share (laws, bending, bodies, current, relaxation), and
internal_forces / dg_rhs must pick them for exactly the sizes of SIZED.

Marked ``jit_off``: `make test` also runs them with NUMBA_DISABLE_JIT=1.
"""

import inspect

import numpy as np
import pytest

from tether_sim.solvers.dg import kernels as K
from tether_sim.solvers.dg import layout as Y
from tether_sim.solvers.dg.soa import TMP_HEAD

from test_twins import cable_solver  # (test/solvers/dg on the path)

pytestmark = pytest.mark.jit_off

# (solver arguments, relaxation rate, current profile): every size of SIZED, both laws without compression and
# the linear and tabulated ones, bending (the nested LDG inside tension_scalar), a body end, a current (the
# positions and the current look-up of momentum_rate)
CASES = [
    (dict(N=5, P=2, kinds=("prescribed", "body")), 0.0, False),
    (dict(N=6, P=2, EI=50.0), 0.7, False),
    (dict(N=3, P=2, law="linear", kinds=("fixed", "force")), 0.0, True),
    (dict(N=3, P=4), 0.0, False),
    (dict(N=2, P=4, EI=50.0), 0.0, True),
    (dict(N=4, P=4, law="table"), 0.7, False),
]


def _solver(args, relax, current):
    s = cable_solver(**args)
    s.ws.prm[Y.P_RELAX] = relax
    if current:  # a uniform current (the table of one depth), read per Gauss point from its position
        s.ws.iprm[Y.I_CURRENT] = s.ws.iprm[Y.I_NEEDPOS] = 1
        s.ws.cx[:] = 0.4
        s.ws.cy[:] = -0.2
    s.ws.vbc[:] = np.random.default_rng(1).standard_normal((2, 6))
    return s


def _tension_args(s, out):
    ws = s.ws
    return (ws.U, ws.prm, ws.iprm, ws.h, ws.V, ws.Pj, ws.D, ws.Lf, ws.Tr, ws.tab_eps, ws.tab_T, ws.bc, ws.vbc,
            out["wq"], out["wm"], out["trc"], out["fl"], out["dU"])


def _momentum_args(s, out):
    ws = s.ws
    return (ws.U, ws.ra, ws.prm, ws.iprm, ws.h, ws.V, ws.Pj, ws.D, ws.Lf, ws.Iq, ws.cz, ws.cx, ws.cy, out["wq"],
            out["wm"], out["trc"], out["fl"], out["rs"], out["tmp"], out["dU"])


def _work(s):
    ws = s.ws
    return dict(wq=ws.wq.copy(), wm=ws.wm.copy(), trc=ws.trc.copy(), fl=ws.fl.copy(), dU=ws.dU.copy(),
                rs=ws.rs.copy(), tmp=ws.tmp[:TMP_HEAD].copy())  # (element-wise momentum path)


@pytest.mark.parametrize("args, relax, current", CASES)
def test_the_sized_kernels_give_the_generic_bits(args, relax, current):
    s = _solver(args, relax, current)
    nm, nq = s.ws.V.shape[1], s.ws.V.shape[0]
    assert (nm, nq) in K.SIZED
    s._evaluate()  # work arrays of a full evaluation: what momentum_rate reads
    generic, sized = _work(s), _work(s)
    K.tension_scalar(*_tension_args(s, generic))
    getattr(K, f"tension_scalar_{nm}_{nq}")(*_tension_args(s, sized))
    for name in generic:
        assert np.array_equal(generic[name], sized[name]), name
    K.momentum_rate(*_momentum_args(s, generic))
    getattr(K, f"momentum_rate_{nm}_{nq}")(*_momentum_args(s, sized))
    for name in generic:
        assert np.array_equal(generic[name], sized[name]), name
    assert np.any(generic["dU"][:, :, 3:6] != 0.0) and np.all(np.isfinite(generic["dU"]))


def test_the_sized_source_is_the_generic_one_with_two_numbers():
    for nm, nq in K.SIZED:
        for fn in (K.tension_scalar, K.momentum_rate):
            a = inspect.getsource(getattr(fn, "py_func", fn)).splitlines()
            b = [ln for ln in K.sized_source(fn, nm, nq).splitlines()[-len(a):]]
            diff = [(x.strip(), y.strip()) for x, y in zip(a, b) if x != y]
            assert sorted(diff) == sorted([(a[0].strip(), ""), (f"def {fn.__name__}(" + a[1].split("(", 1)[1].strip(),
                                            f"def {fn.__name__}_{nm}_{nq}(" + a[1].split("(", 1)[1].strip()),
                                           ("nq = V.shape[0]", f"nq = {nq}"), ("nm = V.shape[1]", f"nm = {nm}")])


def test_every_size_is_dispatched():
    """internal_forces and dg_rhs name the sized kernel of every size of SIZED (and no other)."""
    for fn, kernel in ((K.internal_forces, "tension_scalar"), (K.dg_rhs, "momentum_rate")):
        src = inspect.getsource(getattr(fn, "py_func", fn))
        named = {tuple(int(x) for x in w.split("(")[0].split("_")[-2:]) for w in src.split()
                 if w.startswith(f"{kernel}_") and w.split("(")[0].split("_")[-1].isdigit()}
        assert named == set(K.SIZED)
        for nm, nq in K.SIZED:
            assert f"if nm == {nm} and nq == {nq}:" in src or f"elif nm == {nm} and nq == {nq}:" in src
