"""Per-point hydrodynamic kernels [PE2020 Eq. 13-14, 17]."""

import math

import numpy as np
import pytest

from tether_sim.physics.cable import CableProperties
from tether_sim.physics.environment import Environment
from tether_sim.physics.hydrodynamics import (
    add_morison_drag, added_mass_per_length, buoyancy_vector, current_at, current_table, solve_added_mass,
)


def test_drag_splits_tangential_and_normal_with_sqrt_l():
    i = np.array([1.0, 0.0, 0.0])
    nu = np.array([-2.0, 0.0, 3.0])  # relative flow v* = -nu = (2, 0, -3)
    out = np.zeros(3)
    add_morison_drag(i, 1.21, nu, np.zeros(3), 0.5 * 1000.0 * 0.1, 0.02, 1.2, out)
    k = 0.5 * 1000.0 * 0.1 * math.sqrt(1.21)
    assert np.allclose(out, [k * 0.02 * 2.0 * 2.0, 0.0, -k * 1.2 * 3.0 * 3.0])


def test_drag_uses_relative_velocity_to_current():
    i = np.array([0.0, 0.0, 1.0])
    out = np.zeros(3)
    add_morison_drag(i, 1.0, np.array([0.5, 0.0, 0.0]), np.array([0.5, 0.0, 0.0]), 10.0, 1.0, 1.0, out)
    assert np.allclose(out, 0.0)  # moving with the current: no drag


def test_added_mass_solved_per_direction():
    i = np.array([0.6, 0.8, 0.0])
    F = np.array([3.0, -1.0, 2.0])
    out = np.zeros(3)
    g0, mt, mn = 2.0, 0.5, 3.0
    solve_added_mass(i, F, g0, mt, mn, out)
    a = out / g0
    Fpar = np.dot(F, i) * i
    # (gamma0 + m_t) a_par = F_par and (gamma0 + m_n) a_perp = F_perp
    assert np.allclose((g0 + mt) * np.dot(a, i) * i, Fpar)
    assert np.allclose((g0 + mn) * (a - np.dot(a, i) * i), F - Fpar)


def test_buoyancy_and_added_mass_coefficients():
    cab = CableProperties(gamma0=3.01, density=7153.0, diameter=0.03, Cmn=1.0, Cmt=0.0)
    env = Environment(g=9.81, fluid_density=1025.0)
    fb = buoyancy_vector(cab, env)
    assert fb[2] == pytest.approx(cab.area * 9.81 * (1025.0 - 7153.0))  # Eq. 14
    mt, mn = added_mass_per_length(cab, env)
    assert mt == 0.0 and mn == pytest.approx(1025.0 * math.pi * 0.03**2 / 4)


def test_current_profile_interpolates_in_depth():
    env = Environment(current_z=(-100.0, 0.0), current_x=(0.0, 1.0), current_y=(0.5, 0.5))
    cz, cx, cy = current_table(env)
    out = np.zeros(3)
    current_at(-25.0, cz, cx, cy, out)
    assert np.allclose(out, [0.75, 0.5, 0.0])
    current_at(-500.0, cz, cx, cy, out)
    assert np.allclose(out, [0.0, 0.5, 0.0])
    with pytest.raises(ValueError, match="current_z"):
        current_table(Environment(current_z=(0.0, -1.0), current_x=(0.0, 0.0), current_y=(0.0, 0.0)))
