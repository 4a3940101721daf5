"""Prototype IMEX (additive Runge-Kutta) time integration of the DG cable (issue 14, gate study).

Not production code: a Python driver around the compiled right-hand side ``stepper.dg_evaluate``
(called, never modified), to measure how the first snap peak depends on the step before a compiled
integrator is built. The solver object only supplies its operators, parameters and work arrays.

Split (additive, on the full state y = (U, r_a, bodies)):

    f_E(y) = ( 0,  RHS_v(u; EA = zeta = lambda = 0),  dr_a/dt,  body derivatives )
    f_I(y) = ( RHS_q(u),  RHS_v(u) - RHS_v(u; EA = zeta = lambda = 0),  0,  0 )

RHS_v(u; EA = zeta = lambda = 0) is the momentum rate of the compiled right-hand side with the
axial stiffness, the axial damping and the Lax-Friedrichs speed (interior and ends) set to zero:
what is left is weight, buoyancy, drag, added mass and the LDG bending shear force (central
fluxes). f_I is the whole q equation dq/dt = d(v/gamma0)/ds with its penalty (the transport must
be implicit with the tension: an explicit q transport against an implicit tension is a
symplectic-Euler-like pair, stable only below the axial-wave CFL), the whole tension
T(eps, deps/dt) i (axial stiffness, axial damping and with it the geometric stiffness T/l of the
transverse string waves) and every Lax-Friedrichs penalty (interior jumps of q and v, upwind end
terms). Only the cable unknowns U
are implicit; r_a and the body states are explicit, so an implicit stage solves for U alone with
the bodies' stage values known. Bilinear and linear laws only (EA = 0 must remove the elastic
tension; a tabulated law would not).

Scheme: ARK3(2)4L[2]SA of Kennedy & Carpenter (2003): ESDIRK implicit part (L-stable, stiffly
accurate, gamma = 0.4358665215), 4-stage explicit part, third order, embedded second order,
shared weights b. ``ARS222`` (Ascher-Ruuth-Spiteri 1997, second order, L-stable) is kept for
comparison. The stage equation U_i = Z_i + dt a_ii f_I(U_i) is solved by a simplified Newton
iteration with the Jacobian J = d f_I / dU, formed by coloured finite differences of f_I (columns
of elements ``stride`` apart share a probe) and factored (scipy splu of I - dt a_ii J). J is
refreshed every ``refresh`` steps and, within a step, whenever the Newton iteration has not
converged after ``slow_after`` iterations (slack/taut switches change J by EA at a point).
"""

import math
import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from tether_sim.physics.constitutive import LAW_BILINEAR, LAW_LINEAR
from tether_sim.solvers.dg import layout as Y
from tether_sim.solvers.dg.stepper import dg_evaluate, fill_end_kinematics


class NewtonFailure(RuntimeError):
    """The stage equation of an implicit stage did not converge."""


class Tableau:
    """Additive Runge-Kutta tableau: explicit AE, implicit AI (ESDIRK), weights b, embedded bhat."""

    def __init__(self, name, AE, AI, b, bhat, order, emb_order):
        self.name = name
        self.AE, self.AI = np.asarray(AE, float), np.asarray(AI, float)
        self.b = np.asarray(b, float)
        self.bhat = None if bhat is None else np.asarray(bhat, float)
        self.c = self.AI.sum(axis=1)
        self.order, self.emb_order = order, emb_order
        self.s = self.b.size


def _ark3():
    g = 1767732205903.0 / 4055673282236.0
    b = [1471266399579.0 / 7840856788654.0, -4482444167858.0 / 7529755066697.0,
         11266239266428.0 / 11593286722821.0, g]
    bhat = [2756255671327.0 / 12835298489170.0, -10771552573575.0 / 22201958757719.0,
            9247589265047.0 / 10645013368117.0, 2193209047091.0 / 5459859503100.0]
    AE = [[0, 0, 0, 0],
          [2 * g, 0, 0, 0],
          [5535828885825.0 / 10492691773637.0, 788022342437.0 / 10882634858940.0, 0, 0],
          [6485989280629.0 / 16251701735622.0, -4246266847089.0 / 9704473918619.0,
           10755448449292.0 / 10357097424841.0, 0]]
    AI = [[0, 0, 0, 0],
          [g, g, 0, 0],
          [2746238789719.0 / 10658868560708.0, -640167445237.0 / 6845629431997.0, g, 0],
          [b[0], b[1], b[2], g]]
    return Tableau("ARK3(2)4L[2]SA", AE, AI, b, bhat, 3, 2)


def _ars222():
    g = 1.0 - 1.0 / math.sqrt(2.0)
    d = 1.0 - 1.0 / (2.0 * g)
    AE = [[0, 0, 0], [g, 0, 0], [d, 1 - d, 0]]
    AI = [[0, 0, 0], [0, g, 0], [0, 1 - g, g]]
    b = [0.0, 1 - g, g]
    bE = [d, 1 - d, 0.0]
    t = Tableau("ARS(2,2,2)", AE, AI, b, None, 2, None)
    t.bE = np.asarray(bE)
    return t


ARK3 = _ark3()
ARS222 = _ars222()


def order_conditions(tab):
    """Residuals of the classical and coupling order conditions up to order 3 (both parts share
    the abscissae c here). Returns a dict name -> residual."""
    bE = getattr(tab, "bE", tab.b)
    bI = tab.b
    cE, cI = tab.AE.sum(1), tab.AI.sum(1)
    out = {"c_E = c_I": np.abs(cE - cI).max()}
    for nb, bb in (("E", bE), ("I", bI)):
        out[f"sum b_{nb} = 1"] = bb.sum() - 1.0
        out[f"b_{nb} c = 1/2"] = bb @ cI - 0.5
        if tab.order >= 3:
            out[f"b_{nb} c^2 = 1/3"] = bb @ cI**2 - 1.0 / 3.0
            for na, A in (("E", tab.AE), ("I", tab.AI)):
                out[f"b_{nb} A_{na} c = 1/6"] = bb @ A @ cI - 1.0 / 6.0
    return out


class DGImex:
    """ARK IMEX stepper over a DGCableSolver's state (prototype; module docstring)."""

    def __init__(self, solver, dt, tableau=ARK3, refresh=20, stride=None, newton_tol=(1e-7, 1e-4),
                 max_newton=8, slow_after=3, loose=20.0, max_refresh=1, max_halvings=0):
        s = solver
        if s.iprm[Y.I_LAW] not in (LAW_LINEAR, LAW_BILINEAR):
            raise ValueError("imex prototype: linear or bilinear law only")
        if s.prm[Y.P_ZETAB] != 0.0:
            raise ValueError("imex prototype: no bending damping")
        self.s, self.dt, self.tab = s, float(dt), tableau
        self.refresh, self.max_newton, self.slow_after = int(refresh), int(max_newton), int(slow_after)
        self.max_refresh = int(max_refresh)
        self.max_halvings = int(max_halvings)
        self.loose = float(loose)  # accepted scaled update of a Newton iteration stalled on a kink
        self.prm, self.iprm = s.prm.copy(), s.iprm.copy()
        self.prmE, self.iprmE = s.prm.copy(), s.iprm.copy()
        for k in (Y.P_EA, Y.P_ZETA, Y.P_LAMBDA_BC, Y.P_LAMBDA_FLOOR):
            self.prmE[k] = 0.0
        self.iprmE[Y.I_AXDAMP] = 0
        self.shape = s.U.shape
        N, nm, nv = self.shape
        self.n = N * nm * nv
        self.nel = nm * nv
        self.stride = int(stride) if stride else 5  # dependency of f_I: elements e-2..e+2 (checked in tests)
        self.tol = np.zeros(self.shape)
        self.tol[..., 0:3] = newton_tol[0]
        self.tol[..., 3:6] = newton_tol[1] * s.prm[Y.P_GAMMA0]
        self.hfd = np.zeros(self.shape)
        self.hfd[..., 0:3] = 1e-7
        self.hfd[..., 3:6] = 1e-6 * s.prm[Y.P_GAMMA0]
        self._dU = np.zeros(self.shape)
        self._dra = np.zeros(3)
        self._dbs = np.zeros_like(s._dbs)
        self._endf = np.zeros_like(s._endf)
        self.lu = None
        self.lu_dt = None
        self.age = 0
        self.stats = {"rhs": 0, "jac": 0, "lu": 0, "solves": 0, "newton_fail": 0, "steps": 0, "max_iter": 0,
                      "rejected": 0, "min_dt": self.dt, "backtracks": 0, "loose": 0, "loose_max": 0.0,
                      "fallback": 0, "fallback_time": 0.0, "fallback_substeps": 0,
                      "t_rhs": 0.0, "t_jac": 0.0, "t_lu": 0.0, "t_solve": 0.0}
        self.err_log = []
        self.fail_elements = {}  # element of the largest Newton update when a stage failed
        self.verbose = False

    # ------------------------------------------------------------ right-hand sides
    def _eval(self, t, U, ra, bs, explicit_part):
        s = self.s
        prm, iprm = (self.prmE, self.iprmE) if explicit_part else (self.prm, self.iprm)
        c0 = time.perf_counter()
        dg_evaluate(t, U, ra, prm, iprm, s.h, s.V, s.Pj, s.D, s.Lf, s.Tr, s.Iq, s.law.tab_eps, s.law.tab_T, s.cz, s.cx,
                    s.cy, s.bc, s._vbc, s._wq, s._wm, s._tr, s._fl, s._rs, s._tmp, self._dU, self._dra, self._endf, bs,
                    s._bp, self._dbs, s._no_fdamp, False)
        self.stats["t_rhs"] += time.perf_counter() - c0
        self.stats["rhs"] += 1

    def split_rhs(self, t, U, ra, bs):
        """(fE_U, fI_U, dra, dbs, endf) at a state: two compiled right-hand sides."""
        self._eval(t, U, ra, bs, False)
        full = self._dU.copy()
        dra, dbs, endf = self._dra.copy(), self._dbs.copy(), self._endf.copy()
        self._eval(t, U, ra, bs, True)
        fE = self._dU.copy()
        fE[..., 0:3] = 0.0  # the whole q equation (transport + penalty) is implicit
        return fE, full - fE, dra, dbs, endf

    def f_implicit(self, t, U, ra, bs):
        return self.split_rhs(t, U, ra, bs)[1]

    # ------------------------------------------------------------ Jacobian of f_I
    def jacobian(self, t, U, ra, bs, f0=None):
        """d f_I / dU (sparse CSC, n x n) by coloured forward differences."""
        c0 = time.perf_counter()
        N, nm, nv = self.shape
        f0 = self.f_implicit(t, U, ra, bs) if f0 is None else f0
        w = (self.stride - 1) // 2
        rows, cols, vals = [], [], []
        Up = U.copy()
        for colour in range(self.stride):
            els = np.arange(colour, N, self.stride)
            for k in range(nm):
                for c in range(nv):
                    Up[...] = U
                    hh = self.hfd[0, k, c]
                    Up[els, k, c] += hh
                    df = (self.f_implicit(t, Up, ra, bs) - f0) / hh
                    for e in els:
                        lo, hi = max(0, e - w), min(N, e + w + 1)
                        blk = df[lo:hi].reshape(-1)
                        r = np.arange(lo * self.nel, hi * self.nel)
                        nz = blk != 0.0
                        rows.append(r[nz])
                        cols.append(np.full(nz.sum(), e * self.nel + k * nv + c))
                        vals.append(blk[nz])
        J = sp.csc_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(self.n, self.n))
        self.stats["jac"] += 1
        self.stats["t_jac"] += time.perf_counter() - c0
        return J

    def factor(self, J, ha):
        """LU of I - ha J (ha = dt a_ii), natural column order (band), partial pivoting."""
        c0 = time.perf_counter()
        M = sp.identity(self.n, format="csc") - ha * J
        self.lu = spla.splu(M.tocsc(), permc_spec="NATURAL")
        self.lu_dt = ha
        self.age = 0
        self.stats["lu"] += 1
        self.stats["t_lu"] += time.perf_counter() - c0

    def solve(self, r):
        c0 = time.perf_counter()
        x = self.lu.solve(r.reshape(-1)).reshape(self.shape)
        self.stats["solves"] += 1
        self.stats["t_solve"] += time.perf_counter() - c0
        return x

    # ------------------------------------------------------------ one ARK step
    def _newton_update(self, t, U, Z, ra, bs, ha):
        F = self.split_rhs(t, U, ra, bs)
        dU = self.solve(-(U - Z - ha * F[1]))
        size = np.max(np.abs(dU) / self.tol)
        return F, dU, size if np.isfinite(size) else np.inf

    def _stage_solve(self, t, Z, guess, ra, bs, ha):
        """U = Z + ha f_I(U) by a simplified Newton iteration with backtracking (natural monotonicity
        test on the scaled update: the tension law is only piecewise smooth -- slack, the damping
        clip and the no-compression clip of the end fluxes -- and undamped Newton can cycle across
        those kinks). Converged when the scaled update max |dU| / tol <= 1. The Jacobian is refreshed
        at the current iterate when the iteration is slow or stalls; an iteration that stalls even
        with a fresh Jacobian (it sits on a kink: the one-sided Jacobian overshoots) is accepted if
        its scaled update is <= ``loose`` (default 20: |dq| <= 2e-6, a tension change <= ~100 N on
        ROPOS), counted in stats "loose". Returns U, fE, fI, dra, dbs, endf at U; raises
        NewtonFailure (the caller halves the step)."""
        U = guess.copy()
        refreshes = 0
        F, dU, size = self._newton_update(t, U, Z, ra, bs, ha)
        for it in range(self.max_newton):
            if self.verbose:
                print(f"      newton t = {t:.6f} it {it} size {size:.3e} refreshes {refreshes}")
            if size <= 1.0:
                self.stats["max_iter"] = max(self.stats["max_iter"], it + 1)
                return (U,) + F
            lam = 1.0
            while True:
                Un = U + lam * dU
                Fn, dUn, sn = self._newton_update(t, Un, Z, ra, bs, ha)
                if sn <= (1.0 - 0.5 * lam) * size or lam < 0.1:
                    break
                lam *= 0.5
                self.stats["backtracks"] += 1
            stalled = sn > (1.0 - 0.5 * lam) * size
            if not stalled:
                U, F, dU, size = Un, Fn, dUn, sn
            # semismooth Newton: a fresh Jacobian at the iterate whenever the step had to be damped
            # (a kink was crossed) or the iteration is slow
            if (stalled or lam < 1.0 or it + 1 >= self.slow_after) and refreshes < self.max_refresh and size > 1.0:
                self.factor(self.jacobian(t, U, ra, bs, F[1]), ha)
                refreshes += 1
                F, dU, size = self._newton_update(t, U, Z, ra, bs, ha)
            elif stalled:
                if size <= self.loose:  # stalled on a kink, close enough: accept, counted
                    self.stats["loose"] += 1
                    self.stats["loose_max"] = max(self.stats["loose_max"], float(size))
                    return (U,) + F
                break
        self.stats["newton_fail"] += 1
        e = int(np.unravel_index(np.argmax(np.abs(dU) / self.tol), dU.shape)[0])
        self.fail_elements[e] = self.fail_elements.get(e, 0) + 1
        raise NewtonFailure(t)

    def _try_step(self, t, dt):
        s, tab = self.s, self.tab
        U0, ra0, bs0 = s.U.copy(), s.ra.copy(), s._bs.copy()
        ns = tab.s
        FE, FI, FR, FB = [None] * ns, [None] * ns, [None] * ns, [None] * ns
        ha = dt * tab.AI[1, 1]
        tension = None
        try:
            for i in range(ns):
                ti = t + tab.c[i] * dt
                ra = ra0 + dt * sum(tab.AE[i, j] * FR[j] for j in range(i)) if i else ra0
                bs = bs0 + dt * sum(tab.AE[i, j] * FB[j] for j in range(i)) if i else bs0.copy()
                Z = U0 + dt * sum(tab.AE[i, j] * FE[j] + tab.AI[i, j] * FI[j] for j in range(i)) if i else U0
                if tab.AI[i, i] == 0.0:
                    fE, fI, dra, dbs, endf = self.split_rhs(ti, Z, ra, bs)
                    if i == 0:
                        tension = (endf[0, Y.E_T], endf[1, Y.E_T])
                        if self.lu is None or self.age >= self.refresh or self.lu_dt != ha:
                            self.factor(self.jacobian(ti, U0, ra, bs, fI), ha)
                else:
                    guess = Z + ha * FI[i - 1]
                    _, fE, fI, dra, dbs, endf = self._stage_solve(ti, Z, guess, ra, bs, ha)
                FE[i], FI[i], FR[i], FB[i] = fE, fI, dra, dbs
        except NewtonFailure:
            s.U[...], s.ra[:], s._bs[...] = U0, ra0, bs0
            raise
        bE = getattr(tab, "bE", tab.b)
        s.U[...] = U0 + dt * sum(bE[j] * FE[j] + tab.b[j] * FI[j] for j in range(ns))
        s.ra[:] = ra0 + dt * sum(bE[j] * FR[j] for j in range(ns))
        s._bs[...] = bs0 + dt * sum(bE[j] * FB[j] for j in range(ns))
        if tab.bhat is not None:
            err = dt * sum((tab.b[j] - tab.bhat[j]) * (FE[j] + FI[j]) for j in range(ns))
            self.err_log.append((t, np.abs(err[..., 0:3]).max(), np.abs(err[..., 3:6]).max()))
        self._set_anchor(t + dt)
        self.age += 1
        self.stats["steps"] += 1
        if not np.all(np.isfinite(s.U)):
            raise FloatingPointError(f"IMEX state non-finite at t = {t + dt:.6g} s")
        return tension

    def step(self, t, dt=None, depth=0):
        """One ARK step from (t, solver state) to t + dt, in place; returns the end tensions at t.
        A step whose Newton iteration fails is redone as two half steps (counted in stats
        "rejected"), at most ``max_halvings`` times; below that the interval is integrated by the
        explicit solver itself (compiled SSP-RK3 at its stable step, ``explicit_fallback``,
        counted in stats "fallback" / "fallback_time")."""
        dt = self.dt if dt is None else dt
        try:
            return self._try_step(t, dt)
        except NewtonFailure:
            if depth >= self.max_halvings:
                return self.explicit_fallback(t, dt)
            self.stats["rejected"] += 1
            self.stats["min_dt"] = min(self.stats["min_dt"], 0.5 * dt)
            tension = self.step(t, 0.5 * dt, depth + 1)
            self.step(t + 0.5 * dt, 0.5 * dt, depth + 1)
            return tension

    def explicit_fallback(self, t, dt):
        """Integrate [t, t + dt] with the solver's own compiled explicit loop (SSP-RK3, explicit
        damping, its stable substep). The prescribed end follows the same cubic: the Hermite segment
        of the sub-interval with the tick's position and velocity at its ends is the same cubic."""
        s = self.s
        bc_saved = s.bc.copy()
        pv0, pv1 = np.zeros(6), np.zeros(6)
        from tether_sim.solvers.dg.kernels import hermite_end
        for e in range(2):
            if s.kinds[e] == "prescribed":
                hermite_end(bc_saved, e, t, pv0)
                hermite_end(bc_saved, e, t + dt, pv1)
                s._end_pos[e], s._end_vel[e] = pv0[0:3].copy(), pv0[3:6].copy()
                s.set_end_motion(("ship", "vehicle")[e], pv1[0:3].copy(), pv1[3:6].copy())
        s.time = t
        s.drain_end_tensions()
        n = s.advance_to(t + dt)
        tt, t0, t1 = s.drain_end_tensions()
        s.bc[...] = bc_saved
        self.stats["fallback"] += 1
        self.stats["fallback_time"] += dt
        self.stats["fallback_substeps"] += n
        self.lu = None  # the state moved: fresh Jacobian on the next IMEX step
        return (t0[0], t1[0]) if len(t0) else (np.nan, np.nan)

    def _set_anchor(self, t):
        s = self.s
        anchor = s.iprm[Y.I_ANCHOR]
        if s.kinds[anchor] in ("prescribed", "fixed", "clamped", "body"):
            fill_end_kinematics(s.bc, s.iprm, t, s._vbc, s._bs, s._bp)
            s.ra[:] = s._vbc[anchor, 0:3]


def set_hermite(solver, end, t0, t1, p0, v0, p1, v1):
    """Prescribed end on the cubic Hermite segment (t0, p0, v0) -> (t1, p1, v1), as advance_to does."""
    b = solver.bc[end]
    b[Y.B_T0], b[Y.B_T1] = t0, t1
    b[Y.B_P0:Y.B_P0 + 3], b[Y.B_V0:Y.B_V0 + 3] = p0, v0
    b[Y.B_P1:Y.B_P1 + 3], b[Y.B_V1:Y.B_V1 + 3] = p1, v1


def run_driven(solver, imex, duration, motion=None, rate=50.0, end=0, progress=None):
    """Drive the ship end like benchmarks/drive.py (targets at ``rate`` Hz, Hermite in between) and
    take IMEX steps; returns t, T_ship, T_vehicle at the start of every step (like
    drain_end_tensions) and the thread-CPU time."""
    dt = imex.dt
    n_sub = int(round(1.0 / (rate * dt)))
    if abs(n_sub * dt * rate - 1.0) > 1e-9:
        raise ValueError("the step must divide the tick")
    p, v = (solver._end_pos[end].copy(), solver._end_vel[end].copy())
    ts, ts0, ts1 = [], [], []
    c0 = time.thread_time()
    t = t_start = solver.time
    for k in range(int(round(duration * rate))):
        t1 = t_start + (k + 1) / rate
        if motion is not None:
            p1, v1 = motion(t1)
            set_hermite(solver, end, t1 - 1.0 / rate, t1, p, v, np.asarray(p1), np.asarray(v1))
            p, v = np.asarray(p1, float), np.asarray(v1, float)
        for j in range(n_sub):
            tt = t1 - 1.0 / rate + j * dt
            T = imex.step(tt)
            ts.append(tt)
            ts0.append(T[0])
            ts1.append(T[1])
        t = t1
        if progress and (k + 1) % int(rate) == 0:
            progress(t)
    solver.time = t
    solver._end_pos[end], solver._end_vel[end] = p, v
    return np.array(ts), np.array(ts0), np.array(ts1), time.thread_time() - c0


class DGRosW(DGImex):
    """Linearly implicit IMEX: the two-stage Rosenbrock-W method ROS2 of Verwer, Spee, Blom &
    Hundsdorfer (1999), gamma = 1 + 1/sqrt(2), with W = I - gamma dt J_I, J_I = d f_I / dU (the
    implicit part of the split above, frozen between refreshes), f the whole right-hand side:

        W k1 = f(t, y),    W k2 = f(t + dt, y + dt k1) - 2 k1,    y+ = y + dt (3/2 k1 + 1/2 k2)

    Second order for ANY matrix J (a W-method), L-stable for J = df/dy (R(-inf) = 0). With
    J = J_I the non-stiff part f_E is treated explicitly inside the same stages (no splitting);
    r_a and the body states have zero rows in J (explicit). No Newton iteration: the slack/taut,
    damping-clip and end-clip switches are in f (evaluated exactly at both stages), J sees them as
    at its last refresh. Cost per step: 2 right-hand sides + 2 banded solves (+ J, LU on refresh)."""

    GAMMA = 1.0 + 1.0 / math.sqrt(2.0)

    def __init__(self, solver, dt, refresh=1, **kw):
        super().__init__(solver, dt, refresh=refresh, **kw)
        self.tab = None

    def _full(self, t, U, ra, bs):
        self._eval(t, U, ra, bs, False)
        return self._dU.copy(), self._dra.copy(), self._dbs.copy(), self._endf.copy()

    def _try_step(self, t, dt):
        s = self.s
        U0, ra0, bs0 = s.U.copy(), s.ra.copy(), s._bs.copy()
        ha = self.GAMMA * dt
        f1, r1, b1, endf = self._full(t, U0, ra0, bs0)
        tension = (endf[0, Y.E_T], endf[1, Y.E_T])
        if self.lu is None or self.age >= self.refresh or self.lu_dt != ha:
            fI = self.f_implicit(t, U0, ra0, bs0)
            self.factor(self.jacobian(t, U0, ra0, bs0, fI), ha)
        k1 = self.solve(f1)
        f2, r2, b2, _ = self._full(t + dt, U0 + dt * k1, ra0 + dt * r1, bs0 + dt * b1)
        k2 = self.solve(f2 - 2.0 * k1)
        s.U[...] = U0 + dt * (1.5 * k1 + 0.5 * k2)
        s.ra[:] = ra0 + dt * (1.5 * r1 + 0.5 * (r2 - 2.0 * r1))
        s._bs[...] = bs0 + dt * (1.5 * b1 + 0.5 * (b2 - 2.0 * b1))
        self.err_log.append((t, np.abs(0.5 * dt * (k2 + k1))[..., 0:3].max(), np.abs(0.5 * dt * (k2 + k1))[..., 3:6].max()))
        self._set_anchor(t + dt)
        self.age += 1
        self.stats["steps"] += 1
        if not np.all(np.isfinite(s.U)):
            raise FloatingPointError(f"ROS2 state non-finite at t = {t + dt:.6g} s")
        return tension

    def step(self, t, dt=None, depth=0):
        return self._try_step(t, self.dt if dt is None else dt)
