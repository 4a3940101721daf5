"""Bending multirate (solvers/dg/stepper.py, timestep.bending_multirate_steps): the nested LDG of the bending
shear every K substeps, T_s extrapolated quadratically from its last three evaluations in between.

- The rule: K = 1 (every stage) without bending stiffness, with bending damping or a torque; otherwise the macro
  step K dt keeps w_max K dt <= 0.25 (AB3 is stable on the imaginary axis up to 0.72) and K dt <= 25 ms.
- A slack, curved cable in vacuum with free ends (its bending energy exchanged with kinetic energy, nothing
  else but the elastic tension): with the multirate the motion follows the every-stage solution and the
  energy never grows (the second-order extrapolation would feed the bending modes: |rho| = 1 + (w H)^4 / 4).
- dg.bending_multirate false is the every-stage stepper bit for bit.

Marked ``jit_off``: `make test` runs them again with the kernels as plain Python (shorter runs there).
"""

import os

import numpy as np
import pytest

from tether_sim.config import SimConfig
from tether_sim.physics.boundary import EndCondition
from tether_sim.physics.cable import CableProperties
from tether_sim.physics.environment import Environment
from tether_sim.solvers.config import DGOptions, InitialState
from tether_sim.solvers.dg import layout as Y
from tether_sim.solvers.dg.solver import DGCableSolver
from tether_sim.solvers.dg.stepper import BMR_OK
from tether_sim.solvers.dg.timestep import (
    BENDING_MULTIRATE_MAX_H, BENDING_MULTIRATE_WH, SHORT_CHORD_STIFFENING, _C, bending_multirate_steps,
)

from test_slack_bending import cable_energy  # the same energy, written once (test/solvers/dg on the path)

pytestmark = pytest.mark.jit_off

JIT_OFF = os.environ.get("NUMBA_DISABLE_JIT") == "1"


def solver(multirate, EI=2620.0, N=4, h=10.0, **cable):
    """The ROPOS tether's EA and gamma0 with bending factor 1 on the Sec. 6.2 element size, in vacuum (no
    weight, drag, added mass or material damping), free ends."""
    args = dict(length=N * h, EA=4.55e7, gamma0=3.01, diameter=0.03, density=7153.0, EI=EI, compression="none",
                damping=0.0, material="bilinear", Cdn=0.0, Cdt=0.0, Cmn=0.0, Cmt=0.0)
    args.update(cable)
    cfg = SimConfig(cable=CableProperties(**args), environment=Environment(g=0.0, fluid_density=1025.0),
                    ship_end=EndCondition(kind="free", position=(0, 0, 0)),
                    vehicle_end=EndCondition(kind="free", position=(0.0, 0, -N * h)),
                    dg=DGOptions(n_elements=N, order=4, q_penalty_jump="strain", bending_multirate=multirate),
                    initial=InitialState(kind="straight"))
    return DGCableSolver(cfg)


def start(s):
    """A slack (chord 0.9), curved line bent at the scale of an element, at rest."""
    s.set_shape(lambda x: 0.9 * np.stack([0.4 * np.sin(0.3 * x), 0 * x, -np.sqrt(1 - (0.4 * np.sin(0.3 * x)) ** 2)], 1),
                origin=np.zeros(3))


def test_rule():
    h, P, g0, EI = np.full(20, 10.0), 4, 3.01, 2620.0
    dt = 1.8e-5
    K = bending_multirate_steps(h, P, g0, EI, 0.0, 0.0, dt)
    w = SHORT_CHORD_STIFFENING * 3**0.5 * _C[P] * (EI / g0) ** 0.5 / 10.0**2
    assert K > 1
    assert w * K * dt <= BENDING_MULTIRATE_WH * (1 + 1e-9) and K * dt <= BENDING_MULTIRATE_MAX_H * (1 + 1e-9)
    assert w * (K + 1) * dt > BENDING_MULTIRATE_WH or (K + 1) * dt > BENDING_MULTIRATE_MAX_H  # the largest such K
    for args in ((0.0, 0.0, 0.0), (EI, 10.0, 0.0), (EI, 0.0, 5.0)):  # no EI, bending damping, torque
        assert bending_multirate_steps(h, P, g0, args[0], args[1], args[2], dt) == 1
    assert bending_multirate_steps(h, P, g0, 100 * EI, 0.0, 0.0, 1e-3) == 1  # stiff bending: every stage


def test_off_is_the_every_stage_stepper_bit_for_bit():
    a, b = solver(False), solver(True)
    assert a.bending_multirate_k == 1 and b.bending_multirate_k > 1
    b.ws.iprm_step[Y.I_BMR_K] = b.ws.iprm[Y.I_BMR_K] = 1  # the same solver with K = 1
    for s in (a, b):
        start(s)
        s.advance_to(0.01)
    assert np.array_equal(a.ws.U, b.ws.U)


def test_multirate_follows_the_every_stage_solution_and_gains_no_energy():
    T = 0.03 if JIT_OFF else 0.5  # 0.5 s: 4600 substeps, about 10 bending periods of the element-scale modes
    arc = np.linspace(0.0, 40.0, 41)
    runs = {}
    for multirate in (False, True):
        s = solver(multirate)
        start(s)
        x_start = s.positions_at(arc)
        e0 = cable_energy(s)
        worst = 0.0
        for k in range(1, 11):
            s.advance_to(T * k / 10)
            worst = max(worst, cable_energy(s) / e0)
        runs[multirate] = (s.positions_at(arc), worst, s.bending_multirate_k, np.max(np.abs(s.positions_at(arc) - x_start)))
    (x0, w0, _, moved), (x1, w1, k1, _) = runs[False], runs[True]
    diff = np.max(np.abs(x1 - x0))
    print("K", k1, "E max / E0 every stage", w0, "multirate", w1, "moved", moved, "m; largest difference", diff, "m")
    assert k1 > 1
    assert moved > (1e-4 if JIT_OFF else 0.05)  # the line did move
    assert w1 <= 1.0 + 1e-4  # no energy gained
    assert diff <= 1e-3 * moved


def short_k(K=4):
    """solver(True) with the records every K substeps (short runs do many of them)."""
    s = solver(True)
    s.ws.iprm_step[Y.I_BMR_K] = s.ws.iprm[Y.I_BMR_K] = K
    return s


def _run(s, ends, restart=False):
    """advance_to every time in ends; restart: the carried records dropped before each call (as before they
    were carried)."""
    for t in ends:
        if restart:
            s.ws.bmr[BMR_OK] = 0.0
        s.advance_to(t)
    return s.ws.U.copy()


def test_records_carry_from_one_call_to_the_next():
    """Ten calls with the records carried (each call's first stage in full) stay closer to one call of the
    same substeps than ten calls with the records dropped at every call (each call's first 2K substeps at
    every stage): the records do carry."""
    dt = solver(True)._substep()
    steps = 40 if JIT_OFF else 400
    ends = [dt * steps * k / 10 for k in range(1, 11)]
    runs = []
    for calls, restart in ((ends[-1:], False), (ends, False), (ends, True)):
        s = short_k()
        start(s)
        runs.append(_run(s, calls, restart))
    one, carried, restarted = runs
    scale = np.max(np.abs(one))
    d_carry, d_restart = np.max(np.abs(carried - one)), np.max(np.abs(restarted - one))
    print("carried", d_carry, "restarted", d_restart, "scale", scale)
    assert d_restart > 3.0 * d_carry and d_restart > 1e-9 * scale


def test_restore_brings_back_the_records_and_a_new_state_restarts_them():
    dt = solver(True)._substep()
    n = 12 if JIT_OFF else 300
    a = short_k()
    start(a)
    a.advance_to(n * dt)
    snap = a.snapshot()
    first = _run(a, [2 * n * dt, 3 * n * dt])
    a.restore(snap)
    assert np.array_equal(_run(a, [2 * n * dt, 3 * n * dt]), first)  # the same records: bit for bit
    # a state set between calls (at the same time): the records restart, as with them dropped
    b, c = short_k(), short_k()
    for s, drop in ((b, False), (c, True)):
        start(s)
        s.advance_to(n * dt)
        s.set_shape(lambda x: np.stack([0.3 * np.sin(0.2 * x), 0 * x, -np.sqrt(1 - (0.3 * np.sin(0.2 * x)) ** 2)], 1),
                    origin=np.zeros(3))
        if drop:
            s.ws.bmr[BMR_OK] = 0.0
        s.advance_to(2 * n * dt)
    assert np.array_equal(b.ws.U, c.ws.U)
