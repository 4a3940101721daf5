"""Rotations: the matrix of a unit quaternion, and the incremental rotations of body-fixed frames
[GP Eq. 15-18] (Bottasso & Borri 1998).

``L`` is the 3x3 tensor taking inertial components to body components (v_body = L @ v_world).
A frame turning with angular velocity omega (body components) over a step changes as
L(t) = Phi L(t - dt), Phi = exp(-skew(theta)), theta ~ omega*dt [GP Eq. 15-16], with the closed
form exponential of Eq. 18 (no matrix power series).
"""

import math

import numpy as np

from tether_sim.numerics.jit import jit, jit_alloc


@jit
def quaternion_rotation(x, y, z, w):
    """R (body -> world) of the quaternion (x, y, z, w), normalised here, as 9 scalars, row major
    (scalars, not an array: the per-stage body kernels allocate nothing)."""
    n = math.sqrt(x * x + y * y + z * z + w * w)
    x, y, z, w = x / n, y / n, z / n, w / n
    return (1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y - z * w), 2.0 * (x * z + y * w),
            2.0 * (x * y + z * w), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z - x * w),
            2.0 * (x * z - y * w), 2.0 * (y * z + x * w), 1.0 - 2.0 * (x * x + y * y))


def quaternion_matrix(q) -> np.ndarray:
    """R (3, 3), body -> world, of the quaternion q = (x, y, z, w), normalised (quaternion_rotation)."""
    x, y, z, w = (float(c) for c in q)
    plain = getattr(quaternion_rotation, "py_func", quaternion_rotation)  # no compiled call from Python
    return np.array(plain(x, y, z, w)).reshape(3, 3)


@jit
def skew(x, out):
    """out = x~ with x~ y = x cross y [GP Eq. 17]."""
    out[0, 0] = 0.0
    out[0, 1] = -x[2]
    out[0, 2] = x[1]
    out[1, 0] = x[2]
    out[1, 1] = 0.0
    out[1, 2] = -x[0]
    out[2, 0] = -x[1]
    out[2, 1] = x[0]
    out[2, 2] = 0.0


@jit
def exp_skew(x, out):
    """out = exp(x~) = I + u~ sin|x| + u~^2 (1 - cos|x|) [GP Eq. 18] (series for tiny |x|)."""
    n2 = x[0] * x[0] + x[1] * x[1] + x[2] * x[2]
    n = math.sqrt(n2)
    if n < 1e-6:
        a = 1.0 - n2 / 6.0
        b = 0.5 - n2 / 24.0
    else:
        a = math.sin(n) / n
        b = (1.0 - math.cos(n)) / n2
    # x~^2 = x x^T - |x|^2 I
    for i in range(3):
        for j in range(3):
            out[i, j] = b * x[i] * x[j]
        out[i, i] += 1.0 - b * n2
    out[0, 1] -= a * x[2]
    out[0, 2] += a * x[1]
    out[1, 0] += a * x[2]
    out[1, 2] -= a * x[0]
    out[2, 0] -= a * x[1]
    out[2, 1] += a * x[0]


@jit_alloc
def rotate_frame(L_old, theta, out):
    """out = exp(-theta~) @ L_old: incremental frame update [GP Eq. 15-16], theta in body components."""
    mt = np.empty(3)
    for k in range(3):
        mt[k] = -theta[k]
    phi = np.empty((3, 3))
    exp_skew(mt, phi)
    for i in range(3):
        for j in range(3):
            acc = 0.0
            for k in range(3):
                acc += phi[i, k] * L_old[k, j]
            out[i, j] = acc


def frame_with_tangent(t, reference=None) -> np.ndarray:
    """L (world -> body) whose first body axis is the unit tangent t.

    The roll about t is fixed by the minimal rotation from ``reference`` (a previous L), or from the
    world frame when none is given, so successive calls do not add twist.
    """
    t = np.asarray(t, dtype=float)
    t = t / np.linalg.norm(t)
    if reference is None:
        reference = np.eye(3)
    a1 = np.asarray(reference, dtype=float)[0]
    rot = minimal_rotation(a1, t)
    return np.asarray(reference, dtype=float) @ rot.T


def minimal_rotation(a, b) -> np.ndarray:
    """Rotation matrix R (world components) with R a = b along the great circle (unit vectors)."""
    a = np.asarray(a, dtype=float) / np.linalg.norm(a)
    b = np.asarray(b, dtype=float) / np.linalg.norm(b)
    axis = np.cross(a, b)
    s = np.linalg.norm(axis)
    c = float(np.dot(a, b))
    if s < 1e-12:
        if c > 0:
            return np.eye(3)
        perp = np.cross(a, [1.0, 0.0, 0.0])
        if np.linalg.norm(perp) < 1e-6:
            perp = np.cross(a, [0.0, 1.0, 0.0])
        perp /= np.linalg.norm(perp)
        out = np.empty((3, 3))
        exp_skew(np.pi * perp, out)
        return out
    out = np.empty((3, 3))
    exp_skew(axis / s * math.atan2(s, c), out)
    return out


def rotation_vector(R) -> np.ndarray:
    """Inverse of Eq. 18: the vector x with exp(x~) = R (|x| < pi)."""
    R = np.asarray(R, dtype=float)
    c = max(-1.0, min(1.0, 0.5 * (np.trace(R) - 1.0)))
    ang = math.acos(c)
    w = 0.5 * np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    if ang < 1e-8:
        return w
    return w * ang / math.sin(ang)
