"""Slack with bending, step by step: one case of benchmarks/studies/slack_bending_ladder.py driven tick by tick
(the fairlead orbit of the case file), with a snapshot to resume from and per-tick or per-step prints of the
cable near the cage (docs/dg_solver.md, "Slack with bending").

    PYTHONPATH=. python benchmarks/probes/slack_fold_probe.py save T              # run to T, pickle out/snap_<tag>_T.pkl
    PYTHONPATH=. python benchmarks/probes/slack_fold_probe.py trace SNAP|- T0 T1  # per tick after T0: largest cable
                                                                                  # speed, shortest chord, end tensions
    PYTHONPATH=. python benchmarks/probes/slack_fold_probe.py steps SNAP T1       # every substep: end tensions, chords
    PYTHONPATH=. python benchmarks/probes/slack_fold_probe.py fine SNAP T0 T1     # one substep at a time: the cage
                                                                                  # end trace (q, v, T+, flux)
    PYTHONPATH=. python benchmarks/probes/slack_fold_probe.py gauss SNAP T0 T1    # the last two elements' Gauss points
    env: LL (200), FF (0.2), AL (alpha, 100), NN (N, 40), EXTRA (a dict of further overrides), TAG
"""
import ast
import os
import pickle
import sys
import time

import numpy as np
sys.path.insert(0, '.')
from benchmarks.studies.slack_bending_ladder import case_config
from tether_sim.solvers import factory
from tether_sim.physics.motion import build_motion
from tether_sim.physics.waves import wave_components
from tether_sim.solvers.dg import layout as Y

L, f, alpha, N = float(os.environ.get("LL", 200)), float(os.environ.get("FF", 0.2)), float(os.environ.get("AL", 100)), int(os.environ.get("NN", 40))
extra = ast.literal_eval(os.environ.get("EXTRA", "{}"))
cfg = case_config(L, f, alpha, N, 2.0, extra)
s = factory.build_solver(cfg)
mot = build_motion(cfg.motion, np.asarray(cfg.ship_end.position, float), wave_components(cfg))
s.drain_end_tensions()
mode = sys.argv[1]
tag = os.environ.get("TAG", f"a{alpha:g}N{N}")
dt_tick = 0.02
if mode == "save":
    t_save = float(sys.argv[2])
    k = 0
    c0 = time.process_time()
    while k * dt_tick < t_save - 1e-9:
        k += 1
        p, v = mot.at(k * dt_tick)[:2]
        s.set_end_motion("ship", p, v)
        s.advance_to(k * dt_tick)
        tt, a, b = s.drain_end_tensions()
        if k % 50 == 0:
            print(f"t {k*dt_tick:.2f} Tship max {a.max():.0f} Tcage max {b.max():.0f} lmin {s._wq[:,:,Y.W_L].min():.3f} cpu {time.process_time()-c0:.0f}", flush=True)
    pickle.dump(s.snapshot(), open(f"out/snap_{tag}_{t_save:g}.pkl", "wb"))
elif mode == "steps":
    snap = pickle.load(open(sys.argv[2], "rb"))
    s.restore(snap)
    t_end = float(sys.argv[3])
    k = int(round(s.time / dt_tick))
    rows = []
    while k * dt_tick < t_end - 1e-9:
        k += 1
        p, v = mot.at(k * dt_tick)[:2]
        s.set_end_motion("ship", p, v)
        s.advance_to(k * dt_tick)
        tt, a, b = s.drain_end_tensions()
        wl = s._wq[:, :, Y.W_L]
        for x in range(len(tt)):
            rows.append((tt[x], a[x], b[x], wl.min(), wl[-1].min(), wl[-1].max(), np.argmin(wl.min(axis=1))))
    R = np.array(rows)
    np.save(f"out/steps_{tag}.npy", R)
    i = np.argmax(R[:, 2])
    print("max cage T", R[i, 2], "at", R[i, 0], "max ship", R[:, 1].max(), "at", R[np.argmax(R[:,1]), 0])
    for r in R[max(0, i - 8): i + 8]:
        print(" ".join(f"{x:.5g}" for x in r))

if mode == "fine":
    # restore, tick to T1, then single substeps to T2 printing the cage end trace
    snap = pickle.load(open(sys.argv[2], "rb"))
    s.restore(snap)
    T1, T2 = float(sys.argv[3]), float(sys.argv[4])
    k = int(round(s.time / dt_tick))
    while (k + 1) * dt_tick <= T1 + 1e-9:
        k += 1
        p, v = mot.at(k * dt_tick)[:2]
        s.set_end_motion("ship", p, v)
        s.advance_to(k * dt_tick)
    s.drain_end_tensions()
    Nn = s._tr.shape[0]
    while s.time < T2:
        h = s.stable_time_step()
        t = s.time + h
        p, v = mot.at(t)[:2]
        s.set_end_motion("ship", p, v)
        s.advance_to(t)
        tt, a, b = s.drain_end_tensions()
        tr = s._tr[Nn - 1, 1]
        fl = s._fl[Nn]
        q = tr[Y.T_Q:Y.T_Q + 3]; vv = tr[Y.T_V:Y.T_V + 3]; TV = tr[Y.T_TV:Y.T_TV + 3]; FV = fl[Y.F_V:Y.F_V + 3]
        vb = s.ws.vbc[1, 3:6] if hasattr(s.ws, 'vbc') else np.full(3, np.nan)
        print(f"{s.time:.7f} Tcage {b[-1]:10.1f} |q| {np.linalg.norm(q):.4f} q {q.round(4)} v+ {vv.round(3)} vbc {np.round(vb,3)} T+ {TV.round(0)} Fv {FV.round(0)} lam {tr[Y.T_LAM]:.0f}")

if mode == "gauss":
    snap = pickle.load(open(sys.argv[2], "rb"))
    s.restore(snap)
    T1, T2 = float(sys.argv[3]), float(sys.argv[4])
    k = int(round(s.time / dt_tick))
    while (k + 1) * dt_tick <= T1 + 1e-9:
        k += 1
        p, v = mot.at(k * dt_tick)[:2]
        s.set_end_motion("ship", p, v)
        s.advance_to(k * dt_tick)
    s.drain_end_tensions()
    Nn = s._tr.shape[0]
    np.set_printoptions(linewidth=250, precision=4, suppress=False)
    while s.time < T2:
        h = s.stable_time_step()
        t = s.time + h
        p, v = mot.at(t)[:2]
        s.set_end_motion("ship", p, v)
        s.advance_to(t)
        tt, a, b = s.drain_end_tensions()
        wq = s._wq
        print(f"t {s.time:.7f} Tcage {b[-1]:.0f}")
        for e in (Nn - 2, Nn - 1):
            T = np.linalg.norm(wq[e, :, Y.W_TV:Y.W_TV + 3], axis=1)
            print(f"  e{e} l {wq[e,:,Y.W_L].round(4)}\n      edot {wq[e,:,Y.W_EDOT].round(3)}\n      |TV| {T.round(0)}\n      vz {wq[e,:,Y.W_V+2].round(2)}")

if mode == "trace":
    # from 0 or a snapshot; print per tick after T0: max cable speed, where, min l, max end tensions
    if sys.argv[2] != "-":
        s.restore(pickle.load(open(sys.argv[2], "rb")))
    T0, T2 = float(sys.argv[3]), float(sys.argv[4])
    k = int(round(s.time / dt_tick))
    g0 = cfg.cable.gamma0
    while k * dt_tick < T2 - 1e-9:
        k += 1
        p, v = mot.at(k * dt_tick)[:2]
        s.set_end_motion("ship", p, v)
        s.advance_to(k * dt_tick)
        tt, a, b = s.drain_end_tensions()
        if k * dt_tick >= T0 - 1e-9:
            wq = s._wq
            sp = np.linalg.norm(wq[:, :, Y.W_V:Y.W_V + 3], axis=2) / g0
            e = np.unravel_index(np.argmax(sp), sp.shape)
            wl = wq[:, :, Y.W_L]
            print(f"t {k*dt_tick:.2f} vmax {sp.max():6.2f} at e{e[0]} | lmin {wl.min():.3f} at e{np.unravel_index(np.argmin(wl), wl.shape)[0]} | slack pts {(wl<1).sum()} | Tship {a.max():9.0f} Tcage {b.max():9.0f}", flush=True)
