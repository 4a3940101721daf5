"""The RKL2 damping step (dg.damping = rkl2; solvers/dg/rkl_damping.py).

1. The coefficients are RKL2's [Meyer, Balsara & Aslam 2014]: on the scalar problem y' = z y the s-stage
   recursion is stable (|R| <= 1) and never negative on z in [-(s^2 + s - 2) / 2, 0], and second order
   (|R(z) - e^z| ~ z^3).
2. The compiled step equals the same recursion written out with numpy on the dense operator of the frozen
   damping problem (clip set and released ends included), and the stage rule covers that operator's spectrum.
The closed-form damped axial mode, the order of the whole scheme and the stability far above the explicit limit
are run for rkl2 in test_implicit_damping.py.
"""

import numpy as np
import pytest

from tether_sim.physics.hydrodynamics import added_mass_per_length
from tether_sim.scenarios import harness
from tether_sim.solvers.dg import damping_layout as DL
from tether_sim.solvers.dg import damping_ops as DO
from tether_sim.solvers.dg import implicit_damping as ID
from tether_sim.solvers.dg import layout as Y
from tether_sim.solvers.dg import rkl_damping as RK

from test_implicit_damping import curved_flat, curved_solver, dense_damping_problem  # (test/solvers/dg on the path)

pytestmark = pytest.mark.jit_off


def amplification(s, z):
    """R_s(z): the RKL2 recursion of rkl_damping.rkl2_step on y' = z y, y0 = 1, step 1."""
    w1 = 4.0 / (s * s + s - 2)
    y0, f0 = 1.0, z
    prev, y = y0, y0 + w1 / 3.0 * f0
    for j in range(2, s + 1):
        mu, nu, mt, gt = RK.rkl2_coefficients(s, j)
        prev, y = y, mu * y + nu * prev + (1.0 - mu - nu) * y0 + mt * z * y + gt * f0
    return y


@pytest.mark.parametrize("s", [2, 3, 4, 5, 8, 13])
def test_rkl2_is_stable_non_negative_and_second_order(s):
    edge = 0.5 * (s * s + s - 2)
    z = np.linspace(-edge, 0.0, 2001)
    R = np.array([amplification(s, x) for x in z])
    b_s = (s * s + s - 2) / (2.0 * s * (s + 1))
    assert R.max() <= 1.0 + 1e-12 and R.min() >= 1.0 - 2.0 * b_s - 1e-12 >= 0.0
    assert amplification(s, -1.05 * edge - 0.5) < -1e-3 or abs(amplification(s, -1.3 * edge)) > 1.0  # the edge is real
    err = [abs(amplification(s, x) - np.exp(x)) for x in (-0.02, -0.01)]
    assert 6.0 < err[0] / err[1] < 10.0  # local error ~ z^3: halving z divides it by 8
    assert RK.rkl2_stages(edge) == s and RK.rkl2_stages(edge + 1e-9) == s + 1


@pytest.mark.parametrize("push", [False, True])
def test_rkl2_step_equals_the_dense_recursion(push):
    s = curved_solver("prescribed", "fixed", 0.0, law="bilinear")
    s.ws.vbc[:] = 3.0 * np.random.default_rng(2).standard_normal((2, 6))
    if push:
        s.ws.vbc[0, 3], s.ws.vbc[1, 3] = 8.0, -8.0  # ends pushed into the cable: released
    cab, env = s.config.cable, s.config.environment
    dw = ID.DampingWork(DL.MODE_RKL2, s.ops, s.ws.h, s.kinds, cab, cab.gamma0, *added_mass_per_length(cab, env), 0.0,
                        s.law.code, (s.ws.iprm[Y.I_KIND0], s.ws.iprm[Y.I_KIND1]), s._damp.dprm[DL.DP_LAMBDA])
    U0, hs = s.ws.U.copy(), 0.01
    ID.damping_step(hs, s.ws.U, s.ws.vbc, dw.idp, dw.dprm, dw.blk, dw.bvec, s.ws.V, s.ws.Pj, s.ws.Tr, s.law.tab_eps,
                    s.law.tab_T, dw.wp, dw.wd, dw.band, dw.vec, dw.tmp, dw.wood, dw.fdamp)
    fd_step = dw.fdamp.copy()
    A, b, released = dense_damping_problem(s, dw, U0)
    assert released == (2 if push else 0)
    rho = np.abs(np.linalg.eigvals(A)).max()
    m = int(np.ceil(hs * dw.dprm[DL.DP_RHO] / RK.RKL_MAX_X))  # RKL2 steps of hs / m
    hm = hs / m
    stages = RK.rkl2_stages(hm * dw.dprm[DL.DP_RHO])
    assert m >= 2 and stages >= 3 and 0.5 * (stages * stages + stages - 2) >= hm * rho  # the rule covers the operator
    assert rho > 0.3 * dw.dprm[DL.DP_RHO]  # and is not far above it (RKL_SAFETY and the curved geometry)
    y = v0 = U0[:, :, 3:6].ravel()
    for _ in range(m):
        y0 = y
        f0 = A @ y0 + b
        prev, y = y0, y0 + hm * 4.0 / (3.0 * (stages * stages + stages - 2)) * f0
        for j in range(2, stages + 1):
            mu, nu, mt, gt = RK.rkl2_coefficients(stages, j)
            prev, y = y, mu * y + nu * prev + (1.0 - mu - nu) * y0 + hm * mt * (A @ y + b) + hm * gt * f0
    assert np.abs(y - v0).max() > 0.1
    np.testing.assert_allclose(s.ws.U[:, :, 3:6].ravel(), y, atol=1e-11 * np.abs(y).max())
    np.testing.assert_array_equal(s.ws.U[:, :, 0:3], U0[:, :, 0:3])  # q untouched
    # end forces: those of the damping tension of the new state (as the SDIRK2 step's, stiffly accurate)
    DO.strain_rates(s.ws.U, 3, True, s.ws.vbc, dw.blk, dw.bvec, dw.wp, DL.WP_X)
    DO.axial_tension_points(dw.wp, DL.WP_X, True)
    DO.end_damping_forces(dw.idp, dw.dprm, dw.bvec, s.ws.U, s.ws.Tr, dw.wp, dw.fdamp)
    np.testing.assert_allclose(fd_step, dw.fdamp, rtol=0, atol=1e-12 * max(np.abs(dw.fdamp).max(), 1.0))


def test_rkl2_refuses_bending_damping():
    flat = curved_flat("prescribed", "free", 0.5)
    flat["dg.damping"] = "rkl2"
    with pytest.raises(ValueError, match="rkl2 steps the axial damping only"):
        harness.make_solver(flat)
