"""Third-order strong-stability-preserving Runge-Kutta (Shu-Osher form) [PE2020 Eq. 31-33].

    u1      = u_n + dt L(u_n, t_n)
    u2      = 3/4 u_n + 1/4 (u1 + dt L(u1, t_n + dt))
    u_{n+1} = 1/3 u_n + 2/3 (u2 + dt L(u2, t_n + dt/2))

The DG solver inlines these stages in its compiled loop (same coefficients, ``SSPRK3_STAGES``);
:func:`ssprk3_step` is the plain version used by tests and small problems.
"""

import numpy as np

# (a, b, c): u_stage = a * u_n + b * (u_prev + dt * L(u_prev, t_n + c * dt)) [Eq. 31-33]
SSPRK3_STAGES = ((0.0, 1.0, 0.0), (0.75, 0.25, 1.0), (1.0 / 3.0, 2.0 / 3.0, 0.5))

# Explicit steppers of the DG solver (dg.stepper), as rows (a, b, d, c, keep) of the two-register form
#   u <- a r + b (u + d dt L(u, t_n + c dt)),   r = u_n, replaced by u after a row with keep = 1,
# and their stability limits on the DG cable's own spectrum relative to SSP-RK3's: (waves per order P, real axis,
# imaginary axis), factors on the terms of timestep.stable_dt, measured by benchmarks/probes/stepper_gate.py on
# the linearised upwind operator (rounded down; beyond P = 12 the P = 12 factor, the wave factor grows with P).
# ssprk43: Kraaijevanger's SSPRK(4,3); ssprk93: Ketcheson's SSPRK(n^2,3) with n = 3 (SIAM J. Sci. Comput. 30,
# 2008), r = 6.
_S6 = 1.0 / 6.0
_ONE = {P: 1.0 for P in range(1, 13)}
_W43 = (1.445, 1.462, 1.528, 1.595, 1.658, 1.717, 1.769, 1.810, 1.848, 1.885, 1.920, 1.953)
_W93 = (3.393, 3.411, 3.611, 3.863, 4.067, 4.222, 4.376, 4.526, 4.670, 4.809, 4.943, 5.072)
STEPPERS = {
    "ssprk3": (tuple((a, b, 1.0, c, 0.0) for a, b, c in SSPRK3_STAGES), _ONE, 1.0, 1.0),
    "ssprk43": (((0.0, 1.0, 0.5, 0.0, 0.0), (0.0, 1.0, 0.5, 0.5, 0.0), (2.0 / 3.0, 1.0 / 3.0, 0.5, 1.0, 0.0),
                 (0.0, 1.0, 0.5, 0.5, 0.0)), dict(zip(range(1, 13), _W43)), 2.04, 1.24),
    "ssprk93": (((0.0, 1.0, _S6, 0.0, 1.0),) + tuple((0.0, 1.0, _S6, k * _S6, 0.0) for k in range(1, 5))
                + ((0.6, 0.4, _S6, 5 * _S6, 0.0),) + tuple((0.0, 1.0, _S6, 0.5 + k * _S6, 0.0) for k in range(3)),
                dict(zip(range(1, 13), _W93)), 5.28, 2.37),
}
STEPPER_NAMES = tuple(STEPPERS)


def stepper_table():
    """(rows, first): all steppers' rows stacked (n x 5 array) and the first row of stepper k (k + 1 entries)."""
    rows, first = [], [0]
    for stages, *_ in STEPPERS.values():
        rows.extend(stages)
        first.append(len(rows))
    return np.array(rows, dtype=np.float64), np.array(first, dtype=np.int64)


def stepper_step(name, rhs, u: np.ndarray, t: float, dt: float) -> np.ndarray:
    """One step of stepper ``name`` on du/dt = rhs(u, t) (the plain form of the compiled rows)."""
    r = u.copy()
    for a, b, d, c, keep in STEPPERS[name][0]:
        u = a * r + b * (u + d * dt * rhs(u, t + c * dt))
        if keep:
            r = u.copy()
    return u


def stepper_factors(name, P):
    """(waves, real axis, imaginary axis): the stable substep of stepper ``name`` over SSP-RK3's, per term."""
    _, waves, real, imag = STEPPERS[name]
    return waves[min(max(int(P), 1), 12)], real, imag


# Stability boundaries of SSP-RK3 used by the time-step rule (docs/dg_solver.md):
SSPRK3_IMAG_LIMIT = 3.0**0.5  # |dt * lambda| on the imaginary axis
SSPRK3_REAL_LIMIT = 2.5127453266183286  # |dt * lambda| on the negative real axis


def ssprk3_step(rhs, u: np.ndarray, t: float, dt: float) -> np.ndarray:
    """One SSP-RK3 step of du/dt = rhs(u, t); returns u_{n+1} (a new array)."""
    u1 = u + dt * rhs(u, t)
    u2 = 0.75 * u + 0.25 * (u1 + dt * rhs(u1, t + dt))
    return u / 3.0 + 2.0 / 3.0 * (u2 + dt * rhs(u2, t + 0.5 * dt))


def ssprk3_amplification(z):
    """Amplification factor R(z) = 1 + z + z^2/2 + z^3/6 of SSP-RK3 for du/dt = lambda u, z = dt lambda."""
    z = np.asarray(z, dtype=complex)
    return 1.0 + z + z**2 / 2.0 + z**3 / 6.0
