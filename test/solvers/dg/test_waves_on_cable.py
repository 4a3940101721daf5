"""Waves on the DG cable: wave particle velocity in the drag, wave acceleration in the Froude-Krylov +
added-mass term (docs/waves.md), current and waves together, and the wetted part following eta(x, y, t).

Case: a very taut vertical cable (T ~ 1 MN, so it hardly moves: its lateral deflection under the
~10 N/m wave load is ~0.1 mm and its own inertia is negligible) held from 3 m above the still water to
27.5 m below, in a regular deep-water wave (H = 2 m, T = 8 s) plus a uniform 0.3 m/s current along the
wave. Then the sum of the end forces is the integral of the distributed load along the cable:

    F_x = int phi [(rho A + rho A_h C_mn) a_w,x + 0.5 rho d sqrt(1 + eps) |u_x| u_x] ds,  u_x = U_c + u_w,x
    F_z = int [-gamma0 g + phi rho g A + (1 - phi) rho_air g A + phi rho A a_w,z] ds    (C_mt = 0)

(A = gamma0 / rho_c the displaced area, A_h = pi d^2 / 4). In deep water the vertical Froude-Krylov term
-rho A w^2 e^{kz} eta nearly cancels the buoyancy swing rho g A eta of the wetted length (w^2 = g k): what
is left is the pressure swing at the lower end, e^{k z_end} of it.

with phi the wetted fraction about eta(0, 0, t) (physics/hydrodynamics.wetted_fraction, same band),
integrated with 400 Gauss points, and the wave kinematics of physics/waves.py at the same points.

Tolerances. The load is largest at the surface (drag ~30 N/m under the crest) where the DG solver
integrates the wetted-fraction ramp with its Gauss points, 0.8 m apart (N = 6, P = 4): one point's
share of the crest load is ~24 N, and the ramp quadrature error is a fraction of it. F_x: 2.5 % of its
peak (340 N; measured 1.6 %). F_z: error < 2 N (the rest being the axial vibration started by the
straight initial state), where leaving out either the buoyancy swing (+-10 N) or the vertical
Froude-Krylov term (-+8 N) would be off by more than 6 N.
"""

import math

import numpy as np
import pytest

from tether_sim.physics import waves
from tether_sim.physics.hydrodynamics import wetted_fraction
from tether_sim.scenarios import harness

TOP, L, STRAIN = 3.0, 30.0, 0.05
RHO, D, G, GAMMA0, RHO_C, UC = 1025.0, 0.05, 9.81, 2.0, 2000.0, 0.3
H, PERIOD = 2.0, 8.0


FLAT = {"solver": "dg", "dg.n_elements": 6, "dg.order": 4, "dg.damping": "implicit",
        "cable.length": L, "cable.EA": 2.0e7, "cable.gamma0": GAMMA0, "cable.density": RHO_C, "cable.diameter": D,
        "cable.Cdn": 1.0, "cable.Cdt": 0.0, "cable.Cmn": 1.0, "cable.Cmt": 0.0,
        "cable.damping": 1.2e4,  # ~10 % of critical on the first axial mode (53 Hz): the start transient dies
        "environment.free_surface": True, "environment.air_Cdn": 0.0,
        "environment.current_z": [-100.0, 0.0], "environment.current_x": [UC, UC], "environment.current_y": [0.0, 0.0],
        "ship_end.kind": "fixed", "ship_end.position": [0.0, 0.0, TOP],
        "vehicle_end.kind": "fixed", "vehicle_end.position": [0.0, 0.0, TOP - L * (1 + STRAIN)],
        "initial.kind": "straight",
        "waves.kind": "regular", "waves.height": H, "waves.period": PERIOD, "waves.direction": 0.0}


@pytest.fixture(scope="module")
def run():
    config, solver = harness.make_solver(FLAT)
    comps = waves.wave_components(config)
    assert comps.amp.size == 1 and comps.k[0] == pytest.approx((2.0 * math.pi / PERIOD) ** 2 / G)  # deep water
    res = harness.run_sampled(solver, np.arange(0.05, 12.0001, 0.05), keep=())
    return config, solver, comps, res


def reference(comps, times, b):
    x, w = np.polynomial.legendre.leggauss(400)
    ls = L * (1 + STRAIN)
    z = TOP - ls * (x + 1.0) / 2.0
    w = w * L / 2.0  # per unstretched metre
    rho_ah, area = RHO * math.pi * D * D / 4.0, GAMMA0 / RHO_C
    fk = []
    u, a = np.empty(3), np.empty(3)
    fx, fz, eta_t = [], [], []
    for t in times:
        sx = sz = fkz = 0.0
        for zi, wi in zip(z, w):
            eta = waves.wave_kinematics(0.0, 0.0, zi, t, comps.amp, comps.omega, comps.k, comps.cos_dir,
                                        comps.sin_dir, comps.phase, comps.depth, comps.stretch, u, a)
            phi, _ = wetted_fraction(zi, eta, b)
            ux = u[0] + UC
            sx += wi * phi * ((RHO * area + rho_ah) * a[0] + 0.5 * RHO * D * math.sqrt(1 + STRAIN) * abs(ux) * ux)
            sz += wi * (-GAMMA0 * G + (phi * RHO + (1.0 - phi) * 1.225) * G * area + phi * RHO * area * a[2])
            fkz += wi * phi * RHO * area * a[2]
        fx.append(sx)
        fz.append(sz)
        fk.append(fkz)
        eta_t.append(waves.wave_elevation(0.0, 0.0, t, comps.amp, comps.omega, comps.k, comps.cos_dir, comps.sin_dir,
                                          comps.phase))
    return np.array(fx), np.array(fz), np.array(eta_t), np.array(fk)


def test_wave_and_current_loads_and_the_wetted_part_follow_the_wave(run):
    config, solver, comps, res = run
    nq = solver.ws.V.shape[0]
    b = max(0.5 * config.environment.surface_smoothing, 0.5 * (L / 6) / nq * (1 + STRAIN))  # kernels.momentum_rate
    late = res["t"] > 6.0  # after the start transient (the wave is switched on at t = 0)
    t = res["t"][late]
    F = (res["ship_force"] + res["vehicle_force"])[late]
    fx, fz, eta, fkz = reference(comps, t, b)
    err_x = np.abs(F[:, 0] - fx).max()
    err_z = np.abs(F[:, 2] - fz).max()
    swing = np.polyfit(eta, fz - fkz, 1)[0]  # buoyancy of the wetted part: (rho - rho_air) g A but for the band
    print(f"F_x peak {np.abs(fx).max():.1f} N, max error {err_x:.2f} N; F_z swing {np.ptp(fz):.2f} N "
          f"(Froude-Krylov {np.ptp(fkz):.2f} N), max error {err_z:.2f} N")
    assert err_x < 0.025 * np.abs(fx).max()
    assert err_z < 2.0
    assert swing == pytest.approx((RHO - 1.225) * G * GAMMA0 / RHO_C, rel=0.1)
    assert np.ptp(fkz) > 12.0 and np.abs(fz - fkz - fz.mean()).max() > 6.0  # either term missing fails
