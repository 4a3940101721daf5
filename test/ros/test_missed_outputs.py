"""A tick that comes late by whole output periods (the timer skipped them: a starved process) publishes
the states of the instants it missed, each with its own stamp, as the node ticking on time would have.

Two nodes of the same file are driven by hand (test/ros/sim_harness.py ``HandDriven``: a hand clock,
the ship pose given to the pose callback 20 ms apart, the tick called directly, no wall-clock budget).
The first ticks every period; the second gets the same poses but its ticks skip periods (two, then one,
then more than the node catches up on). Every TetherState and wrench the second node publishes must
be one the first published at the same stamp (equal fields but the wall-clock real-time factor), in
order, none repeated, and the second must publish the states of the skipped periods (at most
``node.missed_outputs`` of them). Before the late tick caught up, it published only the newest instant:
the skipped periods' stamps were missing. The line-network node (config/ropos_tms.yaml, the vehicle held) is
driven the same way and checked the same on its lines' states, the wrenches and the cage's pose: it shares the
single-line node's catch-up, and published only the newest instant before.
"""

import math

import numpy as np
import pytest

pytest.importorskip("rclpy")
pytest.importorskip("tether_sim_msgs")
import rclpy  # noqa: E402
from geometry_msgs.msg import PoseStamped, WrenchStamped  # noqa: E402
from rclpy.serialization import deserialize_message  # noqa: E402
from sim_harness import HandDriven  # noqa: E402
from tether_sim_msgs.msg import TetherState  # noqa: E402

from tether_sim.io.params import load_config, to_flat  # noqa: E402

pytestmark = pytest.mark.ros

ROOT = __import__("pathlib").Path(__file__).resolve().parents[2]
TICKS = 70
MISSED_OUTPUTS_MAX = 5  # node.missed_outputs (the default)
# the late node's instants are the clock minus whole periods, the on-time node's the clock's running sum: they
# differ by float rounding (~1e-14 s), and so do the states, by ~1e-12 relative (measured: 1.8e-7 N in 73 kN)
RTOL = 1e-8
ATOL = {"force": 1e-6, "torque": 1e-6, "ship_end_tension": 1e-6, "vehicle_end_tension": 1e-6, "time_step": 0.0, "lag": 1e-9,
        "arc_length": 0.0, "tension": 1e-6, "orientation": 1e-12, "curvature": 1e-12, "bending_moment": 1e-9, "position": 1e-9, "velocity": 1e-9}
# periods whose tick the late node skips (its next tick comes that many periods late): two, one, and a stall
# longer than the node catches up on
SKIPPED = {20, 21, 30} | set(range(40, 40 + MISSED_OUTPUTS_MAX + 3))


def heave(t):
    return 0.3 * math.sin(2.0 * math.pi * 0.25 * (t - 100.0))  # (taut throughout: no slack period to amplify rounding)


def stamp(msg) -> float:
    return round(msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9, 6)


def fields(msg) -> dict:
    """The message's fields as plain values, without the real-time factor (wall clock)."""
    if isinstance(msg, TetherState):
        out = {k: getattr(msg, k) for k in ("ship_end_tension", "vehicle_end_tension", "time_step", "lag", "degraded", "solver")}
        out.update({k: np.asarray(getattr(msg, k)).tolist() for k in ("arc_length", "tension", "curvature", "bending_moment")})
        out.update({k: [(p.x, p.y, p.z) for p in getattr(msg, k)] for k in ("position", "velocity")})
        return out
    if isinstance(msg, PoseStamped):
        p, q = msg.pose.position, msg.pose.orientation
        return {"position": (p.x, p.y, p.z), "orientation": (q.x, q.y, q.z, q.w)}
    w = msg.wrench
    return {"force": (w.force.x, w.force.y, w.force.z), "torque": (w.torque.x, w.torque.y, w.torque.z)}


TYPES = {"/tether/state": TetherState, "/tether/ship_wrench": WrenchStamped, "/tether/vehicle_wrench": WrenchStamped}


def published(log, topic, types=TYPES) -> list:
    """[(tick, stamp, fields)] of every message of ``topic``."""
    out = []
    for k, entries in enumerate(log):
        for t, data in entries:
            if t == topic:
                msg = deserialize_message(data, types[topic])
                out.append((k, stamp(msg), fields(msg)))
    return out


@pytest.fixture(scope="module")
def runs():
    flat = to_flat(load_config(ROOT / "config/ropos_L200.yaml"))
    flat.update({"node.tick_budget": 1.0e6, "node.missed_outputs": MISSED_OUTPUTS_MAX})
    context = rclpy.Context()
    rclpy.init(context=context)
    on_time, late = HandDriven(context, flat, node_name="on_time"), HandDriven(context, flat, node_name="late")
    drive(on_time, late)
    yield on_time, late
    for driven in (on_time, late):
        driven.node.destroy_node()
    rclpy.shutdown(context=context)


def drive(on_time, late):
    """The same poses to both nodes; the late one's ticks skip the periods of SKIPPED."""
    for k in range(TICKS):
        z = heave(on_time.clock + 0.02)
        on_time.tick(z)
        if k in SKIPPED:
            late.feed(z)  # the pose arrives, the timer's call does not
        else:
            late.tick(z)


def check_caught_up(on_time, late, topic, types=TYPES, rtol=RTOL, atol=ATOL):
    """Every message of ``topic`` the late node published is the on-time node's of its stamp, in order, none
    repeated, and each late tick published the skipped periods' states (at most MISSED_OUTPUTS_MAX)."""
    reference = {s: f for _, s, f in published(on_time.log, topic, types)}
    got = published(late.log, topic, types)
    stamps = [s for _, s, _ in got]
    assert stamps == sorted(set(stamps)), "stamps repeated or out of order"
    stall = 40 + MISSED_OUTPUTS_MAX + 3  # the late node's tick after the stall (its ends then moved over one long chunk)
    for k, s, f in got:  # the solver sampled at instants an on-time node published, the same numbers
        assert s in reference, f"{topic}: stamp {s} is not an output instant of the node on time"
        if k >= stall:
            continue  # (the periods not caught up were stepped as one chunk: ~1e-5 relative, measured)
        for key, value in f.items():  # (the instants agree to the float sums of the two clocks, ~1e-14 s)
            if isinstance(value, (str, bool)):
                assert value == reference[s][key], f"{topic} at {s}: {key} differs from the node on time"
            else:
                assert np.allclose(value, reference[s][key], rtol=rtol, atol=atol[key]), \
                    f"{topic} at {s}: {key} differs from the node on time"
    by_tick = {}
    for k, s, _ in got:
        by_tick.setdefault(k, []).append(s)
    late_ticks = sorted(k for k in range(1, TICKS) if k - 1 in SKIPPED and k not in SKIPPED)
    assert late_ticks == [22, 31, stall]
    period = 0.02
    for k, skipped in zip(late_ticks, (2, 1, MISSED_OUTPUTS_MAX + 3)):
        caught = min(skipped, MISSED_OUTPUTS_MAX)
        assert len(by_tick[k]) == caught + 1, f"tick {k} after {skipped} skipped periods published {by_tick[k]}"
        assert np.allclose(np.diff(by_tick[k]), period, atol=1e-6)
    # every period of the run but those beyond the catch-up has its state: 50 per simulated second
    missing = sorted(set(reference) - set(stamps))
    assert len(missing) == len(SKIPPED) - sum(min(n, MISSED_OUTPUTS_MAX) for n in (2, 1, MISSED_OUTPUTS_MAX + 3))


@pytest.mark.parametrize("topic", sorted(TYPES))
def test_a_late_tick_publishes_the_skipped_periods_states_as_an_on_time_node(runs, topic):
    check_caught_up(*runs, topic)


NETWORK_TYPES = {"/tether/tether/state": TetherState, "/tether/excursion/state": TetherState,
                 "/tether/ship_wrench": WrenchStamped, "/tether/vehicle_wrench": WrenchStamped,
                 "/tether/cage_wrench": WrenchStamped, "/cage/sim_pose": PoseStamped}


@pytest.fixture(scope="module")
def network_runs():
    """The line-network node (config/ropos_tms.yaml: ship on the heave, the vehicle held), on time and late."""
    context = rclpy.Context()
    rclpy.init(context=context)
    keys = {"node.tick_budget": 1.0e6, "node.missed_outputs": MISSED_OUTPUTS_MAX}
    on_time, late = (HandDriven.tms(context, keys, node_name=name) for name in ("on_time", "late"))
    drive(on_time, late)
    yield on_time, late
    for driven in (on_time, late):
        driven.node.destroy_node()
    rclpy.shutdown(context=context)


@pytest.mark.parametrize("topic", sorted(NETWORK_TYPES))
def test_the_network_node_catches_up_on_skipped_periods_as_the_single_line_node(network_runs, topic):
    """The same on the line-network node (its lines' states, the points' and the cage's wrenches, the cage's
    pose). Before it shared the single-line node's catch-up, its late tick published only the newest instant."""
    check_caught_up(*network_runs, topic, NETWORK_TYPES)


def test_the_real_time_factor_of_a_late_tick_spans_the_periods_it_caught_up_on(monkeypatch):
    """A late tick after three skipped periods, 80 ms of wall time after the last: the skipped periods' ticks
    (microseconds apart) leave the factor alone and add their 20 ms each to the tick's, 80 ms of simulated time
    over 80 ms of wall time, a factor of 1 (before: 20 ms over the microseconds since the last catch-up tick)."""
    import tether_sim.ros.driver as driver_module
    from tether_sim.ros.driver import SimulationDriver

    wall = [0.0]
    monkeypatch.setattr(driver_module, "wallclock", type("Clock", (), {"perf_counter": staticmethod(lambda: wall[0])}))
    d = SimulationDriver(load_config(ROOT / "config/ropos_L200.yaml"))
    d._last_wall = 0.0
    d.real_time_factor = 0.9  # the last regular tick's
    d.catching_up = True
    for k in range(3):
        wall[0] = 0.060 + 1e-6 * k
        d._update_rate(0.02, wall[0])
        assert d.real_time_factor == 0.9  # (their outputs carry the last regular tick's factor)
    d.catching_up = False
    wall[0] = 0.080
    d._update_rate(0.02, 0.0601)
    assert d.real_time_factor == pytest.approx(1.0, rel=1e-12)
