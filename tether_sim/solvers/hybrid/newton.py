"""Newton helpers of the hybrid solver: backtracking line search and the per-unknown scales of the
stopping test. Mixed into HybridRodCatenarySolver (uses its chain, stats, options and end data)."""

import math

import numpy as np

from tether_sim.solvers.hybrid import zoning
from tether_sim.solvers.hybrid.assembly import assemble_residual

LINE_SEARCH_HALVINGS = 6


class NewtonMixin:
    """Line search and unknown scales (see docs/hybrid_solver.md, 'Solving a step')."""

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
        tension = max(float(np.abs(np.where(cat, Yc[:, 3], 0.0)).max()),
                      float(np.abs(Yc[~cat, 9:12]).max(initial=0.0)), self.net_weight * self.length, loads, 1e-12)
        speed = max(float(np.abs(Yc[:, 0:3]).max()), 1e-3 * math.sqrt(self.config.environment.g * self.length),
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
