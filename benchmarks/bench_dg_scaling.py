"""Cost of the DG solver versus mesh and order on the ROPOS tether (writes docs/figures/dg_rtf.png).

CPU-time real-time factor (simulated s per CPU s of this process) for N in (10, 20, 40) and
P in (2, 4, 6), without and with bending (EI = 2.62 kN m^2); ship on a 2 m, 0.2 Hz orbit.

    PYTHONPATH=. python benchmarks/bench_dg_scaling.py [sim_seconds]
"""

import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_dg import ropos_config, run  # noqa: E402


def main(sim_seconds=3.0, out="docs/figures/dg_rtf.png"):
    Ns, Ps = (10, 20, 40), (2, 4, 6)
    fig, ax = plt.subplots(figsize=(6, 4))
    for EI, ls in ((0.0, "-"), (2.62e3, "--")):
        for P, col in zip(Ps, ("C0", "C1", "C2")):
            r = []
            for N in Ns:
                _, rtf_cpu, per_s, s = run(ropos_config(EI, N=N, P=P), sim_seconds)
                r.append(rtf_cpu)
                print(f"N={N:3d} P={P} EI={EI:7.0f}: RTF(cpu) {rtf_cpu:8.2f}  dt {s._substep():.2e} s", flush=True)
            ax.loglog(Ns, r, ls, color=col, marker="o", label=f"P={P}" + (" EI" if EI else ""))
    ax.axhline(1.0, color="k", lw=0.8)
    ax.set_xticks(Ns)
    ax.set_xticklabels([str(n) for n in Ns])
    ax.minorticks_off()
    ax.set_xlabel("elements N")
    ax.set_ylabel("real-time factor (CPU time)")
    ax.set_title("DG solver, ROPOS L = 1730 m (dashed: with bending)")
    ax.legend(ncol=2, fontsize=8)
    ax.grid(True, which="both", alpha=0.3)
    os.makedirs(os.path.dirname(out), exist_ok=True)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    print("wrote", out)


if __name__ == "__main__":
    main(float(sys.argv[1]) if len(sys.argv) > 1 else 3.0)
