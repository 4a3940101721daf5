"""Linear waves (physics/waves.py) against closed forms: dispersion, Airy kinematics, the stretchings,
the JONSWAP discretisation (m0 = Hs^2/16, peak), seeding, and a plain numpy twin of the compiled sums."""

import math
from dataclasses import replace

import numpy as np
import pytest

from tether_sim.config import SimConfig
from tether_sim.physics.waves import (STRETCHINGS, WaveConfig, jonswap_spectrum, no_waves, spreading_weights,
                                      wave_components, wave_elevation, wave_kinematics, wave_number)

G = 9.81


def _config(**waves):
    return replace(SimConfig(), waves=WaveConfig(**waves))


def _kin(comp, x, y, z, t):
    u = np.zeros(3)
    a = np.zeros(3)
    eta = wave_kinematics(x, y, z, t, *comp.arrays(), comp.depth, comp.stretch, u, a)
    return eta, u, a


def _plain_kinematics(comp, x, y, z, t):
    """Numpy twin: the stretched Airy sums written with cosh/sinh directly (docs/waves.md)."""
    th = comp.k * (x * comp.cos_dir + y * comp.sin_dir) - comp.omega * t + comp.phase
    eta = float(np.sum(comp.amp * np.cos(th)))
    name = STRETCHINGS[comp.stretch]
    if z > eta or (name == "none" and z > 0.0):
        return eta, np.zeros(3), np.zeros(3)
    d = comp.depth
    if name == "wheeler":
        zs = z - eta if math.isinf(d) else max((z - eta) * d / (d + eta), -d)
    else:
        zs = min(z, 0.0) if math.isinf(d) else max(min(z, 0.0), -d)
    if math.isinf(d):
        ch = sh = np.exp(comp.k * zs)
    else:
        ch = np.cosh(comp.k * (zs + d)) / np.sinh(comp.k * d)
        sh = np.sinh(comp.k * (zs + d)) / np.sinh(comp.k * d)
    if name == "extrapolation" and z > 0.0:  # first-order Taylor from z = 0
        ch, sh = ch + comp.k * z * sh, sh + comp.k * z * ch
    aw = comp.amp * comp.omega
    uh = aw * ch * np.cos(th)
    ah = aw * comp.omega * ch * np.sin(th)
    u = np.array([np.sum(uh * comp.cos_dir), np.sum(uh * comp.sin_dir), np.sum(aw * sh * np.sin(th))])
    a = np.array([np.sum(ah * comp.cos_dir), np.sum(ah * comp.sin_dir), -np.sum(aw * comp.omega * sh * np.cos(th))])
    return eta, u, a


def test_dispersion_relation_finite_deep_and_shallow():
    omega = np.array([0.2, 0.5, 0.7, 1.0, 2.0, 4.0])
    for d in (5.0, 50.0, 500.0):
        k = wave_number(omega, G, d)
        # the residual of omega^2 = g k tanh(kd), relative: Newton converged to round-off
        assert np.max(np.abs(G * k * np.tanh(k * d) / omega**2 - 1.0)) < 1e-13
    np.testing.assert_allclose(wave_number(omega, G), omega**2 / G, rtol=0, atol=0)
    # deep limit: kd > pi gives k within 0.4 % of omega^2/g (tanh(pi) = 0.9963)
    k = wave_number(np.array([2.0]), G, 100.0)
    assert abs(k[0] / (4.0 / G) - 1.0) < 1e-12
    # shallow limit: k d << 1 gives k -> omega / sqrt(g d) (relative error ~ (kd)^2 / 6)
    d = 1.0
    k = wave_number(np.array([0.05]), G, d)
    assert abs(k[0] / (0.05 / math.sqrt(G * d)) - 1.0) < 1e-4


@pytest.mark.parametrize("depth", [0.0, 30.0])
def test_regular_airy_kinematics_closed_form(depth):
    """One component, below the trough: u_h = a w cosh(k(z'+d))/sinh(kd) cos th, w = a w sinh/sinh sin th,
    du/dt = a w^2 cosh/sinh sin th, dw/dt = -a w^2 sinh/sinh cos th at z' = Wheeler(z)."""
    cfg = _config(kind="regular", height=2.0, period=8.0, direction=30.0, phase=20.0, depth=depth)
    comp = wave_components(cfg)
    assert comp.n == 1
    a, om, k, b = 1.0, 2 * math.pi / 8.0, comp.k[0], math.radians(30.0)
    x, y, z, t = 12.0, -7.0, -6.0, 3.3
    th = k * (x * math.cos(b) + y * math.sin(b)) - om * t + math.radians(20.0)
    eta_cf = a * math.cos(th)
    if depth == 0.0:
        zs = z - eta_cf
        ch = sh = math.exp(k * zs)
    else:
        zs = (z - eta_cf) * depth / (depth + eta_cf)
        ch = math.cosh(k * (zs + depth)) / math.sinh(k * depth)
        sh = math.sinh(k * (zs + depth)) / math.sinh(k * depth)
    eta, u, acc = _kin(comp, x, y, z, t)
    assert eta == pytest.approx(eta_cf, abs=1e-14)
    uh, ah = a * om * ch * math.cos(th), a * om * om * ch * math.sin(th)
    np.testing.assert_allclose(u, [uh * math.cos(b), uh * math.sin(b), a * om * sh * math.sin(th)], rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(acc, [ah * math.cos(b), ah * math.sin(b), -a * om * om * sh * math.cos(th)], rtol=1e-12, atol=1e-14)


@pytest.mark.parametrize("depth", [0.0, 40.0])
def test_small_amplitude_field_is_incompressible_and_meets_the_surface_conditions(depth):
    """For a -> 0 (stretching negligible) the field must satisfy du/dx + dw/dz = 0, the kinematic surface
    condition w(z = 0) = d eta/dt, and a = du/dt at a fixed point (central differences, O(h^2) ~ 1e-7)."""
    cfg = _config(kind="regular", height=2e-6, period=6.0, depth=depth)
    comp = wave_components(cfg)
    x, z, t, h = 3.0, -4.0, 1.7, 1e-3
    _, up, _ = _kin(comp, x + h, 0.0, z, t)
    _, um, _ = _kin(comp, x - h, 0.0, z, t)
    _, wp, _ = _kin(comp, x, 0.0, z + h, t)
    _, wm, _ = _kin(comp, x, 0.0, z - h, t)
    _, u0, a0 = _kin(comp, x, 0.0, z, t)
    scale = comp.amp[0] * comp.omega[0] * comp.k[0]
    assert abs((up[0] - um[0]) / (2 * h) + (wp[2] - wm[2]) / (2 * h)) < 1e-5 * scale
    _, ut1, _ = _kin(comp, x, 0.0, z, t + h)
    _, ut0, _ = _kin(comp, x, 0.0, z, t - h)
    np.testing.assert_allclose((ut1 - ut0) / (2 * h), a0, atol=1e-5 * scale * comp.omega[0] / comp.k[0])
    e1 = wave_elevation(x, 0.0, t + h, *comp.arrays())
    e0 = wave_elevation(x, 0.0, t - h, *comp.arrays())
    _, us, _ = _kin(comp, x, 0.0, -1e-12, t)
    assert us[2] == pytest.approx((e1 - e0) / (2 * h), rel=1e-5)


def test_wheeler_surface_value_equals_linear_mean_level_value_and_air_is_still():
    cfg = _config(kind="regular", height=4.0, period=10.0, depth=60.0)
    comp = wave_components(cfg)
    for t in np.linspace(0.0, 10.0, 7):
        eta = wave_elevation(0.0, 0.0, t, *comp.arrays())
        _, u_surf, a_surf = _kin(comp, 0.0, 0.0, eta, t)
        # linear theory at z = 0 for depth d: cosh(kd)/sinh(kd) horizontally, 1 vertically
        th = -comp.omega[0] * t
        aw = comp.amp[0] * comp.omega[0]
        coth = 1.0 / math.tanh(comp.k[0] * 60.0)
        np.testing.assert_allclose(u_surf, [aw * coth * math.cos(th), 0.0, aw * math.sin(th)], rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(a_surf[2], -aw * comp.omega[0] * math.cos(th), rtol=1e-12, atol=1e-12)
        _, u_air, a_air = _kin(comp, 0.0, 0.0, eta + 0.01, t)
        assert not u_air.any() and not a_air.any()


def test_jonswap_discretisation_m0_peak_and_spreading():
    """m0 = sum a^2/2: each bin carries the integral of S over it, so m0 is the spectrum's energy in the
    band (0.5, 4) w_p whatever the bin count. Pierson-Moskowitz (gamma = 1) has it in closed form:
    Hs^2/16 (exp(-5/4 / 4^4) - exp(-5/4 / 0.5^4)); the normalisation (trapezoid on 4e5 points) and the
    16-point Gauss rule per bin are accurate to ~1e-7: tolerance 1e-6. For gamma = 3.3 the band misses
    the omega^-5 tail beyond 4 w_p, at most 5/4 * 4^-4 = 0.49 % of m0 (the PM tail, relative to a
    larger total): m0 within 0.5 % of Hs^2/16, with 40 bins as with 256."""
    Hs, Tp = 3.0, 9.0
    pm = wave_components(_config(kind="jonswap", Hs=Hs, Tp=Tp, gamma=1.0, n_frequencies=40, seed=2))
    band = math.exp(-1.25 / 4.0**4) - math.exp(-1.25 / 0.5**4)
    assert float(np.sum(pm.amp**2) / 2.0) == pytest.approx(Hs * Hs / 16.0 * band, rel=1e-6)
    for bins in (40, 256):
        coarse = wave_components(_config(kind="jonswap", Hs=Hs, Tp=Tp, n_frequencies=bins, seed=5))
        m0_c = float(np.sum(coarse.amp**2) / 2.0)
        assert Hs * Hs / 16.0 * (1 - 0.005) < m0_c < Hs * Hs / 16.0
    cfg = _config(kind="jonswap", Hs=Hs, Tp=Tp, n_frequencies=256, n_directions=1, seed=7)
    comp = wave_components(cfg)
    assert comp.n == 256
    m0 = float(np.sum(comp.amp**2) / 2.0)
    # the largest component sits at the peak frequency (within one bin width)
    wp = 2 * math.pi / Tp
    dw = (4.0 - 0.5) * wp / 256
    assert abs(comp.omega[np.argmax(comp.amp)] - wp) < 1.5 * dw
    # continuous spectrum: its quadrature is Hs^2/16 to the quadrature error
    w = np.linspace(0.2 * wp, 30 * wp, 400001)
    assert np.trapezoid(jonswap_spectrum(w, Hs, Tp, 3.3), w) == pytest.approx(Hs * Hs / 16.0, rel=2e-4)
    # long-crested: one direction; short-crested: weights sum to one, symmetric about the mean direction
    assert np.allclose(comp.cos_dir, 1.0) and np.allclose(comp.sin_dir, 0.0)
    dirs, wts = spreading_weights(9, 10.0, 0.3)
    assert wts.sum() == pytest.approx(1.0, abs=1e-15)
    np.testing.assert_allclose(wts, wts[::-1], rtol=1e-13)
    assert dirs[np.argmax(wts)] == pytest.approx(0.3, abs=2 * math.pi / 9 / 2 + 1e-12)
    short = wave_components(_config(kind="jonswap", Hs=Hs, Tp=Tp, n_frequencies=256, n_directions=9, seed=7))
    assert short.n == 256 * 9
    assert float(np.sum(short.amp**2) / 2.0) == pytest.approx(m0, rel=1e-12)  # spreading keeps the energy


def test_jonswap_is_seeded_and_its_time_record_has_the_spectral_variance():
    cfg = _config(kind="jonswap", Hs=3.0, Tp=9.0, n_frequencies=64, seed=3)
    a, b = wave_components(cfg), wave_components(cfg)
    for x, y in zip(a.arrays(), b.arrays()):
        np.testing.assert_array_equal(x, y)
    c = wave_components(replace(cfg, waves=replace(cfg.waves, seed=4)))
    assert not np.array_equal(a.phase, c.phase)
    # a 3-hour record sampled at 0.5 s: its variance is m0 within sampling error (components with
    # incommensurate frequencies decorrelate; 3 h holds ~1200 peak periods: a few % expected)
    t = np.arange(0.0, 3 * 3600.0, 0.5)
    eta = np.array([wave_elevation(0.0, 0.0, ti, *a.arrays()) for ti in t])
    assert np.var(eta) == pytest.approx(np.sum(a.amp**2) / 2.0, rel=0.03)
    assert 4 * np.std(eta) == pytest.approx(3.0, rel=0.03)


@pytest.mark.jit_off  # `make test` also runs it with NUMBA_DISABLE_JIT=1 (the kernels as plain Python)
def test_compiled_sums_equal_the_numpy_twin():
    cfg = _config(kind="jonswap", Hs=3.0, Tp=9.0, n_frequencies=24, n_directions=5, seed=11, depth=80.0)
    rng = np.random.default_rng(0)
    for depth, name in [(d, n) for d in (80.0, 0.0) for n in STRETCHINGS]:
        comp = wave_components(replace(cfg, waves=replace(cfg.waves, depth=depth, stretching=name)))
        for _ in range(20):
            x, y, t = rng.uniform(-100, 100), rng.uniform(-100, 100), rng.uniform(0, 100)
            z = rng.uniform(-60.0, 2.0)
            eta, u, acc = _kin(comp, x, y, z, t)
            eta2, u2, a2 = _plain_kinematics(comp, x, y, z, t)
            assert eta == pytest.approx(eta2, rel=1e-12, abs=1e-13)
            np.testing.assert_allclose(u, u2, rtol=1e-10, atol=1e-12)
            np.testing.assert_allclose(acc, a2, rtol=1e-10, atol=1e-12)


@pytest.mark.parametrize("depth", [0.0, 40.0])
def test_stretchings_closed_forms_in_the_crest_and_below_the_mean_level(depth):
    """One regular component under its crest (eta = a = 2 m at x = t = 0). Below z = 0 the three
    unstretched choices are Airy at z itself; above it (0 < z <= eta): none = still water, vertical =
    the values at z = 0, extrapolation = values + z * slopes at z = 0 (d cosh/dz = k sinh, d sinh/dz =
    k cosh); wheeler = Airy at z' = (z - eta) d / (d + eta). Above eta all are still."""
    a = 2.0
    comps = {n: wave_components(_config(kind="regular", height=2 * a, period=9.0, depth=depth, stretching=n))
             for n in STRETCHINGS}
    c0 = comps["none"]
    k, om, d = c0.k[0], c0.omega[0], depth if depth > 0.0 else math.inf

    def factors(z):  # cosh k(z + d)/sinh kd, sinh k(z + d)/sinh kd (deep: e^{kz})
        if math.isinf(d):
            return math.exp(k * z), math.exp(k * z)
        return math.cosh(k * (z + d)) / math.sinh(k * d), math.sinh(k * (z + d)) / math.sinh(k * d)

    def airy(ch, sh):  # theta = 0 under the crest: u = (a w ch, 0, 0), a = (0, 0, -a w^2 sh)
        return np.array([a * om * ch, 0.0, 0.0]), np.array([0.0, 0.0, -a * om * om * sh])

    for z in (-5.0, -0.3):
        for n in ("none", "vertical", "extrapolation"):
            eta, u, acc = _kin(comps[n], 0.0, 0.0, z, 0.0)
            assert eta == pytest.approx(a, rel=1e-14)
            ue, ae = airy(*factors(z))
            np.testing.assert_allclose(u, ue, rtol=1e-13, atol=1e-14)
            np.testing.assert_allclose(acc, ae, rtol=1e-13, atol=1e-14)
    ch0, sh0 = factors(0.0)
    for z in (0.5, 1.9):
        _, u, acc = _kin(comps["none"], 0.0, 0.0, z, 0.0)
        assert not u.any() and not acc.any()
        _, u, acc = _kin(comps["vertical"], 0.0, 0.0, z, 0.0)
        ue, ae = airy(ch0, sh0)
        np.testing.assert_allclose(u, ue, rtol=1e-13)
        np.testing.assert_allclose(acc, ae, rtol=1e-13)
        _, u, acc = _kin(comps["extrapolation"], 0.0, 0.0, z, 0.0)
        ue, ae = airy(ch0 + k * z * sh0, sh0 + k * z * ch0)
        np.testing.assert_allclose(u, ue, rtol=1e-13)
        np.testing.assert_allclose(acc, ae, rtol=1e-13)
        assert u[0] > a * om * ch0  # extrapolation grows above the mean level, vertical holds it
    for z in (-5.0, 0.5, 1.9):
        zs = (z - a) if math.isinf(d) else (z - a) * d / (d + a)
        _, u, acc = _kin(comps["wheeler"], 0.0, 0.0, z, 0.0)
        ue, ae = airy(*factors(zs))
        np.testing.assert_allclose(u, ue, rtol=1e-13)
        np.testing.assert_allclose(acc, ae, rtol=1e-13)
    for n in STRETCHINGS:
        _, u, acc = _kin(comps[n], 0.0, 0.0, a + 0.01, 0.0)
        assert not u.any() and not acc.any()


def test_unknown_stretching_is_rejected_naming_the_key():
    with pytest.raises(ValueError, match="waves.stretching"):
        wave_components(_config(kind="regular", stretching="delta"))


def test_no_waves_is_empty_and_still():
    comp = wave_components(SimConfig())
    assert comp.n == 0 and no_waves().n == 0
    eta, u, acc = _kin(comp, 1.0, 2.0, -3.0, 4.0)
    assert eta == 0.0 and not u.any() and not acc.any()
