"""Linear (Airy) waves: regular waves and seeded JONSWAP sea states, surface stretching, compiled evaluation.

A sea state is a sum of n linear components (docs/waves.md)

    eta(x, y, t) = sum_n a_n cos(theta_n),   theta_n = k_n (x cos b_n + y sin b_n) - omega_n t + phi_n

with b_n the direction the component travels toward (from +x counter-clockwise, world ENU, z up) and
omega_n^2 = g k_n tanh(k_n d) (d = water depth; deep water k = omega^2 / g). The particle velocity and
local acceleration du/dt of each component are the Airy ones; near the surface ``waves.stretching``
places them (STRETCHINGS, docs/waves.md): by default at the Wheeler-stretched height
z' = (z - eta) d / (d + eta) (deep water: z' = z - eta), so the kinematics at the instantaneous surface
z = eta are those linear theory gives at the mean level z = 0; or unstretched up to z = 0 (none), held
(vertical) or linearly extrapolated (extrapolation) above it. Above the surface they are zero. The
time derivative of the stretching itself is not included in du/dt (common practice; second order).

The spectrum is discretised once (``wave_components``) into the arrays of :class:`WaveComponents`; the
kernels ``wave_elevation`` / ``wave_kinematics`` sum them at a point (numba, no allocation).
"""

import math
from dataclasses import dataclass

import numpy as np

from tether_sim.numerics.jit import jit
from tether_sim.spec import param

WAVE_KINDS = ("none", "regular", "jonswap")
# kinematics near the free surface (docs/waves.md "Stretching"); the code is the index into this tuple
STRETCHINGS = ("none", "wheeler", "vertical", "extrapolation")
STRETCH_NONE, STRETCH_WHEELER, STRETCH_VERTICAL, STRETCH_EXTRAPOLATION = range(4)


@dataclass(frozen=True)
class WaveConfig:
    """Section ``waves``: the sea state acting on the cable (and on the ship through an RAO source)."""

    kind: str = param("none", doc="sea state: none, regular (one Airy wave) or jonswap (irregular, seeded)", choices=WAVE_KINDS)
    height: float = param(2.0, unit="m", doc="regular wave height H (crest to trough, amplitude H/2)", min=0.0, max=100.0)
    period: float = param(9.0, unit="s", doc="regular wave period T", min=0.1, max=100.0)
    phase: float = param(0.0, unit="deg", doc="regular wave phase phi at x = y = t = 0 (eta = H/2 cos(phi))", min=-360.0, max=360.0)
    direction: float = param(0.0, unit="deg", doc="mean direction the waves travel toward, from +x (east) counter-clockwise", min=-360.0, max=360.0)
    Hs: float = param(3.0, unit="m", doc="JONSWAP significant wave height H_s = 4 sqrt(m0)", min=0.0, max=30.0)
    Tp: float = param(9.0, unit="s", doc="JONSWAP peak period T_p", min=0.5, max=40.0)
    gamma: float = param(3.3, doc="JONSWAP peak enhancement factor gamma (1 = Pierson-Moskowitz)", min=1.0, max=10.0)
    n_frequencies: int = param(64, doc="JONSWAP frequency bins (equal width, one random frequency per bin)", min=1, max=2000)
    min_frequency_ratio: float = param(0.5, doc="lowest discretised frequency as a fraction of the peak frequency", min=0.05, max=1.0)
    max_frequency_ratio: float = param(4.0, doc="highest discretised frequency as a multiple of the peak frequency", min=1.0, max=20.0)
    n_directions: int = param(1, doc="JONSWAP directions (1 = long-crested; > 1 short-crested with cos-2s spreading)", min=1, max=180)
    spreading: float = param(10.0, doc="cos-2s spreading exponent s: D(b) ~ cos^(2s)((b - b0)/2) (n_directions > 1)", min=0.5, max=200.0)
    seed: int = param(1, doc="random seed of the JONSWAP phases and in-bin frequencies (same seed, same sea)", min=0, max=2**31 - 1)
    depth: float = param(0.0, unit="m", doc="water depth d for the dispersion relation and the kinematics (0 = deep water)", min=0.0, max=1e5)
    stretching: str = param("wheeler", doc="kinematics near the surface: wheeler (Airy at the height stretched to the instantaneous surface), none (Airy up to the mean level z = 0, still water above it), vertical (above z = 0 the values at z = 0, up to eta), extrapolation (above z = 0 linear in z from the values and slopes at z = 0, up to eta); docs/waves.md", choices=STRETCHINGS)


@dataclass(frozen=True)
class WaveComponents:
    """The discretised sea state: float64 arrays of shape (n,); n = 0 when waves are off."""

    amp: np.ndarray  # a_n [m]
    omega: np.ndarray  # omega_n [rad/s]
    k: np.ndarray  # k_n [rad/m]
    cos_dir: np.ndarray  # cos b_n (b_n: direction of travel, from +x counter-clockwise)
    sin_dir: np.ndarray  # sin b_n
    phase: np.ndarray  # phi_n [rad]
    depth: float = math.inf  # d [m] (math.inf: deep water)
    stretch: int = STRETCH_WHEELER  # index into STRETCHINGS

    @property
    def n(self) -> int:
        return int(self.amp.shape[0])

    def arrays(self):
        """(amp, omega, k, cos_dir, sin_dir, phase): the kernels' argument order."""
        return self.amp, self.omega, self.k, self.cos_dir, self.sin_dir, self.phase


def no_waves() -> WaveComponents:
    z = np.zeros(0)
    return WaveComponents(z, z.copy(), z.copy(), z.copy(), z.copy(), z.copy(), math.inf, STRETCH_WHEELER)


def wave_number(omega, g, depth=math.inf):
    """k solving omega^2 = g k tanh(k d) (Newton from the deep-water value; d = inf: k = omega^2/g)."""
    omega = np.asarray(omega, float)
    k = omega * omega / g
    if not math.isfinite(depth):
        return k
    k = np.maximum(k, omega / math.sqrt(g * depth))  # start above the root (tanh(kd) <= 1, <= kd)
    for _ in range(100):
        th = np.tanh(k * depth)
        f = g * k * th - omega * omega
        df = g * th + g * k * depth * (1.0 - th * th)
        step = f / df
        k = k - step
        if np.all(np.abs(step) <= 1e-15 * np.maximum(k, 1e-300)):
            break
    return k


def jonswap_spectrum(omega, Hs, Tp, gamma):
    """JONSWAP S(omega) [m^2 s/rad] with sigma 0.07/0.09, normalised so that its integral is Hs^2/16.

    Shape: omega^-5 exp(-5/4 (omega_p/omega)^4) gamma^exp(-(omega - omega_p)^2 / (2 sigma^2 omega_p^2));
    the normalisation is computed by quadrature (the usual closed-form 1 - 0.287 ln(gamma) is approximate).
    """
    wp = 2.0 * math.pi / Tp

    def shape(w):
        w = np.asarray(w, float)
        sigma = np.where(w <= wp, 0.07, 0.09)
        r = np.exp(-((w - wp) ** 2) / (2.0 * sigma**2 * wp**2))
        return w**-5.0 * np.exp(-1.25 * (wp / w) ** 4) * gamma**r

    fine = np.linspace(0.2 * wp, 30.0 * wp, 200001)
    m0_shape = np.trapezoid(shape(fine), fine) + shape(fine[-1]) * fine[-1] / 4.0  # + the omega^-5 tail
    return shape(omega) * (Hs * Hs / 16.0) / m0_shape


def spreading_weights(n_directions, s, mean_direction):
    """Directions b_j [rad] and weights w_j (sum 1) of cos-2s spreading on n equal sectors around b0."""
    if n_directions == 1:
        return np.array([mean_direction]), np.array([1.0])
    rel = -math.pi + (np.arange(n_directions) + 0.5) * (2.0 * math.pi / n_directions)
    w = np.cos(rel / 2.0) ** (2.0 * s)
    return mean_direction + rel, w / w.sum()


def _regular(w: WaveConfig, g, depth, stretch):
    omega = np.array([2.0 * math.pi / w.period])
    b = math.radians(w.direction)
    return WaveComponents(np.array([w.height / 2.0]), omega, wave_number(omega, g, depth),
                          np.array([math.cos(b)]), np.array([math.sin(b)]),
                          np.array([math.radians(w.phase)]), depth, stretch)


def _bin_energy(edges, Hs, Tp, gamma):
    """Integral of S over each bin [edges[i], edges[i+1]] (16-point Gauss-Legendre: S is smooth)."""
    x, wq = np.polynomial.legendre.leggauss(16)
    a, b = edges[:-1, None], edges[1:, None]
    nodes = 0.5 * (a + b) + 0.5 * (b - a) * x[None, :]
    return 0.5 * np.diff(edges) * (jonswap_spectrum(nodes, Hs, Tp, gamma) @ wq)


def _jonswap(w: WaveConfig, g, depth, stretch):
    """Equal frequency bins with one seeded frequency per bin (no repetition period), a random phase per
    component, amplitude a = sqrt(2 E_bin D(b)) with E_bin the integral of S over the bin, so that
    m0 = sum a^2 / 2 is the spectrum's integral over the discretised band whatever the bin count."""
    rng = np.random.default_rng(w.seed)
    wp = 2.0 * math.pi / w.Tp
    edges = np.linspace(w.min_frequency_ratio * wp, w.max_frequency_ratio * wp, w.n_frequencies + 1)
    dw = np.diff(edges)
    omega = edges[:-1] + dw * rng.uniform(0.0, 1.0, w.n_frequencies)
    energy = _bin_energy(edges, w.Hs, w.Tp, w.gamma)
    dirs, weights = spreading_weights(w.n_directions, w.spreading, math.radians(w.direction))
    amp = np.sqrt(2.0 * np.outer(energy, weights)).ravel()
    om = np.repeat(omega, dirs.size)
    b = np.tile(dirs, omega.size)
    phase = rng.uniform(0.0, 2.0 * math.pi, amp.size)
    return WaveComponents(amp, om, wave_number(om, g, depth), np.cos(b), np.sin(b), phase, depth, stretch)


def wave_components(config) -> WaveComponents:
    """The sea state of a run configuration (``config.waves``, gravity from ``config.environment``)."""
    w = getattr(config, "waves", None)
    if w is None or w.kind == "none":
        return no_waves()
    g = config.environment.g
    if g <= 0.0:
        raise ValueError("waves: environment.g must be > 0 for waves")
    depth = w.depth if w.depth > 0.0 else math.inf
    if w.stretching not in STRETCHINGS:
        raise ValueError(f"waves.stretching must be one of {STRETCHINGS}, got {w.stretching!r}")
    stretch = STRETCHINGS.index(w.stretching)
    if w.kind == "regular":
        return _regular(w, g, depth, stretch)
    if w.kind == "jonswap":
        return _jonswap(w, g, depth, stretch)
    raise ValueError(f"waves.kind must be one of {WAVE_KINDS}, got {w.kind!r}")


@jit
def wave_elevation(x, y, t, amp, omega, k, cdir, sdir, phase):
    """eta(x, y, t) = sum a cos(k (x cos b + y sin b) - omega t + phi) [m]."""
    eta = 0.0
    for n in range(amp.shape[0]):
        eta += amp[n] * math.cos(k[n] * (x * cdir[n] + y * sdir[n]) - omega[n] * t + phase[n])
    return eta


@jit
def _depth_factors(kn, zs, depth):
    """(cosh k(z'+d) / sinh kd, sinh k(z'+d) / sinh kd), overflow-free; deep water: (e^{kz'}, e^{kz'})."""
    if depth == math.inf:
        e = math.exp(kn * zs)
        return e, e
    e = math.exp(kn * zs)
    f = math.exp(-kn * (zs + 2.0 * depth))
    den = 1.0 - math.exp(-2.0 * kn * depth)
    return (e + f) / den, (e - f) / den


@jit
def wave_kinematics(x, y, z, t, amp, omega, k, cdir, sdir, phase, depth, stretch, u_out, a_out):
    """Particle velocity u_out (3,) [m/s] and local acceleration a_out (3,) [m/s^2] at (x, y, z) and t,
    Airy kinematics with the stretching ``stretch`` (STRETCH_*, docs/waves.md); zeros above the surface
    (and, with STRETCH_NONE, above the mean level). Returns eta(x, y, t) [m]."""
    for c in range(3):
        u_out[c] = 0.0
        a_out[c] = 0.0
    eta = wave_elevation(x, y, t, amp, omega, k, cdir, sdir, phase)
    if z > eta:
        return eta
    lin = 0.0  # height above z = 0 of a linear extrapolation
    if stretch == STRETCH_WHEELER:
        if depth == math.inf:
            zs = z - eta
        else:
            zs = max((z - eta) * depth / (depth + eta), -depth)
    elif z <= 0.0:
        zs = max(z, -depth)
    elif stretch == STRETCH_NONE:
        return eta
    else:
        zs = 0.0
        if stretch == STRETCH_EXTRAPOLATION:
            lin = z
    for n in range(amp.shape[0]):
        th = k[n] * (x * cdir[n] + y * sdir[n]) - omega[n] * t + phase[n]
        ch, sh = _depth_factors(k[n], zs, depth)
        if lin > 0.0:  # d(ch)/dz = k sh, d(sh)/dz = k ch at z = 0
            ch, sh = ch + k[n] * lin * sh, sh + k[n] * lin * ch
        c = math.cos(th)
        s = math.sin(th)
        aw = amp[n] * omega[n]
        aw2 = aw * omega[n]
        uh = aw * ch * c  # horizontal speed along b_n
        ah = aw2 * ch * s  # d(uh)/dt
        u_out[0] += uh * cdir[n]
        u_out[1] += uh * sdir[n]
        u_out[2] += aw * sh * s
        a_out[0] += ah * cdir[n]
        a_out[1] += ah * sdir[n]
        a_out[2] -= aw2 * sh * c
    return eta
