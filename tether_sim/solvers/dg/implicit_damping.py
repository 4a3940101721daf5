"""Implicit treatment of the material damping terms of the DG cable (IMEX by Strang splitting).

The axial damping zeta deps/dt [PE2020 Eq. 22] and the bending damping zeta_b kappa-dot [Eq. 19]
are linear in the velocity once the geometry (tangent i, stretch l_eps) is frozen:

    dv/dt|_damp = f_d(v) = Pj AM Div[ Z (i . G v) i  +  (1/l) i x Tau( zeta_b i x Kdot(Pi G v) / l^2 ) ]

with G the DG derivative of v/gamma0 with central fluxes (the boundary velocity at velocity ends),
Pi = (I - i i^T)/l, Kdot and Tau the nested-LDG derivatives (beta-weighted fluxes, Table 1),
Div the strong derivative of the tension vector with the central part of the Lax-Friedrichs
flux, AM the per-point added-mass solve and Z = zeta where the law transmits tension (eps > 0 for
laws without compression, everywhere for the linear law). These are exactly the terms dg_rhs
adds when zeta, zeta_b > 0, so f_elastic(u; zeta = 0) + f_d(u) = f(u) (tested).

The stepper (stepper.py) alternates D(dt/2) E(dt) D(dt/2) with E the explicit SSP-RK3 of the
elastic part and D a step of dv/dt = f_d(v) (consecutive half steps merged). D is the 2-stage,
L-stable, stiffly accurate SDIRK2 (gamma = 1 - 1/sqrt 2): second order, and the unresolved stiff
damping modes are removed (|R(-inf)| = 0) instead of ringing as with the trapezoidal rule.

Two linear-algebra paths (docs/dg_solver.md):

* ``MODE_AXIAL`` (zeta_b = 0): Z (i . G v) is a scalar per Gauss point, so by Woodbury the system
  is solved for the strain rates e (N Q unknowns, block-pentadiagonal Q x Q blocks) instead of v
  (3 (P+1) N unknowns): (I - gamma h K) e = e_0, K = i^T G Pj AM Div Z i assembled analytically
  from precomputed geometry-free block operators.
* ``MODE_GENERAL`` (bending damping): the v-system with block bandwidth 4 elements, assembled by
  probing f_d with coloured unit vectors.

Both use a banded LU without pivoting (the matrix is I plus a dissipative operator times dt). The
strain-rate LU is reused across steps (refactored after LU_MAX_AGE steps; with dg.damping_correction a
defect correction with K applied matrix-free, refactored when the correction exceeds LU_TOL; one LU is
kept per step size and released ends, damping_update.select_lu). A change of Z at up to MAX_CHANGED points (the clip switching) is a change of as many
columns: carried by a low-rank update of the stored LU (damping_update.py) instead of a refactor.
Boundary conditions: velocity ends (prescribed, fixed, clamped, body) supply v_BC in G, their
damping tension flux is the interior trace (axially replaced by a constant when the end is
released, release_ends); force ends (free, force) carry no damping flux (the prescribed force is
the total); clamped ends have i_hat-dot = 0 and M*_hat = M*+. The no-compression clip of the
laws without compression is applied per step (clip_set).
"""

import numpy as np

from tether_sim.numerics.banded import band_factor, band_solve
from tether_sim.numerics.jit import jit
from tether_sim.physics.constitutive import LAW_LINEAR, cap_stiffness, compression_cap
from tether_sim.solvers.dg.damping_layout import (
    DP_AN, DP_AT, DP_EA, DP_G0, DP_LAMBDA, DP_LU_H, DP_RHO, DP_ZETA, DP_ZETAB, GAMMA_SDIRK, ID_KIND0, ID_KIND1, ID_KL, ID_LAW,
    ID_DEFECT, ID_EVERY, ID_LU_AGE, ID_MODE, ID_NCH, ID_NFACT, ID_NSTEPS, ID_NUPD, ID_NWHY, ID_PARK0, ID_REACH, ID_REL0, ID_RELF0,
    LU_INTS, LU_MAX_AGE, LU_SLOTS, LU_TOL, WHY_AGE, WHY_ENDS, WHY_POINTS, WHY_STEP, WHY_TOL,
    MAX_CHANGED, MODE_AXIAL, MODE_GENERAL, MODE_RKL2, N_DP, N_ID, NWD, NWP, OP_DIV, OP_GP, OP_H, WD_F, WD_K1, WD_P, WD_Y, WOOD_ROWS, WP_BC0, WP_E0, WP_E1, WP_E2, WP_I,
    WP_KX, WP_KY, WP_PC, WP_TC, WP_TV, WP_X, WP_Z, WP_ZF, DP_IP0, build_operators,
)
from tether_sim.solvers.dg.damping_ops import (
    axial_tension_points, clip_set, damping_force, damping_geometry, end_damping_forces, release_ends,
    strain_rates, tension_divergence,
)
from tether_sim.solvers.dg.damping_update import age_lus, select_lu, update_columns, update_solve
from tether_sim.solvers.dg.rkl_damping import rho_bound, rkl2_step


class DampingWork:
    """Arrays of the implicit damping step (allocated once; passed to the compiled loop)."""

    def __init__(self, mode, ops, h, kinds, cable, gamma0, m_t, m_n, beta, law_code, kind_codes, lam_bc, substeps=1,
                 correction=True):
        """substeps: SSP-RK3 substeps per damping step (MODE_AXIAL; stepper.dg_advance); correction: the defect
        correction of a stored LU's stage solves (_stage_solve)."""
        N, nq, nm = len(h), ops.vandermonde.shape[0], ops.vandermonde.shape[1]
        self.mode = mode
        self.blk, self.bvec = build_operators(ops, h, kinds, gamma0, beta)
        reach = 4 if cable.bending_damping > 0.0 else 2
        if mode == MODE_AXIAL:
            n, kl = N * nq, 3 * nq - 1
        elif mode == MODE_GENERAL:
            n, kl = N * 3 * nm, (reach + 1) * 3 * nm - 1
        else:
            n, kl = 1, 0
        kl = min(kl, n - 1)
        self.dprm = np.zeros(N_DP)
        self.dprm[DP_ZETA], self.dprm[DP_ZETAB], self.dprm[DP_G0] = cable.damping, cable.bending_damping, gamma0
        self.dprm[DP_AT], self.dprm[DP_AN] = gamma0 / (gamma0 + m_t), gamma0 / (gamma0 + m_n)
        self.dprm[DP_EA] = cable.EA
        self.dprm[DP_LAMBDA] = lam_bc
        if mode == MODE_RKL2:
            self.dprm[DP_RHO] = rho_bound(h, nm - 1, cable.damping, gamma0)
        self.idp = np.zeros(N_ID, dtype=np.int64)
        self.idp[ID_MODE], self.idp[ID_LAW] = mode, law_code
        self.idp[ID_KIND0], self.idp[ID_KIND1] = kind_codes
        self.idp[ID_REACH], self.idp[ID_KL] = reach, kl
        self.idp[ID_LU_AGE] = -1
        # macro steps of several substeps with bending or the linear law only: a law without compression and no
        # bending leaves the slack cable's element-scale folds to the damping alone, and there a damping step over
        # two substeps broke the slack phases of the PE2020 Sec. 6.2 case (docs/dg_solver.md "Implicit damping")
        smooth = law_code == LAW_LINEAR or cable.EI > 0.0
        self.idp[ID_EVERY] = substeps if mode == MODE_AXIAL and smooth else 1
        self.idp[ID_DEFECT] = int(correction)
        for s in range(LU_SLOTS - 1):  # no parked LU (its age)
            self.idp[ID_PARK0 + s * LU_INTS] = -1
        self.wp = np.zeros((N, nq, NWP))
        for e in range(N):  # (a winch, which would change h, is refused with implicit damping: winch_driver.py)
            self.wp[e, :, WP_PC] = compression_cap(law_code, cap_stiffness(cable), nm - 1, h[e])
        self.wd = np.zeros((N, nm, NWD))
        self.band = np.zeros((LU_SLOTS * n if mode == MODE_AXIAL else n, 2 * kl + 1))  # (the parked LUs below row n)
        self.vec = np.zeros((4, max(n, kl + 1)))
        self.tmp = np.zeros((2, N, 3, nq, nq))
        self.wood = np.zeros((LU_SLOTS * WOOD_ROWS, max(n, MAX_CHANGED)))
        self.fdamp = np.zeros((2, 4))


@jit
def _dot_i(wp, e, j, e2, j2):
    return (wp[e, j, WP_I] * wp[e2, j2, WP_I] + wp[e, j, WP_I + 1] * wp[e2, j2, WP_I + 1]
            + wp[e, j, WP_I + 2] * wp[e2, j2, WP_I + 2])


@jit
def assemble_axial(blk, bvec, idp, dprm, wp, gh, A, kl, tmp):
    """A = I - gh K with K = i^T G Pj AM Div Z i on the strain rates at the points (e, j):

        K = a_n (H o i_j . i_jj) Z_jj + (a_t - a_n) X Y,
        X[(e,j), (e1,m)] = GP[e,e1][j,m] i_j . i_m,   Y[(e1,m), (e2,jj)] = Div[e1,e2][m,jj] i_m . i_jj Z_jj

    (AM = a_n I + (a_t - a_n) i i^T; H = GP Div precomputed). tmp (2, N, 3, Q, Q) holds X and Y."""
    N, nq = wp.shape[0], wp.shape[1]
    at = dprm[DP_AT]
    an = dprm[DP_AN]
    aniso = at != an
    for r in range(N * nq):
        for c in range(A.shape[1]):
            A[r, c] = 0.0
    for e in range(N):
        for d in range(5):
            e2 = e + d - 2
            if e2 < 0 or e2 >= N:
                continue
            for j in range(nq):
                o = e2 * nq - (e * nq + j) + kl
                for jj in range(nq):
                    A[e * nq + j, o + jj] = -gh * an * _dot_i(wp, e, j, e2, jj) * blk[OP_H, e, d, j, jj] * wp[e2, jj, WP_Z]
        if aniso:
            for d in range(1, 4):
                e2 = e + d - 2
                if e2 < 0 or e2 >= N:
                    continue
                for j in range(nq):
                    for m in range(nq):
                        tmp[0, e, d - 1, j, m] = -gh * (at - an) * blk[OP_GP, e, d, j, m] * _dot_i(wp, e, j, e2, m)
                        tmp[1, e, d - 1, j, m] = blk[OP_DIV, e, d, j, m] * _dot_i(wp, e, j, e2, m) * wp[e2, m, WP_Z]
    if aniso:
        for e in range(N):
            for d1 in range(3):
                e1 = e + d1 - 1
                if e1 < 0 or e1 >= N:
                    continue
                for d2 in range(3):
                    e2 = e1 + d2 - 1
                    if e2 < 0 or e2 >= N:
                        continue
                    for j in range(nq):
                        r = e * nq + j
                        o = e2 * nq - r + kl
                        for m in range(nq):
                            x = tmp[0, e, d1, j, m]
                            if x != 0.0:
                                for jj in range(nq):
                                    A[r, o + jj] += x * tmp[1, e1, d2, m, jj]
    for end in range(2):
        if idp[ID_REL0 + end] != 0:
            release_correction(blk, bvec, dprm, wp, gh, A, kl, end)
    for r in range(N * nq):
        A[r, kl] += 1.0


@jit
def release_correction(blk, bvec, dprm, wp, gh, A, kl, end):
    """K of a released end: Div of the end element loses the axial part of the trace flux, a rank-one
    change; K += -GP[e, e_end] (i_j^T AM_m i+) (i+ . i_jj) bvec[end]_m bvec[2 + end]_jj Z_jj."""
    N, nq = wp.shape[0], wp.shape[1]
    at = dprm[DP_AT]
    an = dprm[DP_AN]
    ee = end * (N - 1)
    for e in range(max(0, ee - 1), min(N, ee + 2)):
        d = ee - e + 2
        for j in range(nq):
            r = e * nq + j
            o = ee * nq - r + kl
            for jj in range(nq):
                p0 = dprm[DP_IP0 + 3 * end]
                p1 = dprm[DP_IP0 + 3 * end + 1]
                p2 = dprm[DP_IP0 + 3 * end + 2]
                zt = wp[ee, jj, WP_Z] * bvec[2 + end, jj] * (
                    p0 * wp[ee, jj, WP_I] + p1 * wp[ee, jj, WP_I + 1] + p2 * wp[ee, jj, WP_I + 2])
                if zt == 0.0:
                    continue
                dj = wp[e, j, WP_I] * p0 + wp[e, j, WP_I + 1] * p1 + wp[e, j, WP_I + 2] * p2
                s = 0.0
                for m in range(nq):
                    gb = blk[OP_GP, e, d, j, m] * bvec[end, m]
                    mp = wp[ee, m, WP_I] * p0 + wp[ee, m, WP_I + 1] * p1 + wp[ee, m, WP_I + 2] * p2
                    s += gb * (an * dj + (at - an) * _dot_i(wp, e, j, ee, m) * mp)
                A[r, o + jj] += gh * s * zt


@jit
def axial_step(hs, U, vbc, idp, dprm, blk, bvec, V, Pj, Tr, tab_eps, tab_T, wp, wd, band, vec, tmp, wood, fdamp):
    """SDIRK2 step of size hs of dv/dt = f_d(v) = C (Z e(v) + T_c) (axial damping only), solved for
    the strain rates e at the points (see module doc; T_c: clip_set)."""
    N, nq = wp.shape[0], wp.shape[1]
    nm = U.shape[1]
    kl = idp[ID_KL]
    g = GAMMA_SDIRK
    damping_geometry(U, V, idp, dprm, wp, tab_eps, tab_T)
    strain_rates(U, 3, True, vbc, blk, bvec, wp, WP_E0)
    nclip = clip_set(idp, dprm, wp, tab_eps, tab_T)
    nclip += release_ends(U, vbc, idp, dprm, bvec, Tr, wp, tab_eps, tab_T)
    if nclip > 0:  # strain rate per unit time of the constant force: B c0 (WP_BC0)
        for e in range(N):
            for j in range(nq):
                for c in range(3):
                    wp[e, j, WP_TV + c] = wp[e, j, WP_TC] * wp[e, j, WP_I + c]
        tension_divergence(blk, Pj, bvec, idp, dprm, wp, wd, WD_P, True)
        strain_rates(wd, WD_P, False, vbc, blk, bvec, wp, WP_BC0)
    else:
        for e in range(N):
            for j in range(nq):
                wp[e, j, WP_BC0] = 0.0
    gh = g * hs
    select_lu(idp, dprm, wp, band, wood, gh)  # the LU kept for this step size and released ends, if any
    why = _lu_invalid(idp, dprm, gh)
    if why < 0 and not update_columns(gh, Pj, vbc, idp, dprm, blk, bvec, wp, wd, band, kl, wood):
        why = WHY_POINTS
    exact = why >= 0
    if exact:
        idp[ID_NWHY + why] += 1
        _refactor(blk, bvec, idp, dprm, wp, gh, band, kl, tmp, vec)
    _rhs_stage1(wp, gh, vec)
    if not _stage_solve(0, exact, gh, Pj, vbc, idp, dprm, blk, bvec, wp, wd, band, kl, vec, wood):
        exact = True
        idp[ID_NWHY + WHY_TOL] += 1
        _refactor(blk, bvec, idp, dprm, wp, gh, band, kl, tmp, vec)
        _rhs_stage1(wp, gh, vec)
        _stage_solve(0, True, gh, Pj, vbc, idp, dprm, blk, bvec, wp, wd, band, kl, vec, wood)
    for e in range(N):
        for j in range(nq):
            wp[e, j, WP_E1] = vec[0, e * nq + j]
    _rhs_stage2(wp, hs, g, vec)
    if not _stage_solve(1, exact, gh, Pj, vbc, idp, dprm, blk, bvec, wp, wd, band, kl, vec, wood):
        exact = True
        idp[ID_NWHY + WHY_TOL] += 1
        _refactor(blk, bvec, idp, dprm, wp, gh, band, kl, tmp, vec)
        _rhs_stage2(wp, hs, g, vec)
        _stage_solve(1, True, gh, Pj, vbc, idp, dprm, blk, bvec, wp, wd, band, kl, vec, wood)
    age_lus(idp)
    idp[ID_NSTEPS] += 1
    if exact:
        idp[ID_NFACT] += 1
    elif idp[ID_NCH] > 0:
        idp[ID_NUPD] += 1
    for e in range(N):
        for j in range(nq):
            wp[e, j, WP_E2] = vec[1, e * nq + j]
            wp[e, j, WP_X] = (1.0 - g) * wp[e, j, WP_E1] + g * wp[e, j, WP_E2]
    axial_tension_points(wp, WP_X, True)
    tension_divergence(blk, Pj, bvec, idp, dprm, wp, wd, WD_F, True)
    for e in range(N):
        for k in range(nm):
            for c in range(3):
                U[e, k, 3 + c] += hs * wd[e, k, WD_F + c]
    axial_tension_points(wp, WP_E2, True)  # stiffly accurate: E2 is the strain rate of the new state
    end_damping_forces(idp, dprm, bvec, U, Tr, wp, fdamp)


@jit
def _lu_invalid(idp, dprm, gh):
    """-1 if the stored LU was built for this step size and released ends, recently enough (a changed
    active set is the low-rank update's: damping_update.update_columns), else why not (WHY_*)."""
    if idp[ID_LU_AGE] < 0 or dprm[DP_LU_H] != gh:
        return WHY_STEP
    if idp[ID_REL0] != idp[ID_RELF0] or idp[ID_REL0 + 1] != idp[ID_RELF0 + 1]:
        return WHY_ENDS
    if idp[ID_LU_AGE] >= LU_MAX_AGE:
        return WHY_AGE
    return -1


@jit
def _refactor(blk, bvec, idp, dprm, wp, gh, band, kl, tmp, vec):
    """Assemble and factor I - gh K for the present geometry; remember what it was built for."""
    N, nq = wp.shape[0], wp.shape[1]
    assemble_axial(blk, bvec, idp, dprm, wp, gh, band, kl, tmp)
    band_factor(band, N * nq, kl, vec[2])
    dprm[DP_LU_H] = gh
    idp[ID_RELF0] = idp[ID_REL0]
    idp[ID_RELF0 + 1] = idp[ID_REL0 + 1]
    idp[ID_LU_AGE] = 0
    idp[ID_NCH] = 0
    for e in range(N):
        for j in range(nq):
            wp[e, j, WP_ZF] = wp[e, j, WP_Z]


@jit
def _rhs_stage1(wp, gh, vec):
    N, nq = wp.shape[0], wp.shape[1]
    for e in range(N):
        for j in range(nq):
            vec[0, e * nq + j] = wp[e, j, WP_E0] + gh * wp[e, j, WP_BC0]


@jit
def _rhs_stage2(wp, hs, g, vec):
    N, nq = wp.shape[0], wp.shape[1]
    c1 = (1.0 - g) / g
    for e in range(N):
        for j in range(nq):
            e0 = wp[e, j, WP_E0]
            bc0 = wp[e, j, WP_BC0]
            vec[1, e * nq + j] = e0 + hs * bc0 + c1 * (wp[e, j, WP_E1] - e0 - g * hs * bc0)


@jit
def _stage_solve(col, exact, gh, Pj, vbc, idp, dprm, blk, bvec, wp, wd, band, kl, vec, wood):
    """vec[col]: right-hand side -> solution of (I - gh K) x = rhs with the stored LU (and its low-rank
    update). If that LU is not exact for the present geometry and the defect correction is on (idp ID_DEFECT),
    one defect correction with K applied matrix-free (K x = i . G Pj AM Div(Z x i)); returns False when the
    correction exceeds LU_TOL of the solution."""
    N, nq = wp.shape[0], wp.shape[1]
    n = N * nq
    for r in range(n):
        vec[3, r] = vec[col, r]
    update_solve(band, n, kl, vec, col, wood, idp)
    if exact or idp[ID_DEFECT] == 0:
        return True
    for e in range(N):
        for j in range(nq):
            wp[e, j, WP_KX] = vec[col, e * nq + j]
    axial_tension_points(wp, WP_KX, False)
    tension_divergence(blk, Pj, bvec, idp, dprm, wp, wd, WD_P, False)
    strain_rates(wd, WD_P, False, vbc, blk, bvec, wp, WP_KY)
    for e in range(N):
        for j in range(nq):
            r = e * nq + j
            vec[3, r] = vec[3, r] - vec[col, r] + gh * wp[e, j, WP_KY]
    update_solve(band, n, kl, vec, 3, wood, idp)
    nd = 0.0
    nx = 0.0
    for r in range(n):
        vec[col, r] += vec[3, r]
        nd = max(nd, abs(vec[3, r]))
        nx = max(nx, abs(vec[col, r]))
    return nd <= LU_TOL * nx


@jit
def _gather_force(wd, vec, row, N, nm, b):
    """vec[row] = the damping force wd[..., WD_F:WD_F+3] in the banded system's (e, c, k) order."""
    for e in range(N):
        for c in range(3):
            for k in range(nm):
                vec[row, e * b + c * nm + k] = wd[e, k, WD_F + c]


@jit
def general_step(hs, U, vbc, idp, dprm, blk, bvec, V, Pj, Tr, tab_eps, tab_T, wp, wd, band, vec, fdamp):
    """SDIRK2 step of size hs of dv/dt = f_d(v) (axial and bending damping) on the v-system,
    its matrix built by probing f_d with unit vectors coloured every 2 reach + 1 elements."""
    N, nm = U.shape[0], U.shape[1]
    b = 3 * nm
    n = N * b
    kl = idp[ID_KL]
    reach = idp[ID_REACH]
    period = 2 * reach + 1
    g = GAMMA_SDIRK
    gh = g * hs
    damping_geometry(U, V, idp, dprm, wp, tab_eps, tab_T)
    strain_rates(U, 3, True, vbc, blk, bvec, wp, WP_E0)
    clip_set(idp, dprm, wp, tab_eps, tab_T)
    release_ends(U, vbc, idp, dprm, bvec, Tr, wp, tab_eps, tab_T)
    for r in range(band.shape[0]):
        for c in range(band.shape[1]):
            band[r, c] = 0.0
    for colour in range(min(period, N)):
        for c in range(3):
            for k in range(nm):
                for e in range(N):
                    for kk in range(nm):
                        for cc in range(3):
                            wd[e, kk, WD_P + cc] = 0.0
                for e in range(colour, N, period):
                    wd[e, k, WD_P + c] = 1.0
                damping_force(wd, WD_P, False, vbc, idp, dprm, blk, bvec, Pj, wp, wd, WD_F)
                for e in range(colour, N, period):
                    col = e * b + c * nm + k
                    for ee in range(max(0, e - reach), min(N, e + reach + 1)):
                        for cc in range(3):
                            for kk in range(nm):
                                row = ee * b + cc * nm + kk
                                band[row, col - row + kl] = -gh * wd[ee, kk, WD_F + cc]
    for r in range(n):
        band[r, kl] += 1.0
    band_factor(band, n, kl, vec[2])
    damping_force(U, 3, True, vbc, idp, dprm, blk, bvec, Pj, wp, wd, WD_F)
    _gather_force(wd, vec, 0, N, nm, b)
    band_solve(band, n, kl, vec, 0)
    for e in range(N):
        for c in range(3):
            for k in range(nm):
                k1 = vec[0, e * b + c * nm + k]
                wd[e, k, WD_K1 + c] = k1
                wd[e, k, WD_Y + c] = U[e, k, 3 + c] + (1.0 - g) * hs * k1
    damping_force(wd, WD_Y, True, vbc, idp, dprm, blk, bvec, Pj, wp, wd, WD_F)
    _gather_force(wd, vec, 1, N, nm, b)
    band_solve(band, n, kl, vec, 1)
    for e in range(N):
        for c in range(3):
            for k in range(nm):
                U[e, k, 3 + c] += hs * ((1.0 - g) * wd[e, k, WD_K1 + c] + g * vec[1, e * b + c * nm + k])
    damping_force(U, 3, True, vbc, idp, dprm, blk, bvec, Pj, wp, wd, WD_F)
    end_damping_forces(idp, dprm, bvec, U, Tr, wp, fdamp)


@jit
def damping_step(hs, U, vbc, idp, dprm, blk, bvec, V, Pj, Tr, tab_eps, tab_T, wp, wd, band, vec, tmp, wood, fdamp):
    """One step of size hs of the damping terms: implicit (MODE_AXIAL, MODE_GENERAL), RKL2 (MODE_RKL2,
    rkl_damping.py), nothing in explicit mode."""
    mode = idp[ID_MODE]
    if mode == MODE_AXIAL:
        axial_step(hs, U, vbc, idp, dprm, blk, bvec, V, Pj, Tr, tab_eps, tab_T, wp, wd, band, vec, tmp, wood, fdamp)
    elif mode == MODE_GENERAL:
        general_step(hs, U, vbc, idp, dprm, blk, bvec, V, Pj, Tr, tab_eps, tab_T, wp, wd, band, vec, fdamp)
    elif mode == MODE_RKL2:
        rkl2_step(hs, U, vbc, idp, dprm, blk, bvec, V, Pj, Tr, tab_eps, tab_T, wp, wd, fdamp)
