"""Linear modes of a held arc about its discrete equilibrium, by q penalty.

The held arc of benchmarks/studies/hybrid_held_arc.py (L = 325 m, ends fixed at (0, 0, -50) and
(300, 0, -150), EI = 2620 N m^2, no material damping) with a stiff (EA = 455 MN) and a soft
(EA = 1 MN) cable. For each q-penalty variant (tension jump = default, Eq. 24 = strain, 0 = central
q flux) the Jacobian of the compiled DG right-hand side about the discrete static equilibrium
(dg/equilibrium.py, coloured differences) is diagonalised. Drag is quadratic in the velocity and
does not enter the linearisation about rest, so the real parts are the scheme's own dissipation
(Re < 0) or growth (Re > 0). Prints the largest Re, and the frequency and damping ratio
-Re/|lambda| of the lowest modes and of the mode nearest the first axial one (c / 2L).

    PYTHONPATH=. python benchmarks/studies/held_arc_modes.py [--n 10 --order 4] [--modes 6]
"""

import argparse
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from benchmarks.studies.hybrid_held_arc import held_arc_config  # noqa: E402
from tether_sim.solvers.dg.equilibrium import _jacobian, _residual  # noqa: E402
from tether_sim.solvers.dg.solver import DGCableSolver  # noqa: E402

VARIANTS = (("tension", 1.0, "tension jump (default)"), ("strain", 1.0, "Eq. 24 (old default)"),
            ("tension", 0.0, "central q flux"))


def spectrum(EA, n, order, form, qp):
    cfg = held_arc_config(solver="dg", ship_kind="fixed")
    cfg = replace(cfg, cable=replace(cfg.cable, EA=EA),
                  dg=replace(cfg.dg, n_elements=n, order=order, q_penalty_jump=form, q_penalty=qp))
    s = DGCableSolver(cfg)
    g0 = cfg.cable.gamma0
    U0 = s.ws.U.copy()
    J, _ = _jacobian(s, U0, _residual(s), np.array([1.0, 1.0, 1.0, g0, g0, g0]))
    lam = np.linalg.eigvals(J.toarray())
    return lam, s.equilibrium_iterations, s.stable_time_step()


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=10)
    ap.add_argument("--order", type=int, default=4)
    ap.add_argument("--modes", type=int, default=6)
    args = ap.parse_args(argv)
    for EA in (4.55e8, 1.0e6):
        for form, qp, label in VARIANTS:
            lam, it, dt = spectrum(EA, args.n, args.order, form, qp)
            osc = lam[np.abs(lam.imag) > 1e-6]
            osc = osc[osc.imag > 0]
            low = osc[np.argsort(np.abs(osc))][: args.modes]
            modes = ", ".join(f"{abs(z) / (2 * np.pi):.4f} Hz ({-z.real / abs(z):+.1e})" for z in low)
            fa = np.sqrt(EA / 3.01) / (2 * 325.0)  # first axial mode of a fixed-fixed string, c / 2L
            ax = osc[np.argmin(np.abs(np.abs(osc) / (2 * np.pi) - fa))]
            print(f"EA={EA:.3g} N N={args.n} P={args.order} {label}: Newton {it}, stable dt {dt:.4g} s, "
                  f"max Re {lam.real.max():+.3e} 1/s; lowest modes (f, damping ratio): {modes}; "
                  f"mode nearest c/2L = {fa:.3f} Hz: {abs(ax) / (2 * np.pi):.4f} Hz ({-ax.real / abs(ax):+.1e})", flush=True)


if __name__ == "__main__":
    main()
