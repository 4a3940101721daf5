"""Swinging cable of Koh et al. (1999) [PE2020 Sec. 5, Table 2, Fig. 3].

A rubber cable hangs in air between two pins 1.805 m apart at z = 0; at t = 0 the pin at s = L is
released and the cable swings about the pin at s = 0 (Table 1: pinned joint / free end). Three
material sets: EI = 0; EI with zeta_b = 0; EI with zeta_b (Table 2). The release is done through
the public interface: the s = L end is a ``force`` end held by its static reaction (the force the
fixed-fixed static solution exerts on the pin, reversed), set to zero at t = 0.

Outputs (Fig. 3): cable positions every 0.05 s for the first swing (t in [0, 1.25] s) and the
second (t in [1.25, 3] s); the pin force (axial tension at s = 0, every substep) vs time; and its
amplitude spectrum, with the longitudinal return period T_r = 2 L / c marked.

``python -m tether_sim.scenarios.swinging_cable [--elements N --order P] [--out DIR]``.
"""

import argparse
import time

import numpy as np

from tether_sim.scenarios import harness
from tether_sim.scenarios import references as ref

NAME = "koh_swinging_cable"
CASES = {  # label -> cable overrides (Table 2 values otherwise)
    "EI = 0": {"cable.EI": 0.0, "cable.bending_damping": 0.0},
    "EI, zeta_b = 0": {"cable.bending_damping": 0.0},
    "EI, zeta_b": {},
}


def released_solver(overrides):
    """Solver at rest in the static two-pin shape with the s = L end held by the pin's force.

    The force the pin exerts on the cable is T(L) of the closed-form elastic catenary between the
    pins (references.elastic_catenary); the solver's static initial state for a cable hanging
    from the s = 0 pin with that end load is the same catenary (bending is not part of the static
    shape, as in the paper, which starts every case from the same hanging cable).
    """
    base, _ = harness.load_scenario(NAME, {"vehicle_end.kind": "fixed", "initial.kind": "straight"}, build=False)
    cab, env = base.cable, base.environment
    span = np.asarray(base.vehicle_end.position, float) - np.asarray(base.ship_end.position, float)
    w = ref.submerged_weight(cab.gamma0, cab.density, env.fluid_density, env.g)
    cat = ref.elastic_catenary(cab.length, cab.EA, w, float(np.hypot(span[0], span[1])), float(span[2]))
    horiz = span[:2] / np.hypot(span[0], span[1])
    H, V = cat.tension_vector([cab.length])[0]
    reaction = np.array([H * horiz[0], H * horiz[1], V])
    flat = dict(overrides)
    flat.update({"vehicle_end.kind": "force", "vehicle_end.force": reaction.tolist(), "initial.kind": "static"})
    config, solver = harness.load_scenario(NAME, flat)
    return config, solver, reaction


def run_case(label, n_elements=10, order=4, t_end=3.0, frame_dt=0.05):
    overrides = dict(CASES[label])
    overrides.update({"dg.n_elements": n_elements, "dg.order": order})
    config, solver, reaction = released_solver(overrides)
    cab = config.cable
    s = np.linspace(0.0, cab.length, 41)
    start = solver.state(s).position.copy()
    wall = time.perf_counter()
    solver.set_end_load("vehicle", (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))  # t = 0: the pin is pulled
    res = harness.run_sampled(solver, np.arange(1, int(round(t_end / frame_dt)) + 1) * frame_dt,
                              arc_lengths=s, keep=("position",))
    t_sub, T_pin = res["sub_t"], res["sub_ship"]
    t_uniform = np.arange(0.0, t_end, 5e-4)
    force = np.interp(t_uniform, t_sub, T_pin)
    freq, amp = harness.amplitude_spectrum(t_uniform, force)
    return {"label": label, "s": s, "frames_t": np.concatenate([[0.0], res["t"]]),
            "frames": np.concatenate([start[None], res["position"]]), "t": t_uniform, "force": force,
            "freq": freq, "amp": amp, "reaction": reaction, "wall": time.perf_counter() - wall,
            "substeps": res["substeps"], "dt": solver.stable_time_step(),
            "T_r": ref.longitudinal_return_period(cab.length, cab.EA, cab.gamma0)}


def peak_near(result, t0=2.0, half_width=0.3):
    """Largest pin force in [t0 - w, t0 + w] (the snap as the cable straightens, Fig. 3c)."""
    sel = np.abs(result["t"] - t0) <= half_width
    return float(np.max(result["force"][sel]))


def band_amplitude(result, f_lo, f_hi):
    """Sum of spectral amplitudes of the pin force in [f_lo, f_hi] Hz."""
    sel = (result["freq"] >= f_lo) & (result["freq"] <= f_hi)
    return float(np.sum(result["amp"][sel]))


def summary(results):
    f_r = 1.0 / results[0]["T_r"]
    lines = [f"T_r = 2L/c = {results[0]['T_r']:.4f} s (f_r = {f_r:.2f} Hz)",
             "case | peak pin force t in [1.7, 2.3] s (N) | spectrum sum in [0.6, 1.4] f_r (N) | substep (s) | wall (s)",
             "-----|-------------------------------------|-----------------------------------|-------------|---------"]
    for r in results:
        lines.append(f"{r['label']} | {peak_near(r):.2f} | {band_amplitude(r, 0.6 * f_r, 1.4 * f_r):.3f} | "
                     f"{r['dt']:.2e} | {r['wall']:.1f}")
    return "\n".join(lines)


def plot(results, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    colors = ("tab:red", "tab:blue", "tab:green")
    fig = plt.figure(figsize=(12, 8))
    ax_a = fig.add_subplot(2, 2, 1)
    ax_b = fig.add_subplot(2, 2, 2)
    ax_c = fig.add_subplot(2, 2, 3)
    ax_d = fig.add_subplot(2, 2, 4)
    for r, col in zip(results, colors):
        for k, (t, frame) in enumerate(zip(r["frames_t"], r["frames"])):
            ax = ax_a if t <= 1.25 + 1e-9 else ax_b
            ax.plot(frame[:, 0], frame[:, 2], color=col, lw=0.7, alpha=0.7,
                    label=r["label"] if k == 0 or abs(t - 1.3) < 1e-9 else None)
        ax_c.plot(r["t"], r["force"], color=col, lw=0.8, label=r["label"])
        ax_d.semilogy(r["freq"], np.maximum(r["amp"], 1e-6), color=col, lw=0.8, label=r["label"])
    for ax, title in ((ax_a, "(a) first swing, t in [0, 1.25] s, every 0.05 s"), (ax_b, "(b) second swing, t in [1.25, 3] s")):
        ax.set_aspect("equal")
        ax.set_xlabel("x (m)")
        ax.set_ylabel("z (m)")
        ax.set_title(title, fontsize=10)
        ax.legend(fontsize=7)
    ax_c.set_xlabel("t (s)")
    ax_c.set_ylabel("pin force (axial tension at s = 0), N")
    ax_c.set_title("(c) pin force", fontsize=10)
    ax_c.legend(fontsize=7)
    f_r = 1.0 / results[0]["T_r"]
    ax_d.axvline(f_r, color="k", ls="--", lw=1, label="1 / T_r")
    ax_d.set_xlim(0, 3 * f_r)
    ax_d.set_ylim(1e-4, None)
    ax_d.set_xlabel("f (Hz)")
    ax_d.set_ylabel("amplitude (N)")
    ax_d.set_title("(d) spectrum of the pin force", fontsize=10)
    ax_d.legend(fontsize=7)
    fig.suptitle("Koh et al. swinging cable (PE2020 Fig. 3), DG/LDG")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--elements", type=int, default=10)
    parser.add_argument("--order", type=int, default=4)
    parser.add_argument("--t-end", type=float, default=3.0)
    parser.add_argument("--cases", nargs="+", default=list(CASES))
    parser.add_argument("--out", default=None, help="figure directory (default docs/figures)")
    args = parser.parse_args(argv)
    results = []
    for label in args.cases:
        results.append(run_case(label, args.elements, args.order, args.t_end))
        print(f"{label}: done in {results[-1]['wall']:.1f} s (substep {results[-1]['dt']:.2e} s)", flush=True)
    print(summary(results))
    path = harness.figure_dir(args.out) / f"koh_swinging_cable_N{args.elements}_P{args.order}.png"
    plot(results, path)
    print(f"figure: {path}")
    return results


if __name__ == "__main__":
    main()
