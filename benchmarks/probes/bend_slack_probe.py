"""Bending in slack parts (2026-11-25): one ROPOS 200 m slack-snap run with DG options from the
environment; prints min chord stretch, ship-tension difference against the EI = 0 record, and
the number of curvature maxima along the cable at a snapshot time.

    PYTHONPATH=. python benchmarks/probes/bend_slack_probe.py N [alpha] [t_end]
    env: QBEND (dg.q_penalty_bending), BETA, ZETAB (N m^2 s), QPEN (strain|tension|auto), QPENV (q_penalty), LFLOOR, END (cage|free), CFL, SNAP (s)
"""
import os
import sys
import time
from dataclasses import replace

import numpy as np

sys.path.insert(0, '.')
from benchmarks import ropos_case as rc  # noqa: E402
from benchmarks.studies import resolution_ladder as rl  # noqa: E402
from tether_sim.solvers import factory  # noqa: E402
from tether_sim.solvers.dg import layout as Y  # noqa: E402

N = int(sys.argv[1]) if len(sys.argv) > 1 else 40
alpha = float(sys.argv[2]) if len(sys.argv) > 2 else 1.0
T_END = float(sys.argv[3]) if len(sys.argv) > 3 else 7.8
END = os.environ.get("END", "cage")
SNAP = float(os.environ.get("SNAP", 7.0))
cfg = rl.case_config(f"200:stiff:{alpha:g}:{END}", N, 4, float(os.environ.get("CFL", 0.5)), 10.2)
dg = cfg.dg
if os.environ.get("LFLOOR"):
    dg = replace(dg, lambda_floor=float(os.environ["LFLOOR"]))
if os.environ.get("BETA"):
    dg = replace(dg, beta=float(os.environ["BETA"]))
if os.environ.get("QBEND"):
    dg = replace(dg, q_penalty_bending=float(os.environ["QBEND"]))
if os.environ.get("QPEN"):
    dg = replace(dg, q_penalty_jump=os.environ["QPEN"])
if os.environ.get("QPENV"):
    dg = replace(dg, q_penalty=float(os.environ["QPENV"]))
cab = cfg.cable
if os.environ.get("ZETAB"):
    cab = replace(cab, bending_damping=float(os.environ["ZETAB"]))
cfg = replace(cfg, dg=dg, cable=cab)
tag = os.environ.get("TAG", "run")
print("N", N, "alpha", alpha, "end", END, "EI", cfg.cable.EI, "zeta_b", cfg.cable.bending_damping, "beta", cfg.dg.beta, "q_penalty_bending", cfg.dg.q_penalty_bending,
      "q_penalty_jump", cfg.dg.q_penalty_jump, "cfl", cfg.dg.cfl, "lambda_floor", cfg.dg.lambda_floor, flush=True)
s = factory.build_solver(cfg)
print("q penalty form", getattr(s, "q_penalty_form", "?"), flush=True)
s.drain_end_tensions()
t0 = s.time
ts, ship, lmins, snap = [], [], [], None
emax, elmin = [], []
c0 = time.time()
k = 0
while s.time - t0 < T_END - 1e-9:
    k += 1
    p, v = rc.fairlead_motion(k * 0.02)
    s.set_end_motion("ship", p, v)
    s.advance_to(t0 + k * 0.02)
    tt, a, b = s.drain_end_tensions()
    ts.append(tt - t0)
    ship.append(a)
    wl = s.ws.wq[:, :, Y.W_L]
    lmins.append((k * 0.02, wl.min()))
    emax.append(np.linalg.norm(s.ws.wq[:, :, Y.W_KAP:Y.W_KAP + 3], axis=2).max(axis=1))
    elmin.append(wl.min(axis=1))
    if snap is None and k * 0.02 >= SNAP - 1e-9:
        snap = dict(l=wl.copy(), kap=s.ws.wq[:, :, Y.W_KAP:Y.W_KAP + 3].copy(), i=s.ws.wq[:, :, Y.W_I:Y.W_I + 3].copy())
    if not np.isfinite(wl).all() or (len(ship[-1]) and np.nanmax(np.abs(ship[-1])) > 5e6):
        print("diverged at", k * 0.02)
        break
t = np.concatenate(ts)
T = np.concatenate(ship)
L = np.array([x[1] for x in lmins])
print(f"min l {L.min():.4f}; max ship T 5-{T_END} s {T[t >= 5].max():.0f} N; steps {s.steps if hasattr(s, 'steps') else '?'}; wall {time.time() - c0:.0f} s")
# the EI = 0 record of benchmarks/studies/bending_effect_study.py (its default --records directory)
ref_path = f"out/bending_effect/200_stiff_0_{END}_N{N}P4c0.5.npz"
if os.path.exists(ref_path):
    ref = np.load(ref_path)
    m = (t >= 5.0) & (t <= min(7.7, t.max()))
    T0 = np.interp(t[m], ref["t"], ref["ship"])
    print(f"vs EI=0 record: rms {np.sqrt(np.mean((T[m] - T0) ** 2)):.0f} N; max |diff| {np.max(np.abs(T[m] - T0)):.0f} N")
    for a_, b_ in ((5.0, 6.5), (6.5, 7.4)):
        mm = (t >= a_) & (t <= b_)
        T0 = np.interp(t[mm], ref["t"], ref["ship"])
        print(f"  {a_}-{b_} s: rms {np.sqrt(np.mean((T[mm] - T0) ** 2)):.0f} N, max {np.max(np.abs(T[mm] - T0)):.0f} N")
if snap is not None:
    kap = np.linalg.norm(snap["kap"], axis=2).ravel()
    lq = snap["l"].ravel()
    slack = lq < 1.0
    mx = np.sum((kap[1:-1] > kap[:-2]) & (kap[1:-1] > kap[2:]) & slack[1:-1])
    print(f"snapshot {SNAP} s: Gauss points slack {slack.sum()} of {lq.size}; |kappa| max {kap.max():.3f} 1/m, "
          f"local maxima in slack {mx}; rms |kappa| slack {np.sqrt(np.mean(kap[slack] ** 2)) if slack.any() else 0:.3f}")
np.savez(f"out/probe_{tag}.npz", t=t, T=T, L=L, emax=np.array(emax), elmin=np.array(elmin), **({k_: v_ for k_, v_ in snap.items()} if snap else {}))
