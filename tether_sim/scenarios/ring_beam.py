"""Ring-shaped beam [PE2020 Sec. 4.1, Eq. 34-36, Fig. 1].

A beam (L = 2 pi, EA = 100 N, gamma0 = 10 kg/m, EI = 1 N m^2), clamped at s = 0 along +x, with an
end moment M_y at s = L, closes into the circle of radius EI/M = 1 m centred at (0, 0, -1)
(``references.ring_beam_shape``). Two runs:

- transient: M_y ramped smoothly 0 -> 1 N m over 500 s (driven through ``set_end_load`` every
  ``update`` seconds), snapshots every 100 s (Fig. 1, lower left);
- static: the converged shape for M_y = 1 (dynamic relaxation, ``initial.kind = relax``), whose
  Eq. 34 error over P = 1..5 and three meshes gives the convergence table (Eq. 36).

``python -m tether_sim.scenarios.ring_beam [--quick] [--out DIR]`` prints the table and writes
ring_beam.png.
"""

import argparse
import time

import numpy as np

from tether_sim.scenarios import harness
from tether_sim.scenarios import references as ref

NAME = "ring_beam"
MOMENT = 1.0  # N m, about +y
RAMP_TIME = 500.0
RELAX_TIME = 800.0  # s of dynamic relaxation for the static ring (48 relax time constants)
# Momentum damping rate of the relaxation, ~ 2 omega_1 with omega_1 = 1.875^2 sqrt(EI/(gamma0 L^4))
# = 0.028 rad/s (first cantilever mode of the straight beam): near-critical for the slowest mode.
RELAX_DAMPING = 0.06


def moment_ramp(t, ramp_time=RAMP_TIME, moment=MOMENT):
    """Smooth ramp M(t) = M (1 - cos(pi t / T)) / 2 for t < T, then M."""
    return moment * (0.5 * (1.0 - np.cos(np.pi * min(t, ramp_time) / ramp_time)))


def ring_error(solver, config, n_points=2001):
    """Eq. 34 error of the current shape against the analytic circle of radius EI/M."""
    s = np.linspace(0.0, config.cable.length, n_points)
    r = solver.state(s).position
    return ref.relative_l2_error(s, r, ref.ring_beam_shape(s, config.cable.EI / MOMENT))


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


def static_error(n_elements, order, relax_time=RELAX_TIME, overrides=None):
    """Eq. 34 error of the relaxed static ring (moment 1 N m from the start, dynamic relaxation)."""
    from tether_sim.io.schema import key_map

    flat = {"dg.n_elements": n_elements, "dg.order": order,
            "vehicle_end.moment": [0.0, MOMENT, 0.0],
            "initial.kind": "relax", "initial.relax_time": relax_time}
    if "initial.relax_damping" in key_map():  # the solver's relaxation rate, when configurable
        flat["initial.relax_damping"] = RELAX_DAMPING
    flat.update(overrides or {})
    config, solver = harness.load_scenario(NAME, flat)
    return ring_error(solver, config)


def convergence_table(orders=(1, 2, 3, 4, 5), meshes=(4, 8, 16), **kw):
    """errors[P index, mesh index] and Eq. 36 rates[P index, pair index] (DOFs n = N (P + 1))."""
    errors = np.array([[static_error(n, p, **kw) for n in meshes] for p in orders])
    rates = np.array([ref.convergence_rates(e) for e in errors])
    return errors, rates


def format_table(orders, meshes, errors, rates):
    head = "| P | " + " | ".join(f"eps N={n}" for n in meshes) + " | " + " | ".join(
        f"alpha {a}->{b}" for a, b in zip(meshes[:-1], meshes[1:])) + " | paper |"
    lines = [head, "|" + "---|" * (2 + len(meshes) + len(meshes) - 1)]
    for p, e, r in zip(orders, errors, rates):
        expected = p + 1 if (p == 1 or p % 2 == 0) else p
        lines.append(f"| {p} | " + " | ".join(f"{x:.3e}" for x in e) + " | " + " | ".join(f"{x:.2f}" for x in r) + f" | {expected} |")
    return "\n".join(lines)


def plot(transient, orders, meshes, errors, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(11, 4.8))
    th = np.linspace(0, 2 * np.pi, 400)
    ax0.plot(np.sin(th), -1 + np.cos(th), "k--", lw=1, label="analytic circle R = EI/M")
    for t, r in zip(transient["t"], transient["positions"]):
        ax0.plot(r[:, 0], r[:, 2], lw=1.5, label=f"t = {t:.0f} s")
    ax0.set_aspect("equal")
    ax0.set_xlabel("x (m)")
    ax0.set_ylabel("z (m)")
    ax0.set_title("Ring beam: snapshots, M ramped 0->1 N m over 500 s")
    ax0.legend(fontsize=7, loc="upper right")
    for p, e in zip(orders, errors):
        n = np.array(meshes) * (p + 1)
        ax1.loglog(n, e, "o-", label=f"P = {p}")
    ax1.set_xlabel("degrees of freedom n = N (P + 1)")
    ax1.set_ylabel("relative L2 error (Eq. 34)")
    ax1.grid(True, which="both", alpha=0.3)
    ax1.legend()
    ax1.set_title("Static ring: convergence")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="P = 1, 2 on N = 4, 8, 16 and a short transient")
    parser.add_argument("--meshes", type=int, nargs="+", default=[4, 8, 16])
    parser.add_argument("--orders", type=int, nargs="+", default=[1, 2, 3, 4, 5])
    parser.add_argument("--relax-time", type=float, default=RELAX_TIME)
    parser.add_argument("--transient-elements", type=int, default=8)
    parser.add_argument("--out", default=None, help="figure directory (default docs/figures)")
    args = parser.parse_args(argv)
    orders = [1, 2] if args.quick else args.orders
    transient = run_transient(n_elements=args.transient_elements, t_end=200.0 if args.quick else 600.0)
    print(f"transient (N={args.transient_elements}, P=4): Eq. 34 error at t_end {transient['error']:.3e}, "
          f"wall {transient['wall']:.1f} s", flush=True)
    errors, rates = convergence_table(orders, args.meshes, relax_time=args.relax_time)
    print(format_table(orders, args.meshes, errors, rates))
    path = harness.figure_dir(args.out) / "ring_beam.png"
    plot(transient, orders, args.meshes, errors, path)
    print(f"figure: {path}")
    return errors, rates


if __name__ == "__main__":
    main()
