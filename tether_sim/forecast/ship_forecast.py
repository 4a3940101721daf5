"""Forecasts of the ship (fairlead) motion over the horizon, as ensembles of trajectories.

Each member is an object with ``at(t) -> (position (3,), velocity (3,))``, t in solver time.

Known sea (:func:`perturbed_members`): the run's own analytic motion (``motion.kind`` rao, sines,
heave) is its future; the ensemble represents the error a real wave forecast would have. Each wave
component n of a member gets its amplitude scaled by a_n = exp(s z_n - s^2) and its phase shifted by
phi_n = s w_n, z_n and w_n independent N(0, 1). The amplitude factor is log-normal with E[a_n^2] = 1:
a member's sea has, on average, the energy (the spectrum) of the sea it forecasts, as an unbiased
forecast must (a factor 1 + alpha_n, alpha_n ~ N(0, s^2), would give every member 1 + s^2 times the
energy: at 10 % of Hs error a sea 4 % higher in Hs, biased towards more, larger and earlier snaps).
With E[a_n] = exp(-s^2 / 2) and E[exp(i phi_n)] = exp(-s^2 / 2) the elevation error of a member is
a zero-mean process of variance sum A_n^2 / 2 E|a_n exp(i phi_n) - 1|^2 = m0 (2 - 2 exp(-s^2)), so
its rms is ``error`` x Hs (Hs = 4 sqrt(m0)) for s^2 = -ln(1 - 8 error^2) (:func:`component_spread`;
10 % of Hs: s = 0.289, i.e. 29 % in log-amplitude and 17 deg in phase). The largest error such a
forecast can have is that of an unrelated sea of the same spectrum, rms sqrt(2 m0) = Hs / sqrt(8)
(35 % of Hs): ``error`` must stay below it. For a sum of sines the same relative spread applies to
its terms (error as a fraction of 4 x rms motion).
A circle orbit is deterministic (no perturbation model; members are all the nominal).

Poses only (:class:`ARShipPredictor`): an autoregressive model per axis, fitted by least squares on
the fairlead history resampled to ``sample_period`` (the ship's motion lies well below the Nyquist
frequency of 1 Hz at 0.5 s, so no anti-alias filter), predicting recursively; members add
innovations drawn from the fit's residuals, so the ensemble spreads as the predictive distribution of
the model grows with the lead time. AR models fitted this way are the usual short-term wave and
vessel-motion predictors of wave-energy and heave-compensation control (Fusco & Ringwood 2010,
"Short-term wave forecasting for real-time control of wave energy converters", IEEE Trans.
Sustainable Energy 1(2); Yumori 1981, "Real time prediction of ship response to ocean waves using
time series analysis", OCEANS 81); their skill decays within one to two wave periods.

External (:func:`external_members`): predicted ship poses from another system (a wave radar or
deterministic sea-wave prediction), validated by the caller, turned into the fairlead trajectory
``p + R(q) r`` by a cubic spline; its members scale the predicted displacement about the current
position by a log-normal factor exp(s z - s^2), z ~ N(0, 1), of mean square 1 (energy-preserving, as
the known sea's), s from ``error`` as above.
"""

import copy
import math

import numpy as np
from scipy.interpolate import CubicSpline
from scipy.optimize import brentq


MAX_SEA_ERROR = 1.0 / math.sqrt(8.0)  # rms error of an unrelated sea of the same spectrum, fraction of Hs


def component_spread(error: float) -> float:
    """s such that the energy-preserving per-component amplitude and phase errors of
    :func:`perturb_motion` give an elevation error of rms ``error`` x Hs: s^2 = -ln(1 - 8 error^2)
    (module doc); ValueError at or above :data:`MAX_SEA_ERROR`."""
    if error <= 0.0:
        return 0.0
    if error >= MAX_SEA_ERROR:
        raise ValueError(f"forecast.sea_error {error:g}: an unbiased sea forecast's error stays below "
                         f"Hs / sqrt(8) = {MAX_SEA_ERROR:.3f} Hs (that of an unrelated sea of the same spectrum)")
    return math.sqrt(-math.log(1.0 - 8.0 * error * error))


def amplitude_factors(spread: float, n: int, rng):
    """n log-normal amplitude factors exp(s z - s^2), z ~ N(0, 1): mean square exactly 1 (module doc)."""
    return np.exp(spread * rng.standard_normal(n) - spread * spread)


class MotionMember:
    """A member from an analytic motion generator (``at(t) -> (p, v, a)``) evaluated at solver time
    plus ``offset`` (the generator's clock minus solver time)."""

    def __init__(self, motion, offset=0.0):
        self.motion, self.offset = motion, float(offset)
        # position and velocity only where the generator can skip the acceleration (the same numbers)
        pv = getattr(motion, "position_velocity", None)
        self._pv = pv if pv is not None else (lambda t: motion.at(t)[:2])

    def at(self, t):
        p, v = self._pv(t + self.offset)
        return np.asarray(p, float), np.asarray(v, float)

    def at_many(self, ts):
        """(positions (k, 3), velocities (k, 3)) at the solver times ``ts``: the numbers of :meth:`at`."""
        many = getattr(self.motion, "position_velocity_many", None)
        ts = np.asarray(ts, float).reshape(-1) + self.offset
        if many is not None:
            return many(ts)
        out = [self._pv(float(t)) for t in ts]
        return (np.array([o[0] for o in out], float).reshape(-1, 3), np.array([o[1] for o in out], float).reshape(-1, 3))


def perturb_motion(motion, spread: float, rng):
    """A copy of an analytic motion with its wave components' (or sines') amplitudes scaled by
    log-normal factors of mean square 1 and phases shifted by N(0, spread^2) (module doc); the motion
    itself when it has no such model."""
    if spread <= 0.0:
        return motion
    response = getattr(motion, "response", None)
    if response is not None:  # RaoMotion: the components of the ship response
        n = response.omega.size
        scale, phi = amplitude_factors(spread, n, rng), rng.normal(0.0, spread, n)
        out = copy.copy(motion)
        out.response = copy.copy(response)
        out.response.coef = response.coef * scale[:, None]
        out.response.theta0 = response.theta0 + phi[:, None]
        return out
    if hasattr(motion, "a") and hasattr(motion, "phi"):  # SinesMotion
        n = motion.a.size
        scale, phi = amplitude_factors(spread, n, rng), rng.normal(0.0, spread, n)
        out = copy.copy(motion)
        out.a, out.phi = motion.a * scale, motion.phi + phi
        return out
    return motion


def can_perturb(motion) -> bool:
    return getattr(motion, "response", None) is not None or (hasattr(motion, "a") and hasattr(motion, "phi"))


def perturbed_members(motion, offset, members, error, rng, nominal_first=True, start=None, condition_nominal=False,
                      covariance=True):
    """``members`` MotionMembers of ``motion``: the first the nominal (unless ``nominal_first`` is
    false), the others perturbed with the spread of ``error`` (fraction of Hs). ``start`` = (t0, p0,
    v0, T): every perturbed member (and the nominal too with ``condition_nominal``) starts from the
    measured state (:class:`ConditionedMember`, conditioned on the covariance of ``motion``'s wave
    components; ``covariance=False``: the exponential fade alone, as before 2026-11-27)."""
    spread = component_spread(error)
    modes = linear_modes(motion) if start is not None and covariance else None
    out = []
    for m in range(members):
        nominal = (m == 0 and nominal_first) or spread == 0.0
        member = MotionMember(motion if nominal else perturb_motion(motion, spread, rng), offset)
        if start is not None and (not nominal or condition_nominal):
            member = ConditionedMember(member, *start, modes=modes)
        out.append(member)
    return out


def linear_modes(motion):
    """(omega (n,), U (n, 3) complex) with the motion's offset, to first order in the ship's rotations,
    Re sum_n U_n exp(-i omega_n t) (RaoMotion: U_n = Rz(heading) (D_n[:3] + D_n[3:] x lever), D_n the
    DOFs' complex amplitudes coef exp(i theta0); SinesMotion: vertical, U_n = a_n exp(i (pi/2 - phi_n)));
    None for a motion without such components (circle, record)."""
    response = getattr(motion, "response", None)
    if response is not None:
        d = response.coef * np.exp(1j * response.theta0)
        lever = np.asarray(motion.lever, float)
        rot = np.cross(d[:, 3:], lever)  # small rotations: R r - r = theta x r
        c, s = math.cos(response.heading), math.sin(response.heading)
        rz = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        return np.asarray(response.omega, float), (d[:, :3] + rot) @ rz.T
    if hasattr(motion, "a") and hasattr(motion, "phi") and hasattr(motion, "w"):
        u = np.zeros((motion.a.size, 3), complex)
        u[:, 2] = motion.a * np.exp(1j * (0.5 * math.pi - motion.phi))
        return np.asarray(motion.w, float), u
    return None


class ConditionedMember:
    """A member started from the measured ship state: at solver time ``t0`` the fairlead is at ``p0``
    with velocity ``v0`` (what the run commands now), while the member's own forecast says (p, v)
    there. The member adds to its own forecast the expected continuation of that difference
    delta = (dp, dv), so it is at (p0, v0) at t0 (C1) and its error grows to the forecast's stated
    error as its lead grows (a real sea-wave forecast is conditioned on the ship it sees; without
    this a perturbed member would jerk the fairlead at the first tick).

    With ``modes`` (:func:`linear_modes` of the forecast sea) the continuation is the conditional
    mean of the error process given delta: the perturbations are independent per wave component
    with the same relative spread (:func:`perturb_motion`), so the error's covariance is the
    motion's own, C(tau) = kappa sum_n Re(W_n W_n^H exp(-i omega_n tau)) / 2 with W_n = (U_n,
    -i omega_n U_n), and the correction is C(tau) C(0)^+ delta (kappa cancels). It oscillates with
    the sea's own frequencies and fades as the sea decorrelates; the member's error variance is
    then C(0) - C(tau) C(0)^+ C(tau)^T, which grows from 0 and never exceeds the unconditioned error.
    What delta has outside the range of C(0) (an axis the modes do not move), and all of it without
    ``modes``, fades as c(tau) = (dp + (dv + dp / T) tau) exp(-tau / T) (c(0) = dp, c'(0) = dv).
    That exponential fade alone, used before 2026-11-27 for the whole delta, does not follow the
    sea: half a wave period on, the error it adds has the sign the member's own error then has, and
    the member's error rose above the stated error at leads of 2-8 s (docs/forecast.md)."""

    def __init__(self, member, t0, p0, v0, T, modes=None):
        self.member, self.t0, self.T = member, float(t0), float(T)
        p, v = member.at(self.t0)
        delta = np.concatenate([np.asarray(p0, float) - p, np.asarray(v0, float) - v])
        self.omega = self.g = self.w = None
        if modes is not None:
            omega, u = modes
            w = np.concatenate([u, -1j * omega[:, None] * u], axis=1)  # (n, 6): position and velocity
            c0 = 0.5 * np.real(w.T @ np.conj(w))  # (6, 6) covariance at lag 0 (up to kappa)
            beta = np.linalg.pinv(c0, rcond=1e-10, hermitian=True) @ delta
            self.omega, self.w = np.asarray(omega, float), w
            self.g = 0.5 * (np.conj(w) @ beta)  # (n,): correction(tau) = Re sum_n w_n g_n exp(-i omega_n tau)
            delta = delta - c0 @ beta  # the residual outside the covariance's range
        self.dp = delta[:3]
        self.b = delta[3:] + self.dp / self.T if self.T > 0.0 else np.zeros(3)

    def at(self, t):
        p, v = self.member.at(t)
        tau = max(t - self.t0, 0.0)
        if self.g is not None:
            corr = np.real((self.g * np.exp(-1j * self.omega * tau)) @ self.w)
            p, v = p + corr[:3], v + corr[3:]
        if self.T <= 0.0:
            return p, v
        e = math.exp(-tau / self.T)
        c = (self.dp + self.b * tau) * e
        return p + c, v + self.b * e - c / self.T

    def at_many(self, ts):
        """(positions (k, 3), velocities (k, 3)) at the solver times ``ts``: the numbers of :meth:`at`
        (the same operations element for element; math.exp as there)."""
        ts = np.asarray(ts, float).reshape(-1)
        many = getattr(self.member, "at_many", None)
        if many is not None:
            p, v = many(ts)
        else:
            out = [self.member.at(float(t)) for t in ts]
            p, v = np.array([o[0] for o in out], float), np.array([o[1] for o in out], float)
        tau = np.array([max(float(t) - self.t0, 0.0) for t in ts])
        if self.g is not None:
            phase = np.exp((-1j * self.omega)[None, :] * tau[:, None])  # (k, n)
            corr = np.real(np.matmul((self.g[None, :] * phase)[:, None, :], self.w)[:, 0, :])  # per time (n,) @ (n, 6)
            p, v = p + corr[:, :3], v + corr[:, 3:]
        if self.T <= 0.0:
            return p, v
        e = np.array([math.exp(-x / self.T) for x in tau])[:, None]
        c = (self.dp + self.b * tau[:, None]) * e
        return p + c, v + self.b * e - c / self.T


class SplineMember:
    """A member from samples of the fairlead position: a cubic spline, velocity its derivative; held
    at its last position (at rest) after the last sample."""

    def __init__(self, times, positions):
        self.t_end = float(times[-1])
        self.spline = CubicSpline(np.asarray(times, float), np.asarray(positions, float), axis=0, bc_type="natural")
        self.p_end = self.spline(self.t_end)

    def at(self, t):
        if t >= self.t_end:
            return self.p_end.copy(), np.zeros(3)
        return self.spline(t), self.spline(t, 1)

    def at_many(self, ts):
        """(positions (k, 3), velocities (k, 3)) at the times ``ts``: the numbers of :meth:`at`."""
        ts = np.asarray(ts, float).reshape(-1)
        p, v = np.empty((ts.size, 3)), np.zeros((ts.size, 3))
        held = ts >= self.t_end
        p[held] = self.p_end
        if not held.all():
            p[~held], v[~held] = self.spline(ts[~held]), self.spline(ts[~held], 1)
        return p, v


class ARShipPredictor:
    """Autoregressive predictor of the fairlead position per axis (module doc)."""

    def __init__(self, order: int, sample_period: float, window: float):
        self.order, self.dt, self.window = int(order), float(sample_period), float(window)

    def min_history(self) -> float:
        """Seconds of history the fit needs (4 x order samples)."""
        return 4.0 * self.order * self.dt

    def fit(self, times, positions, t0):
        """(coefficients (3, p), residual std (3,), mean (3,), resampled history (n, 3)) from the history
        ``times`` (k,), ``positions`` (k, 3) up to ``t0``; ValueError when it is too short or bad."""
        times = np.asarray(times, float)
        positions = np.asarray(positions, float)
        span = min(self.window, t0 - times[0]) if times.size else 0.0
        if span < self.min_history() - 1e-9:
            raise ValueError(f"pose history {max(span, 0.0):.1f} s < {self.min_history():.1f} s needed "
                             f"(4 x forecast.ar_order x forecast.ar_sample_period)")
        n = int(span / self.dt) + 1
        grid = t0 - self.dt * np.arange(n - 1, -1, -1)
        x = np.column_stack([np.interp(grid, times, positions[:, i]) for i in range(3)])
        if not np.all(np.isfinite(x)):
            raise ValueError("pose history has non-finite samples")
        mean = x.mean(axis=0)
        p = self.order
        coef, sigma = np.zeros((3, p)), np.zeros(3)
        for i in range(3):
            y = x[:, i] - mean[i]
            if np.ptp(y) < 1e-9:  # an axis that does not move: predicted to stay
                continue
            # rows k = p..n-1: y_k = sum_j c_j y_{k-1-j}
            A = np.column_stack([y[p - 1 - j:n - 1 - j] for j in range(p)])
            b = y[p:]
            c, *_ = np.linalg.lstsq(A, b, rcond=None)
            coef[i] = c
            sigma[i] = float(np.sqrt(np.mean((b - A @ c) ** 2)))
        return coef, sigma, mean, x

    def members(self, times, positions, t0, horizon, members, rng):
        """``members`` SplineMembers over [t0, t0 + horizon]: the first the mean prediction, the
        others simulated with innovations (module doc)."""
        coef, sigma, mean, x = self.fit(times, positions, t0)
        p = self.order
        steps = int(math.ceil(horizon / self.dt)) + 2
        head = x[-max(p, 4):] - mean  # the last samples (spline continuity at t0, AR seeds)
        t_head = t0 - self.dt * np.arange(head.shape[0] - 1, -1, -1)
        t_pred = t0 + self.dt * np.arange(1, steps + 1)
        out = []
        for m in range(members):
            noise = sigma * rng.standard_normal((steps, 3)) if m > 0 else np.zeros((steps, 3))
            y = np.vstack([head, np.zeros((steps, 3))])
            h = head.shape[0]
            for k in range(steps):
                past = y[h + k - 1::-1][:p] if h + k - 1 >= 0 else y[:0]
                y[h + k] = np.einsum("ij,ji->i", coef[:, :past.shape[0]], past) + noise[k]
            out.append(SplineMember(np.concatenate([t_head, t_pred]), y + mean))
        return out


def external_members(times, positions, current, members, error, rng):
    """Members from a validated external forecast of the fairlead (``times`` (k,) solver time,
    ``positions`` (k, 3)): the nominal first, then the displacement about ``current`` scaled by a
    log-normal factor exp(s z - s^2) of mean square 1 (module doc: the members keep, on average, the
    forecast's energy; a factor 1 + alpha, alpha ~ N(0, s^2), used before 2026-11-27, gave them
    1 + s^2 = 1.08 times it at 10 % of Hs)."""
    spread = component_spread(error)
    positions = np.asarray(positions, float)
    out = []
    for m in range(members):
        scale = 1.0 if m == 0 or spread == 0.0 else float(amplitude_factors(spread, 1, rng)[0])
        out.append(SplineMember(times, current + scale * (positions - current)))
    return out
