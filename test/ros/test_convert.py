"""The periodic outputs of a driver state (convert.tick_outputs): decoded with rclpy they carry the
solver's numbers; only the wanted topics are built, and without a shape topic no state is sampled.

Driven by the exact elastic string of test_driver: a 100 m string pinned 101 m apart is stretched
1 %, so T = EA * 0.01 = 1e4 N everywhere and the points lie on the straight chord."""

import numpy as np
import pytest

pytest.importorskip("rclpy")
pytest.importorskip("tether_sim_msgs")
from geometry_msgs.msg import WrenchStamped  # noqa: E402
from nav_msgs.msg import Path  # noqa: E402
from rclpy.serialization import deserialize_message  # noqa: E402
from tether_sim_msgs.msg import TetherState  # noqa: E402
from test_driver import ElasticString, make_config  # noqa: E402
from visualization_msgs.msg import Marker  # noqa: E402

from tether_sim.ros.convert import tick_outputs  # noqa: E402
from tether_sim.ros.driver import SimulationDriver  # noqa: E402

pytestmark = pytest.mark.ros
TYPES = {"/tether/state": TetherState, "/tether/marker": Marker, "/tether/path": Path,
         "/tether/ship_wrench": WrenchStamped, "/tether/vehicle_wrench": WrenchStamped}


class CountingString(ElasticString):
    state_calls = 0

    def state(self, arc_lengths=None):
        CountingString.state_calls += 1
        return super().state(arc_lengths)


@pytest.fixture
def driver():
    d = SimulationDriver(make_config(), solver_factory=CountingString)
    d.start(12.5)
    d.tick(12.52)
    CountingString.state_calls = 0
    return d


def test_every_output_decodes_to_the_solver_state(driver):
    arc = np.linspace(0.0, 100.0, 11)
    out = dict(tick_outputs(driver, arc))
    assert set(out) == set(TYPES)  # the vehicle end is fixed: no /vehicle/sim_pose
    msgs = {topic: deserialize_message(data, TYPES[topic]) for topic, data in out.items()}
    chord = np.outer(arc / 100.0, [101.0, 0.0, 0.0])  # ship end at the origin
    for msg in msgs.values():
        assert (msg.header.stamp.sec, msg.header.stamp.nanosec) == (12, 520_000_000)
    state = msgs["/tether/state"]
    assert state.solver == "string" and state.header.frame_id == "map"
    np.testing.assert_allclose([(p.x, p.y, p.z) for p in state.position], chord, atol=1e-9)
    np.testing.assert_allclose(state.tension, 1.0e4, rtol=1e-9)
    np.testing.assert_array_equal(state.arc_length, arc)
    assert state.ship_end_tension == pytest.approx(1.0e4) and state.time_step == 0.01
    marker = msgs["/tether/marker"]
    np.testing.assert_allclose([(p.x, p.y, p.z) for p in marker.points], chord, atol=1e-9)
    # colour scale = 2 x the static tension, so T = static is half-way: pure green
    np.testing.assert_allclose([(c.r, c.g, c.b, c.a) for c in marker.colors], [[0.0, 1.0, 0.0, 1.0]] * 11, atol=1e-6)
    np.testing.assert_allclose([(p.pose.position.x, p.pose.position.y, p.pose.position.z) for p in msgs["/tether/path"].poses],
                               chord, atol=1e-9)
    ship = msgs["/tether/ship_wrench"].wrench.force  # the string pulls the ship end towards the vehicle
    assert (ship.x, ship.y, ship.z) == pytest.approx((1.0e4, 0.0, 0.0))
    assert msgs["/tether/vehicle_wrench"].header.frame_id == "rov/base_link"
    assert CountingString.state_calls == 1  # one sampling for the three shape topics


def test_only_wanted_outputs_are_built(driver):
    arc = np.linspace(0.0, 100.0, 11)
    out = tick_outputs(driver, arc, {"/tether/ship_wrench"})
    assert [topic for topic, _ in out] == ["/tether/ship_wrench"]
    assert CountingString.state_calls == 0  # no shape topic wanted: the state is not sampled
    assert tick_outputs(driver, arc, set()) == []
    assert [t for t, _ in tick_outputs(driver, arc, {"/tether/path", "/tether/vehicle_wrench"})] == [
        "/tether/path", "/tether/vehicle_wrench"]
