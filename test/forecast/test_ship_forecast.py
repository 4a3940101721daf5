"""Ship-motion forecasts of the snap forecast (tether_sim.forecast.ship_forecast, service.ExternalForecast)."""

import math
from types import SimpleNamespace

import numpy as np
import pytest

from tether_sim.forecast.service import ExternalForecast
from tether_sim.forecast.ship_forecast import (
    ARShipPredictor, ConditionedMember, MotionMember, component_spread, external_members, linear_modes,
    perturb_motion, perturbed_members,
)
from tether_sim.config import SimConfig
from tether_sim.physics.motion import MotionConfig, SinesMotion, build_motion
from tether_sim.physics.waves import WaveConfig, wave_components


@pytest.mark.parametrize("error", [0.05, 0.1, 0.2])
def test_component_spread_gives_the_stated_elevation_error(error):
    """Members of a many-component sea: the rms of (member - truth) is error x Hs (Hs = 4 sqrt(m0))."""
    rng = np.random.default_rng(3)
    n = 200
    amp = rng.rayleigh(0.1, n)
    omega = rng.uniform(0.3, 1.5, n)
    phase = rng.uniform(0, 2 * np.pi, n)
    motion = SinesMotion((0.0, 0.0, 0.0), amp, omega / (2 * np.pi), phase)
    hs = 4.0 * math.sqrt(np.sum(amp ** 2) / 2.0)
    t = np.linspace(0.0, 600.0, 1501)
    heave = lambda m: (m.a * np.sin(np.outer(t, m.w) + m.phi)).sum(axis=1)  # noqa: E731 (SinesMotion's sum)
    truth = heave(motion)
    assert truth[17] == pytest.approx(motion.offset(t[17])[0][2])
    s = component_spread(error)
    errs = []
    for _ in range(20):
        m = perturb_motion(motion, s, rng)
        errs.append(heave(m) - truth)
    rms = math.sqrt(np.mean(np.square(errs)))
    assert rms == pytest.approx(error * hs, rel=0.08)
    assert component_spread(0.0) == 0.0
    assert component_spread(0.1) == pytest.approx(0.289, abs=0.001)  # s^2 = -ln(1 - 8 x 0.01)
    with pytest.raises(ValueError, match="sqrt"):
        component_spread(0.36)  # more than an unrelated sea of the same spectrum


def test_perturbed_members_keep_the_energy_of_the_sea_they_forecast():
    """An unbiased forecast's ensemble has, on average, the spectrum of the sea: the members' mean
    square amplitude per component is the truth's (a factor 1 + alpha, alpha ~ N(0, s^2), gave
    1 + s^2 = 1.08 at 10 % of Hs: members in a sea 4 % higher in Hs)."""
    rng = np.random.default_rng(11)
    n = 400
    amp = rng.rayleigh(0.1, n)
    motion = SinesMotion((0.0, 0.0, 0.0), amp, rng.uniform(0.05, 0.25, n), rng.uniform(0, 2 * np.pi, n))
    s = component_spread(0.1)
    ratio = [np.sum(perturb_motion(motion, s, rng).a ** 2) / np.sum(amp ** 2) for _ in range(100)]
    # sampling error of the mean: std(a^2) = sqrt(exp(4 s^2) - 1) = 0.63 over ~n/2 effective components x 100 draws
    assert np.mean(ratio) == pytest.approx(1.0, abs=0.01)


def test_motion_member_evaluates_at_solver_time_plus_offset():
    motion = SinesMotion((0.0, 0.0, 0.0), [1.0], [0.1], [0.0])
    p, v = MotionMember(motion, offset=2.5).at(1.0)
    assert p[2] == pytest.approx(math.sin(2 * math.pi * 0.1 * 3.5))
    assert v[2] == pytest.approx(2 * math.pi * 0.1 * math.cos(2 * math.pi * 0.1 * 3.5))


def test_conditioned_members_start_from_the_measured_state_and_relax_to_their_forecast():
    """Perturbed members start at the commanded position and velocity (C1); without the sea's
    covariance (and for what lies outside it) the difference fades as (dp + (dv + dp/T) tau)
    exp(-tau/T): gone to 1e-6 after 20 T; the velocity is the position's derivative; the unperturbed
    nominal is left as it is (an exact forecast stays exact)."""
    motion = SinesMotion((0.0, 0.0, 0.0), [1.0, 0.4], [0.11, 0.2], [0.3, 1.0])
    t0, T = 40.0, 2.0
    p0, v0 = motion.at(t0)[:2]
    members = perturbed_members(motion, 0.0, 4, 0.1, np.random.default_rng(5), start=(t0, p0, v0, T),
                                covariance=False)
    assert isinstance(members[0], MotionMember) and members[0].motion is motion
    for m in members[1:]:
        assert isinstance(m, ConditionedMember)
        p, v = m.at(t0)
        assert np.allclose(p, p0, atol=1e-12) and np.allclose(v, v0, atol=1e-12)
        own = m.member.at(t0)[0]
        assert np.linalg.norm(own - p0) > 1e-3  # the perturbation is there...
        far = t0 + 20 * T
        assert np.allclose(m.at(far)[0], m.member.at(far)[0], atol=1e-6)  # ...and the member relaxes to it
        for t in (t0 + 0.7, t0 + 3.1):
            h = 1e-5
            fd = (m.at(t + h)[0] - m.at(t - h)[0]) / (2 * h)
            assert np.allclose(m.at(t)[1], fd, atol=1e-6)
    nominal = perturbed_members(motion, 0.0, 1, 0.1, np.random.default_rng(5), start=(t0, p0 + 0.1, v0, T),
                                condition_nominal=True)[0]
    assert np.allclose(nominal.at(t0)[0], p0 + 0.1)


def narrow_band_sea(seed=4, n=150):
    """A vertical sea of n sines about 0.11 Hz (Tp 9 s), Gaussian-shaped spectrum, Rayleigh amplitudes."""
    rng = np.random.default_rng(seed)
    f = rng.uniform(0.08, 0.16, n)
    amp = 0.1 * np.exp(-((f - 0.11) / 0.02) ** 2) * rng.rayleigh(1.0, n)
    return SinesMotion((0.0, 0.0, 0.0), amp, f, rng.uniform(0.0, 2.0 * np.pi, n))


def test_covariance_conditioned_members_never_exceed_the_unconditioned_error():
    """Members conditioned on the measured state through the sea's covariance start at it (C1), their
    velocity is their position's derivative, and their rms error against the truth grows from 0 and
    stays at or below the error the same members have unconditioned, at every lead (the conditional
    variance C(0) - C(tau) C(0)^+ C(tau)^T); it reaches it as the sea decorrelates. The exponential
    fade alone does not follow the sea: half a wave period on, the error it adds has the sign of the
    member's own error, and the error rises 25 % and more above the unconditioned one (1.41 x at
    4-6 s here; on the 1730 m benchmark sea, 28 against 22 % of Hs at 5 s)."""
    motion = narrow_band_sea()
    hs = 4.0 * math.sqrt(np.sum(motion.a ** 2) / 2.0)
    leads = np.arange(0.0, 40.01, 1.0)
    err = {True: np.zeros(leads.size), False: np.zeros(leads.size)}
    unconditioned = np.zeros(leads.size)
    for k in range(40):
        t0 = 100.0 + 37.3 * k
        p0, v0 = motion.at(t0)[:2]
        truth = np.array([motion.at(t0 + x)[0][2] for x in leads])
        for covariance in (True, False):
            members = perturbed_members(motion, 0.0, 6, 0.1, np.random.default_rng(k), False, (t0, p0, v0, 2.0),
                                        covariance=covariance)
            for m in members:
                assert isinstance(m, ConditionedMember)
                z = np.array([m.at(t0 + x)[0][2] for x in leads])
                err[covariance] += (z - truth) ** 2
                if covariance:
                    own = np.array([m.member.at(t0 + x)[0][2] for x in leads])
                    unconditioned += (own - truth) ** 2
        if k < 3:
            cm = perturbed_members(motion, 0.0, 2, 0.1, np.random.default_rng(k), False, (t0, p0, v0, 2.0))[1]
            p, v = cm.at(t0)
            assert np.allclose(p, p0, atol=1e-12) and np.allclose(v, v0, atol=1e-12)
            for t in (t0 + 0.7, t0 + 6.1):
                h = 1e-5
                assert np.allclose(cm.at(t)[1], (cm.at(t + h)[0] - cm.at(t - h)[0]) / (2 * h), atol=1e-6)
    ratio = {c: np.sqrt(err[c][1:] / unconditioned[1:]) for c in err}
    assert err[True][0] < 1e-20
    assert ratio[True].max() < 1.05  # sampling of 240 draws per lead
    assert ratio[True][-1] > 0.9  # decorrelated after 40 s: the full forecast error
    assert math.sqrt(unconditioned.mean() / (40 * 6)) / hs == pytest.approx(0.1, rel=0.15)  # the stated 10 % of Hs
    assert ratio[False].max() > 1.25


def test_in_a_regular_wave_the_measured_state_is_the_whole_forecast():
    """One wave component: its amplitude and phase follow from the ship's position and velocity now, so
    the members conditioned on them are the truth over the whole horizon, whatever their perturbation."""
    motion = SinesMotion((0.0, 0.0, 0.0), [3.0], [1.0 / 9.0], [0.4])
    t0 = 60.0
    p0, v0 = motion.at(t0)[:2]
    members = perturbed_members(motion, 0.0, 5, 0.2, np.random.default_rng(2), False, (t0, p0, v0, 2.0))
    for m in members:
        assert abs(m.member.at(t0 + 5.0)[0][2] - motion.at(t0 + 5.0)[0][2]) > 1e-3  # perturbed...
        for lead in (0.0, 3.3, 11.0, 40.0):
            p, v = m.at(t0 + lead)
            truth = motion.at(t0 + lead)
            assert np.allclose(p, truth[0], atol=1e-9) and np.allclose(v, truth[1], atol=1e-9)  # ...and conditioned


def test_linear_modes_are_the_ship_motion_to_first_order():
    """The fairlead of the shipped RAO table through linear_modes: Re sum U_n exp(-i w_n t) is the
    motion's offset up to the second order of the ship's rotations (0.3 m sea: rotations of 1e-3 rad,
    the rest below 1 % of the motion); a sum of sines exactly."""
    cfg = SimConfig(waves=WaveConfig(kind="jonswap", Hs=0.3, Tp=9.0, direction=195.0, n_directions=5, spreading=6.0))
    mc = MotionConfig(kind="rao", rao_path="config/rao_support_vessel_80m.txt", rao_lever_arm=(-35.0, 0.0, 5.0))
    motion = build_motion(mc, np.zeros(3), wave_components(cfg))
    omega, u = linear_modes(motion)
    ts = np.arange(50.0, 150.0, 0.5)
    lin = np.array([np.real(u.T @ np.exp(-1j * omega * t)) for t in ts])
    exact = np.array([motion.offset(t)[0] for t in ts])
    assert np.abs(lin - exact).max() < 0.01 * np.abs(exact).max()
    sines = narrow_band_sea(n=20)
    omega, u = linear_modes(sines)
    for t in (3.0, 71.3):
        assert np.allclose(np.real(u.T @ np.exp(-1j * omega * t)), sines.offset(t)[0], atol=1e-12)
    assert linear_modes(build_motion(MotionConfig(kind="circle"), np.zeros(3))) is None


def two_sines(t):
    return 1.5 * np.sin(2 * np.pi * t / 9.0) + 0.6 * np.sin(2 * np.pi * t / 6.3 + 1.0)


def test_autoregressive_predictor_follows_a_narrow_band_motion_and_its_ensemble_spreads():
    """A sum of two sines is an AR process of order 4 exactly: the mean prediction holds over the
    horizon; with measurement-like noise the members spread and the spread grows with the lead."""
    rate = 50.0
    t = np.arange(0.0, 300.0, 1.0 / rate)
    pos = np.zeros((t.size, 3))
    pos[:, 2] = two_sines(t)
    pos[:, 0] = 3.0  # an axis at rest stays at rest
    ar = ARShipPredictor(order=12, sample_period=0.5, window=240.0)
    t0 = t[-1]
    members = ar.members(t, pos, t0, 20.0, 1, np.random.default_rng(0))
    lead = np.linspace(0.5, 20.0, 40)
    pred = np.array([members[0].at(t0 + x)[0] for x in lead])
    assert np.abs(pred[:, 2] - two_sines(t0 + lead)).max() < 0.02  # m, of a 2.1 m motion
    assert np.allclose(pred[:, 0], 3.0)
    # velocity is the derivative of the predicted trajectory
    p1, v1 = members[0].at(t0 + 3.0)
    p2, _ = members[0].at(t0 + 3.0 + 1e-4)
    assert v1[2] == pytest.approx((p2[2] - p1[2]) / 1e-4, rel=1e-3)
    # noisy history: members differ, and more at 15 s than at 1 s
    rng = np.random.default_rng(1)
    noisy = pos + np.column_stack([np.zeros(t.size), np.zeros(t.size), 0.05 * rng.standard_normal(t.size)])
    ens = ar.members(t, noisy, t0, 20.0, 12, np.random.default_rng(2))
    spread = lambda x: np.std([m.at(t0 + x)[0][2] for m in ens])  # noqa: E731
    assert 0.0 < spread(1.0) < spread(15.0)


def test_autoregressive_predictor_refuses_a_short_history():
    ar = ARShipPredictor(order=24, sample_period=0.5, window=300.0)
    t = np.arange(0.0, 20.0, 0.02)
    with pytest.raises(ValueError, match="pose history 20.0 s < 48.0 s needed"):
        ar.members(t, np.zeros((t.size, 3)), t[-1], 20.0, 1, np.random.default_rng(0))


def external():
    return ExternalForecast("map", attachment=(-35.0, 0.0, 5.0), max_age=2.0)


def poses(n=40, dt=0.5, t0=100.0):
    times = t0 + dt * np.arange(n)
    pos = np.zeros((n, 3))
    pos[:, 2] = np.sin(times)
    quat = np.tile([0.0, 0.0, 0.0, 1.0], (n, 1))
    return times, pos, quat


@pytest.mark.parametrize("change, reason", [
    (dict(frame="ship/base_link"), "wrong frame 'ship/base_link'"),
    (dict(nan=True), "non-finite"),
    (dict(now=103.5), "stale: stamped 3.50 s ago"),
    (dict(now=99.0), "in the future"),
    (dict(reverse=True), "pose stamps do not increase"),
    (dict(quat=(0.0, 0.0, 0.0, 2.0)), "quaternion not of unit norm"),
    (dict(n=3), "at least 4 poses"),
])
def test_external_forecast_rejections_name_the_reason(change, reason):
    ext = external()
    times, pos, quat = poses(n=change.get("n", 40))
    if change.get("nan"):
        pos[5, 1] = math.nan
    if change.get("reverse"):
        times = times[::-1].copy()
    if "quat" in change:
        quat[3] = change["quat"]
    got = ext.offer(100.0, change.get("frame", "map"), times, pos, quat, now=change.get("now", 100.2))
    assert got is not None and reason in got
    assert ext.rejected == 1 and ext.accepted == 0 and reason in ext.last_reason
    held, why = ext.current(100.2)
    assert held is None and reason in why


def test_external_forecast_accepted_gives_the_fairlead_and_goes_stale():
    ext = external()
    times, pos, quat = poses()
    # a 90 deg yaw: the lever arm (-35, 0, 5) of the ship frame points to (0, -35, 5) in the world
    quat[:] = (0.0, 0.0, math.sin(math.pi / 4), math.cos(math.pi / 4))
    assert ext.offer(100.0, "/map", times, pos, quat, now=100.5) is None
    (stamp, t, fair), why = ext.current(101.0)
    assert why == "" and stamp == 100.0
    assert np.allclose(fair[:, :2], [0.0, -35.0]) and np.allclose(fair[:, 2], pos[:, 2] + 5.0)
    held, why = ext.current(102.5)
    assert held is None and "stale" in why


def test_external_members_start_at_the_forecast_and_scale_the_displacement():
    times = np.linspace(0.0, 20.0, 41)
    pos = np.column_stack([np.zeros(41), np.zeros(41), np.sin(times)])
    current = np.zeros(3)
    members = external_members(times, pos, current, 5, 0.1, np.random.default_rng(0))
    assert np.allclose(members[0].at(3.0)[0][2], math.sin(3.0), atol=2e-3)
    scales = [m.at(np.pi / 2)[0][2] / members[0].at(np.pi / 2)[0][2] for m in members[1:]]
    assert np.std(scales) > 0.05 and all(abs(s - 1.0) < 1.5 for s in scales)
    # the members keep the forecast's energy on average: mean square scale 1 (1 + alpha gave 1 + s^2 = 1.08)
    many = external_members(times, pos, current, 4001, 0.1, np.random.default_rng(1))[1:]
    sq = [(m.at(np.pi / 2)[0][2] / members[0].at(np.pi / 2)[0][2]) ** 2 for m in many]
    # sampling: std(a^2) = sqrt(exp(4 s^2) - 1) = 0.63, over 4000 draws 0.01
    assert np.mean(sq) == pytest.approx(1.0, abs=0.035)
    assert np.allclose(members[0].at(25.0)[1], 0.0)  # held at rest after the forecast ends


def test_members_evaluated_a_horizon_at_once_are_the_same_numbers_as_tick_by_tick():
    """``at_many`` (the look-ahead evaluates a member's horizon at once) gives the numbers of ``at``
    bit for bit, for every kind of member: a known sea's members (nominal, perturbed, conditioned through
    the covariance and by the fade alone) and the pose predictor's spline members (before and after their
    last sample)."""
    cfg = SimConfig(motion=MotionConfig(kind="rao", rao_path="config/rao_support_vessel_80m.txt",
                                        rao_lever_arm=(-35.0, 0.0, 5.0), ramp_time=5.0),
                    waves=WaveConfig(kind="jonswap", Hs=3.0, Tp=9.0, n_frequencies=10, n_directions=3, spreading=6.0, seed=2))
    truth = build_motion(cfg.motion, np.zeros(3), wave_components(cfg))
    t0 = 40.0
    p0, v0 = truth.at(t0)[:2]
    ts = np.array([(0.0 + (400 + k) / 10.0) - 0.25 for k in range(1, 160)])
    for covariance in (True, False):
        members = perturbed_members(perturb_motion(truth, component_spread(0.1), np.random.default_rng(1)), 0.25, 4, 0.1,
                                    np.random.default_rng(2), True, (t0, p0, v0, 2.0), True, covariance=covariance)
        members.append(MotionMember(truth, 0.25))
        for m in members:
            P, V = m.at_many(ts)
            assert np.array_equal(P, np.array([m.at(t)[0] for t in ts])) and np.array_equal(V, np.array([m.at(t)[1] for t in ts]))
    hist_t = np.arange(0.0, 60.0, 0.1)
    hist_p = np.array([truth.at(t)[0] for t in hist_t])
    for m in ARShipPredictor(8, 0.5, 40.0).members(hist_t, hist_p, hist_t[-1], 10.0, 3, np.random.default_rng(3)):
        ts = np.arange(hist_t[-1], m.t_end + 2.0, 0.1)
        P, V = m.at_many(ts)
        assert np.array_equal(P, np.array([m.at(t)[0] for t in ts])) and np.array_equal(V, np.array([m.at(t)[1] for t in ts]))
