"""Seabed contact [PE2020 Eq. 15-16]."""

import math

import numpy as np
import pytest

from tether_sim.physics.seabed import add_seabed_force


def test_spring_balances_weight_at_w_over_Kd():
    Kd, w = 3e6 * 0.03, 25.0
    out = np.zeros(3)
    add_seabed_force(-100.0 - w / Kd, np.zeros(3), 1.0, -100.0, Kd, 1.0, 1.0, 0.0, 0.01, -w, out)
    assert np.allclose(out, [0.0, 0.0, w])
    out[:] = 0.0
    add_seabed_force(-99.0, np.zeros(3), 1.0, -100.0, Kd, 1.0, 1.0, 0.0, 0.01, -w, out)
    assert np.all(out == 0.0)  # above the seabed: no contact


def test_friction_opposes_sliding_and_saturates():
    out = np.zeros(3)
    nu = np.array([0.3, -0.4, 0.0])
    mu, w = 0.5, 25.0
    add_seabed_force(-100.01, nu, 1.0, -100.0, 0.0, 0.0, 0.0, mu, 0.01, -w, out)
    f = out[:2]
    assert np.dot(f, nu[:2]) < 0 and abs(f[0] * nu[1] - f[1] * nu[0]) < 1e-12
    assert np.linalg.norm(f) == pytest.approx(mu * w * math.tanh(math.pi * 0.5 / 0.01))
    out[:] = 0.0
    add_seabed_force(-100.01, nu * 1e-4, 1.0, -100.0, 0.0, 0.0, 0.0, mu, 0.01, -w, out)
    assert np.linalg.norm(out[:2]) < 0.1 * mu * w  # below v_mu: regularised, proportional to speed


def test_damping_opposes_vertical_velocity():
    Kd = 1e5
    out = np.zeros(3)
    add_seabed_force(-100.001, np.array([0.0, 0.0, -0.1]), 1.0, -100.0, Kd, 2 * math.sqrt(Kd * 3.0), 1.0, 0.0, 0.01, -1.0, out)
    assert out[2] > Kd * 0.001
