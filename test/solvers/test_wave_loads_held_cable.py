"""The wave load of docs/waves.md on a held straight cable, every term, against quadrature of the formula.

A very taut straight cable (EA = 2e7 N, strain 5 %: T ~ 1 MN, so it hardly moves: its own inertia and
the velocity in the relative drag are negligible) held at both ends, fully submerged (no surface band),
in a regular deep-water wave (H = 2 m, T = 6 s, k = 0.112 1/m, wavelength 56 m) travelling along +x.
Vertical, horizontal (along the wave) and inclined (45 deg in the x-z plane). The sum of the end forces is
then the integral of the distributed load along the cable,

    f = rho A a_w + rho A_h (C_mn a_w,perp + C_mt a_w,par)
        + 0.5 rho d sqrt(1 + eps) (C_dn |u_perp| u_perp + C_dt |u_par| u_par) + (rho A - gamma0) g z_hat,

A = gamma0 / rho_c (displaced, as the buoyancy), A_h = pi d^2 / 4 (added mass), u and a_w the wave particle
velocity and local acceleration of physics/waves.py (Wheeler), integrated here with 200 Gauss points. The
coefficients are chosen so that every term shows (C_mt = 0.5, C_dt = 0.2, A != A_h). Compared: the force
along the cable axis and across it (in the x-z plane), over one wave period after the start transient.

Tolerance: 0.5 % of each component's dynamic range plus 0.2 N (the axial vibration the straight start
leaves, the small deflection; measured with the DG solver on 2026-11-26: <= 0.12 N, 0.05 % of the range).
Leaving out the axial Froude-Krylov part rho A a_w,par (PE2020 Eq. 13's form) changes the along-axis force
by 10-12 N, ~20 % of its range: the test fails then.
"""

import math

import numpy as np
import pytest

from tether_sim.physics import waves
from tether_sim.scenarios import harness

L, STRAIN = 20.0, 0.05
RHO, D, G, GAMMA0, RHO_C = 1025.0, 0.05, 9.81, 2.0, 1500.0
CMN, CMT, CDN, CDT = 1.0, 0.5, 1.2, 0.2
H, PERIOD = 2.0, 6.0
T0, T1 = 4.0, 10.0

CASES = {  # ship end, unit axis from the ship end to the vehicle end
    "vertical": ((0.0, 0.0, -2.0), (0.0, 0.0, -1.0)),
    "horizontal": ((0.0, 0.0, -6.0), (1.0, 0.0, 0.0)),
    "inclined": ((0.0, 0.0, -2.0), (math.sqrt(0.5), 0.0, -math.sqrt(0.5))),
}


def flat(solver, case):
    top, e = CASES[case]
    bottom = np.add(top, L * (1 + STRAIN) * np.asarray(e))
    f = {"solver": solver, "dg.n_elements": 4, "dg.order": 3, "dg.damping": "implicit",
         "hybrid.n_segments": 40, "hybrid.time_step": 0.01, "hybrid.zoning": "all_catenary",
         "cable.length": L, "cable.EA": 2.0e7, "cable.gamma0": GAMMA0, "cable.density": RHO_C, "cable.diameter": D,
         "cable.Cdn": CDN, "cable.Cdt": CDT, "cable.Cmn": CMN, "cable.Cmt": CMT,
         "cable.damping": 1.2e4,  # ~10 % of critical on the first axial mode: the start transient dies
         "ship_end.kind": "fixed", "ship_end.position": list(top),
         "vehicle_end.kind": "fixed", "vehicle_end.position": [float(c) for c in bottom],
         "initial.kind": "straight",
         "waves.kind": "regular", "waves.height": H, "waves.period": PERIOD, "waves.direction": 0.0}
    return f


def reference(comps, case, times, axial_fk=True, added_mass_area=math.pi * D * D / 4.0):
    """Integral of the load over the cable (N, world) at each time, 200-point Gauss-Legendre."""
    top, e = CASES[case]
    e = np.asarray(e)
    x, w = np.polynomial.legendre.leggauss(200)
    ls = L * (1 + STRAIN)
    pts = np.asarray(top)[None, :] + ((x + 1.0) / 2.0 * ls)[:, None] * e[None, :]
    w = w * L / 2.0  # per unstretched metre
    rho_a, rho_ah = RHO * GAMMA0 / RHO_C, RHO * added_mass_area
    hrd = 0.5 * RHO * D * math.sqrt(1 + STRAIN)
    u, a = np.empty(3), np.empty(3)
    out = []
    for t in times:
        F = np.zeros(3)
        for p, wi in zip(pts, w):
            waves.wave_kinematics(p[0], p[1], p[2], t, *comps.arrays(), comps.depth, comps.stretch, u, a)
            at = a @ e
            an = a - at * e
            ut = u @ e
            un = u - ut * e
            fk = rho_a * a if axial_fk else rho_a * an
            f = fk + rho_ah * (CMN * an + CMT * at * e) + hrd * (CDN * np.linalg.norm(un) * un + CDT * abs(ut) * ut * e)
            f[2] += (rho_a - GAMMA0) * G
            F += wi * f
        out.append(F)
    return np.array(out)


@pytest.mark.parametrize("solver_name", ["dg", "hybrid"])
@pytest.mark.parametrize("case", list(CASES))
def test_held_cable_wave_load_along_and_across_the_axis(case, solver_name):
    config, solver = harness.make_solver(flat(solver_name, case))
    comps = waves.wave_components(config)
    res = harness.run_sampled(solver, np.arange(0.1, T1 + 1e-9, 0.1), keep=())
    late = res["t"] > T0
    t = res["t"][late]
    F = (res["ship_force"] + res["vehicle_force"])[late]
    # the added-mass area: pi d^2 / 4 in the DG solver, gamma0 / rho_c in the hybrid one (docs/waves.md)
    am_area = math.pi * D * D / 4.0 if solver_name == "dg" else GAMMA0 / RHO_C
    ref = reference(comps, case, t, added_mass_area=am_area)
    old = reference(comps, case, t, axial_fk=False, added_mass_area=am_area)
    e = np.asarray(CASES[case][1])
    n = np.array([-e[2], 0.0, e[0]])  # across the axis in the x-z plane
    for name, d in (("along", e), ("across", n)):
        fs, fr, fo = F @ d, ref @ d, old @ d
        err = np.abs(fs - fr).max()
        tol = 0.005 * np.ptp(fr) + 0.2
        print(f"{solver_name} {case} {name}: range {np.ptp(fr):.1f} N, max error {err:.2f} N (tol {tol:.2f}), "
              f"without the axial Froude-Krylov {np.abs(fo - fr).max():.1f} N")
        assert err < tol
        if name == "along":  # the test can tell the two forms apart
            assert np.abs(fo - fr).max() > 4.0 * tol
    assert np.abs(F[:, 1]).max() < 0.5  # nothing across the plane of the wave
