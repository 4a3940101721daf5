"""Discrete equilibrium and linearised spectrum of the DG cable solver (ring-beam analysis).

The static ring of PE2020 Sec. 4.1 is the fixed point du/dt = 0 of the semi-discrete DG scheme
[Eq. 23] with the end moment applied. Dynamic relaxation reaches it only when every mode decays,
and the paper's model does not guarantee that (see docs/verification.md, ring beam): about the
ring, the linearised operator has a growing in-plane pair where the axial and bending wave
branches cross (k* = sqrt(EA/EI)). So the convergence study solves du/dt = 0 directly by Newton's
method on the compiled right-hand side (the same discrete equations, no time stepping), and
``linearised_spectrum`` measures that instability.

DG-specific: the right-hand side is read through the solver's evaluation routine (``_evaluate``
fills ``_dU`` for the state ``U``), the only place outside the DG package that does so.
"""

import numpy as np

from tether_sim.solvers.dg import layout as Y


def rate(solver, U):
    """du/dt (same shape as U) of a DGCableSolver at its current time for the modal state U."""
    solver.ws.U[...] = U
    solver._evaluate()
    return solver.ws.dU.copy()


def jacobian(solver, U, step=1e-7):
    """Central finite-difference Jacobian d(du/dt)/dU (n x n, n = U.size) and du/dt at U."""
    n = U.size
    flat = U.ravel()
    J = np.empty((n, n))
    for k in range(n):
        up = flat.copy()
        um = flat.copy()
        up[k] += step
        um[k] -= step
        J[:, k] = ((rate(solver, up.reshape(U.shape)) - rate(solver, um.reshape(U.shape))) / (2.0 * step)).ravel()
    f = rate(solver, U)
    solver.ws.U[...] = U
    return J, f


def discrete_equilibrium(solver, tol=1e-12, floor=1e-8, max_iter=40):
    """Newton's method on du/dt = 0 from the solver's current state; the solver is left there.

    Chord variant: the finite-difference Jacobian is factorised once and refreshed only when an
    iteration reduces max |du/dt| by less than 10x. Returns (max |du/dt| at the solution, number of
    iterations). Stops at ``tol`` or, below ``floor``, at the round-off floor (a step with a fresh
    Jacobian that does not halve the residual is rejected; above ``floor`` it is taken).
    Started near the solution it needs 1-3 Jacobians."""
    from scipy.linalg import lu_factor, lu_solve

    U = solver.ws.U.copy()
    J, f = jacobian(solver, U)
    lu = lu_factor(J)
    fresh = True
    res = float(np.abs(f).max())
    it = 0
    for it in range(1, max_iter + 1):
        if res < tol:
            break
        step = lu_solve(lu, -f.ravel()).reshape(U.shape)
        f_new = rate(solver, U + step)
        new = float(np.abs(f_new).max())
        if new < 0.5 * res:  # accept; refresh the Jacobian when the contraction is slow
            U, f = U + step, f_new
            slow = new > 0.1 * res
            res, fresh = new, False
            if slow:
                J, f = jacobian(solver, U)
                lu, fresh = lu_factor(J), True
        elif fresh and res < floor:  # a fresh Jacobian does not halve a tiny residual: round-off
            break
        elif fresh:  # far from the solution: take the full Newton step anyway
            U, f, res = U + step, f_new, new
            J, f = jacobian(solver, U)
            lu = lu_factor(J)
        else:
            J, f = jacobian(solver, U)
            lu, fresh = lu_factor(J), True
    solver.ws.U[...] = U
    return res, it


def linearised_spectrum(solver, relax_damping=0.0):
    """Eigenvalues of the linearised DG operator about the current (planar, x-z) state, by plane.

    Returns (in_plane, out_of_plane): the eigenvalues of the Jacobian block of the channels q_x, q_z,
    v_x, v_z and of the block of q_y, v_y. About a state in the x-z plane the two blocks decouple
    (the coupling blocks vanish; checked, ValueError otherwise). ``relax_damping`` adds the
    relaxation's momentum damping rate (1/s), as during ``initial.kind = relax``."""
    U = solver.ws.U.copy()
    saved = solver.ws.prm[Y.P_RELAX]
    solver.ws.prm[Y.P_RELAX] = relax_damping
    try:
        J, _ = jacobian(solver, U)
    finally:
        solver.ws.prm[Y.P_RELAX] = saved
    channel = np.broadcast_to(np.arange(U.shape[2]), U.shape).ravel()
    out = (channel == 1) | (channel == 4)
    coupling = max(np.abs(J[np.ix_(out, ~out)]).max(), np.abs(J[np.ix_(~out, out)]).max())
    if coupling > 1e-6 * np.abs(J).max():
        raise ValueError(f"linearised_spectrum: state not planar (coupling {coupling:.3g})")
    return np.linalg.eigvals(J[np.ix_(~out, ~out)]), np.linalg.eigvals(J[np.ix_(out, out)])
