"""Energy of an undamped free vibration never grows and is nearly conserved.

Taut string (linear law, no gravity, no fluid, no damping). The ship end makes one smooth
transverse Gaussian excursion and then stays fixed, after which the cable vibrates freely between
two fixed ends. Energy = int (0.5 gamma0 |nu|^2 + 0.5 EA eps^2) ds from the DG fields (Gauss
quadrature with P + 3 points per element); the vibration energy is E(t) - E(rest).

The Lax-Friedrichs flux and SSP-RK3 may only dissipate: the vibration energy must never increase
(tolerance 1e-6 of it for quadrature of the non-polynomial eps = |q| - 1) and, for this resolved
pulse (~8 nodes per pulse width), lose less than 0.1% over ten fundamental periods.
"""

import numpy as np
import pytest

from tether_sim.scenarios import harness
from tether_sim.scenarios import references as ref

L, EA, GAMMA0, EPS0 = 10.0, 2.5e3, 1.0, 0.08  # T0 = 200 N; c = 50 m/s keeps the substep large
AMP, SIGMA = 0.02, 0.15  # transverse pulse: ~2 m wide on the string, slope ~1%
T_C = 4 * SIGMA


def flat():
    return {
        "solver": "dg", "dg.n_elements": 10, "dg.order": 4,
        "cable.length": L, "cable.EA": EA, "cable.gamma0": GAMMA0, "cable.density": 1000.0,
        "cable.material": "linear", "cable.damping": 0.0, "cable.EI": 0.0,
        "environment.g": 0.0, "environment.fluid_density": 0.0,
        "ship_end.kind": "prescribed", "ship_end.position": [0.0, 0.0, 0.0],
        "vehicle_end.kind": "fixed", "vehicle_end.position": [L * (1 + EPS0), 0.0, 0.0],
        "initial.kind": "straight",
    }


def ship_motion(t):
    if t >= 2 * T_C:  # exp(-16) ~ 1e-7 of the amplitude: held exactly fixed from here on
        return {"ship": ([0.0, 0.0, 0.0], [0.0, 0.0, 0.0])}
    g, dg = ref.gaussian_pulse(t, AMP, T_C, SIGMA)
    return {"ship": ([0.0, float(g), 0.0], [0.0, float(dg), 0.0])}


def test_free_vibration_energy():
    config, solver = harness.make_solver(flat())
    s, w = harness.quadrature_points(config)
    st0 = solver.state(s)
    e_rest = harness.mechanical_energy(st0.velocity, st0.strain, st0.position, w, config)
    omega1 = ref.taut_string_frequency(1, L, EA * EPS0, GAMMA0, EPS0)
    period = 2 * np.pi / omega1
    harness.run_sampled(solver, np.arange(0.01, 2 * T_C + 1e-9, 0.01), motion=ship_motion, keep=())
    t0 = solver.time
    times = t0 + np.linspace(0.0, 10 * period, 201)[1:]
    res = harness.run_sampled(solver, times, arc_lengths=s, motion=ship_motion, keep=("velocity", "strain", "position"))
    e_vib = np.array([harness.mechanical_energy(res["velocity"][k], res["strain"][k], res["position"][k], w, config)
                      for k in range(len(times))]) - e_rest
    assert e_vib[0] > 0.0
    gains = np.diff(e_vib) / e_vib[0]
    print(f"vibration energy {e_vib[0]:.4e} J, loss over 10 periods {1 - e_vib[-1] / e_vib[0]:.3e}, max gain {gains.max():.2e}")
    assert np.all(gains < 1e-6)
    assert e_vib[-1] > (1 - 1e-3) * e_vib[0]
