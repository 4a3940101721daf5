"""The node logs the bending caution of resolution.bending_mesh_warning next to its "DG mesh" line
(docs/performance.md "Bending effect at 200 m"), and only when it applies. Fake quasi-static solver
(winch_fake.py): the caution depends on the configuration alone."""

import pytest

pytest.importorskip("rclpy")
pytest.importorskip("tether_sim_msgs")

from sim_harness import SimHarness  # noqa: E402
from tether_sim.ros.sim_node import TetherSimNode  # noqa: E402
from winch_fake import HangingCable  # noqa: E402

pytestmark = pytest.mark.ros

FLAT = {"ship_end.kind": "fixed", "ship_end.position": (0.0, 0.0, 0.0), "vehicle_end.kind": "fixed",
        "vehicle_end.position": (0.0, 0.0, -200.0), "cable.length": 200.0, "node.input_delay": 0.0,
        "dg.resolution": "manual", "dg.order": 4}


class Logger:
    def __init__(self):
        self.lines = []

    def __getattr__(self, level):
        return lambda text, *args, **kwargs: self.lines.append((level, text))


@pytest.mark.parametrize("n, EI, cautioned", [(40, 2620.0, True), (20, 2620.0, False), (40, 0.0, False)])
def test_node_logs_the_bending_caution_on_fine_meshes(monkeypatch, n, EI, cautioned):
    logger = Logger()
    monkeypatch.setattr(TetherSimNode, "get_logger", lambda self: logger)
    h = SimHarness({**FLAT, "dg.n_elements": n, "cable.EI": EI}, solver_factory=HangingCable)
    try:
        warned = [text for level, text in logger.lines if level == "warning" and "DG mesh: bending" in text]
        assert any(level == "info" and text.startswith("DG mesh: N = ") for level, text in logger.lines)
        assert bool(warned) == cautioned
        if cautioned:
            assert "1.25 m" in warned[0] and "slack" in warned[0]
    finally:
        h.close()
