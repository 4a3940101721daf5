"""Incremental rotations [GP Eq. 15-18]."""

import numpy as np

from tether_sim.numerics.rotations import (exp_skew, frame_with_tangent, minimal_rotation, rotate_frame,
                                           rotation_vector, skew)


def test_skew_is_the_cross_product():
    x, y = np.array([0.3, -1.2, 2.0]), np.array([1.0, 0.5, -0.7])
    S = np.empty((3, 3))
    skew(x, S)
    assert np.allclose(S @ y, np.cross(x, y))


def test_exp_skew_is_a_rotation_by_the_vector_angle():
    rng = np.random.default_rng(1)
    for x in [np.zeros(3), 1e-8 * np.ones(3), rng.normal(size=3), np.array([0.0, 0.0, np.pi / 2])]:
        R = np.empty((3, 3))
        exp_skew(x, R)
        assert np.allclose(R @ R.T, np.eye(3), atol=1e-14)
        assert np.isclose(np.linalg.det(R), 1.0)
        assert np.allclose(R @ x, x)  # the axis is fixed
        assert np.allclose(rotation_vector(R), x, atol=1e-12)
    R = np.empty((3, 3))
    exp_skew(np.array([0.0, 0.0, np.pi / 2]), R)
    assert np.allclose(R @ [1.0, 0.0, 0.0], [0.0, 1.0, 0.0])


def test_incremental_frame_update_follows_a_constant_spin():
    # d L/dt = -omega~ L: after n steps of exp(-omega~ dt) the frame has turned by omega*t (exactly)
    L = frame_with_tangent([1.0, 1.0, 0.0])
    omega = np.array([0.2, -0.1, 0.4])  # body components
    out = np.empty((3, 3))
    L0 = L.copy()
    for _ in range(50):
        rotate_frame(L, 0.01 * omega, out)
        L = out.copy()
    assert np.allclose(rotation_vector(L @ L0.T), -0.5 * omega, atol=1e-12)


def test_minimal_rotation_and_frame_with_tangent():
    a, b = np.array([0.0, 0.0, -1.0]), np.array([0.6, 0.0, -0.8])
    assert np.allclose(minimal_rotation(a, b) @ a, b)
    assert np.allclose(minimal_rotation(a, -a) @ a, -a)
    L = frame_with_tangent([0.0, 0.0, -1.0])  # vertical tether: no singularity
    assert np.allclose(L[0], [0.0, 0.0, -1.0]) and np.allclose(L @ L.T, np.eye(3))
