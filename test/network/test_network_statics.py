"""Statics of a two-line network (ship, umbilical, body, excursion tether, fixed end) against an
independent solution: the two elastic catenaries integrated as ODEs (scipy, not the closed form of
physics/statics.py) and joined at the body with its wet weight."""

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import fsolve

from tether_sim.network.body import NetworkBody
from tether_sim.network.spec import parse_network
from tether_sim.network.statics import solve_network_statics

G, RHO = 9.81, 1025.0
UMB = dict(length=200.0, EA=45.5e6, gamma0=3.01, density=7153.0, diameter=0.03, material="linear")
EXC = dict(length=30.0, EA=2.0e6, gamma0=1.0, density=2000.0, diameter=0.025, material="linear")
BODY = dict(mass=4995.0, density=8448.0, initial_position=[0.0, 0.0, -200.0])
ANCHOR = np.array([20.0, 0.0, -225.0])


def network_tree(body_attach=(0.0, 0.0, 0.0)):
    return dict(
        environment=dict(g=G, fluid_density=RHO),
        points=dict(ship=dict(kind="prescribed", position=[0.0, 0.0, 0.0]),
                    anchor=dict(kind="fixed", position=ANCHOR.tolist())),
        bodies=dict(cage=BODY),
        lines={"umbilical": {"from": "ship", "to": "cage", "to_attachment": list(body_attach), "cable": UMB},
               "excursion": {"from": "cage", "to": "anchor", "from_attachment": [-a for a in body_attach],
                             "cable": EXC}})


def wet(c):
    return c["gamma0"] * G * (1.0 - RHO / c["density"])


def span(c, H, V0):
    """End of an elastic cable (x-z plane) whose force on its s = 0 end is (H, V0): the internal force
    tau(s) = (H, V0 + w s), dr/ds = (1 + |tau| / EA) tau / |tau|, integrated to s = L."""
    w, EA = wet(c), c["EA"]

    def rhs(s, y):
        tx, tz = H, V0 + w * s
        T = np.hypot(tx, tz)
        return [(1 + T / EA) * tx / T, (1 + T / EA) * tz / T]

    sol = solve_ivp(rhs, (0.0, c["length"]), [0.0, 0.0], method="DOP853", rtol=1e-13, atol=1e-12)
    return sol.y[:, -1]


def independent_solution():
    """(body position (x, z), force on the ship (H, V)) of the two-catenary system."""
    W = BODY["mass"] * G * (1.0 - RHO / BODY["density"])

    def resid(u):
        H, V = u[0] * 1e3, u[1] * 1e3
        body = span(UMB, H, V)
        # body balance: the umbilical pulls with -tau1(L), the excursion with tau2(0), weight -W
        V2 = V + wet(UMB) * UMB["length"] + W
        end = body + span(EXC, H, V2)
        return (end - ANCHOR[[0, 2]]) / 10.0

    u = fsolve(resid, [0.1, -48.0], xtol=1e-12)
    assert np.max(np.abs(resid(u))) < 1e-11
    H, V = u * 1e3
    return span(UMB, H, V), np.array([H, V])


def test_two_line_statics_match_independent_catenaries():
    spec = parse_network(network_tree())
    bodies = {"cage": NetworkBody("cage", spec.bodies["cage"].props, spec.environment, [[0, 0, 0], [0, 0, 0]])}
    st, res = solve_network_statics(spec, bodies)
    assert res < 1e-10
    body_ref, ship_force_ref = independent_solution()
    pos = bodies["cage"].state[0:3]
    np.testing.assert_allclose(pos[[0, 2]], body_ref, rtol=1e-6, atol=1e-6 * np.linalg.norm(body_ref))
    assert abs(pos[1]) < 1e-9
    shapes = st.shapes({"cage": bodies["cage"].state})
    f_ship = shapes["umbilical"][2][0]
    np.testing.assert_allclose(f_ship[[0, 2]], ship_force_ref, rtol=1e-6, atol=1e-6 * np.linalg.norm(ship_force_ref))


def test_offset_attachments_tilt_the_body_to_moment_balance():
    """Attachments 2.1 m above and below the CoG: the body tilts until the two line forces' moments
    cancel (they are then collinear with the CoG, since the weight acts there)."""
    spec = parse_network(network_tree(body_attach=(0.0, 0.0, 2.1)))
    b = NetworkBody("cage", spec.bodies["cage"].props, spec.environment, [[0, 0, 2.1], [0, 0, -2.1]])
    st, res = solve_network_statics(spec, {"cage": b})
    assert res < 1e-10
    sh = st.shapes({"cage": b.state})
    f_top, f_bottom = sh["umbilical"][2][1], sh["excursion"][2][0]
    R = b.rotation
    moment = np.cross(R @ [0, 0, 2.1], f_top) + np.cross(R @ [0, 0, -2.1], f_bottom)
    assert np.linalg.norm(moment) < 1e-9 * 2.1 * np.linalg.norm(f_top)
    tilt = np.degrees(np.arccos(R[2, 2]))
    assert 0.05 < tilt < 5.0  # the excursion tether's horizontal pull tilts it, a little


def test_statics_stay_on_the_hanging_branch():
    """A slack excursion tether pulling sideways from below the cage: Newton from upright must end
    at the hanging equilibrium (the upside-down one balances forces and moments too)."""
    tree = network_tree(body_attach=(0.0, 0.0, 2.1))
    tree["points"]["ship"]["position"] = [0.0, 0.0, -3.0]
    tree["points"]["anchor"]["position"] = [20.0, 0.0, -222.4]
    tree["bodies"]["cage"] = dict(BODY, initial_position=[0.0, 0.0, -205.1])
    tree["lines"]["excursion"]["cable"] = dict(EXC, density=1100.0)
    spec = parse_network(tree)
    b = NetworkBody("cage", spec.bodies["cage"].props, spec.environment, [[0, 0, 2.1], [0, 0, -2.1]])
    solve_network_statics(spec, {"cage": b})
    assert b.rotation[2, 2] > 0.999
    assert -206.3 < b.state[2] < -204.3
