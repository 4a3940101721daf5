"""Can the axial damping of the PE2020 Sec. 6.2 case (L = 200 m, N = 20, P = 4, f = 0.2 Hz, cage body) be
stepped explicitly by a super-time-stepping method (RKL2, Meyer, Balsara & Aslam 2014) inside the Strang
splitting of ``dg.damping: implicit``?

At states sampled through the run (implicit damping, the fairlead orbit of bench_slack_bending.py):

1. the spectral radius rho of the frozen damping operator K (the strain-rate matrix of implicit_damping.py,
   whose non-zero spectrum is that of f_d on the velocities: K = B C, f_d = C B), from the dense eigenvalues of
   the assembled I - K, and dt rho for the substep dt of the splitting (D steps of dt; half steps at the ends);
2. the stages s an RKL2 step of dt needs: stable for real eigenvalues in [-rho, 0] while
   dt rho <= (s^2 + s - 2) / 2 (Meyer et al. 2014, Eq. 16: dt <= dt_FE (s^2 + s - 2) / 4, dt_FE = 2 / rho);
3. the CPU time of one damping-only right-hand side f_d(v) (frozen geometry: strain rates, tension points,
   divergence through the added mass) and of the geometry set-up, each in a compiled loop of --reps calls;
   and the implicit damping step with the stored LU, for comparison.

Usage: PYTHONPATH=. python benchmarks/probes/damping_rhs_gate.py [--alpha 1] [--start 5] [--seconds 3]
       [--samples 4] [--reps 5000]
"""

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np
from numba import njit

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from benchmarks.bench_slack_bending import tree  # noqa: E402
from benchmarks.studies.slack_bending_ladder import EI_STAR  # noqa: E402
from tether_sim.solvers.dg import damping_layout as DL  # noqa: E402
from tether_sim.solvers.dg.damping_ops import (  # noqa: E402
    axial_tension_points, clip_set, damping_geometry, release_ends, strain_rates, tension_divergence,
)
from tether_sim.solvers.dg.implicit_damping import assemble_axial  # noqa: E402
from tether_sim.solvers.dg.stepper import _damping  # noqa: E402
from tether_sim.solvers.dg.workspace import (  # noqa: E402
    X_BLK, X_BVEC, X_DPRM, X_DTMP, X_IDP, X_PJ, X_TAB_EPS, X_TAB_T, X_TR, X_U, X_V, X_VBC, X_WD, X_WP, bind,
)


@njit
def _geometry(F, I, S, n):
    A = bind(F, I, S)
    U, wp, idp, dprm = A[X_U], A[X_WP], A[X_IDP], A[X_DPRM]
    for _ in range(n):
        damping_geometry(U, A[X_V], idp, dprm, wp, A[X_TAB_EPS], A[X_TAB_T])
        strain_rates(U, 3, True, A[X_VBC], A[X_BLK], A[X_BVEC], wp, DL.WP_E0)
        clip_set(idp, dprm, wp, A[X_TAB_EPS], A[X_TAB_T])
        release_ends(U, A[X_VBC], idp, dprm, A[X_BVEC], A[X_TR], wp, A[X_TAB_EPS], A[X_TAB_T])


@njit
def _fd(F, I, S, n):
    A = bind(F, I, S)
    U, wp, idp, dprm, wd = A[X_U], A[X_WP], A[X_IDP], A[X_DPRM], A[X_WD]
    for _ in range(n):
        strain_rates(U, 3, True, A[X_VBC], A[X_BLK], A[X_BVEC], wp, DL.WP_X)
        axial_tension_points(wp, DL.WP_X, True)
        tension_divergence(A[X_BLK], A[X_PJ], A[X_BVEC], idp, dprm, wp, wd, DL.WD_F, True)


@njit
def _damp(F, I, S, n, dt, U0):
    A = bind(F, I, S)
    U = A[X_U]
    idp = A[X_IDP]
    for _ in range(n):
        U[:] = U0
        idp[DL.ID_LU_AGE] = 1
        _damping(dt, A)


@njit
def _assemble(F, I, S, gh, out, kl):
    A = bind(F, I, S)
    assemble_axial(A[X_BLK], A[X_BVEC], A[X_IDP], A[X_DPRM], A[X_WP], gh, out, kl, A[X_DTMP])


def spectral_radius(s):
    """max |lambda(K)| and min Re lambda(K) of the frozen strain-rate operator at the present state."""
    ws = s.ws
    args = (ws.F, ws.I, ws.spec)
    _geometry(*args, 1)
    wp = ws.wp
    n = wp.shape[0] * wp.shape[1]
    kl = int(ws.idp[DL.ID_KL])
    band = np.zeros((n, 2 * kl + 1))
    _assemble(*args, 1.0, band, kl)
    M = np.zeros((n, n))
    for r in range(n):
        for c in range(2 * kl + 1):
            cc = r + c - kl
            if 0 <= cc < n:
                M[r, cc] = band[r, c]
    lam = np.linalg.eigvals(np.eye(n) - M)
    return np.abs(lam).max(), lam.real.min(), np.abs(lam.imag).max()


def timings(s, reps):
    ws = s.ws
    F0, I0 = ws.F.copy(), ws.I.copy()
    args = (ws.F, ws.I, ws.spec)
    dt = s._substep()
    row = {}
    for name, fn, extra in (("geometry + clip set (once per D)", _geometry, ()), ("f_d(v), one evaluation", _fd, ()),
                            ("implicit D step, stored LU", _damp, (dt, ws.U.copy()))):
        _geometry(*args, 1)
        fn(*args, 2, *extra)
        ws.F[:] = F0
        ws.I[:] = I0
        _geometry(*args, 1)
        c = time.process_time()
        fn(*args, reps, *extra)
        row[name] = 1e6 * (time.process_time() - c) / reps
        ws.F[:] = F0
        ws.I[:] = I0
    return row


def stages_for(x):
    """Least s >= 2 with (s^2 + s - 2) / 2 >= x."""
    s = 2
    while (s * s + s - 2) / 2.0 < x:
        s += 1
    return s


def sec62_case(alpha):
    """PE2020 Sec. 6.2's 200 m case on the paper's mesh (N 20, P 4), f = 0.2 Hz, EI = alpha EI*, implicit
    damping with the bending multirate: (ship motion, solver)."""
    load_config, build_motion, build_solver = tree("tether_sim")
    overrides = {"cable.EI": alpha * EI_STAR, "motion.kind": "circle", "motion.amplitude": 2.0,
                 "motion.frequency": 0.2, "motion.ramp_time": 5.0, "duration": 60.0, "dg.n_elements": 20,
                 "dg.order": 4, "dg.damping": "implicit", "dg.bending_multirate": True}
    cfg = load_config(ROOT / "config" / "ropos_L200_paper.yaml", overrides)
    return build_motion(cfg.motion, cfg.ship_end.position), build_solver(cfg)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--alpha", type=float, default=1.0)
    ap.add_argument("--start", type=float, default=5.0)
    ap.add_argument("--seconds", type=float, default=3.0)
    ap.add_argument("--samples", type=int, default=4)
    ap.add_argument("--reps", type=int, default=5000)
    args = ap.parse_args(argv)
    motion, s = sec62_case(args.alpha)
    dt = s._substep()
    print(f"# {time.strftime('%Y-%m-%d %H:%M')} load {os.getloadavg()[0]:.1f}; alpha {args.alpha:g}, substep dt "
          f"{dt:.4e} s; window {args.start:g}-{args.start + args.seconds:g} s", flush=True)
    rate, t0 = 50.0, s.time
    k = 0
    samples = [0.0] + list(np.linspace(args.start, args.start + args.seconds, args.samples))
    for ts in samples:
        while k / rate < ts - 1e-9:
            k += 1
            p, v, _ = motion.at(k / rate)
            s.set_end_motion("ship", p, v)
            s.advance_to(t0 + k / rate)
            s.drain_end_tensions()
        rho, remin, immax = spectral_radius(s)
        row = timings(s, args.reps)
        x = dt * rho
        ns = stages_for(x)
        print(f"t = {s.time:6.3f} s: rho(K) = {rho:9.0f} 1/s (min Re {remin:9.0f}, max |Im| {immax:7.1f}), "
              f"dt rho = {x:5.2f} (forward Euler limit 2), RKL2 stages s = {ns}; clipped points "
              f"{int((ws_z := s.ws.wp[:, :, DL.WP_Z] == 0).sum())}/{ws_z.size}, released ends "
              f"{int(s.ws.idp[DL.ID_REL0])}{int(s.ws.idp[DL.ID_REL0 + 1])}", flush=True)
        print("   " + "; ".join(f"{n} {v:.2f} us" for n, v in row.items())
              + f"; RKL2 estimate s f_d + geometry = {ns * row['f_d(v), one evaluation'] + row['geometry + clip set (once per D)']:.1f} us",
              flush=True)
    print(f"# load {os.getloadavg()[0]:.1f} at the end")


if __name__ == "__main__":
    main()
