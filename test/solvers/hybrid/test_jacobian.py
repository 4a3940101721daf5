"""Analytic band Jacobian (hybrid.jacobian: analytic) against its forward-difference twin, the band LU,
and the converged step against the twin's (docs/hybrid_solver.md, "Jacobian").

Tolerance of the Jacobian comparison: the twin's forward difference with the relative step
h = 1e-7 (1 + |y|) has a truncation error h |f''| / 2 and a round-off error ~ 2 u |f| / h (u = 1.1e-16).
Per row, relative to the row's largest entry, both are O(1e-7) for these states (measured: <= 1.2e-7
at the ROPOS states below), so 2e-6 leaves a margin of ~15 while a wrong term (a missing factor
alpha_f = 1, a sign, a missing drag or added-mass term: >= 1e-3 of the row) fails. The states stay
away from the tension-only transition of the law (|EA eps| >> W), where the forward difference itself
is wrong by up to 5 % (its step moves the law argument by ~5 N of the W = 48 N transition width).
"""

from dataclasses import replace

import numpy as np
import pytest
from scipy.sparse import csr_matrix

from benchmarks.ropos_case import ropos_config
from tether_sim.solvers.hybrid.assembly import assemble_jacobian
from tether_sim.solvers.hybrid.jac_env import external_force_jac
from tether_sim.solvers.hybrid.jacobian import assemble_band_jacobian
from tether_sim.solvers.hybrid.kernels import external_force
from tether_sim.solvers.hybrid.layout import HP_CCRIT, HP_CMT, HP_KD, HP_M, HP_MU, HP_SBZETA, HP_SEABED, HP_VMU, HP_ZG
from tether_sim.solvers.hybrid.newton_band import band_lu, band_solve
from tether_sim.solvers.hybrid.solver import HybridRodCatenarySolver


def _case(zoning):
    """ROPOS L = 200 m (EI* = 2620 N m^2) with the cage as a simulated body and a sheared current."""
    cfg = ropos_config(200.0, alpha=1.0, solver="hybrid", hybrid_segments=20, hybrid_dt=0.01)
    env = replace(cfg.environment, current_z=(-300.0, 0.0), current_x=(0.1, 0.6), current_y=(0.0, -0.2))
    return replace(cfg, environment=env, hybrid=replace(cfg.hybrid, zoning=zoning, static_relax_time=5.0))


def _arrays(s):
    ch = s.chain
    bodies = sorted((e for e in (0, 1) if ch.body_node[e] >= 0), key=lambda e: ch.body_node[e])
    nb = len(bodies)
    rn = np.ascontiguousarray(np.vstack([np.hstack([s.positions, s.rdot]), np.zeros((nb, 6))]))
    Yn = np.vstack([s.Y] + [s.body_x[e][None] for e in bodies])
    Ytn = np.vstack([s.Yt] + [s.body_xd[e][None] for e in bodies])
    Ln = np.ascontiguousarray(np.concatenate([s.Lf, np.repeat(np.eye(3)[None], nb, axis=0)]))
    return Yn, Ytn, Ln, rn


def _dense_pair(s, Y, Yn, Ytn, Ln, rn):
    ch = s.chain
    n = ch.n_unknowns
    P = s._parameters(s.opt.time_step)
    args = (Yn, Ytn, Ln, rn, ch.s, P, s.cz, s.cx, s.cy)
    rows, cols, vals = s._coo
    nnz = assemble_jacobian(ch.gkind, ch.ga, ch.gb, ch.grow, ch.gpar, ch.noff, ch.nslot, Y, *args, rows, cols, vals)
    Jfd = csr_matrix((vals[:nnz], (rows[:nnz], cols[:nnz])), shape=(n, n)).toarray()
    kl, ku = ch.kl, ch.ku
    ab = np.zeros((2 * kl + ku + 1, n))
    assemble_band_jacobian(ch.gkind, ch.ga, ch.gb, ch.grow, ch.gpar, ch.noff, ch.nslot, Y, *args, kl, ku, ab)
    i, j = np.nonzero(Jfd)
    assert np.all(i - j <= kl) and np.all(j - i <= ku), "forward-difference entry outside the band"
    Jan = np.zeros((n, n))
    for jj in range(n):
        lo, hi = max(0, jj - ku), min(n, jj + kl + 1)
        Jan[lo:hi, jj] = ab[kl + ku + np.arange(lo, hi) - jj, jj]
    return Jan, Jfd, ab


@pytest.mark.parametrize("zoning", ["all_catenary", "all_rod"])
def test_analytic_jacobian_matches_forward_differences(zoning):
    s = HybridRodCatenarySolver(_case(zoning))
    s.set_end_motion("ship", np.array([0.5, 0.2, -2.0]), np.array([0.5, 0.2, -1.0]))
    s.advance_to(0.3)  # moving, with added mass and drag in every cell
    Yn, Ytn, Ln, rn = _arrays(s)
    rng = np.random.default_rng(7)
    for trial in range(3):  # random states around the step's start (perturbed by 0.1 % of each value)
        Y = Yn * (1.0 + 1e-3 * rng.standard_normal(Yn.shape)) + 1e-4 * rng.standard_normal(Yn.shape)
        Jan, Jfd, _ = _dense_pair(s, Y, Yn, Ytn, Ln, rn)
        row = np.abs(Jan).max(axis=1)
        err = np.abs(Jan - Jfd).max(axis=1) / row
        assert err.max() < 2e-6, (trial, err.max(), int(err.argmax()))


def test_band_lu_solves_the_jacobian():
    """The profile-skipping banded LU with partial pivoting solves J x = b like a dense solve."""
    s = HybridRodCatenarySolver(_case("all_catenary"))
    Yn, Ytn, Ln, rn = _arrays(s)
    Jan, _, ab = _dense_pair(s, Yn.copy(), Yn, Ytn, Ln, rn)
    ch = s.chain
    n = ch.n_unknowns
    b = np.random.default_rng(3).standard_normal(n)
    x = b.copy()
    ipiv = np.empty(n, dtype=np.int64)
    assert band_lu(ab, n, ch.kl, ch.ku, ch.low, ch.last.copy(), ipiv) == 0
    band_solve(ab, n, ch.kl, ch.ku, ch.low, ipiv, x)
    ref = np.linalg.solve(Jan, b)
    # both are backward stable: agreement to cond(J) u (row-equilibrated cond ~ 1e7 here)
    assert np.abs(x - ref).max() <= 1e-6 * np.abs(ref).max()


def test_same_converged_steps_as_the_twin():
    """Taut ROPOS steps with a moving fairlead: the analytic and forward-difference Jacobians take
    different Newton iterates to the same solution; both stop at |dx| <= 1e-9 x scale, so the states
    agree to ~1e-9 relative (asserted 1e-7: the stop allows up to 1000 x the tolerance at round-off)."""
    out = []
    for jac in ("analytic", "finite_difference"):
        cfg = _case("adaptive")
        s = HybridRodCatenarySolver(replace(cfg, hybrid=replace(cfg.hybrid, jacobian=jac)))
        p0 = np.asarray(cfg.ship_end.position, dtype=float)
        for k in range(1, 11):
            t = 0.05 * k
            s.set_end_motion("ship", p0 + 0.5 * np.array([np.sin(t), 0.0, 1.0 - np.cos(t)]),
                             0.5 * np.array([np.cos(t), 0.0, np.sin(t)]))
            s.advance_to(t)
        assert s.end_forces().ship_tension > 1e4  # taut
        out.append((s.end_forces(), s.state()))
    (fa, sa), (fb, sb) = out
    assert abs(fa.ship_tension - fb.ship_tension) <= 1e-7 * fb.ship_tension
    assert abs(fa.vehicle_tension - fb.vehicle_tension) <= 1e-7 * fb.vehicle_tension
    assert np.abs(sa.position - sb.position).max() <= 1e-7 * 200.0
    assert np.abs(sa.tension - sb.tension).max() <= 1e-7 * np.abs(sb.tension).max()


def test_environment_force_derivatives_with_seabed_contact():
    """dF/dv, dF/dt, dF/da, dF/deps of the environment force (drag, added mass, sheared current, seabed
    spring, damping ramp and friction) against central differences (step 1e-6: error ~1e-12 relative
    truncation + 1e-10 round-off for |F| ~ 1e2 N; asserted 1e-6 of the largest entry). Penetrations are
    kept below 2 cm so that the contact force (K_g d delta) stays comparable to the other terms."""
    s = HybridRodCatenarySolver(_case("all_catenary"))
    P = s._parameters(0.01).copy()
    P[HP_SEABED], P[HP_ZG], P[HP_KD], P[HP_SBZETA], P[HP_MU], P[HP_VMU] = 1.0, -100.0, 9e3, 0.5, 0.3, 0.05
    P[HP_CCRIT] = 2.0 * np.sqrt(P[HP_KD] * P[HP_M])
    P[HP_CMT] = 0.2
    cz, cx, cy = np.array([-300.0, -50.0, 0.0]), np.array([0.1, 0.5, 1.0]), np.array([0.0, 0.2, -0.3])
    rng = np.random.default_rng(11)
    W = np.empty(130)
    for _ in range(40):
        v, t, a = rng.standard_normal(3), rng.standard_normal(3), rng.standard_normal(3)
        eps = rng.uniform(-0.01, 0.01)
        rn = np.concatenate([[0.0, 0.0, rng.uniform(-100.02, -99.9)], 0.1 * rng.standard_normal(3)])
        F, Jv, Jt, Ja, Je = np.empty(3), np.empty((3, 3)), np.empty((3, 3)), np.empty((3, 3)), np.empty(3)
        external_force_jac(v, t, a, rn, eps, P, cz, cx, cy, F, Jv, Jt, Ja, Je, W)
        F0 = np.empty(3)
        external_force(v, t, a, rn, eps, P, cz, cx, cy, F0)
        assert np.allclose(F, F0, rtol=1e-13, atol=1e-12)

        def f(x):
            out = np.empty(3)
            external_force(x[0:3], x[3:6], x[6:9], rn, x[9], P, cz, cx, cy, out)
            return out

        x0 = np.concatenate([v, t, a, [eps]])
        J = np.empty((3, 10))
        for j in range(10):
            e = np.zeros(10)
            e[j] = 1e-6
            J[:, j] = (f(x0 + e) - f(x0 - e)) / 2e-6
        ref = np.hstack([Jv, Jt, Ja, Je[:, None]])
        assert np.abs(ref - J).max() <= 1e-6 * np.abs(ref).max()


@pytest.mark.jit_off
@pytest.mark.parametrize("zoning", ["all_catenary", "all_rod", "mixed"])
def test_assembled_residual_is_the_group_residuals_bit_for_bit(zoning):
    """assemble_residual (cells from per-node terms shared by two cells, catenary cell, unit-tangent and law rows
    written straight from the node arrays) against group_residual of every group in turn, on a moving state
    perturbed off the step's start: equal to the last bit (the same operations on the same numbers). The mixed
    chain has a rod block inside catenary (both joint kinds), the cage as a body at the vehicle end."""
    from tether_sim.solvers.hybrid.assembly import GROUP_ROWS, assemble_residual, group_residual
    from tether_sim.solvers.hybrid.state_io import convert_state

    s = HybridRodCatenarySolver(_case("all_catenary" if zoning == "mixed" else zoning))
    if zoning == "mixed":
        zones = np.zeros_like(s.zones)
        zones[6:12] = 1
        s.Y, s.Yt, s.Lf, s.positions, s.rdot = convert_state(s, zones)
        s.zones = zones
        s._set_chain()
    s.set_end_motion("ship", np.array([0.5, 0.2, -2.0]), np.array([0.5, 0.2, -1.0]))
    s.advance_to(0.05)
    ch = s.chain
    kinds = set(ch.gkind.tolist())
    assert {0, 4, 12} <= kinds if zoning == "all_catenary" else True
    if zoning == "mixed":
        assert {2, 3} <= kinds  # both joints
    Yn, Ytn, Ln, rn = _arrays(s)
    P = s._parameters(s.opt.time_step)
    Y = Yn * (1.0 + 1e-3 * np.random.default_rng(2).standard_normal(Yn.shape))
    R = np.full(ch.n_unknowns, np.nan)
    assemble_residual(ch.gkind, ch.ga, ch.gb, ch.grow, ch.gpar, Y, Yn, Ytn, Ln, rn, ch.s, P, s.cz, s.cx, s.cy, R)
    ref = np.full(ch.n_unknowns, np.nan)
    out = np.empty(13)
    for g in range(ch.gkind.size):
        group_residual(ch.gkind[g], ch.ga[g], ch.gb[g], ch.gpar[g], Y, Yn, Ytn, Ln, rn, ch.s, P, s.cz, s.cx, s.cy, out)
        ref[ch.grow[g]:ch.grow[g] + GROUP_ROWS[ch.gkind[g]]] = out[:GROUP_ROWS[ch.gkind[g]]]
    assert np.all(np.isfinite(ref))
    assert np.array_equal(R, ref)
