"""node.shape_rate: the shape outputs (state, marker, path) at most this often, the other outputs at
every tick, the values those of a run at the full rate (a lower rate only leaves messages out)."""

import pytest

pytest.importorskip("rclpy")
pytest.importorskip("tether_sim_msgs")
from mcap.reader import make_reader  # noqa: E402
from rclpy.serialization import deserialize_message  # noqa: E402
from test_offline import write_params  # noqa: E402
from tether_sim_msgs.msg import TetherState  # noqa: E402

from tether_sim.ros.convert import SHAPE_TOPICS, ShapeGate  # noqa: E402
from tether_sim.ros.offline import main  # noqa: E402

pytestmark = pytest.mark.ros


def test_gate_every_fifth_output_at_a_fifth_of_the_rate():
    gate = ShapeGate(10.0)
    stamps = [12.3 + 0.02 * k for k in range(26)]  # 50 Hz outputs; sums of floats, as the driver's stamps
    assert [k for k, t in enumerate(stamps) if gate.due(t)] == [0, 5, 10, 15, 20, 25]
    assert gate.due(1.0)  # the clock jumped back: start over
    assert not gate.due(1.02)
    assert all(ShapeGate(0.0).due(t) for t in stamps)  # 0: every output


def test_offline_run_at_shape_rate_keeps_the_other_outputs_and_the_values(tmp_path):
    motion = {"kind": "circle", "amplitude": 0.5, "frequency": 0.5}
    full, slow = tmp_path / "full.mcap", tmp_path / "slow.mcap"
    assert main(["--params", write_params(tmp_path / "a.yaml", motion=motion), "--output", str(full), "--no-progress"]) == 0
    assert main(["--params", write_params(tmp_path / "b.yaml", motion=motion, node={"shape_rate": 5.0}),
                 "--output", str(slow), "--no-progress"]) == 0
    a, b = _raw(full), _raw(slow)
    assert set(a) == set(b)
    for topic in a:  # output_rate 20 Hz, 2 s: 41 outputs; the shapes at 5 Hz: every 4th
        if topic in SHAPE_TOPICS:
            assert [ns for ns, _ in b[topic]] == [ns for ns, _ in a[topic]][::4]
            if topic != "/tether/state":  # (its real-time factor is measured on the wall clock)
                assert b[topic] == a[topic][::4]
        elif topic not in ("/diagnostics", "/tether/description"):
            assert [ns for ns, _ in b[topic]] == [ns for ns, _ in a[topic]], topic
    assert len(b["/tether/state"]) == 11
    for (_, x), (_, y) in zip(b["/tether/state"], a["/tether/state"][::4]):
        x, y = deserialize_message(x, TetherState), deserialize_message(y, TetherState)
        x.real_time_factor = y.real_time_factor = 0.0
        assert x == y


def _raw(path):
    """{topic: [(log time, serialized bytes)]}."""
    out = {}
    with open(path, "rb") as f:
        for _schema, channel, msg in make_reader(f).iter_messages():
            out.setdefault(channel.topic, []).append((msg.log_time, msg.data))
    return out
