"""The discrete static equilibrium of a DG cable held at both ends (initial.kind = static).

The elastic catenary of physics/statics.py, L2-projected on the modes, is the continuous
equilibrium without bending; the DG semi-discretisation has its own, nearby equilibrium (with the
bending shear of the nested LDG, the projection of the non-polynomial tension and, with the q
penalty on, a small steady v that balances the penalty on the jumps of the tension). Started from
the projection, a stiff cable (EA/T ~ 1e4 and more) rings about it by a few 1e-4 of the tension
and, without material damping, keeps ringing. `polish_equilibrium` solves the discrete problem

    dU/dt (U) = 0,   with   sum_e h_e U[e, 0, q] = r(L) - r(0)   (the ends stay where they are)

by Newton from the projected catenary. The q rows of the mode-0 coefficients sum (weighted by h_e)
to v_hat(L) - v_hat(0) = 0 at held ends, so three of them are dependent: the last element's are
replaced by the end-position constraint. The Jacobian is taken by coloured forward differences of
the compiled right-hand side (an element couples with at most COUPLING elements on each side:
nested LDG fluxes, then the tension fluxes) and solved as a sparse system.
"""

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

DENSE_MAX = 2400  # unknowns (N (P+1) <= 400) solved densely
COUPLING = 4  # elements on each side an element's right-hand side depends on (bending: 3)


def _residual(solver):
    solver._evaluate()
    return solver.ws.dU.copy()


def _jacobian(solver, U0, R0, scale):
    """Sparse dR/dU by coloured forward differences (probe steps scale x 1e-7)."""
    N, nm, nc = U0.shape
    stride = 2 * COUPLING + 1
    rows, cols, vals = [], [], []
    idx = np.arange(N * nm * nc).reshape(N, nm, nc)
    for colour in range(min(stride, N)):
        els = np.arange(colour, N, stride)
        for l in range(nm):
            for c in range(nc):
                d = 1e-7 * scale[c]
                solver.ws.U[:] = U0
                solver.ws.U[els, l, c] += d
                dR = (_residual(solver) - R0) / d
                for e in els:
                    lo, hi = max(0, e - COUPLING), min(N, e + COUPLING + 1)
                    blk = dR[lo:hi]
                    nz = np.nonzero(blk)
                    rows.append(idx[lo:hi][nz])
                    cols.append(np.full(nz[0].size, idx[e, l, c]))
                    vals.append(blk[nz])
    solver.ws.U[:] = U0
    n = idx.size
    return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n)), idx


def _solve(J, rhs, col):
    """Newton update J dx = -rhs. The central-flux derivative of v can have null modes on coarse
    meshes (e.g. N = 3, P = 2) while the drag's derivative vanishes at v = 0, so J may be singular
    in v: the minimum-norm least-squares update (rows equilibrated, columns in units of `col`)
    leaves those modes at 0. Dense up to DENSE_MAX unknowns, else a sparse LU."""
    n = J.shape[0]
    if n > DENSE_MAX:
        return spla.spsolve(J.tocsc(), -rhs)
    A = J.toarray() * col[None, :]
    r = np.max(np.abs(A), axis=1)
    r[r == 0.0] = 1.0
    y = np.linalg.lstsq(A / r[:, None], -rhs / r, rcond=1e-11)[0]
    return y * col


def polish_equilibrium(solver, chord, max_iter=6, tol=1e-12):
    """Newton to the discrete equilibrium (module docstring); chord = r(L) - r(0) of the held ends.

    Returns the number of Newton iterations, or -1 (state left as projected) if it did not converge.
    """
    N = solver.N
    g0 = solver.config.cable.gamma0
    scale = np.array([1.0, 1.0, 1.0, g0, g0, g0])
    U_start = solver.ws.U.copy()
    h = solver.ws.h
    for it in range(max_iter + 1):
        U0 = solver.ws.U.copy()
        R0 = _residual(solver)
        con = np.sum(h[:, None] * U0[:, 0, 0:3], axis=0) - chord
        J, idx = _jacobian(solver, U0, R0, scale)
        rhs = R0.ravel().copy()
        J = J.tolil()
        for c in range(3):  # replace the dependent q rows by the position constraint
            r = idx[N - 1, 0, c]
            J.rows[r], J.data[r] = [], []
            for e in range(N):
                J[r, idx[e, 0, c]] = h[e]
            rhs[r] = con[c]
        dx = _solve(J.tocsr(), rhs, np.tile(scale, J.shape[0] // 6))
        if not np.all(np.isfinite(dx)):
            break
        solver.ws.U[:] = U0 + dx.reshape(U0.shape)
        if np.max(np.abs(dx.reshape(U0.shape)[:, :, 0:3])) < tol:
            solver._outputs_valid = False
            return it + 1
    solver.ws.U[:] = U_start
    solver._outputs_valid = False
    return -1
