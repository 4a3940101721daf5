"""ROPOS tether-cage case [PE2020 Sec. 6, Table 3]: configuration, statics, snap front, slack-snap.

The solver runs here are the cheap subsets; the 48-case study and the mesh study are scripts
(``python -m tether_sim.scenarios.ropos_study``) whose numbers are in docs/ropos.md.
"""

import math
from dataclasses import replace

import numpy as np
import pytest

from tether_sim.io.params import load_config
from tether_sim.scenarios.ropos import (
    CONFIG_DIR,
    point_load_config,
    ropos_config,
    run_case,
    snap_lag,
    static_end_tensions,
)
from tether_sim.solvers.factory import build_solver
from tether_sim.solvers.resolution import choose


LIVE_TOLERANCE = {975: 0.02}


@pytest.mark.parametrize("length", [200, 500, 975, 1730])
def test_live_config_files_differ_from_the_paper_files_only_in_the_mesh(length):
    """The live files choose their mesh by dg.resolution auto; everything else is the paper file's."""
    live = load_config(CONFIG_DIR / f"ropos_L{length}.yaml")
    paper = load_config(CONFIG_DIR / f"ropos_L{length}_paper.yaml")
    # 975 m states 2 % for real time (its 1 % mesh, N = 24, P = 4, runs below 10x): the mesh that picks
    # must still have measured within 1 % on every ladder case there (the rule's margin is what is given up)
    tolerance = LIVE_TOLERANCE.get(length, 0.01)
    assert (live.dg.resolution, live.dg.snap_tolerance, paper.dg.resolution) == ("auto", tolerance, "manual")
    chosen = choose(float(length), tolerance)
    assert chosen.measured_error <= 0.01
    assert (live.dg.n_elements, live.dg.order, live.dg.cfl) == (chosen.n_elements, chosen.order, chosen.cfl)
    assert replace(live, dg=paper.dg) == paper


@pytest.mark.parametrize("length", [200, 500, 975, 1730])
def test_config_files_carry_table3_and_calibration(length):
    cfg = load_config(CONFIG_DIR / f"ropos_L{length}_paper.yaml")
    c, b = cfg.cable, cfg.body
    assert c.length == length and (c.EA, c.gamma0, c.density, c.diameter) == (45.5e6, 3.01, 7153.0, 0.03)
    assert (c.damping, c.Cdn, c.Cdt, c.Cmn, c.Cmt) == (45.5e3, 1.0, 0.02, 1.0, 0.0)
    assert (b.mass, b.density, b.added_mass[2], b.drag_coefficients[2], b.inertia[1]) == (4995.0, 8448.0, 9200.0, 2.7, 19e3)
    assert b.drag_areas[2] == pytest.approx(math.pi / 4 * 3.01**2, rel=1e-4)  # lid area of D = 3.01 m
    assert b.drag_areas[0] == pytest.approx(3.01 * 4.2, rel=1e-4)  # side area D x H
    assert b.attachment == (0.0, 0.0, 2.1)  # top of a 4.2 m high cage, CoG at its centre
    assert (cfg.dg.n_elements, cfg.dg.order, cfg.vehicle_end.kind) == (20, 4, "body")
    # c = sqrt(EA/gamma0) = 3888 m/s: L/c = 0.445 s at 1730 m [PE2020 Sec. 6.1]
    assert 1730.0 / c.wave_speed == pytest.approx(0.445, abs=5e-4)


def test_validation_config_uses_the_synthetic_record():
    cfg = load_config(CONFIG_DIR / "ropos_validation.yaml")
    assert cfg.motion.kind == "record" and cfg.motion.record_scale == 1.0 and cfg.cable.length == 1730.0
    assert (CONFIG_DIR.parent / cfg.motion.record_path).is_file()


def test_closed_form_static_tensions():
    ship, cage = static_end_tensions(ropos_config(1730.0))
    assert cage == pytest.approx(4995 * 9.81 * (1 - 1025 / 8448), rel=1e-12)
    # The tether's submerged weight at L = 1730 m: "44 kN" [PE2020 Sec. 6.1]
    assert (ship - cage) / 1e3 == pytest.approx(44.0, abs=0.5)
    cfg = ropos_config(500.0, alpha=10.0, frequency=0.25, n_elements=7)
    assert (cfg.cable.EI, cfg.motion.frequency, cfg.dg.n_elements, cfg.duration) == (26.2e3, 0.25, 7, 48.0)


@pytest.mark.parametrize("point_load", [False, True], ids=["cage_body", "point_load"])
def test_static_L1730_end_tensions(point_load):
    cfg = ropos_config(1730.0)
    if point_load:
        cfg = point_load_config(cfg)
    ship, cage = static_end_tensions(cfg)
    solver = build_solver(cfg)
    forces = solver.end_forces()
    # Acceptance: both within 0.5% of the closed form.
    assert forces.vehicle_tension == pytest.approx(cage, rel=5e-3)
    assert forces.ship_tension - forces.vehicle_tension == pytest.approx(ship - cage, rel=5e-3)
    # ... and the dynamic equations keep that state (body weight, buoyancy, end coupling consistent).
    solver.drain_end_tensions()
    solver.advance_to(2.0)
    _, T_ship, T_vehicle = (np.asarray(a) for a in solver.drain_end_tensions())
    assert np.abs(T_vehicle / cage - 1.0).max() < 5e-3
    assert np.abs((T_ship - T_vehicle) / (ship - cage) - 1.0).max() < 5e-3


def test_snap_front_reaches_the_ship_after_L_over_c():
    """A tension step at the cage end (point load) arrives at the ship after L/c = 0.445 s."""
    cfg = point_load_config(ropos_config(1730.0))
    ship, cage = static_end_tensions(cfg)
    solver = build_solver(cfg)
    solver.drain_end_tensions()
    t_step, step = 0.02, 20e3
    solver.advance_to(t_step)
    solver.set_end_load("vehicle", (0.0, 0.0, -(cage + step)))
    solver.advance_to(0.8)
    t, T_ship, _ = (np.asarray(a) for a in solver.drain_end_tensions())
    # The front doubles on reflection at the pinned ship end: its middle is at T0 + step.
    i = np.nonzero(T_ship > ship + step)[0][0]
    t_half = t[i - 1] + (ship + step - T_ship[i - 1]) * (t[i] - t[i - 1]) / (T_ship[i] - T_ship[i - 1])
    lag = t_half - t_step
    assert lag == pytest.approx(1730.0 / cfg.cable.wave_speed, rel=0.02)


def test_slack_and_snap_at_cage_L1730():
    """a = 2 m orbit (PE2020 Sec. 6.2): slack + snap at the cage for f = 0.25 Hz, none at 0.10 Hz.

    L = 1730 m is the cheapest depth for the explicit DG (largest elements); the full L x alpha x f
    grid is the study script (docs/ropos.md).
    """
    cfg = ropos_config(1730.0, frequency=0.25, periods=3.0, cfl=0.9)  # 0.9: checked against 0.5 in docs/ropos.md
    fast_wave_speed = cfg.cable.wave_speed
    fast = run_case(cfg, output_rate=25.0)
    assert not fast.error
    # Stored tensions: one maximum per 1 ms bin (bins without a substep are absent: dt ~ 1.05 ms
    # here), never a bin split in two across output intervals.
    gaps = np.diff(fast.t) * 1e3
    assert gaps.min() > 0.5 and np.allclose(gaps, np.round(gaps), atol=1e-6)
    snaps = fast.snaps("vehicle")
    assert fast.slacks("vehicle") and snaps
    assert all(e.peak_tension > e.static_tension for e in snaps)
    # The snap front at the cage reaches the ship L/c = 0.445 s later (2%; tensions kept at 1 kHz).
    wave = 1730.0 / fast_wave_speed
    for e in snaps:
        assert snap_lag(fast.t, fast.ship_tension, fast.vehicle_tension, e, wave) == pytest.approx(wave, rel=0.02)
    slow = run_case(ropos_config(1730.0, frequency=0.10, periods=1.5, cfl=0.9), output_rate=10.0)
    assert not slow.error and not slow.events
    # The 1-D model gives a cage minimum of 18 kN (41% of static) at f = 0.1 Hz: far from slack.
    assert slow.vehicle_tension.min() > 0.2 * slow.static[1]
