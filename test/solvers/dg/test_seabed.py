"""Seabed contact [PE2020 Eq. 15-16]: static penetration w/(K_g d) and sliding friction.

Sink: a free cable laid straight on the seabed settles (critically damped contact) at
z_g - w / (K_g d). K_g is chosen soft (3e4 N/m^3) so the 16 mm penetration is resolvable; 1% of it.

Friction: a cable lying along +x from the ship end is dragged by the ship end moving in -x at a
steady speed U (smoothly started). In steady sliding every point moves at U and the friction
Eq. 16, f = -mu tanh(pi U / v_mu) w per metre (opposing the motion), is carried by the tension:
the cable pulls the ship end with +x force mu w L tanh(pi U / v_mu). Checked at U >> v_mu (fully
developed) and at U = 0.2 v_mu (the tanh branch), to 1%; drag and added-mass coefficients are zero
so friction is the only horizontal force. The axial strain is < 2e-3, so the sqrt(l_eps) factor
changes the friction by < 0.1%.
"""

import numpy as np
import pytest

from tether_sim.scenarios import harness
from tether_sim.scenarios import references as ref

L, GAMMA0, RHO_C, D, RHO_F = 20.0, 2.0, 4000.0, 0.03, 1025.0
Z_G, K_G, MU, V_MU = -50.0, 3.0e4, 0.5, 0.01
W = ref.submerged_weight(GAMMA0, RHO_C, RHO_F)


def flat(ship_kind):
    return {
        "solver": "dg", "dg.n_elements": 4, "dg.order": 4,
        "cable.length": L, "cable.EA": 1.0e6, "cable.gamma0": GAMMA0, "cable.density": RHO_C,
        "cable.diameter": D, "cable.Cdn": 0.0, "cable.Cdt": 0.0, "cable.Cmn": 0.0, "cable.Cmt": 0.0,
        "cable.EI": 0.0, "cable.damping": 50.0,
        "environment.g": 9.81, "environment.fluid_density": RHO_F,
        "environment.seabed": True, "environment.seabed_z": Z_G, "environment.seabed_stiffness": K_G,
        "environment.seabed_damping": 1.0, "environment.seabed_friction": MU,
        "environment.seabed_friction_speed": V_MU,
        "ship_end.kind": ship_kind, "ship_end.position": [0.0, 0.0, Z_G],
        "vehicle_end.kind": "free", "vehicle_end.position": [L, 0.0, Z_G],
        "initial.kind": "straight",
    }


def test_resting_cable_sinks_by_w_over_Kg_d():
    config, solver = harness.make_solver(flat("free"))
    s = np.linspace(0.0, L, 21)
    res = harness.run_sampled(solver, np.arange(0.25, 3.01, 0.25), arc_lengths=s)
    delta = ref.seabed_sink_depth(W, K_G, D)
    z = res["position"][-1][:, 2]
    print(f"seabed sink: {Z_G - z.mean():.5f} m vs w/(K_g d) = {delta:.5f} m ({(Z_G - z.mean()) / delta - 1:+.2e})")
    np.testing.assert_allclose(z, Z_G - delta, atol=0.01 * delta)
    assert np.max(np.abs(res["velocity"][-1])) < 1e-4  # at rest (contact time scale ~0.05 s, 3 s run)


@pytest.mark.parametrize("speed", [0.2, 0.2 * V_MU], ids=["developed", "tanh_branch"])
def test_friction_opposes_sliding(speed):
    config, solver = harness.make_solver(flat("prescribed"))
    ramp = 1.0

    def ship_motion(t):  # velocity U (1 - cos(pi t / ramp)) / 2 up to t = ramp, then U
        if t < ramp:
            x = -speed * (0.5 * t - 0.5 * ramp / np.pi * np.sin(np.pi * t / ramp))
            v = -speed * 0.5 * (1.0 - np.cos(np.pi * t / ramp))
        else:
            x, v = -speed * (t - 0.5 * ramp), -speed
        return {"ship": ([x, 0.0, Z_G - ref.seabed_sink_depth(W, K_G, D)], [v, 0.0, 0.0])}

    s = np.linspace(0.0, L, 21)
    res = harness.run_sampled(solver, np.arange(0.02, 4.001, 0.02), arc_lengths=s, motion=ship_motion)
    late = res["t"] > 3.0
    force = res["ship_force"][late].mean(axis=0)
    expected = MU * np.tanh(np.pi * speed / V_MU) * W * L
    print(f"U={speed}: ship force {force}, expected +x {expected:.3f} N")
    assert force[0] == pytest.approx(expected, rel=0.01)  # cable pulls the ship back: friction opposes sliding
    assert abs(force[1]) < 1e-6 * expected
    # The whole cable slides at U in the direction the ship moves: displacement of every point over the
    # last second (a small undamped axial oscillation, ~2 mm at U = 0.2, rides on it: 2% + 1 mm).
    i0 = np.searchsorted(res["t"], 3.0)
    moved = res["position"][-1][:, 0] - res["position"][i0][:, 0]
    np.testing.assert_allclose(moved, -speed * (res["t"][-1] - res["t"][i0]), rtol=0.02, atol=1e-3)
