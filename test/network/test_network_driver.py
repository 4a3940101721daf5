"""The network node's driver (tether_sim/ros/network_driver.py, no rclpy): clock, inputs, snap
detectors per line, re-synchronisation with blended points, a failing line stops the run."""

import numpy as np
import pytest

from tether_sim.config import SimConfig
from tether_sim.network.spec import parse_network
from tether_sim.physics.snap import SnapEvent
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
    from tether_sim.ros import network_outputs as outputs

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
    # 3 s late (beyond node.max_lag): the gap is skipped, the ship point catches up with its input
    held = d.net.points["ship"].pos.copy()
    now += 3.0
    r = d.tick(now)
    assert r.dropped == pytest.approx(3.0, abs=0.03) and d.resyncs == 1 and d.degraded and d.catchup.active("ship")
    assert d.stamp == pytest.approx(now - node.input_delay)
    step = np.linalg.norm(d.net.points["ship"].pos - held)
    assert step < 0.5 * node.max_end_speed * 0.02  # no jump onto the input
    while d.catchup or d.degraded:
        now += 0.02
        r = d.tick(now)
        for line, evs in r.events.items():  # detection runs on (this excursion tether snaps in the heave
            # without any skip too, 231 N at 0.9 s); what overlaps the catch-up is published degraded
            msgs = outputs.event_outputs(d, node, line, [e for e in evs if isinstance(e, SnapEvent)])
            assert all(m.degraded for _, m in msgs)
    assert d.net.points["ship"].pos[2] == pytest.approx(0.5 * np.sin(d.stamp), abs=1e-9)
    # a line solver failing (e.g. a hybrid Newton failure) stops the run with its reason, for good
    def fail(*a, **k):
        raise RuntimeError("hybrid: Newton failed to converge at t = 8.96 s")
    d.net.lines["excursion"].tick = fail
    r = d.tick(now + 0.02)
    assert "Newton failed" in r.error and "Newton failed" in d.failed and not r.advanced
    assert not d.tick(now + 0.04).advanced


class Circle:
    """The ship's fairlead on the PE2020 circle (radius 2 m, 0.2 Hz, in x-z), ramped in over 1 s, as a
    function of the network's own time (like the node's RAO ship): a re-synchronisation moves the clock,
    not the motion the lines feel."""

    has_data = True

    def __init__(self, driver, a=2.0, f=0.2):
        self.d, self.a, self.w = driver, a, 2 * np.pi * f

    def attachment_at(self, t):
        tau = t - self.d.anchor
        u = min(max(tau, 0.0), 1.0)
        r, dr = u * u * (3 - 2 * u), 6 * u * (1 - u)
        x, z = np.sin(self.w * tau), np.cos(self.w * tau) - 1
        dx, dz = self.w * np.cos(self.w * tau), -self.w * np.sin(self.w * tau)
        return self.a * r * np.array([x, 0, z]), self.a * np.array([dr * x + r * dx, 0.0, dr * z + r * dz])


def test_a_resynchronisation_in_a_slack_period_keeps_its_snap(spec):
    """The umbilical goes slack at 0.18 s (cage end) and 0.20 s (ship end) under the circling fairlead
    and snaps at 2.9 s: 206 kN at the cage end, 215 kN at the ship (4.8 and 4.5 x static). A 1.5 s stall
    of the clock at 2.0 s makes the driver re-synchronise in the slack period. The network driver used
    to restart detection with fresh detectors after the skip's blend: the slack period was dropped and
    both snaps went unreported. Now, as the single-line driver (one code path, tether_sim/ros/bridging.py),
    detection goes on across the skip: both snaps are published, degraded, with their slack period's
    start moved by the skipped clock time, and no second slack warning."""
    from tether_sim.physics.snap import SlackStarted
    from tether_sim.ros import network_outputs as outputs

    node = SimConfig().node
    d = NetworkDriver(spec, node)
    d.sources["ship"] = Circle(d)
    d.start(0.0)
    events, k, stalled = [], 0, False
    while k / 50.0 < 6.5:
        k += 1
        if not stalled and k / 50.0 >= 2.0:
            k += 75  # 1.5 s of clock
            stalled = True
        r = d.tick(k / 50.0)
        for line, evs in r.events.items():
            msgs = dict(zip([id(e) for e in evs if isinstance(e, (SnapEvent, SlackStarted))],
                            [m for _, m in outputs.event_outputs(d, node, line, evs)]))
            events += [(ev, msgs.get(id(ev))) for ev in evs]
    assert d.resyncs == 1 and d.dropped_total == pytest.approx(1.5 - 0.02 - node.input_delay + 0.2, abs=0.05)
    snaps = sorted([(ev, m) for ev, m in events if isinstance(ev, SnapEvent) and ev.location.startswith("umbilical")],
                   key=lambda x: x[0].location)
    assert [ev.location for ev, _ in snaps] == ["umbilical/ship", "umbilical/vehicle"]
    slack = {ev.location: ev.time for ev, _ in events if isinstance(ev, SlackStarted) and ev.location.startswith("umbilical")
             and ev.time < min(e.time for e, _ in snaps)}
    assert sorted(slack) == ["umbilical/ship", "umbilical/vehicle"]  # one slack warning per end
    for ev, msg in snaps:
        assert ev.amplification > 3.0 and ev.slack_start == pytest.approx(slack[ev.location] + d.dropped_total)
        assert d.bridged(ev) and msg.degraded and msg.peak_tension == ev.peak_tension


def test_settle_quiet_is_the_tension_range_against_half_a_newton_and_five_percent():
    from tether_sim.ros.network_driver import settle_quiet

    t = np.linspace(0.0, 1.0, 101)
    steady = np.vstack([t, 6.0 + 0.3 * np.sin(40 * t), 2.4 + 0.2 * np.cos(30 * t)])  # ranges 0.6 / 0.4 N
    assert settle_quiet(steady) and settle_quiet(np.zeros((3, 0)))
    ringing = steady.copy()
    ringing[2, 50] = 3.5  # one sample 1.1 N above: beyond 0.5 N + 5 % of 2.4 N
    assert not settle_quiet(ringing)
    heavy = np.vstack([t, 1e4 + 200.0 * np.sin(40 * t), 5e3 + 0 * t])  # 400 N of 10 kN: within 5 %
    assert settle_quiet(heavy)
    heavy[1] *= 1.0 + 0.02 * t  # and a 2 % drift on top: 600 N, not
    assert not settle_quiet(heavy)


def test_tms_excursion_tether_is_at_rest_when_the_clock_starts():
    """The TMS file's excursion tether (its static polish fails: it starts off its discrete equilibrium
    and rings) has settled before the clock starts: over the first two seconds with the points held
    its end tensions (2.4 and 5.7 N) stay within 2 N of their median (blips of ~1 N remain on its
    coarse mesh); three seconds of settling were not enough there: up to 54 N at the vehicle end and
    118 N at the cage end in those two seconds."""
    from pathlib import Path

    from tether_sim.network.params import load_network_files
    from tether_sim.ros.network_driver import SETTLE_MAX, SETTLE_TIME

    spec, cfg = load_network_files([Path(__file__).resolve().parents[2] / "config" / "ropos_tms.yaml"])
    d = NetworkDriver(spec, cfg.node)
    d.start(0.0)
    assert d.settled == ["excursion"] and SETTLE_TIME <= d.net.time <= SETTLE_MAX
    s = np.concatenate([d.net.tick(d.net.time + 1.0)["excursion"]["samples"] for _ in range(2)], axis=1)
    assert s.shape[1] > 100
    for row in s[1:3]:
        assert np.max(np.abs(row - np.median(row))) < 2.0
