"""The coupling step of a network body in two compiled calls (numerics/jit.py style: plain numba
functions over arrays, nothing allocated).

They do what :class:`tether_sim.network.body.NetworkBody` does with small numpy arrays (its
``loads``, ``accelerations``, ``kick``, ``drift``, ``predicted_end_state`` and
``attachment_points``; those methods stay the readable reference, and
test/network/test_network_dynamics.py checks these kernels against them): the same formulas in the
same order, written out on scalars. numpy's 3 x 3 products may sum in another order (BLAS), so the
two agree to round-off, not bit for bit.

- :func:`kdk_open`: the first half kick with the line loads at t_n, the drift, and the attachment
  points' positions and velocities of the predicted end state (the lines' end targets);
- :func:`kdk_close`: the closing half kick with the new line loads (velocity-dependent loads at the
  end velocities of a trial kick).

``prm`` (N_BP,): mass + added mass per body axis, inertia + added inertia, rotational damping,
0.5 rho Cd A per body axis, wet weight. ``loads`` (n_lines, 2, 7): every line's end loads (the
columns of solvers/base.py: force, axial tension, moment), ``rows`` (k, 2): the (line, end) of each
attachment. ``impulse`` (3, 3): line, weight and drag impulses. ``work`` (3, 13): scratch (loads, accelerations, the trial state).
"""

import math

from tether_sim.numerics.jit import jit
from tether_sim.numerics.rotations import quaternion_rotation
from tether_sim.solvers.base import LOAD_F, LOAD_M

BP_MASS, BP_INERTIA, BP_ROT_DAMPING, BP_DRAG, BP_WET = 0, 3, 6, 9, 12
N_BP = 13
IMP_LINES, IMP_WEIGHT, IMP_DRAG = 0, 1, 2


@jit
def _loads(s, att, loads, rows, prm, fluid, out):
    """out[0:3] net force, [3:6] moment about the CoG (world), [6:9] line force, [9:12] drag
    (NetworkBody.loads; the weight is (0, 0, -wet weight))."""
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = quaternion_rotation(s[3], s[4], s[5], s[6])
    fx = fy = fz = 0.0
    cx = cy = cz = 0.0
    sx = sy = sz = 0.0
    for j in range(att.shape[0]):
        a0, a1, a2 = att[j, 0], att[j, 1], att[j, 2]
        l0 = a0 * r00 + a1 * r01 + a2 * r02  # lever = att @ R.T
        l1 = a0 * r10 + a1 * r11 + a2 * r12
        l2 = a0 * r20 + a1 * r21 + a2 * r22
        row = loads[rows[j, 0], rows[j, 1]]
        f0, f1, f2 = row[LOAD_F], row[LOAD_F + 1], row[LOAD_F + 2]
        fx += f0
        fy += f1
        fz += f2
        cx += l1 * f2 - l2 * f1
        cy += l2 * f0 - l0 * f2
        cz += l0 * f1 - l1 * f0
        sx += row[LOAD_M]
        sy += row[LOAD_M + 1]
        sz += row[LOAD_M + 2]
    mx, my, mz = cx + sx, cy + sy, cz + sz
    u0, u1, u2 = s[7] - fluid[0], s[8] - fluid[1], s[9] - fluid[2]
    b0 = r00 * u0 + r10 * u1 + r20 * u2  # vb = R.T @ (v - fluid)
    b1 = r01 * u0 + r11 * u1 + r21 * u2
    b2 = r02 * u0 + r12 * u1 + r22 * u2
    d0 = -prm[BP_DRAG] * abs(b0) * b0
    d1 = -prm[BP_DRAG + 1] * abs(b1) * b1
    d2 = -prm[BP_DRAG + 2] * abs(b2) * b2
    gx = r00 * d0 + r01 * d1 + r02 * d2  # f_drag = R @ (...)
    gy = r10 * d0 + r11 * d1 + r12 * d2
    gz = r20 * d0 + r21 * d1 + r22 * d2
    w = -prm[BP_WET]
    out[0] = fx + 0.0 + gx
    out[1] = fy + 0.0 + gy
    out[2] = fz + w + gz
    out[3], out[4], out[5] = mx, my, mz
    out[6], out[7], out[8] = fx, fy, fz
    out[9], out[10], out[11] = gx, gy, gz


@jit
def _accelerations(s, prm, lo, acc):
    """acc[0:3] CoG acceleration, acc[3:6] angular acceleration (world) for the loads lo
    (NetworkBody.accelerations)."""
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = quaternion_rotation(s[3], s[4], s[5], s[6])
    F0, F1, F2, M0, M1, M2 = lo[0], lo[1], lo[2], lo[3], lo[4], lo[5]
    p0 = (r00 * F0 + r10 * F1 + r20 * F2) / prm[BP_MASS]
    p1 = (r01 * F0 + r11 * F1 + r21 * F2) / prm[BP_MASS + 1]
    p2 = (r02 * F0 + r12 * F1 + r22 * F2) / prm[BP_MASS + 2]
    acc[0] = r00 * p0 + r01 * p1 + r02 * p2
    acc[1] = r10 * p0 + r11 * p1 + r12 * p2
    acc[2] = r20 * p0 + r21 * p1 + r22 * p2
    w0 = r00 * s[10] + r10 * s[11] + r20 * s[12]  # wb = R.T @ omega
    w1 = r01 * s[10] + r11 * s[11] + r21 * s[12]
    w2 = r02 * s[10] + r12 * s[11] + r22 * s[12]
    t0 = r00 * M0 + r10 * M1 + r20 * M2  # tb = R.T @ M
    t1 = r01 * M0 + r11 * M1 + r21 * M2
    t2 = r02 * M0 + r12 * M1 + r22 * M2
    I0, I1, I2 = prm[BP_INERTIA], prm[BP_INERTIA + 1], prm[BP_INERTIA + 2]
    h0, h1, h2 = I0 * w0, I1 * w1, I2 * w2
    q0 = (t0 - (w1 * h2 - w2 * h1) - prm[BP_ROT_DAMPING] * w0) / I0
    q1 = (t1 - (w2 * h0 - w0 * h2) - prm[BP_ROT_DAMPING + 1] * w1) / I1
    q2 = (t2 - (w0 * h1 - w1 * h0) - prm[BP_ROT_DAMPING + 2] * w2) / I2
    acc[3] = r00 * q0 + r01 * q1 + r02 * q2
    acc[4] = r10 * q0 + r11 * q1 + r12 * q2
    acc[5] = r20 * q0 + r21 * q1 + r22 * q2


@jit
def _record(impulse, dt, lo, wet):
    impulse[IMP_LINES, 0] += dt * lo[6]
    impulse[IMP_LINES, 1] += dt * lo[7]
    impulse[IMP_LINES, 2] += dt * lo[8]
    impulse[IMP_WEIGHT, 0] += dt * 0.0
    impulse[IMP_WEIGHT, 1] += dt * 0.0
    impulse[IMP_WEIGHT, 2] += dt * -wet
    impulse[IMP_DRAG, 0] += dt * lo[9]
    impulse[IMP_DRAG, 1] += dt * lo[10]
    impulse[IMP_DRAG, 2] += dt * lo[11]


@jit
def _rotate_world(s, p0, p1, p2):
    """s[3:7] = exp(phi) applied on the world side (body.quat_rotate_world), normalised."""
    a = math.sqrt(p0 * p0 + p1 * p1 + p2 * p2)
    if a == 0.0:
        return
    f = math.sin(0.5 * a) / a
    px, py, pz, pw = p0 * f, p1 * f, p2 * f, math.cos(0.5 * a)
    x, y, z, w = s[3], s[4], s[5], s[6]
    o0 = pw * x + px * w + py * z - pz * y
    o1 = pw * y - px * z + py * w + pz * x
    o2 = pw * z + px * y - py * x + pz * w
    o3 = pw * w - px * x - py * y - pz * z
    n = math.sqrt(o0 * o0 + o1 * o1 + o2 * o2 + o3 * o3)
    s[3], s[4], s[5], s[6] = o0 / n, o1 / n, o2 / n, o3 / n


@jit
def kdk_open(state, att, loads, rows, prm, fluid, dt, impulse, work, targets):
    """Half kick by dt / 2 with the loads at t_n, drift by dt, and targets (k, 6): the attachment
    points' positions and velocities of the end state predicted with the same loads."""
    h = 0.5 * dt
    lo, acc = work[0], work[1]
    _loads(state, att, loads, rows, prm, fluid, lo)
    _accelerations(state, prm, lo, acc)
    for c in range(3):
        state[7 + c] += h * acc[c]
    for c in range(3):
        state[10 + c] += h * acc[3 + c]
    _record(impulse, h, lo, prm[BP_WET])
    for c in range(3):
        state[c] += dt * state[7 + c]
    _rotate_world(state, dt * state[10], dt * state[11], dt * state[12])
    _loads(state, att, loads, rows, prm, fluid, lo)
    _accelerations(state, prm, lo, acc)
    v0, v1, v2 = state[7] + h * acc[0], state[8] + h * acc[1], state[9] + h * acc[2]
    o0, o1, o2 = state[10] + h * acc[3], state[11] + h * acc[4], state[12] + h * acc[5]
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = quaternion_rotation(state[3], state[4], state[5], state[6])
    for j in range(att.shape[0]):
        a0, a1, a2 = att[j, 0], att[j, 1], att[j, 2]
        l0 = a0 * r00 + a1 * r01 + a2 * r02
        l1 = a0 * r10 + a1 * r11 + a2 * r12
        l2 = a0 * r20 + a1 * r21 + a2 * r22
        targets[j, 0] = state[0] + l0
        targets[j, 1] = state[1] + l1
        targets[j, 2] = state[2] + l2
        targets[j, 3] = v0 + (o1 * l2 - o2 * l1)
        targets[j, 4] = v1 + (o2 * l0 - o0 * l2)
        targets[j, 5] = v2 + (o0 * l1 - o1 * l0)


@jit
def kdk_close(state, att, loads, rows, prm, fluid, dt, impulse, work):
    """The closing half kick by dt / 2 with the new line loads; drag, gyroscopic and damping
    moments at the end velocities of a trial kick (NetworkBody.kick with closing)."""
    h = 0.5 * dt
    lo, acc = work[0], work[1]
    _loads(state, att, loads, rows, prm, fluid, lo)
    _accelerations(state, prm, lo, acc)
    v = work[2]
    for c in range(13):
        v[c] = state[c]
    for c in range(3):
        v[7 + c] += h * acc[c]
    for c in range(3):
        v[10 + c] += h * acc[3 + c]
    _loads(v, att, loads, rows, prm, fluid, lo)
    _accelerations(v, prm, lo, acc)
    for c in range(3):
        state[7 + c] += h * acc[c]
    for c in range(3):
        state[10 + c] += h * acc[3 + c]
    _record(impulse, h, lo, prm[BP_WET])


body_loads = _loads  # out[0:3] net force, [3:6] moment, [6:9] line force, [9:12] drag (NetworkSolver.body_motion)
body_accelerations = _accelerations  # acc[0:6] of those loads (NetworkSolver.body_motion)
