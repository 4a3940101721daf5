"""node.visual_rate: the simulation node sends its visualisation outputs (marker, path, /tf) on every
output_rate / visual_rate-th output and builds nothing of them in between; those messages, and every
message of the other outputs, are the bytes a node at the full rate publishes at the same ticks."""

import math

import pytest

pytest.importorskip("rclpy")
pytest.importorskip("tether_sim_msgs")
import rclpy  # noqa: E402
from sim_harness import HandDriven  # noqa: E402

from tether_sim.io.params import load_config, to_flat  # noqa: E402
from tether_sim.ros import convert  # noqa: E402
from tether_sim.ros.tf import TFMessage  # noqa: E402

pytestmark = pytest.mark.ros

ROOT = __import__("pathlib").Path(__file__).resolve().parents[2]
TICKS = 40
VISUAL = {"/tether/marker", "/tether/path", "/tf"}


def _run(context, name, visual_rate, calls):
    """Publishes of a node driven by hand for TICKS ticks at 50 Hz: [[(topic, bytes)] per tick]."""
    flat = to_flat(load_config(ROOT / "config/ropos_L200.yaml"))
    flat.update({"node.tick_budget": 1.0e6, "node.tf_tether_frames": 2})
    if visual_rate is not None:
        flat["node.visual_rate"] = visual_rate
    driven = HandDriven(context, flat, node_name=name)
    calls[name] = calls_of(convert)  # counts what the node builds
    for _ in range(TICKS):
        driven.tick(0.8 * math.sin(2.0 * math.pi * 0.5 * (driven.clock + 0.02 - 100.0)))
    calls[name] = calls[name]()
    driven.node.destroy_node()
    return driven.log


def calls_of(module):
    """Counts the marker colourings of ``module`` until the returned function is called (it gives the count)."""
    original, count = module.tension_colours, [0]

    def counted(*a, **k):
        count[0] += 1
        return original(*a, **k)
    module.tension_colours = counted

    def stop():
        module.tension_colours = original
        return count[0]
    return stop


@pytest.fixture(scope="module")
def runs():
    context = rclpy.Context()
    rclpy.init(context=context)
    calls = {}
    try:
        default = _run(context, "tether_sim_default", None, calls)
        full = _run(context, "tether_sim_full", 0.0, calls)
    finally:
        rclpy.shutdown(context=context)
    return default, full, calls


def test_visual_outputs_every_fifth_output_at_the_default_10_hz(runs):
    default, full, calls = runs
    started = [k for k, msgs in enumerate(full) if any(t == "/tether/state" for t, _ in msgs)]
    assert len(started) >= TICKS - 2
    visual = VISUAL if TFMessage is not None else VISUAL - {"/tf"}
    sent = {topic: [k for k in started if any(t == topic for t, _ in default[k])] for topic in visual}
    first = started[0]
    for topic in visual:
        assert sent[topic] == list(range(first, started[-1] + 1, 5)), topic  # 50 Hz / 10 Hz: every fifth
        assert [k for k in started if any(t == topic for t, _ in full[k])] == started  # 0: every output
    # the marker's colours are computed only for the outputs that send it
    assert calls["tether_sim_default"] == len(sent["/tether/marker"]) and calls["tether_sim_full"] == len(started)


def test_the_messages_are_those_of_the_full_rate_node(runs):
    default, full, _ = runs
    for k, (mine, theirs) in enumerate(zip(default, full)):
        theirs_by_topic = {}
        for topic, data in theirs:
            theirs_by_topic.setdefault(topic, []).append(data)
        mine_topics = [t for t, _ in mine]
        # the data outputs (state, wrenches, sim pose) at every output, in the same order
        assert [t for t in mine_topics if t not in VISUAL] == [t for t, _ in theirs if t not in VISUAL], k
        for topic, data in mine:
            if topic == "/tether/state":
                continue  # (its real-time factor is measured on the wall clock: test_shape_rate.py masks it)
            if topic in ("/tether/description", "/tf_static"):
                continue  # (object messages; the description names the node's own parameter values)
            assert data == theirs_by_topic[topic].pop(0), (k, topic)  # bytes (events: message objects)


NETWORK_VISUAL = {"/tether/tether/marker", "/tether/tether/path", "/tether/excursion/marker",
                  "/tether/excursion/path", "/tf"}


@pytest.fixture(scope="module")
def network_runs():
    """The line-network node of config/ropos_tms.yaml (the vehicle held) at the default visual rate and at 0."""
    context = rclpy.Context()
    rclpy.init(context=context)
    logs, calls = {}, {}
    try:
        for name, keys in (("tms_default", {}), ("tms_full", {"node.visual_rate": 0.0})):
            driven = HandDriven.tms(context, keys, node_name=name)
            count = calls_of(convert)
            for _ in range(TICKS):
                driven.tick(0.8 * math.sin(2.0 * math.pi * 0.5 * (driven.clock + 0.02 - 100.0)))
            calls[name] = count()
            logs[name] = driven.log
            driven.node.destroy_node()
    finally:
        rclpy.shutdown(context=context)
    return logs["tms_default"], logs["tms_full"], calls


def test_the_network_node_sends_its_visual_outputs_every_fifth_output_the_full_rate_nodes_bytes(network_runs):
    """The line-network node as the single-line node: its lines' marker and path and its /tf on every fifth
    output at the default 10 Hz, nothing of them built in between, every message the bytes of a node at the
    full rate at the same tick (before, they went out at every output whatever node.visual_rate said)."""
    default, full, calls = network_runs
    started = [k for k, msgs in enumerate(full) if any(t == "/tether/tether/state" for t, _ in msgs)]
    assert len(started) >= TICKS - 3
    visual = NETWORK_VISUAL if TFMessage is not None else NETWORK_VISUAL - {"/tf"}
    for topic in visual:
        sent = [k for k in started if any(t == topic for t, _ in default[k])]
        assert sent == list(range(started[0], started[-1] + 1, 5)), topic
        assert [k for k in started if any(t == topic for t, _ in full[k])] == started, topic
    assert calls["tms_default"] == 2 * len(range(started[0], started[-1] + 1, 5)) and calls["tms_full"] == 2 * len(started)
    for k, (mine, theirs) in enumerate(zip(default, full)):
        theirs_by_topic = {}
        for topic, data in theirs:
            theirs_by_topic.setdefault(topic, []).append(data)
        assert [t for t, _ in mine if t not in NETWORK_VISUAL] == [t for t, _ in theirs if t not in NETWORK_VISUAL], k
        for topic, data in mine:
            if topic.startswith("/tether/") and topic.endswith("/state") or not isinstance(data, bytes):
                continue  # (TetherState's real-time factor is the wall clock's; events and the description are objects)
            assert data == theirs_by_topic[topic].pop(0), (k, topic)
