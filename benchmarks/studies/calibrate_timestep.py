"""Measure the SSP-RK3 stability limit of the linearised DG cable operator (docs/dg_solver.md).

For each order P and each mechanism (axial waves, axial damping, bending, bending damping) a straight
cable between two pins (no gravity, no fluid) is linearised by finite differences of the compiled
right-hand side; the largest dt with |R(dt lambda)| <= 1 for every eigenvalue lambda of the Jacobian
gives the coefficient of the corresponding term of solvers/dg/timestep.py. Run:

    PYTHONPATH=. python benchmarks/studies/calibrate_timestep.py
"""

import sys

import numpy as np

from tether_sim.config import SimConfig
from tether_sim.numerics.integrators import ssprk3_amplification
from tether_sim.physics.boundary import EndCondition
from tether_sim.physics.cable import CableProperties
from tether_sim.physics.environment import Environment
from tether_sim.solvers.config import DGOptions, InitialState
from tether_sim.solvers.dg.solver import DGCableSolver


def jacobian_eigs(solver):
    U = solver.ws.U.copy()
    n = U.size
    J = np.empty((n, n))
    eps = 1e-7
    for k in range(n):
        for sgn in (1, -1):
            solver.ws.U[...] = U
            solver.ws.U.reshape(-1)[k] += sgn * eps
            solver._evaluate()
            if sgn == 1:
                fp = solver.ws.dU.reshape(-1).copy()
            else:
                J[:, k] = (fp - solver.ws.dU.reshape(-1)) / (2 * eps)
    solver.ws.U[...] = U
    return np.linalg.eigvals(J)


def max_stable_dt(lam):
    lam = lam[np.abs(lam) > 1e-9 * np.max(np.abs(lam))]
    lo, hi = 0.0, 10.0 / np.max(np.abs(lam))
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if np.all(np.abs(ssprk3_amplification(mid * lam)) <= 1.0 + 1e-9):
            lo = mid
        else:
            hi = mid
    return lo


def make(P, N, EA, zeta, EI, zetab, strain=0.01):
    L = float(N)
    cab = CableProperties(length=L, EA=EA, gamma0=1.0, diameter=0.01, density=1000.0, EI=EI,
                          bending_damping=zetab, damping=zeta, material="linear", Cdn=0, Cdt=0, Cmn=0, Cmt=0)
    cfg = SimConfig(cable=cab, environment=Environment(g=0.0, fluid_density=0.0),
                    ship_end=EndCondition(kind="fixed", position=(0, 0, 0)),
                    vehicle_end=EndCondition(kind="fixed", position=(L * (1 + strain), 0, 0)),
                    dg=DGOptions(n_elements=N, order=P), initial=InitialState(kind="straight"))
    return DGCableSolver(cfg)


def main(orders=range(1, 13), N=4):
    rows = []
    for P in orders:
        h = 1.0
        s = make(P, N, 1.0, 0.0, 0.0, 0.0)
        A = h / max_stable_dt(jacobian_eigs(s))  # c = 1
        s = make(P, N, 1e-8, 1.0, 0.0, 0.0)
        B = h**2 / max_stable_dt(jacobian_eigs(s))  # zeta/gamma0 = 1
        s = make(P, N, 1e-8, 0.0, 1.0, 0.0)
        C = h**2 / max_stable_dt(jacobian_eigs(s))  # sqrt(EI/gamma0) = 1
        s = make(P, N, 1e-8, 0.0, 1e-12, 1.0)
        E = h**4 / max_stable_dt(jacobian_eigs(s))  # zeta_b/gamma0 = 1
        rows.append((P, A, B, C, E))
        print(f"P={P:2d}  A={A:10.4f}  B={B:12.4f}  C={C:12.4f}  E={E:14.4f}", flush=True)
    return rows


if __name__ == "__main__":
    main(range(1, int(sys.argv[1]) + 1) if len(sys.argv) > 1 else range(1, 13))
