"""Stable SSP-RK3 substep of the DG cable (see docs/dg_solver.md for the derivation and tables).

The semi-discrete operator has three kinds of eigenvalues on an element of size h and order P:
axial waves ~ c (P+1)^2 / h (hyperbolic, Lax-Friedrichs), axial material damping
~ (zeta / gamma0) ((P+1)^2 / h)^2 (parabolic) and bending waves ~ sqrt(EI / gamma0)
((P+1)^2 / h)^2 (dispersive), bending damping ~ (zeta_b / gamma0) ((P+1)^2 / h)^4. The limit is

    dt = 1 / max_e [ A_P c / h + B_P (zeta / gamma0) / h^2 + C_P sqrt(EI / gamma0) / h^2
                     + E_P (zeta_b / gamma0) / h^4 ]

with A_P..E_P measured from the spectrum of the linearised DG operator (``calibrate_timestep``
in docs/dg_solver.md) so that dt is at the SSP-RK3 stability boundary for a straight taut cable;
the solver then multiplies by the safety factor dg.cfl (default 0.5).
"""

import math

import numpy as np

from tether_sim.numerics.integrators import SSPRK3_IMAG_LIMIT

# Coefficients per order P = 1..12, measured by benchmarks/studies/calibrate_timestep.py (see docs).
_A = {1: 2.4398, 2: 4.775, 3: 7.9559, 4: 11.9302, 5: 16.6979, 6: 22.2589, 7: 28.6133, 8: 35.761, 9: 43.702, 10: 52.4363, 11: 61.9639, 12: 72.2848}
_B = {1: 6.319, 2: 25.7774, 3: 68.3371, 4: 151.323, 5: 294.064, 6: 519.196, 7: 853.848, 8: 1329.01, 9: 1979.52, 10: 2844.1, 11: 3965.34, 12: 5389.69}
_C = {1: 8.9859, 2: 36.6578, 3: 97.1828, 4: 215.201, 5: 418.198, 6: 738.367, 7: 1214.29, 8: 1890.03, 9: 2815.16, 10: 4044.72, 11: 5639.28, 12: 7664.91}
_E = {1: 96.4163, 2: 1604.48, 3: 11276.4, 4: 55293, 5: 208806, 6: 650913, 7: 1.76044e+06, 8: 4.26496e+06, 9: 9.46195e+06, 10: 1.95322e+07, 11: 3.79684e+07, 12: 7.01437e+07}


def _coef(table, P, power):
    """Tabulated coefficient, or the P = 12 value scaled by ((P + 1) / 13)^power beyond the table."""
    if P in table:
        return table[P]
    return table[12] * ((P + 1) / 13.0) ** power


def stable_dt(h, P, max_slope, gamma0, zeta, EI, zeta_b, lambda_floor=0.0, seabed_Kd=0.0, seabed_zeta=0.0,
              implicit_damping=False):
    """SSP-RK3 stability limit (s) of the DG cable on element sizes h (array) at order P.

    With implicit_damping (dg.damping = implicit) the damping terms B_P and E_P are dropped: the
    damping is then integrated by the L-stable implicit step of implicit_damping.py.

    A seabed in contact adds a local spring-damper of frequency w = sqrt(K_g d / gamma0) and damping
    ratio zeta_s, eigenvalues -zeta_s w +- w sqrt(zeta_s^2 - 1); its rate w (1 + 2 zeta_s) bounds
    their modulus and is added (divided by the SSP-RK3 imaginary-axis limit sqrt(3)).
    """
    h = np.asarray(h, float)
    c = max((max_slope / gamma0) ** 0.5, lambda_floor)
    if implicit_damping:
        zeta, zeta_b = 0.0, 0.0
    rate = (_coef(_A, P, 2) * c / h
            + _coef(_B, P, 4) * (zeta / gamma0) / h**2
            + _coef(_C, P, 4) * (EI / gamma0) ** 0.5 / h**2
            + _coef(_E, P, 8) * (zeta_b / gamma0) / h**4)
    if seabed_Kd > 0.0:
        w = (seabed_Kd / gamma0) ** 0.5
        rate = rate + w * (1.0 + 2.0 * seabed_zeta) / SSPRK3_IMAG_LIMIT
    rmax = float(np.max(rate))
    return 1.0 / rmax if rmax > 0 else 1.0


def damping_rate(h, P, zeta, gamma0) -> float:
    """The rule's axial-damping rate max_e B_P (zeta / gamma0) / h_e^2 (1/s): the SSP-RK3 limit of that term alone
    is 1 / rate, so the operator's spectral radius is about SSP-RK3's real-axis limit times it."""
    h = np.asarray(h, float)
    return float(np.max(_coef(_B, P, 4) * (zeta / gamma0) / h**2))


def config_stable_dt(config, h, max_slope, implicit_damping) -> float:
    """The automatic substep: dg.cfl x :func:`stable_dt` with the cable, environment and dg keys of
    ``config`` on element sizes ``h`` (the solver's ``stable_time_step`` and the load-time work
    estimate both call this)."""
    cab, env, opt = config.cable, config.environment, config.dg
    kd = env.seabed_stiffness * cab.diameter if env.seabed else 0.0
    return opt.cfl * stable_dt(h, int(opt.order), max_slope, cab.gamma0, cab.damping, cab.EI, cab.bending_damping,
                               opt.lambda_floor, kd, env.seabed_damping, implicit_damping)


# Bending multirate (stepper.py): the nested LDG every K substeps, the bending shear T_s extrapolated
# quadratically from its last three evaluations in between. For a bending mode of frequency w that is
# the third-order Adams-Bashforth method on the macro step H = K dt, stable on the imaginary axis for
# w H <= 0.72 (its stability region holds [-0.72i, 0.72i]; the second-order extrapolation would not:
# |rho| = 1 + (w H)^4 / 4 per step). The rule keeps w H <= BENDING_MULTIRATE_WH for the largest bending
# frequency of the mesh, w_max = sqrt(3) C_P sqrt(EI / gamma0) / h^2 (the imaginary-axis limit of SSP-RK3
# times the measured rate of the bending term, the taut straight cable) times SHORT_CHORD_STIFFENING = 2
# (the short-chord tangent b = 2 q / (1 + l^2) of a slack part has |db/dq| <= 2: four times the
# stiffness, twice the frequency; ldg.py), and H <= BENDING_MULTIRATE_MAX_H for accuracy.
BENDING_MULTIRATE_WH = 0.25
BENDING_MULTIRATE_MAX_H = 0.025  # s (about the node tick)
SHORT_CHORD_STIFFENING = 2.0


def bending_multirate_steps(h, P, gamma0, EI, zeta_b, torque, dt):
    """K of the bending multirate for substep dt on element sizes h (1: the nested LDG at every stage).
    1 without bending stiffness, with bending damping (a stiff real eigenvalue ~ h^-4) or a torque."""
    if EI <= 0.0 or zeta_b > 0.0 or torque != 0.0 or dt <= 0.0:
        return 1
    hmin = float(np.min(np.asarray(h, float)))
    w = SHORT_CHORD_STIFFENING * SSPRK3_IMAG_LIMIT * _coef(_C, P, 4) * (EI / gamma0) ** 0.5 / hmin**2
    H = min(BENDING_MULTIRATE_WH / w, BENDING_MULTIRATE_MAX_H)
    return max(1, int(math.floor(H / dt * (1.0 + 1e-12))))
