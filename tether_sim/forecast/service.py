"""The snap forecast beside a running simulation (node or offline runner; no ROS here).

:class:`ForecastService` watches the driver after each tick (``observe``: constant, small work in
the tick) and, every 1 / ``forecast.rate`` seconds of clock, hands a :class:`ForecastRequest` (a
solver snapshot, a copy of the snap detector, the ship-motion plan) to a :class:`LookAhead` of its
own. ``threaded=True`` (the node) runs the look-aheads in a worker thread: the tick never waits for
them (the solver kernels release the GIL; the worker thread runs at a lower OS priority and the GIL
switch interval is lowered while it exists, so the tick gets the GIL back quickly), and a forecast falling due while the previous one still
runs is skipped (counted). ``threaded=False`` (the offline runner, tests) runs each one at once,
so an offline run gives the same forecasts on every machine.

Which ship-motion forecast drives the members (``forecast.source``; ship_forecast.py):

- ``known_sea``: the run's own analytic ship motion (``motion.kind`` rao, sines, heave, circle), the
  members perturbed by ``forecast.sea_error``;
- ``external``: the last accepted external forecast (:class:`ExternalForecast`, fed by the node from
  ``tether/ship_motion_forecast``); rejected or stale, the pose predictor takes over and the
  forecast says so (degraded, with the reason);
- ``poses``: the autoregressive predictor on the commanded fairlead history the service keeps;
- ``auto``: known_sea for an analytic motion, else external while a valid one is held, else poses.

No forecast is started while the driver has snap detection suspended (a blend, re-synchronisation,
recovery: the detector the members would copy is about to be rebuilt), before it has started, or
while the ship's analytic motion is still ramping in (``motion.ramp_time``): a ramp is the
simulation's start-up device, not a sea; neither the known sea's perturbation model (stationary
components) nor the pose predictor (fitted on a stationary history) describes it, and a forecast
issued in it would score the start-up transient, not the forecast.
"""

import copy
import math
import os
import sys
import threading
from collections import deque
from dataclasses import replace

import numpy as np

from tether_sim.forecast.lagged import LaggedEnsemble
from tether_sim.forecast.lookahead import EndForecast, ForecastRequest, LookAhead
from tether_sim.forecast.ship_forecast import (
    ARShipPredictor, MotionMember, can_perturb, component_spread, external_members, perturb_motion, perturbed_members,
)
from tether_sim.numerics.rotations import quaternion_matrix
from tether_sim.physics.boundary import END_NAMES
from tether_sim.solvers.factory import build_solver


class ExternalForecast:
    """Validated external forecasts of the ship pose (a wave radar, a sea-wave prediction system).

    ``offer`` takes one forecast: a header stamp and frame, and predicted ship poses (stamps, positions,
    quaternions x, y, z, w of the ship body in the world frame, like ``ship/pose``). It is rejected,
    with the reason returned and kept, when the frame is not the world frame, any value is non-finite,
    a quaternion is degenerate, the pose stamps do not increase, fewer than 4 poses are given, or the
    stamp is older than ``max_age`` (stale) or in the future beyond ``future_tolerance``. ``current``
    returns the last accepted one while it is not stale.
    """

    def __init__(self, world_frame, attachment, max_age, future_tolerance=0.25):
        self.world_frame = str(world_frame).lstrip("/")
        self.attachment = np.asarray(attachment, float).reshape(3)
        self.max_age, self.future_tolerance = float(max_age), float(future_tolerance)
        self.accepted = self.rejected = 0
        self.last_reason = ""
        self._held = None  # (stamp, times (k,), fairlead positions (k, 3))

    def _reject(self, reason):
        self.rejected += 1
        self.last_reason = reason
        return reason

    def offer(self, stamp, frame, times, positions, orientations, now):
        """Accept or reject one forecast; the rejection reason, or None when accepted."""
        times = np.asarray(times, float).reshape(-1)
        positions = np.asarray(positions, float).reshape(-1, 3)
        orientations = np.asarray(orientations, float).reshape(-1, 4)
        if str(frame).lstrip("/") != self.world_frame:
            return self._reject(f"wrong frame {frame!r} (expected {self.world_frame!r})")
        if not (math.isfinite(stamp) and np.all(np.isfinite(times)) and np.all(np.isfinite(positions))
                and np.all(np.isfinite(orientations))):
            return self._reject("non-finite stamp, position or orientation")
        if times.size < 4 or positions.shape[0] != times.size or orientations.shape[0] != times.size:
            return self._reject(f"needs at least 4 poses with stamps (got {times.size})")
        if np.any(np.diff(times) <= 0.0):
            return self._reject("pose stamps do not increase")
        norms = np.linalg.norm(orientations, axis=1)
        if np.any(np.abs(norms - 1.0) > 0.01):
            return self._reject("quaternion not of unit norm")
        if now - stamp > self.max_age:
            return self._reject(f"stale: stamped {now - stamp:.2f} s ago (forecast.external_max_age "
                                f"{self.max_age:g} s)")
        if stamp - now > self.future_tolerance:
            return self._reject(f"stamp {stamp - now:.2f} s in the future")
        q = orientations / norms[:, None]
        fair = positions + np.stack([quaternion_matrix(qi) @ self.attachment for qi in q])
        self._held = (float(stamp), times, fair)
        self.accepted += 1
        return None

    def current(self, now):
        """(stamp, times, fairlead positions) of the last accepted forecast, or (None, reason)."""
        if self._held is None:
            return None, ("no external forecast received" if not self.last_reason
                          else f"external forecast rejected: {self.last_reason}")
        if now - self._held[0] > self.max_age:
            return None, f"external forecast stale ({now - self._held[0]:.1f} s old)"
        return self._held, ""


class ForecastService:
    """Forecasts beside a :class:`~tether_sim.ros.driver.SimulationDriver` (module doc)."""

    def __init__(self, config, *, solver_factory=build_solver, threaded=False, nominal_error=0.0, covariance=True):
        fc = config.forecast
        if config.winch.enabled:
            raise ValueError("forecast.enabled: the snap forecast does not run with winch.enabled (the winch's "
                             "future commands are not forecast)")
        self.config, self.fc = config, fc
        self.solver_factory = solver_factory
        self.threaded = threaded
        # known_sea: the run knows its sea exactly; > 0 (the skill benchmark) gives each forecast a nominal
        # sea that is itself in error by this fraction of Hs (a fresh draw per forecast), as a real
        # sea-wave forecast would be, and the members spread about that nominal
        self.nominal_error = float(nominal_error)
        # known_sea: members conditioned on the measured ship state through the sea's covariance (False: the
        # exponential fade alone, as before 2026-11-27; the skill benchmark's --fade, for comparison)
        self.covariance = bool(covariance)
        self.predictor = ARShipPredictor(fc.ar_order, fc.ar_sample_period, fc.ar_window)
        node = config.node
        self.external = ExternalForecast(node.world_frame, node.ship_attachment, fc.external_max_age,
                                         node.future_stamp_tolerance)
        n_hist = int(math.ceil(fc.ar_window * node.output_rate)) + 2
        self._hist_t = deque(maxlen=n_hist)
        self._hist_p = deque(maxlen=n_hist)
        self.period = 1.0 / fc.rate
        self.next_due = None
        self.issued = self.skipped = self.completed = 0
        self.last_wall = 0.0  # wall time of the last look-ahead, s
        self.last_status = "waiting for the first forecast"
        self.last = []  # the newest EndForecasts (as published: pooled when forecast.lagged > 1)
        self._lagged = LaggedEnsemble(fc.lagged, self.period)
        self._engine = None
        self._results = []
        self._lock = threading.Lock()
        self._busy = False
        self._work = None
        self._wake = threading.Condition(self._lock)
        self._closed = False
        self._thread = None
        self._switch_interval = None
        if threaded:
            # the look-aheads' Python between kernels holds the GIL; with the default 5 ms switch interval
            # the tick waits up to that long each time it needs the GIL back (benchmarks/forecast_tick_load.py)
            self._switch_interval = sys.getswitchinterval()
            sys.setswitchinterval(min(self._switch_interval, WORKER_SWITCH_INTERVAL))
            self._thread = threading.Thread(target=self._worker, name="snap-forecast", daemon=True)
            self._thread.start()

    # ------------------------------------------------------------------ tick side
    def observe(self, driver, now=None, clock_origin=None, tick_index=0):
        """After a tick: record the ship's commanded position; start a forecast when one is due.
        ``clock_origin``, ``tick_index``: the runner's tick clock is ``clock_origin + k / output_rate``
        and this was tick ``tick_index`` (the offline runner; the look-ahead then steps on the same grid)."""
        if driver.solver is None:
            return
        ship = driver._end_state.get("ship")
        if ship is not None and (not self._hist_t or driver.solver.time > self._hist_t[-1]):
            self._hist_t.append(driver.solver.time)
            self._hist_p.append(np.array(ship[0], float))
        stamp = driver.stamp
        if self.next_due is None:
            self.next_due = stamp
        if stamp + 1e-9 < self.next_due:
            return
        self.next_due += self.period * max(1, math.floor((stamp - self.next_due) / self.period) + 1)
        if driver._suspended_until is not None or driver.detector is None:
            self.last_status = "waiting: snap detection suspended (blend, re-synchronisation or recovery)"
            return
        ramp_left = _ramp_left(driver)
        if ramp_left > 0.0:
            self.last_status = f"waiting: the ship motion's ramp-in (motion.ramp_time) ends in {ramp_left:.1f} s"
            return
        if self.threaded and self._busy:
            self.skipped += 1
            return
        request = self._request(driver, stamp if now is None else now)
        if not self.fc.command_rate or self.fc.command_rate == self.config.node.output_rate:
            request.clock_origin, request.tick_index = clock_origin, tick_index
        self.issued += 1
        if self.threaded:
            with self._lock:
                self._work = request
                self._busy = True
                self._wake.notify()
        else:
            self._run(request)

    def _request(self, driver, now):
        fc = self.fc
        rng = np.random.default_rng(fc.seed + self.issued)
        src = driver.sources.get("ship")
        motion = getattr(src, "motion", None)
        source, degraded = fc.source, ""
        anchor, t_solver = driver.anchor, driver.solver.time
        if source == "auto":
            source = "known_sea" if motion is not None else ("external" if self.external.current(now)[0] else "poses")
        if source == "known_sea" and motion is None:
            source, degraded = "poses", "no analytic ship motion to take as the known sea"
        if source == "external":
            held, reason = self.external.current(now)
            if held is None:
                source, degraded = "poses", reason
        members = fc.members
        if source == "known_sea":
            offset = 0.0 if getattr(src, "time_base", "clock") == "solver" else anchor
            if not can_perturb(motion) and members > 1:
                degraded = "the ship motion has no perturbation model: one member"
                members = 1
            if self.nominal_error > 0.0 and can_perturb(motion):
                motion = perturb_motion(motion, component_spread(self.nominal_error), rng)
            ship = driver._end_state.get("ship")
            start = None
            if fc.condition_time > 0.0 and ship is not None:
                start = (t_solver, np.array(ship[0], float), np.array(ship[1], float), fc.condition_time)
            plan = _Plan(perturbed_members, motion, offset, members, fc.sea_error, rng, True, start,
                         self.nominal_error > 0.0, self.covariance)
        elif source == "external":
            stamp, times, fair = held
            current = driver._end_state.get("ship", (fair[0],))[0]
            plan = _Plan(external_members, times - anchor, fair, np.asarray(current, float), members, fc.sea_error, rng)
        else:
            plan = _Plan(self.predictor.members, np.array(self._hist_t), np.array(self._hist_p), t_solver,
                         fc.horizon, members, rng)
            source = "poses"
        if self._engine is None:
            self._solver_config = driver._solver_config
        return ForecastRequest(
            issued=driver.stamp, solver_time=t_solver, anchor=anchor, snapshot=driver.solver.snapshot(),
            detector=copy.deepcopy(driver.detector),
            end_state={e: (np.array(p, float), np.array(v, float)) for e, (p, v) in driver._end_state.items()},
            members=plan, horizon=fc.horizon, tick=1.0 / (fc.command_rate or self.config.node.output_rate), source=source,
            degraded=degraded)

    def poll(self) -> list:
        """The EndForecasts finished since the last call (oldest first)."""
        with self._lock:
            out, self._results = self._results, []
        return out

    # ------------------------------------------------------------------ look-ahead side
    def _run(self, request):
        import time as wallclock

        wall0 = wallclock.perf_counter()
        if self._engine is None:
            self._engine = LookAhead(replace(self._solver_config, forecast=self.fc), self.solver_factory)
        try:
            request.members = request.members()
        except ValueError as exc:  # the ship-motion forecast cannot be made (e.g. too little history)
            reason = "; ".join([r for r in (request.degraded, f"no ship-motion forecast: {exc}") if r])
            results = [EndForecast(request.issued, end, request.horizon, math.nan, math.nan, math.nan, math.nan, 0,
                                   request.source, True, reason) for end in END_NAMES]
        else:
            results = self._engine.run(request)
        results = [self._lagged(f) for f in results]
        self.last_wall = wallclock.perf_counter() - wall0
        self.last_status = results[0].reason or "ok"
        with self._lock:
            self._results.extend(results)
            self.last = results
            self.completed += 1

    def _worker(self):
        _lower_thread_priority(WORKER_NICE)
        while True:
            with self._lock:
                while self._work is None and not self._closed:
                    self._wake.wait()
                if self._closed:
                    return
                request, self._work = self._work, None
            try:
                self._run(request)
            except Exception as exc:  # noqa: BLE001 -- never let the worker die silently
                self.last_status = f"forecast failed: {type(exc).__name__}: {exc}"
            finally:
                with self._lock:
                    self._busy = False

    def close(self):
        with self._lock:
            self._closed = True
            self._wake.notify()
        if self._thread is not None:
            self._thread.join(timeout=30.0)
        if self._switch_interval is not None:
            sys.setswitchinterval(self._switch_interval)
            self._switch_interval = None

    def diagnostics(self) -> dict:
        """Key values for /diagnostics."""
        last = {f.end: f for f in self.last}
        out = {"forecast issued": self.issued, "forecast completed": self.completed,
               "forecast skipped (previous still running)": self.skipped,
               "forecast wall time s": round(self.last_wall, 4), "forecast status": self.last_status,
               "external forecasts accepted": self.external.accepted,
               "external forecasts rejected": self.external.rejected,
               "external last rejection": self.external.last_reason}
        for end, f in last.items():
            out[f"forecast {end} probability"] = f.probability
            out[f"forecast {end} time_to_snap s"] = f.time_to_snap
        return out


def _ramp_left(driver) -> float:
    """Seconds until the ship's analytic motion has ramped in (0 when it has, or has no ramp)."""
    src = driver.sources.get("ship")
    motion = getattr(src, "motion", None)
    ramp_time = float(getattr(motion, "ramp_time", 0.0) or 0.0)
    if ramp_time <= 0.0:
        return 0.0
    t = driver.solver.time + (0.0 if getattr(src, "time_base", "clock") == "solver" else driver.anchor)
    return max(ramp_time - t, 0.0)


WORKER_SWITCH_INTERVAL = 5e-4  # s, GIL switch interval while a look-ahead worker runs (CPython default 5e-3)
WORKER_NICE = 10  # the worker thread's nice increment: the tick thread gets the CPU first


def _lower_thread_priority(increment):
    """Raise the calling thread's nice value by ``increment`` (Linux: setpriority on a thread id
    acts on that thread only); best effort, a no-op where it is not supported."""
    try:
        tid = threading.get_native_id()
        os.setpriority(os.PRIO_PROCESS, tid, min(19, os.getpriority(os.PRIO_PROCESS, tid) + increment))
    except (AttributeError, OSError):
        pass


class _Plan:
    """A deferred ship-motion forecast: built in the look-ahead (worker) side, not in the tick."""

    def __init__(self, fn, *args):
        self.fn, self.args = fn, args

    def __call__(self):
        return self.fn(*self.args)


__all__ = ["ForecastService", "ExternalForecast", "MotionMember"]
