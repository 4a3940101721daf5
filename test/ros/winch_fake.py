"""A quasi-static fake solver with a winch API, for the winch layer's tests (no numerics).

A vertical cable of unstretched length L from the fixed ship end down to a hanging weight:
top tension T = W + w L (submerged weight of load and cable), bottom tension W. The pay-out API is
the one agreed with the DG solver: ``set_pay_out_rate(rate)`` ramps the rate linearly from its
current value to ``rate`` over the next ``advance_to`` (so L follows the trapezoid exactly), and
``unstretched_length`` is a property.
"""

import numpy as np

from tether_sim.errors import SolverDivergedError
from tether_sim.solvers.base import EndForces, SolverState, compose_tick

W, w = 43000.0, 25.0  # N, N/m: ROPOS cage and tether in water, rounded
DT = 0.01


class HangingCable:
    name = "hanging"

    def __init__(self, config):
        self.L = float(config.cable.length)
        self.rate = 0.0
        self.target_rate = 0.0
        self.time = 0.0
        self.fail_next = 0
        self.built_length = self.L
        self._log = []

    unstretched_length = property(lambda self: self.L)

    def set_pay_out_rate(self, rate):
        self.target_rate = float(rate)

    def set_end_motion(self, end, position, velocity):
        pass

    def stable_time_step(self):
        return DT

    def advance_to(self, t):
        if self.fail_next:
            self.fail_next -= 1
            self.L = np.nan
            raise SolverDivergedError("state became non-finite")
        span = t - self.time
        n = max(1, int(np.ceil(span / DT - 1e-9)))
        v0, v1 = self.rate, self.target_rate
        for k in range(1, n + 1):
            tau = span * k / n
            self._log.append((self.time + tau, W + w * (self.L + v0 * tau + 0.5 * (v1 - v0) * tau * tau / span)))
        self.L += 0.5 * (v0 + v1) * span
        self.rate, self.time = v1, t
        return n

    def tension_at(self, s):
        return W + w * (self.L - np.asarray(s, float))

    def state(self, arc_lengths=None):
        s = np.linspace(0.0, self.L, 5) if arc_lengths is None else np.asarray(arc_lengths, float)
        pos = np.column_stack([0.0 * s, 0.0 * s, -s])
        z = np.zeros(len(s))
        return SolverState(self.time, s, pos, np.zeros_like(pos), self.tension_at(s), z, z, z, DT)

    def end_forces(self):
        top, bottom = W + w * self.L, W
        return EndForces(ship_force=np.array([0.0, 0.0, -top]), vehicle_force=np.array([0.0, 0.0, bottom]),
                         ship_tension=top, vehicle_tension=bottom)

    def body_state(self, end):
        return None

    def drain_end_tensions(self):
        log, self._log = self._log, []
        t = np.array([x[0] for x in log])
        T = np.array([x[1] for x in log])
        return t, T, np.full(len(t), W)

    def tick(self, t, ship=None, vehicle=None, drain=True):
        return compose_tick(self, t, ship, vehicle, drain)

    def snapshot(self):
        return (self.time, self.L, self.rate, self.target_rate)

    def restore(self, snap):
        self.time, self.L, self.rate, self.target_rate = snap
