"""Super-time-stepped axial damping (``dg.damping: rkl2``): the D step of the Strang splitting of
implicit_damping.py taken by the explicit second-order Runge-Kutta-Legendre method RKL2 instead of SDIRK2.

The axial damping term of PE2020 Eq. 22 with frozen geometry, f_d(v) = Pj AM Div[Z (i . G v) i + T_c i]
(implicit_damping.py), is parabolic: on the Sec. 6.2 mesh (L = 200 m, N = 20, P = 4, h = 10 m) its
spectrum is real, in [-rho, 0] with rho = 5.85e4 1/s (``benchmarks/probes/damping_rhs_gate.py``:
SSP-RK3's real-axis limit 2.51 times the step rule's damping rate 2.29e4 1/s), while the waves allow
dt = 1.06e-4 s: dt rho = 6.2, three times forward Euler's limit of 2. RKL2 (Meyer, Balsara & Aslam,
J. Comput. Phys. 257, 2014, Eq. 13-17) is an s-stage recursion of Legendre polynomials whose stability
polynomial R_s(z) = a_s + b_s P_s(1 + w1 z), w1 = 4 / (s^2 + s - 2), stays in [1 - 2 b_s, 1] for
z in [-(s^2 + s - 2) / 2, 0]: s evaluations of f_d stabilise s^2 / 2 times forward Euler's step, and R
never turns negative there (no ringing with alternating sign, the objection to the trapezoidal rule).
Second order, as the splitting needs. No matrix, no LU: per step the frozen geometry, clip set and
released ends of implicit_damping.py's step (so the same affine problem, integrated otherwise), then
s evaluations of f_d, one of them reusing the start's strain rates.

Steps and stages: m = ceil(hs rho_b / RKL_MAX_X) RKL2 steps of hs / m, each with the least s >= 2 with
(s^2 + s - 2) / 2 >= hs rho_b / m, rho_b = DP_RHO = RKL_SAFETY x SSP-RK3's
real-axis limit x max_e B_P (zeta / gamma0) / h_e^2 (the step rule's damping rate; timestep.py); Sec. 6.2 mesh:
m = 2, s = 3 for the merged steps, m = 1, s = 3 for the half steps. The
frozen operator's spectral radius is at most that of the taut straight cable (|i_j . i_m| <= 1, Z <= zeta,
a_n <= a_t); the probe measured it 1.8 % above the rule's estimate, so RKL_SAFETY = 1.25.
"""

import math

from tether_sim.numerics.jit import jit
from tether_sim.solvers.dg.damping_layout import DP_RHO, ID_NSTEPS, WD_F, WD_K1, WD_P, WD_Y, WP_E0, WP_X
from tether_sim.solvers.dg.damping_ops import (
    axial_tension_points, clip_set, damping_force, damping_geometry, end_damping_forces, release_ends, strain_rates,
    tension_divergence,
)

RKL_SAFETY = 1.25
# The step of the frozen problem is cut into m RKL2 steps with hs rho_b / m <= RKL_MAX_X: RKL2's error on the
# stiff modes (|R| ~ 0.5 where e^-z is ~0) moved the Sec. 6.2 snaps 2.56 ms at hs rho_b = 7.8 in one step, 0.5 ms
# at half of it (docs/dg_solver.md "RKL2 damping")
RKL_MAX_X = 4.0


@jit
def rkl2_stages(x):
    """The least s >= 2 with (s^2 + s - 2) / 2 >= x (x = hs rho: RKL2 stable on [-x, 0])."""
    s = 2
    while 0.5 * (s * s + s - 2) < x:
        s += 1
    return s


@jit
def rkl2_coefficients(s, j):
    """(mu_j, nu_j, mu~_j, gamma~_j) of RKL2 stage j >= 2 of s [Meyer et al. 2014, Eq. 16-17]: b_0 = b_1 = b_2
    = 1/3, b_j = (j^2 + j - 2) / (2 j (j + 1)), a_j = 1 - b_j, mu_j = (2j - 1)/j b_j / b_{j-1},
    nu_j = -(j - 1)/j b_j / b_{j-2}, mu~_j = mu_j w1, gamma~_j = -a_{j-1} mu~_j."""
    w1 = 4.0 / (s * s + s - 2)
    bj = _b(j)
    bj1 = _b(j - 1)
    mu = (2.0 * j - 1.0) / j * bj / bj1
    nu = -(j - 1.0) / j * bj / _b(j - 2)
    mt = mu * w1
    return mu, nu, mt, -(1.0 - bj1) * mt


@jit
def _b(j):
    if j <= 2:
        return 1.0 / 3.0
    return (j * j + j - 2.0) / (2.0 * j * (j + 1.0))


@jit
def rkl2_step(hs, U, vbc, idp, dprm, blk, bvec, V, Pj, Tr, tab_eps, tab_T, wp, wd, fdamp):
    """RKL2 step of size hs of dv/dt = f_d(v) (axial damping only, the frozen problem of implicit_damping.axial_step).

    Y_0 = v, Y_1 = Y_0 + mu~_1 hs f(Y_0), Y_j = mu_j Y_{j-1} + nu_j Y_{j-2} + (1 - mu_j - nu_j) Y_0
    + mu~_j hs f(Y_{j-1}) + gamma~_j hs f(Y_0), v <- Y_s. Y_{j-1} lives in U's velocity columns, Y_0 in WD_K1,
    Y_{j-2} in WD_Y, f(Y_0) in WD_P, f(Y_{j-1}) in WD_F. Taken as m steps of hs / m (RKL_MAX_X), all on the frozen
    problem of the start (geometry, clip set, released ends)."""
    N, nm = U.shape[0], U.shape[1]
    damping_geometry(U, V, idp, dprm, wp, tab_eps, tab_T)
    strain_rates(U, 3, True, vbc, blk, bvec, wp, WP_E0)
    clip_set(idp, dprm, wp, tab_eps, tab_T)
    release_ends(U, vbc, idp, dprm, bvec, Tr, wp, tab_eps, tab_T)
    m = max(1, int(math.ceil(hs * dprm[DP_RHO] / RKL_MAX_X)))  # RKL2 steps of hs / m
    hm = hs / m
    s = rkl2_stages(hm * dprm[DP_RHO])
    m1 = hm * 4.0 / (3.0 * (s * s + s - 2))  # hm mu~_1 = hm w1 b_1
    for sub in range(m):
        if sub == 0:  # f(Y_0) from the start's strain rates
            axial_tension_points(wp, WP_E0, True)
            tension_divergence(blk, Pj, bvec, idp, dprm, wp, wd, WD_P, True)
        else:
            damping_force(U, 3, True, vbc, idp, dprm, blk, bvec, Pj, wp, wd, WD_P)
        for e in range(N):
            for k in range(nm):
                for c in range(3):
                    y0 = U[e, k, 3 + c]
                    wd[e, k, WD_K1 + c] = y0
                    wd[e, k, WD_Y + c] = y0
                    U[e, k, 3 + c] = y0 + m1 * wd[e, k, WD_P + c]
        for j in range(2, s + 1):
            mu, nu, mt, gt = rkl2_coefficients(s, j)
            c0 = 1.0 - mu - nu
            mt *= hm
            gt *= hm
            damping_force(U, 3, True, vbc, idp, dprm, blk, bvec, Pj, wp, wd, WD_F)
            for e in range(N):
                for k in range(nm):
                    for c in range(3):
                        y = U[e, k, 3 + c]
                        U[e, k, 3 + c] = (mu * y + nu * wd[e, k, WD_Y + c] + c0 * wd[e, k, WD_K1 + c]
                                          + mt * wd[e, k, WD_F + c] + gt * wd[e, k, WD_P + c])
                        wd[e, k, WD_Y + c] = y
    idp[ID_NSTEPS] += 1
    strain_rates(U, 3, True, vbc, blk, bvec, wp, WP_X)  # the damping tension of the new state: end forces
    axial_tension_points(wp, WP_X, True)
    end_damping_forces(idp, dprm, bvec, U, Tr, wp, fdamp)


def rho_bound(h, P, zeta, gamma0):
    """DP_RHO: RKL_SAFETY x SSP-RK3's real-axis limit x the step rule's damping rate (1/s) on element sizes h."""
    from tether_sim.numerics.integrators import SSPRK3_REAL_LIMIT
    from tether_sim.solvers.dg.timestep import damping_rate

    return RKL_SAFETY * SSPRK3_REAL_LIMIT * damping_rate(h, P, zeta, gamma0)

