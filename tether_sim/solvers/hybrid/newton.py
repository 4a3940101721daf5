"""Newton helpers of the hybrid solver: backtracking line search and the per-unknown scales of the
stopping test. Mixed into HybridRodCatenarySolver (uses its chain, stats, options and end data)."""

import math

import numpy as np
from scipy.sparse import csr_matrix, diags
from scipy.sparse.linalg import splu

from tether_sim.solvers.hybrid import zoning
from tether_sim.solvers.hybrid.assembly import assemble_jacobian, assemble_residual
from tether_sim.solvers.hybrid.layout import CAT_T, CAT_V, ROD_F
from tether_sim.solvers.hybrid.newton_band import STAGNATION

LINE_SEARCH_HALVINGS = 6
MAX_TURN = 0.3  # rad, largest tangent change per Newton iteration


class _NewtonFailure(Exception):
    pass


class NewtonMixin:
    """Line search and unknown scales (see docs/hybrid_solver.md, 'Solving a step')."""

    def _newton_python(self, Y, Yn, Ytn, Ln, rn, P, scale, tangent_unknowns, n, bodies):
        """Newton iterations in Python with the forward-difference twin (hybrid.jacobian: finite_difference);
        the same algorithm as newton_band.newton_band, the factorisation kept across steps included. Returns the
        iteration count."""
        kept = self._fd_lu if self._factorisation_kept() else None
        self._fd_lu = None
        if kept is not None:
            Y0 = Y.copy()
            try:
                return self._newton_iterations(Y, Yn, Ytn, Ln, rn, P, scale, tangent_unknowns, n, bodies, kept)
            except _NewtonFailure:
                self.stats["kept_factorisation_failures"] = self.stats.get("kept_factorisation_failures", 0) + 1
                Y[...] = Y0
        return self._newton_iterations(Y, Yn, Ytn, Ln, rn, P, scale, tangent_unknowns, n, bodies, None)

    _fd_lu = None  # (solve, row scales) of the last step's factorisation

    def _newton_iterations(self, Y, Yn, Ytn, Ln, rn, P, scale, tangent_unknowns, n, bodies, kept):
        """newton_band._iterate in Python: starting with kept = (solve, row scales) if given, else a fresh Jacobian."""
        ch = self.chain
        R = np.empty(n)
        lin, rs = kept if kept is not None else (None, None)
        own = False
        res_prev = np.inf
        err_prev = np.inf
        args = (Yn, Ytn, Ln, rn, ch.s, P, self.cz, self.cx, self.cy)
        for it in range(1, self.opt.max_newton_iterations + 1):
            assemble_residual(ch.gkind, ch.ga, ch.gb, ch.grow, ch.gpar, Y, Yn, Ytn, Ln, rn, ch.s, P,
                              self.cz, self.cx, self.cy, R)
            if not np.all(np.isfinite(R)):
                raise _NewtonFailure("non-finite residual")
            # modified Newton: keep the factorised Jacobian while the scaled residual falls fast enough
            res = np.abs(rs * R).max() if lin is not None else np.inf
            fresh = lin is None or res > 0.1 * res_prev
            if fresh:
                lin, rs = self._factorise(Y, args, n, bodies)
                own = True
                self.stats["jacobians"] = self.stats.get("jacobians", 0) + 1
                res = np.abs(rs * R).max()
            res_prev = res
            dx = lin(rs * R)
            if not np.all(np.isfinite(dx)):
                raise _NewtonFailure("non-finite Newton update")
            # damping: a catenary tangent may turn at most MAX_TURN per iteration, so Newton cannot jump
            # to the mirror solution (T, t) -> (-T, -t) of the unit-tangent parameterisation
            turn = np.abs(dx[tangent_unknowns]).max(initial=0.0)
            lam = min(1.0, MAX_TURN / turn) if turn > 0.0 else 1.0
            if fresh:
                lam = self._line_search(Y, dx, lam, rs, R, args)
            Y[ch.idx_node, ch.idx_slot] -= lam * dx
            tol = self.opt.newton_tolerance
            err = float(np.max(np.abs(dx) / scale)) / tol
            # converged, or stagnating at round-off (with a Jacobian of this step): within 1000x of the tolerance
            # and STAGNATION of the scale
            if lam == 1.0 and (err <= 1.0 or (own and err <= 1e3 and err * tol <= STAGNATION and err >= 0.5 * err_prev)):
                break
            err_prev = err
        else:
            raise _NewtonFailure(f"no convergence in {self.opt.max_newton_iterations} iterations")
        self._fd_lu = (lin, rs)
        return it

    def _factorise(self, Y, args, n, bodies):
        """Forward-difference Jacobian at Y, row-equilibrated and factorised by SuperLU: (solve(b), row scales)."""
        ch = self.chain
        rows, cols, vals = self._coo
        nnz = assemble_jacobian(ch.gkind, ch.ga, ch.gb, ch.grow, ch.gpar, ch.noff, ch.nslot, Y, *args, rows, cols, vals)
        J = csr_matrix((vals[:nnz], (rows[:nnz], cols[:nnz])), shape=(n, n))
        rs = 1.0 / np.maximum(abs(J).max(axis=1).toarray().ravel(), 1e-300)
        try:
            lu = splu((diags(rs) @ J).tocsc(), permc_spec="NATURAL" if not bodies or bodies == [1] else "COLAMD")
        except RuntimeError as exc:
            raise _NewtonFailure(f"singular Jacobian ({exc})") from None
        return lu.solve, rs

    def _line_search(self, Y, dx, lam, rs, R, args):
        """Backtracking on the scaled residual norm (after a fresh Jacobian): halve the step while it
        raises |rs R|_2. Contact-like kinks (seabed onset, slack-taut switch of the law) otherwise make
        full Newton steps jump between the two sides of the kink without converging."""
        ch = self.chain
        f0 = float(np.dot(rs * R, rs * R))
        Rt = np.empty_like(R)
        Yt = Y.copy()
        for _ in range(LINE_SEARCH_HALVINGS):
            Yt[ch.idx_node, ch.idx_slot] = Y[ch.idx_node, ch.idx_slot] - lam * dx
            assemble_residual(ch.gkind, ch.ga, ch.gb, ch.grow, ch.gpar, Yt, *args, Rt)
            if np.all(np.isfinite(Rt)) and float(np.dot(rs * Rt, rs * Rt)) <= (1.0 - 1e-4 * lam) * f0:
                return lam
            lam *= 0.5
        self.stats["line_search_exhausted"] = self.stats.get("line_search_exhausted", 0) + 1
        return lam * 2.0 ** LINE_SEARCH_HALVINGS if f0 > 0.0 else lam

    def _unknown_scales(self, Y):
        """Per-unknown magnitude used by the Newton stopping test |dx| <= tol * scale: speed, tension,
        1, strain, speed/L, 1/L or L by slot (the category of each unknown is cached per chain)."""
        ch = self.chain
        cat = ch.kind != zoning.ROD
        K = cat.size
        Yc = np.asarray(Y)[:K]
        loads = max(float(np.linalg.norm(f)) for f, _ in self.end_load)
        tension = max(float(np.abs(np.where(cat, Yc[:, CAT_T], 0.0)).max()),
                      float(np.abs(Yc[~cat, ROD_F:ROD_F + 3]).max(initial=0.0)), self.net_weight * self.length, loads,
                      1e-12)
        speed = max(float(np.abs(Yc[:, CAT_V:CAT_V + 3]).max()),  # = ROD_V
                    1e-3 * math.sqrt(self.config.environment.g * self.length),
                    1e-3 * self.length / self.opt.time_step)
        eps = tension * self.ck if self.ck > 0.0 else 1.0
        L = self.length
        values = np.array([speed, tension, 1.0, eps, speed / L, 1.0 / L, L])
        category = getattr(ch, "scale_category", None)
        if category is None:
            c_cat = [0] * 3 + [1] + [2] * 3 + [3] + [2] * 5
            c_rod = [0] * 3 + [4] * 3 + [5] * 3 + [1] * 3 + [3]
            c_body = [6] * 3 + [2] * 4 + [0] * 3 + [4] * 3
            table = np.array([c_cat if k else c_rod for k in cat] + [c_body] * (ch.nslot.size - K), dtype=np.int64)
            category = ch.scale_category = table[ch.idx_node, ch.idx_slot]
        return values[category]
