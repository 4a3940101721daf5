"""Generalized-alpha coefficients for first-order systems M dY/dx + ... = 0 [GP Sec. 3].

GP integrate both in time and in arc length with the generalized-alpha method (Chung & Hulbert 1993;
the first-order form of Jansen, Whiting & Hulbert 2000, used for cables by Gobat & Grosenbaugh 2001).
For a variable Y with derivative Y' = dY/dx over a step h:

    Y_{n+1}      = Y_n + h [(1 - gamma) Y'_n + gamma Y'_{n+1}]
    Y'_{n+a_m}   = (1 - a_m) Y'_n + a_m Y'_{n+1}
    Y_{n+a_f}    = (1 - a_f) Y_n  + a_f Y_{n+1}

and the equation is collocated at (Y_{n+a_f}, Y'_{n+a_m}). With

    a_m = (3 - rho) / (2 (1 + rho)),  a_f = 1 / (1 + rho),  gamma = 1/2 + a_m - a_f

the scheme is second-order accurate and unconditionally stable, with spectral radius ``rho`` (the
``rho_inf`` parameter) at infinite step; rho = 1 is the trapezoidal rule (no dissipation).
In arc length we use rho = 1 (see docs/hybrid_solver.md): then a_m = a_f = gamma = 1/2 and the
derivative eliminates exactly into the two-point box scheme (Y_{i+1} - Y_i) / ds at the cell centre.
"""

import numpy as np

from tether_sim.numerics.jit import jit


def gen_alpha_coefficients(rho_inf: float) -> tuple:
    """(alpha_m, alpha_f, gamma) of the first-order generalized-alpha method for 0 <= rho_inf <= 1."""
    if not 0.0 <= rho_inf <= 1.0:
        raise ValueError(f"rho_inf must be in [0, 1], got {rho_inf}")
    alpha_m = 0.5 * (3.0 - rho_inf) / (1.0 + rho_inf)
    alpha_f = 1.0 / (1.0 + rho_inf)
    gamma = 0.5 + alpha_m - alpha_f
    return alpha_m, alpha_f, gamma


def _step_matrix(rho_inf, lam_h):
    """2x2 one-step matrix of y' = lam*y on (y, h y') [first-order generalized-alpha]."""
    am, af, g = gen_alpha_coefficients(rho_inf)
    # y1 = y0 + h[(1-g) y0' + g y1'];  am*y1' + (1-am) y0' = lam (af y1 + (1-af) y0)
    a = np.array([[1.0, -g], [-af * lam_h, am]], dtype=complex)
    b = np.array([[1.0, 1.0 - g], [(1.0 - af) * lam_h, -(1.0 - am)]], dtype=complex)
    return np.linalg.solve(a, b)


def amplification_factor(rho_inf: float, lam_h: complex) -> complex:
    """Principal root (the one approximating exp(lam*h)) of the step of y' = lam*y."""
    eig = np.linalg.eigvals(_step_matrix(rho_inf, lam_h))
    return eig[np.argmin(np.abs(eig - np.exp(lam_h)))] if abs(lam_h) < 1e3 else eig[np.argmax(np.abs(eig))]


def spectral_radius(rho_inf: float, lam_h: complex) -> float:
    """Largest |root| of the step (stability: <= 1; at lam*h -> -inf it tends to rho_inf)."""
    return float(np.abs(np.linalg.eigvals(_step_matrix(rho_inf, lam_h))).max())


@jit
def derivative_update(y_new, y_old, yd_old, h, gamma, out):
    """Y'_{n+1} from the gamma relation: [(Y_{n+1} - Y_n)/h - (1 - gamma) Y'_n] / gamma."""
    for k in range(y_new.shape[0]):
        out[k] = ((y_new[k] - y_old[k]) / h - (1.0 - gamma) * yd_old[k]) / gamma
