"""The network node's driver (tether_sim/ros/network_driver.py, no rclpy): clock, inputs, snap
detectors per line, re-synchronisation with blended points, a failing line stops the run."""

import numpy as np
import pytest

from tether_sim.config import SimConfig
from tether_sim.network.spec import parse_network
from tether_sim.ros.network_driver import NetworkDriver, line_snap_guard

UMB = dict(length=200.0, EA=45.5e6, gamma0=3.01, density=7153.0, diameter=0.03, damping=45500.0,
           material="bilinear", Cdn=1.0, Cdt=0.02, Cmn=1.0, Cmt=0.0)
EXC = dict(length=30.0, EA=2.0e6, gamma0=1.0, density=2000.0, diameter=0.025, damping=2000.0,
           material="bilinear", Cdn=1.2, Cdt=0.02, Cmn=1.0, Cmt=0.0)
TREE = dict(
    environment=dict(g=9.81, fluid_density=1025.0), coupling_step=0.02,
    points=dict(ship=dict(kind="prescribed", position=[0.0, 0.0, 0.0]),
                anchor=dict(kind="fixed", position=[20.0, 0.0, -225.0])),
    bodies=dict(cage=dict(mass=4995.0, density=8448.0, added_mass=[9200.0] * 3, drag_coefficients=[1.3, 1.3, 2.7],
                          drag_areas=[12.642, 12.642, 7.1158], inertia=[19000.0] * 3, initial_position=[0.0, 0.0, -202.1])),
    lines={"umbilical": {"from": "ship", "to": "cage", "to_attachment": [0.0, 0.0, 2.1], "cable": UMB,
                         "dg": dict(n_elements=4, order=2)},
           "excursion": {"from": "cage", "to": "anchor", "from_attachment": [0.0, 0.0, -2.1], "cable": EXC,
                         "dg": dict(n_elements=4, order=3)}})


class Heave:
    """A ship pose source: z = a sin(w t) (clock time), like an EndPoseInput."""

    has_data = True

    def __init__(self, a=0.5, w=1.0):
        self.a, self.w = a, w

    def attachment_at(self, t):
        return (np.array([0.0, 0.0, self.a * np.sin(self.w * t)]),
                np.array([0.0, 0.0, self.a * self.w * np.cos(self.w * t)]))


@pytest.fixture(scope="module")
def spec():
    return parse_network(TREE)


def test_guard_counts_the_body_mass_on_body_ends(spec):
    from tether_sim.network.solver import NetworkSolver

    net = NetworkSolver(spec)
    g = line_snap_guard(spec, "umbilical", net.lines["umbilical"])
    assert g.mass == pytest.approx(200.0 * 3.01 + 4995.0 + 9200.0)  # ship point kinematic, cage a body
    assert g.impedance == pytest.approx(np.sqrt(45.5e6 * 3.01))


def test_clock_inputs_resync_blend_and_failure(spec):
    node = SimConfig().node
    d = NetworkDriver(spec, node, {"ship": Heave()})
    d.start(10.0)
    assert d.stamp == pytest.approx(10.0 - node.input_delay)
    now = 10.0
    for _ in range(10):
        now += 0.02
        r = d.tick(now)
        assert r.advanced and not r.error and not d.degraded
    assert d.stamp == pytest.approx(now - node.input_delay)
    assert d.net.points["ship"].pos[2] == pytest.approx(0.5 * np.sin(d.stamp), abs=1e-9)  # follows its input
    assert not any(r.events.values())
    # 3 s late (beyond node.max_lag): the gap is skipped, the ship point is blended onto its input
    held = d.net.points["ship"].pos.copy()
    now += 3.0
    r = d.tick(now)
    assert r.dropped == pytest.approx(3.0, abs=0.03) and d.resyncs == 1 and d.degraded and "ship" in d.blends
    assert d.stamp == pytest.approx(now - node.input_delay)
    step = np.linalg.norm(d.net.points["ship"].pos - held)
    assert step < 0.5 * node.max_end_speed * 0.02  # no jump onto the input
    while d.blends or d.degraded:
        now += 0.02
        r = d.tick(now)
        assert not r.events
    assert d.net.points["ship"].pos[2] == pytest.approx(0.5 * np.sin(d.stamp), abs=1e-9)
    # a line solver failing (e.g. a hybrid Newton failure) stops the run with its reason, for good
    def fail(*a, **k):
        raise RuntimeError("hybrid: Newton failed to converge at t = 8.96 s")
    d.net.lines["excursion"].tick = fail
    r = d.tick(now + 0.02)
    assert "Newton failed" in r.error and "Newton failed" in d.failed and not r.advanced
    assert not d.tick(now + 0.04).advanced
