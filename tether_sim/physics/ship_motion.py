"""Ship motion from a sea state: an RAO table and the wave components give the fairlead motion.

Conventions (docs/ship_motion.md):

- Ship axes FLU (x forward/bow, y to port, z up), right-handed, as the node's ``ship_frame``. The
  mean ship sits at the reference point P0 with heading psi0 (``motion.ship_heading``: direction the
  bow points, degrees from +x counter-clockwise). Translations surge, sway, heave are along the mean
  ship axes (the seakeeping frame, which does not yaw); rotations roll, pitch, yaw are about x, y, z
  (pitch positive bow down, yaw positive bow to port), composed without a small-angle approximation
  as R = Rz(yaw) Ry(pitch) Rx(roll).
- Wave heading beta = b - psi0: the direction a component travels toward relative to the bow
  (0 = following sea, 90 = waves travelling toward port (from starboard), 180 = head sea).
- A component with elevation a cos(omega t - psi) at P0 (psi = k (P0 . e_b) + phi) drives DOF j as
  |RAO_j| a cos(omega t - psi + eps_j): eps_j is the phase lead of the response over the wave
  elevation **at the ship's reference point**. Translations in m/m, rotations in deg/m in the file.
- The fairlead is at P0 + lever arm r (body frame) at rest: p = P0 + Rz(psi0) (xi + R r), its velocity
  Rz(psi0) (xi' + w x R r) and acceleration Rz(psi0) (xi'' + w' x R r + w x (w x R r)), with w the
  angular velocity of the Euler-angle rates.

The table is a plain-text file: ``#`` comments, then one row per (heading, frequency) of 14 numbers
``heading_deg omega_rad_s`` and (amplitude, phase_deg) for surge, sway, heave, roll, pitch, yaw. The
rows must form a full grid (every heading with the same frequencies). Between grid points amplitude
and phase are interpolated linearly (phase along the shorter arc), heading periodically over 360 deg.
A wave component outside the table's frequency range is refused (the table must cover the sea).
"""

import math
from dataclasses import dataclass

import numpy as np

from tether_sim.paths import resolve_data_path


@dataclass(frozen=True)
class RaoTable:
    """RAOs on a (heading, frequency) grid: ``amp`` (nh, nw, 6) in m/m and rad/m, ``phase`` (nh, nw, 6) rad."""

    headings: np.ndarray  # deg, increasing in [0, 360)
    omegas: np.ndarray  # rad/s, increasing
    amp: np.ndarray
    phase: np.ndarray


def parse_rao_table(text: str, source: str = "RAO table") -> RaoTable:
    """A :class:`RaoTable` from the plain-text format of the module doc (clear errors on bad input)."""
    rows = []
    for number, line in enumerate(text.splitlines(), 1):
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        try:
            values = [float(v) for v in line.split()]
        except ValueError as exc:
            raise ValueError(f"{source}: line {number}: not a number ({exc})") from None
        if len(values) != 14:
            raise ValueError(f"{source}: line {number}: expected 14 columns (heading, omega, 6 x (amp, phase)), got {len(values)}")
        rows.append(values)
    if not rows:
        raise ValueError(f"{source}: no data rows")
    data = np.asarray(rows)
    if not np.all(np.isfinite(data)):
        raise ValueError(f"{source}: non-finite values")
    heading = np.mod(data[:, 0], 360.0)
    headings, omegas = np.unique(heading), np.unique(data[:, 1])
    if omegas[0] <= 0.0:
        raise ValueError(f"{source}: frequencies must be positive (rad/s)")
    if len(rows) != headings.size * omegas.size:
        raise ValueError(f"{source}: rows do not form a full grid ({headings.size} headings x {omegas.size} "
                         f"frequencies needs {headings.size * omegas.size} rows, got {len(rows)})")
    amp = np.full((headings.size, omegas.size, 6), np.nan)
    phase = np.full_like(amp, np.nan)
    ih, iw = np.searchsorted(headings, heading), np.searchsorted(omegas, data[:, 1])
    amp[ih, iw], phase[ih, iw] = data[:, 2::2], np.radians(data[:, 3::2])
    if np.isnan(amp).any():
        raise ValueError(f"{source}: a (heading, frequency) pair appears twice")
    if np.any(amp < 0.0):
        raise ValueError(f"{source}: negative RAO amplitude")
    amp[:, :, 3:] = np.radians(amp[:, :, 3:])  # rotations: deg/m -> rad/m
    return RaoTable(headings, omegas, amp, phase)


def read_rao_table(path) -> RaoTable:
    """The RAO table in ``path`` (absolute, or relative to the working directory, repository or share)."""
    return parse_rao_table(resolve_data_path(path, "motion.rao_path").read_text(), f"RAO table {path}")


def _wrap(angle):
    return (angle + np.pi) % (2.0 * np.pi) - np.pi


def _blend(amp0, ph0, amp1, ph1, w):
    """Linear interpolation of amplitude and of phase along the shorter arc."""
    return amp0 + w * (amp1 - amp0), ph0 + w * _wrap(ph1 - ph0)


def rao_at(table: RaoTable, omega: float, heading_deg: float):
    """(amplitude (6,), phase (6,) rad) of the RAO at frequency ``omega`` and wave heading (deg)."""
    w_lo, w_hi = table.omegas[0], table.omegas[-1]
    if not (w_lo - 1e-12 <= omega <= w_hi + 1e-12):
        raise ValueError(f"RAO table covers {w_lo:g}-{w_hi:g} rad/s; a wave component has {omega:.4g} rad/s "
                         "(extend the table or narrow waves.min/max_frequency_ratio)")
    if table.omegas.size == 1:
        jw, fw = 0, 0.0
    else:
        jw = int(np.clip(np.searchsorted(table.omegas, omega) - 1, 0, table.omegas.size - 2))
        fw = (omega - table.omegas[jw]) / (table.omegas[jw + 1] - table.omegas[jw])
        fw = min(max(fw, 0.0), 1.0)

    def at_heading(i):
        if table.omegas.size == 1:
            return table.amp[i, 0], table.phase[i, 0]
        return _blend(table.amp[i, jw], table.phase[i, jw], table.amp[i, jw + 1], table.phase[i, jw + 1], fw)

    h, hs = heading_deg % 360.0, table.headings
    if hs.size == 1:
        return at_heading(0)
    i1 = int(np.searchsorted(hs, h, side="right")) % hs.size
    i0 = (i1 - 1) % hs.size
    span = (hs[i1] - hs[i0]) % 360.0
    fh = ((h - hs[i0]) % 360.0) / span
    a0, p0 = at_heading(i0)
    a1, p1 = at_heading(i1)
    return _blend(a0, p0, a1, p1, fh)


def _rot(axis, angle):
    c, s = math.cos(angle), math.sin(angle)
    if axis == 0:
        return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
    if axis == 1:
        return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


class ShipResponse:
    """The 6-DOF response of the ship to the wave components (sums of cosines, exact derivatives)."""

    def __init__(self, table: RaoTable, waves, reference, heading_deg):
        self.reference = np.asarray(reference, float).reshape(3)
        self.heading = math.radians(float(heading_deg))
        self.rz0 = _rot(2, self.heading)  # the mean heading's rotation (the same numbers on every call)
        keep = waves.amp > 0.0
        amp, om, k = waves.amp[keep], waves.omega[keep], waves.k[keep]
        cb, sb, phi = waves.cos_dir[keep], waves.sin_dir[keep], waves.phase[keep]
        self.omega = om
        self.coef = np.zeros((om.size, 6))
        self.theta0 = np.zeros((om.size, 6))
        for n in range(om.size):
            beta = math.degrees(math.atan2(sb[n], cb[n]) - self.heading)
            r_amp, r_phase = rao_at(table, float(om[n]), beta)
            psi = k[n] * (self.reference[0] * cb[n] + self.reference[1] * sb[n]) + phi[n]
            self.coef[n] = amp[n] * r_amp
            self.theta0[n] = psi - r_phase  # DOF j: coef cos(theta0 - omega t)

    def dofs(self, t: float, acceleration: bool = True):
        """(q, q', q'') (6,) each: surge, sway, heave [m], roll, pitch, yaw [rad] and their rates;
        ``acceleration=False``: q'' is None (not computed; q and q' are the same numbers)."""
        arg = self.theta0 - self.omega[:, None] * t
        c, s = np.cos(arg), np.sin(arg)
        w = self.omega
        q = w @ (self.coef * s)  # (n,) @ (n, 6)
        cc = self.coef * c
        return cc.sum(0), q, (-(w * w) @ cc if acceleration else None)


def _cross_many(a, b):
    """Row-wise a x b for (k, 3) arrays, element for element the operations of :func:`_cross`."""
    return np.stack([a[:, 1] * b[:, 2] - a[:, 2] * b[:, 1], a[:, 2] * b[:, 0] - a[:, 0] * b[:, 2],
                     a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]], axis=1)


def _rot_many(axis, angles):
    """(k, 3, 3) rotation matrices of :func:`_rot` for the angles (k,) (math.cos and math.sin, as there:
    numpy's vectorised ones may differ in the last bit)."""
    c = np.array([math.cos(a) for a in angles])
    s = np.array([math.sin(a) for a in angles])
    out = np.zeros((angles.size, 3, 3))
    i, j = [(1, 2), (0, 2), (0, 1)][axis]
    out[:, axis, axis] = 1.0
    out[:, i, i], out[:, j, j] = c, c
    if axis == 1:
        out[:, 0, 2], out[:, 2, 0] = s, -s
    else:
        out[:, i, j], out[:, j, i] = -s, s
    return out


def fairlead_position_velocity_many(response: ShipResponse, lever, ts):
    """(positions (k, 3), velocities (k, 3)) of :func:`fairlead_offset` at the times ``ts`` (k,) in one
    pass: the same floating-point operations element for element (elementwise ufuncs, and the same
    matrix products per time: numpy's stacked matmul multiplies slice by slice), so the numbers are
    those of k calls (checked bit for bit in test/physics/test_ship_motion.py); a forecast's members
    evaluate a whole horizon at once with it."""
    ts = np.asarray(ts, float).reshape(-1)
    k = ts.size
    arg = response.theta0[None, :, :] - response.omega[None, :, None] * ts[:, None, None]  # (k, n, 6)
    c, s = np.cos(arg), np.sin(arg)
    w = response.omega
    qd = np.matmul(w, response.coef[None] * s)  # (k, 6): per slice (n,) @ (n, 6)
    q = (response.coef[None] * c).sum(1)
    roll, pitch, yaw = q[:, 3], q[:, 4], q[:, 5]
    rd, pd, yd = qd[:, 3], qd[:, 4], qd[:, 5]
    Rz = _rot_many(2, yaw)
    Rzy = np.matmul(Rz, _rot_many(1, pitch))
    R = np.matmul(Rzy, _rot_many(0, roll))
    ez = np.array([0.0, 0.0, 1.0])
    ey_r, ex_r = Rz[:, :, 1], Rzy[:, :, 0]
    wv = (yd[:, None] * ez + pd[:, None] * ey_r) + rd[:, None] * ex_r
    r = np.matmul(R, lever)
    pos = np.matmul(response.rz0, (q[:, :3] + r - lever)[:, :, None])[:, :, 0]
    vel = np.matmul(response.rz0, (qd[:, :3] + _cross_many(wv, r))[:, :, None])[:, :, 0]
    return pos, vel


def _cross(a, b):
    """a x b for (3,) arrays (np.cross costs ~10x more on single vectors)."""
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


def lever_arm_kinematics(q, qd, qdd, lever):
    """(R r, w, w') for rotations (roll, pitch, yaw) = q[3:] composed R = Rz Ry Rx, Euler rates qd[3:],
    qdd[3:]; w and w' are the angular velocity and acceleration in the mean ship axes (``qdd`` None:
    w' is None, not computed)."""
    roll, pitch, yaw = q[3:]
    rd, pd, yd = qd[3:]
    Rz = _rot(2, yaw)
    Rzy = Rz @ _rot(1, pitch)
    R = Rzy @ _rot(0, roll)
    ez = np.array([0.0, 0.0, 1.0])
    ey_r, ex_r = Rz[:, 1], Rzy[:, 0]
    w_zy = yd * ez + pd * ey_r
    w = w_zy + rd * ex_r
    if qdd is None:
        return R @ lever, w, None
    rdd, pdd, ydd = qdd[3:]
    dw = ydd * ez + pdd * ey_r + pd * _cross(yd * ez, ey_r) + rdd * ex_r + rd * _cross(w_zy, ex_r)
    return R @ lever, w, dw


def fairlead_offset(response: ShipResponse, lever, t, acceleration: bool = True):
    """Fairlead (offset from its mean position, velocity, acceleration) in world axes at time t;
    ``acceleration=False``: the acceleration is None, not computed (a forecast's members command
    position and velocity only; the other two are the same numbers)."""
    q, qd, qdd = response.dofs(t, acceleration)
    r, w, dw = lever_arm_kinematics(q, qd, qdd, lever)
    Rz0 = response.rz0
    pos = Rz0 @ (q[:3] + r - lever)
    vel = Rz0 @ (qd[:3] + _cross(w, r))
    if not acceleration:
        return pos, vel, None
    acc = Rz0 @ (qdd[:3] + _cross(dw, r) + _cross(w, _cross(w, r)))
    return pos, vel, acc
