"""Ring-shaped beam [PE2020 Sec. 4.1, Eq. 34-36, Fig. 1].

A beam (L = 2 pi, EA = 100 N, gamma0 = 10 kg/m, EI = 1 N m^2), clamped at s = 0 along +x, with an
end moment M_y at s = L, closes into the circle of radius EI/M = 1 m centred at (0, 0, -1)
(``references.ring_beam_shape``). Two computations:

- transient: M_y ramped smoothly 0 -> 1 N m over 500 s (driven through ``set_end_load`` every
  ``update`` seconds), snapshots every 100 s (Fig. 1, lower left);
- static: the discrete fixed point for M_y = 1 (Newton on du/dt = 0, or dynamic relaxation with
  axial damping), whose Eq. 34 error over P = 1..5 and three meshes gives the convergence table
  (Eq. 36). Why not plain relaxation: docs/verification.md (ring beam) and ring_beam_analysis.py.

``python -m tether_sim.scenarios.ring_beam [--quick] [--out DIR]`` prints the table and writes
ring_beam.png.
"""

import argparse
import time

import numpy as np

from tether_sim.scenarios import harness
from tether_sim.scenarios import references as ref
from tether_sim.scenarios.ring_beam_analysis import discrete_equilibrium

NAME = "ring_beam"
MOMENT = 1.0  # N m, about +y
RAMP_TIME = 500.0
RELAX_TIME = 800.0  # s of dynamic relaxation for the static ring (24 decay times of RELAX_DAMPING / 2)
# Momentum damping rate of the relaxation, ~ 2 omega_1 with omega_1 = 1.875^2 sqrt(EI/(gamma0 L^4))
# = 0.028 rad/s (first cantilever mode of the straight beam): near-critical for the slowest mode.
RELAX_DAMPING = 0.06
# Axial material damping (N s) during relaxation only: the paper's model has a growing in-plane pair
# (Re up to +0.41 1/s at ~33 rad/s) on meshes that resolve k* = sqrt(EA/EI) = 10 1/m; zeta = 2 N s
# makes every in-plane mode decay (measured with ring_beam_analysis.linearised_spectrum). The
# static shape does not depend on zeta (the discrete fixed point moves by ~0.5 % of its error).
RELAX_ZETA = 2.0
# Meshes of the convergence table per order: three doublings each, all above round-off and, where
# the cost allows, in the asymptotic range (docs/verification.md).
TABLE_MESHES = {1: (64, 128, 256), 2: (16, 32, 64), 3: (16, 32, 64), 4: (8, 16, 32), 5: (4, 8, 16)}


def moment_ramp(t, ramp_time=RAMP_TIME, moment=MOMENT):
    """Smooth ramp M(t) = M (1 - cos(pi t / T)) / 2 for t < T, then M."""
    return moment * (0.5 * (1.0 - np.cos(np.pi * min(t, ramp_time) / ramp_time)))


def ring_error(solver, config, n_points=4001):
    """Eq. 34 error of the current shape against the analytic circle of radius EI/M."""
    s = np.linspace(0.0, config.cable.length, n_points)
    r = solver.state(s).position
    return ref.relative_l2_error(s, r, ref.ring_beam_shape(s, config.cable.EI / MOMENT))


def curvature_error(solver, config, n_points=4001):
    """RMS error of the LDG curvature |kappa| (Eq. 26) against 1/R = M/EI, relative to 1/R."""
    s = np.linspace(0.0, config.cable.length, n_points)
    k = solver.state(s).curvature
    k_exact = MOMENT / config.cable.EI
    return float(np.sqrt(np.trapezoid((k - k_exact) ** 2, s) / config.cable.length) / k_exact)


def run_transient(n_elements=8, order=4, t_end=600.0, update=1.0, snapshot_every=100.0, overrides=None):
    """Ramp the end moment and record snapshots; returns times, positions and the final error."""
    flat = {"dg.n_elements": n_elements, "dg.order": order}
    flat.update(overrides or {})
    config, solver = harness.load_scenario(NAME, flat)
    s = np.linspace(0.0, config.cable.length, 201)
    times = np.arange(update, t_end + 1e-9, update)
    snaps, snap_t = [], []

    def load(t):  # moment held over (t - update, t]: its value at mid-interval
        return {"vehicle": ((0.0, 0.0, 0.0), (0.0, moment_ramp(t - 0.5 * update), 0.0))}

    wall = time.perf_counter()
    for t in times:
        harness.run_sampled(solver, [t], load=load, keep=())
        if abs(t / snapshot_every - round(t / snapshot_every)) < 1e-9:
            snaps.append(solver.state(s).position.copy())
            snap_t.append(t)
    return {"t": np.array(snap_t), "positions": np.array(snaps), "s": s,
            "error": ring_error(solver, config), "wall": time.perf_counter() - wall}


def ring_solver(n_elements, order, overrides=None):
    """(config, solver) with the full end moment, started on the analytic ring (at rest)."""
    flat = {"dg.n_elements": n_elements, "dg.order": order, "vehicle_end.moment": [0.0, MOMENT, 0.0],
            "initial.kind": "straight"}
    flat.update(overrides or {})
    config, solver = harness.load_scenario(NAME, flat)
    R = config.cable.EI / MOMENT
    solver.set_shape(lambda s: np.stack([np.cos(s / R), 0.0 * s, -np.sin(s / R)], axis=1))
    return config, solver


def static_solution(n_elements, order, method="newton", relax_time=RELAX_TIME, overrides=None):
    """(config, solver) at the static ring for the end moment M_y = 1 N m.

    method "newton": the discrete fixed point du/dt = 0 of the DG scheme by Newton's method
    (ring_beam_analysis.discrete_equilibrium), from the analytic ring; "relax": dynamic relaxation
    from the straight beam with the momentum damping RELAX_DAMPING and the axial material damping
    RELAX_ZETA, which damps the flutter of the paper's model (docs/verification.md)."""
    if method == "newton":
        config, solver = ring_solver(n_elements, order, overrides)
        res, _ = discrete_equilibrium(solver)
        if not res < 1e-8:
            raise RuntimeError(f"ring beam N={n_elements} P={order}: Newton residual {res:.3g}")
        return config, solver
    flat = {"dg.n_elements": n_elements, "dg.order": order, "vehicle_end.moment": [0.0, MOMENT, 0.0],
            "initial.kind": "relax", "initial.relax_time": relax_time, "initial.relax_damping": RELAX_DAMPING,
            "cable.damping": RELAX_ZETA}
    flat.update(overrides or {})
    return harness.load_scenario(NAME, flat)


def static_error(n_elements, order, method="newton", **kw):
    """Eq. 34 error of the static ring (see static_solution)."""
    config, solver = static_solution(n_elements, order, method, **kw)
    return ring_error(solver, config)


def rates(errors):
    """Eq. 36 rates between successive doublings of N (n = N (P + 1) doubles too)."""
    return ref.convergence_rates(errors)


def paper_rate(order):
    """PE2020 Fig. 1: P + 1 for P = 1 and even P, P for odd P > 1."""
    return order + 1 if (order == 1 or order % 2 == 0) else order


def convergence_table(meshes=TABLE_MESHES, method="newton"):
    """{P: (meshes, position errors, curvature errors)} for the static ring."""
    table = {}
    for p, ns in meshes.items():
        pos, cur = [], []
        for n in ns:
            config, solver = static_solution(n, p, method)
            pos.append(ring_error(solver, config))
            cur.append(curvature_error(solver, config))
        table[p] = (tuple(ns), np.array(pos), np.array(cur))
    return table


def format_table(table):
    lines = ["| P | N | eps (Eq. 34) | rates (Eq. 36) | paper | curvature error | curvature rates |",
             "|---|---|---|---|---|---|---|"]
    for p, (ns, pos, cur) in table.items():
        lines.append(f"| {p} | {', '.join(map(str, ns))} | {', '.join(f'{x:.2e}' for x in pos)} | "
                     f"{', '.join(f'{x:.2f}' for x in rates(pos))} | {paper_rate(p)} | "
                     f"{', '.join(f'{x:.2e}' for x in cur)} | {', '.join(f'{x:.2f}' for x in rates(cur))} |")
    return "\n".join(lines)


def plot(transient, table, path):
    """Figure like PE2020 Fig. 1: errors vs degrees of freedom per P with the Eq. 36 rates, and the
    transient snapshots every 100 s (a side panel instead of the paper's inset)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, ax1) = plt.subplots(1, 2, figsize=(13, 5.6), gridspec_kw={"width_ratios": [1.45, 1]})
    for p, (ns, pos, cur) in table.items():
        n = np.array(ns) * (p + 1)
        line, = ax.loglog(n, pos, "o-", label=f"P = {p}: r (Eq. 34)")
        ax.loglog(n, cur, "s--", color=line.get_color(), lw=0.9, ms=3.5, label=f"P = {p}: curvature")
    ax.set_ylim(1e-11, 3.0)  # room for the rate table above the data
    ax.set_xlabel("degrees of freedom n = N (P + 1)")
    ax.set_ylabel("relative L2 error")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(loc="upper left", fontsize=7, ncol=2)
    ax.set_title("Ring beam: static convergence (discrete fixed point)")
    rows = [[str(p), "  ".join(f"{a:.2f}" for a in rates(pos)), "  ".join(f"{a:.2f}" for a in rates(cur)),
             str(paper_rate(p))] for p, (_, pos, cur) in table.items()]
    tab = ax.table(cellText=rows, colLabels=["P", "alpha r", "alpha curv.", "paper"], loc="upper right",
                   colWidths=[0.05, 0.15, 0.15, 0.07])
    tab.set_fontsize(8)
    th = np.linspace(0, 2 * np.pi, 400)
    ax1.plot(np.sin(th), -1 + np.cos(th), "k--", lw=1, label="circle R = EI/M")
    for t, r in zip(transient["t"], transient["positions"]):
        ax1.plot(r[:, 0], r[:, 2], lw=1.4, label=f"t = {t:.0f} s")
    ax1.set_aspect("equal")
    ax1.set_xlabel("x (m)")
    ax1.set_ylabel("z (m)")
    ax1.legend(fontsize=7, loc="lower right")
    ax1.set_title(f"M ramped 0 -> 1 N m over 500 s (N = {transient['N']}, P = {transient['P']})", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="P = 1, 2 on small meshes and a short transient")
    parser.add_argument("--method", choices=("newton", "relax"), default="newton")
    parser.add_argument("--transient-elements", type=int, default=8)
    parser.add_argument("--out", default=None, help="figure directory (default docs/figures)")
    args = parser.parse_args(argv)
    meshes = {1: (16, 32, 64), 2: (8, 16, 32)} if args.quick else TABLE_MESHES
    transient = run_transient(n_elements=args.transient_elements, t_end=200.0 if args.quick else 600.0)
    transient.update(N=args.transient_elements, P=4)
    print(f"transient (N={args.transient_elements}, P=4): Eq. 34 error at t_end {transient['error']:.3e}, "
          f"wall {transient['wall']:.1f} s", flush=True)
    table = convergence_table(meshes, args.method)
    print(format_table(table))
    path = harness.figure_dir(args.out) / "ring_beam.png"
    plot(transient, table, path)
    print(f"figure: {path}")
    return table


if __name__ == "__main__":
    main()
