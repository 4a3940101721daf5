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
