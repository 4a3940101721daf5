"""Goyal & Perkins benchmark [GP Sec. 4, Fig. 5-8]: hybrid (joint at 1.5 m) vs pure rod, same solver.

Writes docs/figures/gp_benchmark.png and prints the rod-zone shear/moment differences, the Newton
iteration counts and the wall/CPU time of both runs, measured side by side.

    PYTHONPATH=. python benchmarks/bench_hybrid.py [--segments 400] [--out docs/figures]
"""

import argparse
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from tether_sim.scenarios.goyal_perkins import JOINT, goyal_perkins_config, run_to_rest  # noqa: E402
from tether_sim.solvers.hybrid.solver import HybridRodCatenarySolver  # noqa: E402
from tether_sim.solvers.hybrid.state_io import node_profile  # noqa: E402


def run(zoning, segments, t_max=100.0):
    """Relax one model to rest; returns (profile, wall s, cpu s, stats, final time)."""
    solver = HybridRodCatenarySolver(goyal_perkins_config(zoning=zoning, n_segments=segments))
    solver.advance_to(1.0)  # compile/warm up outside the timing
    w0, c0 = time.perf_counter(), time.process_time()
    run_to_rest(solver, t_max)
    wall, cpu = time.perf_counter() - w0, time.process_time() - c0
    return node_profile(solver), wall, cpu, dict(solver.stats), solver.time


def iteration_cost(zoning, segments, repeats=10):
    """CPU ms of one full Newton iteration (residual + FD Jacobian + sparse LU + solve) on the same state."""
    from scipy.sparse import csr_matrix, diags
    from scipy.sparse.linalg import splu

    from tether_sim.solvers.hybrid.assembly import assemble_jacobian, assemble_residual

    s = HybridRodCatenarySolver(goyal_perkins_config(zoning=zoning, n_segments=segments))
    s.advance_to(3.0)
    ch, P = s.chain, s._parameters(1.0)
    rn = np.ascontiguousarray(np.hstack([s.positions, s.rdot]))
    rows, cols, vals = s._coo
    n = ch.n_unknowns
    R = np.empty(n)
    args = (s.Y, s.Yt, s.Lf, rn, ch.s, P, s.cz, s.cx, s.cy)
    c0 = time.process_time()
    for _ in range(repeats):
        Y = s.Y.copy()
        assemble_residual(ch.gkind, ch.ga, ch.gb, ch.grow, ch.gpar, Y, *args, R)
        nnz = assemble_jacobian(ch.gkind, ch.ga, ch.gb, ch.grow, ch.gpar, ch.noff, ch.nslot, Y, *args, rows, cols, vals)
        J = csr_matrix((vals[:nnz], (rows[:nnz], cols[:nnz])), shape=(n, n))
        rs = 1.0 / abs(J).max(axis=1).toarray().ravel()
        splu((diags(rs) @ J).tocsc(), permc_spec="NATURAL").solve(rs * R)
    return 1e3 * (time.process_time() - c0) / repeats, n


def rod_zone_difference(hyb, rod, key):
    """Max |hybrid - rod| over s > joint, relative to the rod's max there."""
    s = np.linspace(JOINT + 1e-9, 2.0, 200)
    a = np.interp(s, hyb["s"], hyb[key])
    b = np.interp(s, rod["s"], rod[key])
    return float(np.abs(a - b).max() / np.abs(b).max())


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--segments", type=int, default=400)
    ap.add_argument("--out", default="docs/figures")
    args = ap.parse_args()
    hyb, wh, ch, sh, th = run("fixed", args.segments)
    rod, wr, cr, sr, tr = run("all_rod", args.segments)
    print(f"segments {args.segments}: hybrid wall {wh:.2f} s cpu {ch:.2f} s ({sh['steps']} steps, "
          f"{sh['newton_iterations']} Newton it., max {sh['max_iterations']}, halvings {sh['halvings']}, rest at {th:.0f} s)")
    print(f"                pure rod wall {wr:.2f} s cpu {cr:.2f} s ({sr['steps']} steps, "
          f"{sr['newton_iterations']} Newton it., max {sr['max_iterations']}, halvings {sr['halvings']}, rest at {tr:.0f} s)")
    ih, nh = iteration_cost("fixed", args.segments)
    ir, nr = iteration_cost("all_rod", args.segments)
    print(f"one Newton iteration with a new Jacobian: hybrid {ih:.1f} ms ({nh} unknowns), pure rod {ir:.1f} ms "
          f"({nr} unknowns): speed-up {ir / ih:.2f}x; CPU to rest: speed-up {cr / ch:.2f}x "
          f"(Jacobians: hybrid {sh.get('jacobians')}, rod {sr.get('jacobians')})")
    for key in ("tension", "shear", "moment"):
        print(f"rod zone {key}: max |hybrid - rod| / max rod = {100 * rod_zone_difference(hyb, rod, key):.2f} %")
    j = np.nonzero(np.diff(hyb["s"]) == 0)[0]
    if j.size:
        print(f"joint: T catenary {hyb['tension'][j[0]]:.6g} N, T rod {hyb['tension'][j[0] + 1]:.6g} N; "
              f"T(L) = {hyb['tension'][-1]:.3g} N")
    print(f"max sag: hybrid {-hyb['position'][:, 2].min():.4f} m, rod {-rod['position'][:, 2].min():.4f} m")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(2, 2, figsize=(11, 8))
    cat = hyb["zone"] == 0
    ax[0, 0].plot(rod["position"][:, 0], rod["position"][:, 2], "k--", label="pure rod")
    ax[0, 0].plot(hyb["position"][cat, 0], hyb["position"][cat, 2], "r-", label="hybrid: catenary")
    ax[0, 0].plot(hyb["position"][~cat, 0], hyb["position"][~cat, 2], "k-", label="hybrid: rod")
    ax[0, 0].set(xlabel="x (m)", ylabel="z (m)", title="shape at rest (GP Fig. 5)", aspect="equal")
    for a, key, title in ((ax[0, 1], "tension", "tension (GP Fig. 6)"), (ax[1, 0], "shear", "shear force (GP Fig. 7)"),
                          (ax[1, 1], "moment", "bending moment (GP Fig. 8)")):
        a.plot(rod["s"], rod[key], "k--", label="pure rod")
        mask = np.ones_like(cat) if key == "tension" else ~cat
        a.plot(hyb["s"][mask], hyb[key][mask], "r-", label="hybrid")
        a.axvline(JOINT, color="0.6", lw=0.8)
        a.set(xlabel="s (m)", ylabel=key + (" (N m)" if key == "moment" else " (N)"), title=title)
    for a in ax.flat:
        a.legend(fontsize=8)
        a.grid(alpha=0.3)
    fig.suptitle(f"Goyal & Perkins benchmark, ds = {2.0 / args.segments * 1000:.0f} mm, dt = 1 s")
    fig.tight_layout()
    fig.savefig(out / "gp_benchmark.png", dpi=110)
    print(f"wrote {out / 'gp_benchmark.png'}")


if __name__ == "__main__":
    main()
