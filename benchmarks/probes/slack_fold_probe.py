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
    PYTHONPATH=. python benchmarks/probes/slack_fold_probe.py switch SNAP T0 T1   # one substep at a time: the cage
                    # element's outer Gauss point (chord, strain rate, zeta * strain rate) and its strain rate split
                    # into the lifted end slip (v_BC - v+, the central flux of the strain-rate gradient) and the rest
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


def restore(arg):
    """The snapshot file ``arg`` into the solver ("-": start from the initial state)."""
    if arg != "-":
        with open(arg, "rb") as fh:
            s.restore(pickle.load(fh))


def ticks(t_end):
    """Advance tick by tick (the ship end on its orbit, as the offline runner drives it) up to ``t_end``;
    yield (tick time, substep times, ship tensions, cage tensions) after each tick."""
    k = int(round(s.time / dt_tick))
    while (k + 1) * dt_tick <= t_end + 1e-9:
        k += 1
        yield (k * dt_tick, *advance(k * dt_tick))


def advance(t):
    p, v = mot.at(t)[:2]
    s.set_end_motion("ship", p, v)
    s.advance_to(t)
    return s.drain_end_tensions()


def substeps(t_end):
    """One stable substep per advance up to ``t_end``; yield the cage tension after each."""
    while s.time < t_end:
        yield advance(s.time + s.stable_time_step())[2][-1]


if mode == "save":
    t_save = float(sys.argv[2])
    c0 = time.process_time()
    for t, _, a, b in ticks(t_save):
        if int(round(t / dt_tick)) % 50 == 0:
            print(f"t {t:.2f} Tship max {a.max():.0f} Tcage max {b.max():.0f} lmin {s.ws.wq[:, :, Y.W_L].min():.3f} "
                  f"cpu {time.process_time() - c0:.0f}", flush=True)
    with open(f"out/snap_{tag}_{t_save:g}.pkl", "wb") as fh:
        pickle.dump(s.snapshot(), fh)
elif mode == "steps":
    restore(sys.argv[2])
    rows = []
    for _, tt, a, b in ticks(float(sys.argv[3])):
        wl = s.ws.wq[:, :, Y.W_L]
        for x in range(len(tt)):
            rows.append((tt[x], a[x], b[x], wl.min(), wl[-1].min(), wl[-1].max(), np.argmin(wl.min(axis=1))))
    R = np.array(rows)
    np.save(f"out/steps_{tag}.npy", R)
    i = np.argmax(R[:, 2])
    print("max cage T", R[i, 2], "at", R[i, 0], "max ship", R[:, 1].max(), "at", R[np.argmax(R[:, 1]), 0])
    for r in R[max(0, i - 8): i + 8]:
        print(" ".join(f"{x:.5g}" for x in r))
elif mode in ("fine", "gauss"):  # restore, tick to T1, then one substep at a time to T2
    restore(sys.argv[2])
    for _ in ticks(float(sys.argv[3])):
        pass
    s.drain_end_tensions()
    Nn = s.ws.trc.shape[0]
    np.set_printoptions(linewidth=250, precision=4, suppress=False)
    for Tcage in substeps(float(sys.argv[4])):
        if mode == "fine":  # the cage end trace
            tr, fl = s.ws.trc[Nn - 1, 1], s.ws.fl[Nn]
            q, vv, TV, FV = tr[Y.T_Q:Y.T_Q + 3], tr[Y.T_V:Y.T_V + 3], tr[Y.T_TV:Y.T_TV + 3], fl[Y.F_V:Y.F_V + 3]
            print(f"{s.time:.7f} Tcage {Tcage:10.1f} |q| {np.linalg.norm(q):.4f} q {q.round(4)} v+ {vv.round(3)} "
                  f"vbc {np.round(s.ws.vbc[1, 3:6], 3)} T+ {TV.round(0)} Fv {FV.round(0)} lam {tr[Y.T_LAM]:.0f}")
            continue
        wq = s.ws.wq  # the last two elements' Gauss points
        print(f"t {s.time:.7f} Tcage {Tcage:.0f}")
        for e in (Nn - 2, Nn - 1):
            T = np.linalg.norm(wq[e, :, Y.W_TV:Y.W_TV + 3], axis=1)
            print(f"  e{e} l {wq[e, :, Y.W_L].round(4)}\n      edot {wq[e, :, Y.W_EDOT].round(3)}\n      |TV| {T.round(0)}"
                  f"\n      vz {wq[e, :, Y.W_V + 2].round(2)}")
elif mode == "switch":  # Eq. 22's Kelvin-Voigt switch at the cage end, one substep at a time
    restore(sys.argv[2])
    for _ in ticks(float(sys.argv[3])):
        pass
    s.drain_end_tensions()
    ws, g0, zeta = s.ws, cfg.cable.gamma0, cfg.cable.damping
    e = ws.trc.shape[0] - 1
    lift = (ws.V @ ws.Lf[1]) / ws.h[e]  # the lift of a unit end jump of v / gamma0 onto the Gauss points (1/m)
    for Tcage in substeps(float(sys.argv[4])):
        slip = ws.vbc[1, 3:6] - ws.trc[e, 1, Y.T_V:Y.T_V + 3] / g0
        lifted = lift[-1] * (ws.wq[e, -1, Y.W_I:Y.W_I + 3] @ slip)
        ed = ws.wq[e, -1, Y.W_EDOT]
        print(f"{s.time:.7f} Tcage {Tcage:9.0f} l {ws.wq[e, -1, Y.W_L]:.6f} edot {ed:6.3f} zeta*edot {zeta * ed:8.0f} "
              f"| slip {np.round(slip, 3)} lifted {lifted:6.3f} own {ed - lifted:6.3f}")
elif mode == "trace":  # from 0 or a snapshot; per tick after T0: largest cable speed, shortest chord, end tensions
    restore(sys.argv[2])
    T0 = float(sys.argv[3])
    g0 = cfg.cable.gamma0
    for t, _, a, b in ticks(float(sys.argv[4])):
        if t >= T0 - 1e-9:
            wq = s.ws.wq
            sp = np.linalg.norm(wq[:, :, Y.W_V:Y.W_V + 3], axis=2) / g0
            wl = wq[:, :, Y.W_L]
            print(f"t {t:.2f} vmax {sp.max():6.2f} at e{np.unravel_index(np.argmax(sp), sp.shape)[0]} | lmin "
                  f"{wl.min():.3f} at e{np.unravel_index(np.argmin(wl), wl.shape)[0]} | slack pts {(wl < 1).sum()} | "
                  f"Tship {a.max():9.0f} Tcage {b.max():9.0f}", flush=True)
else:
    sys.exit(f"unknown mode {mode!r}: save, trace, steps, fine, gauss or switch")
