"""A fairlead lifted out of the water: both solvers against the closed-form two-part catenary.

Cable L = 100 m, gamma0 = 2 kg/m, rho_c = 2000 kg/m^3 (weight in air twice the submerged weight), hanging
vertically with a free lower end from a fairlead that rises from 5 m below to 5 m above the still water
in 10 s (z = z_a + dz (x - sin(2 pi x) / 2 pi), x = t / 10 s), then holds. The top tension is compared
with the quasi-static closed form at the fairlead height (physics/statics.py, sharp interface); the
energy balance (fairlead work - static energy change = tangential drag dissipation on the wetted
length) is printed. The same case is test/solvers/dg/test_free_surface.py.

``python -m tether_sim.scenarios.free_surface [--out DIR]`` writes free_surface_lift.png (~1 min).
"""

import argparse

import numpy as np

from tether_sim.physics.statics import solve_static
from tether_sim.scenarios import harness

L, ZA, ZB, TR, T_END = 100.0, -5.0, 5.0, 10.0, 25.0
HRD_CDT = 0.5 * 1025.0 * 0.03 * 0.02


def flat(solver, z0, **extra):
    f = {"solver": solver, "dg.n_elements": 10, "dg.order": 4,
         "hybrid.n_segments": 40, "hybrid.time_step": 0.01, "hybrid.zoning": "all_catenary",
         "cable.length": L, "cable.EA": 2.0e5, "cable.gamma0": 2.0, "cable.density": 2000.0,
         "cable.diameter": 0.03, "cable.damping": 4000.0, "environment.free_surface": True,
         "ship_end.kind": "prescribed", "ship_end.position": [0.0, 0.0, z0],
         "vehicle_end.kind": "free", "vehicle_end.position": [0.0, 0.0, z0 - L], "initial.kind": "static"}
    if solver == "hybrid":
        f.update({"initial.kind": "relax", "initial.relax_time": 60.0, "hybrid.relax_time_step": 0.5})
    f.update(extra)
    return f


def lift(t):
    x = np.minimum(np.asarray(t, float) / TR, 1.0)
    z = ZA + (ZB - ZA) * (x - np.sin(2.0 * np.pi * x) / (2.0 * np.pi))
    v = np.where(np.asarray(t) < TR, (ZB - ZA) / TR * (1.0 - np.cos(2.0 * np.pi * x)), 0.0)
    return z, v


def run(solver):
    _, s = harness.make_solver(flat(solver, ZA))

    def motion(t):
        z, v = lift(t)
        return {"ship": ([0.0, 0.0, float(z)], [0.0, 0.0, float(v)])}

    return harness.run_sampled(s, np.arange(0.02, T_END + 1e-9, 0.02), motion=motion, keep=())


def quasi_static():
    zz = np.linspace(ZA, ZB, 81)
    return zz, np.array([np.linalg.norm(solve_static(harness.make_config(flat("dg", z))).T0) for z in zz])


def energy(t, T, zz, Tq):
    work = np.trapezoid(T * lift(t)[1], t)
    tt = np.linspace(0.0, TR, 20001)
    z, v = lift(tt)
    drag = np.trapezoid(HRD_CDT * np.abs(v) ** 3 * (L - np.maximum(z, 0.0)), tt)
    return work, np.trapezoid(Tq, zz), drag


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=None, help="figure directory (default docs/figures)")
    args = parser.parse_args(argv)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    zz, Tq = quasi_static()
    fig, ax = plt.subplots(2, 1, figsize=(8, 6.5), sharex=True, gridspec_kw={"height_ratios": [3, 1]})
    for solver, style in (("dg", "-"), ("hybrid", "-")):
        res = run(solver)
        t, T = res["t"], res["ship_tension"]
        if solver == "dg":
            t, T = res["sub_t"], res["sub_ship"]
        work, static, drag = energy(np.concatenate([[0.0], t]), np.concatenate([[T[0]], T]), zz, Tq)
        final = T[t > T_END - 3.0]
        print(f"{solver}: settled top tension {final.mean():.2f} N (closed form {Tq[-1]:.2f} N, "
              f"{final.mean() / Tq[-1] - 1:+.2e}); work {work:.1f} J, static energy change {static:.1f} J, "
              f"dissipated {work - static:.1f} J, tangential drag estimate {drag:.1f} J")
        ax[0].plot(t, T, style, lw=0.8, label=f"{solver} top tension" + (" (every substep)" if solver == "dg" else ""))
    tt = np.linspace(0.0, T_END, 2001)
    z, v = lift(tt)
    acc = np.where(tt < TR, (ZB - ZA) / TR * (2.0 * np.pi / TR) * np.sin(2.0 * np.pi * np.minimum(tt / TR, 1.0)), 0.0)
    Tqs = np.interp(z, zz, Tq)
    ax[0].plot(tt, Tqs, "k--", lw=1.0, label="quasi-static closed form at fairlead height")
    rigid = Tqs + 2.0 * L * acc + HRD_CDT * v * np.abs(v) * (L - np.maximum(z, 0.0))
    ax[0].plot(tt, rigid, "k:", lw=1.0, label="+ rigid-cable inertia gamma0 L a + tangential drag")
    ax[0].set_ylabel("top tension (N)")
    ax[0].legend(fontsize=8)
    ax[0].set_title("Fairlead lifted from 5 m below to 5 m above the water (L = 100 m, w_air = 2 w)")
    ax[1].plot(tt, lift(tt)[0])
    ax[1].axhline(0.0, color="0.6", lw=0.6)
    ax[1].set_ylabel("fairlead z (m)")
    ax[1].set_xlabel("t (s)")
    fig.tight_layout()
    path = harness.figure_dir(args.out) / "free_surface_lift.png"
    fig.savefig(path, dpi=90)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
