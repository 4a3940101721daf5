"""The node with motion.kind rao: the ship end follows the RAO response to the configured sea, in solver
time (the clock of the waves on the cable), and ship/pose is not subscribed."""

import math

import numpy as np
import pytest

pytest.importorskip("rclpy")
pytest.importorskip("tether_sim_msgs")
from sim_harness import SimHarness  # noqa: E402
from test_sim_node import ATTACH, VEHICLE, base_params  # noqa: E402

from tether_sim.physics.motion import build_motion  # noqa: E402
from tether_sim.physics.waves import wave_components  # noqa: E402

pytestmark = pytest.mark.ros


def test_node_ship_end_follows_the_rao_source_in_solver_time():
    flat = base_params(**{"motion.kind": "rao", "motion.rao_path": "config/rao_support_vessel_80m.txt",
                          "motion.rao_lever_arm": (-35.0, 0.0, 5.0), "motion.ship_heading": 20.0,
                          "waves.kind": "regular", "waves.height": 2.0, "waves.period": 8.0,
                          "waves.direction": 180.0})
    h = SimHarness(flat)
    try:
        assert "ship" not in h.node.inputs  # no ship/pose input: the sea drives the ship
        h.run(1.5, vehicle=tuple(np.subtract(VEHICLE, ATTACH)))
        cfg = h.node.config
        motion = build_motion(cfg.motion, cfg.ship_end.position, wave_components(cfg))
        driver = h.node.driver
        assert driver.solver is not None and driver.solver.time > 1.0
        # the commanded ship end is the RAO motion at solver time (exact: the same sum of cosines)
        p_cmd, v_cmd = driver._end_state["ship"]
        p, v, _ = motion.at(driver.solver.time)
        np.testing.assert_allclose(p_cmd, p, rtol=0, atol=1e-9)
        np.testing.assert_allclose(v_cmd, v, rtol=0, atol=1e-9)
        # the published cable end follows it: the stamp is anchor + solver time
        states = h.received["/tether/state"]
        assert len(states) > 20
        moved = 0.0
        for st in states[-10:]:
            t_sim = st.header.stamp.sec + 1e-9 * st.header.stamp.nanosec - driver.anchor
            expect = motion.at(t_sim)[0]
            got = np.array([st.position[0].x, st.position[0].y, st.position[0].z])
            # the DG end value carries the prescribed motion (weak boundary condition): 1 mm against
            # motions of ~1 m/s over the interval
            np.testing.assert_allclose(got, expect, atol=1e-3)
            moved = max(moved, float(np.linalg.norm(expect - np.asarray(cfg.ship_end.position))))
        assert moved > 0.05  # a sea that does not move the ship would make the test vacuous
    finally:
        h.close()
