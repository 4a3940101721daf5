"""Slack and snap with the bilinear law T = EA max(eps, 0) [PE2020 Eq. 22].

1. Cycles: a taut cable whose ship end oscillates axially with three times the pre-stretch goes
   slack and is jerked taut every cycle. It must run without NaN, the tension (sampled along the
   cable and at the ends at every substep) must never be negative (zeta = 0, so T >= 0 exactly by
   the law; end tensions get 1e-6 of the peak for round-off), and slack must actually happen.
2. Front speed: a resting, uniformly slack cable (strain -a) is jerked at its ship end at speed V.
   The snap front runs into the slack cable at the Rankine-Hugoniot speed S = V/(e1 + a),
   e1 (e1 + a) = (V/c)^2 (references.snap_front_speed; S -> c as a -> 0), reflects from the fixed
   vehicle end and comes back through the now taut cable at exactly c. Times are half-level
   crossings of the end tensions at every substep; 1% on both travel times.
"""

import numpy as np
import pytest

from tether_sim.scenarios import harness
from tether_sim.scenarios import references as ref

L, EA, GAMMA0 = 10.0, 1.0e5, 1.0
C = ref.axial_wave_speed(EA, GAMMA0)  # 316 m/s, L/c = 31.6 ms


def flat(end_distance, n_elements=10, order=4):
    return {
        "solver": "dg", "dg.n_elements": n_elements, "dg.order": order,
        "cable.length": L, "cable.EA": EA, "cable.gamma0": GAMMA0, "cable.density": 1000.0,
        "cable.material": "bilinear", "cable.damping": 0.0, "cable.EI": 0.0,
        "environment.g": 0.0, "environment.fluid_density": 0.0,
        "ship_end.kind": "prescribed", "ship_end.position": [0.0, 0.0, 0.0],
        "vehicle_end.kind": "fixed", "vehicle_end.position": [end_distance, 0.0, 0.0],
        "initial.kind": "straight",
    }


def test_slack_snap_cycles_stay_finite_and_non_negative():
    eps0 = 1e-3
    amp, freq = 3 * eps0 * L, 3.0
    config, solver = harness.make_solver(flat(L * (1 + eps0)))

    def motion(t):  # toward the vehicle (slackening) first, then away (snap)
        return {"ship": ([amp * np.sin(2 * np.pi * freq * t), 0.0, 0.0],
                         [2 * np.pi * freq * amp * np.cos(2 * np.pi * freq * t), 0.0, 0.0])}

    res = harness.run_sampled(solver, np.arange(0.002, 1.0, 0.002), arc_lengths=np.linspace(0, L, 41), motion=motion)
    peak = max(res["sub_ship"].max(), res["sub_vehicle"].max())
    for key in ("position", "velocity", "tension", "strain", "ship_force", "vehicle_force"):
        assert np.all(np.isfinite(res[key])), key
    assert np.all(res["tension"] >= 0.0)
    assert min(res["sub_ship"].min(), res["sub_vehicle"].min()) >= -1e-6 * peak
    assert res["strain"].min() < 0.0 and np.mean(res["tension"] == 0.0) > 0.05  # really went slack
    assert peak > 2 * EA * eps0  # and snapped above the initial tension


def test_snap_front_speed():
    a, V = 1e-3, 0.02 * C
    S, e1 = ref.snap_front_speed(EA, GAMMA0, V, -a)
    config, solver = harness.make_solver(flat(L * (1 - a)))
    t_start, ramp = 1e-3, 1e-4

    def motion(t):
        if t <= t_start:
            return {"ship": ([0.0, 0.0, 0.0], [0.0, 0.0, 0.0])}
        return {"ship": ([-V * (t - t_start - 0.5 * ramp), 0.0, 0.0], [-V, 0.0, 0.0])}

    times = np.concatenate([[t_start, t_start + ramp], np.arange(t_start + 2e-4, t_start + 2.6 * L / C, 2e-4)])
    res = harness.run_sampled(solver, times, motion=motion, keep=("tension",))
    t, ts, tv = res["sub_t"], res["sub_ship"], res["sub_vehicle"]
    t0 = t_start + 0.5 * ramp
    # Vehicle end: 0 -> EA (e1 + V/c) when the snap front arrives and reflects.
    t_arrive = harness.crossing_time(t, tv, 0.5 * EA * (e1 + V / C))
    # Ship end: EA e1 -> EA (e1 + 2 V/c) when the reflected front, running through taut cable, returns.
    t_return = harness.crossing_time(t, ts, EA * (e1 + V / C), after=t_arrive)
    print(f"S: measured {L / (t_arrive - t0):.2f}, Rankine-Hugoniot {S:.2f}; c: measured {L / (t_return - t_arrive):.2f}, exact {C:.2f}")
    assert np.all(res["tension"] >= 0.0)
    assert t_arrive - t0 == pytest.approx(L / S, rel=0.01)
    assert t_return - t_arrive == pytest.approx(L / C, rel=0.01)
