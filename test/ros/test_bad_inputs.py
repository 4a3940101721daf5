"""Every kind of bad input against the running node: rejected, reported, and the node goes on."""

import math

import numpy as np
import pytest

pytest.importorskip("rclpy")
pytest.importorskip("tether_sim_msgs")
from sim_harness import SimHarness, status, values  # noqa: E402

from tether_sim.errors import SolverDivergedError  # noqa: E402

pytestmark = pytest.mark.ros

SHIP = (0.0, 0.0, 0.0)
VEHICLE = (30.0, 0.0, -40.0)
PARAMS = {"cable.length": 55.0, "cable.EA": 1.0e6, "cable.damping": 1.0e3,
          "ship_end.kind": "prescribed", "ship_end.position": SHIP,
          "vehicle_end.kind": "fixed", "vehicle_end.position": VEHICLE,
          "dg.n_elements": 6, "dg.order": 3, "node.output_points": 11, "node.max_end_speed": 10.0,
          "node.input_timeout": 0.5, "node.snapshot_interval": 0.2,
          "node.tick_budget": 1.0e6}  # sim time: never cap a tick on wall time, so runs are deterministic


@pytest.fixture
def h():
    harness = SimHarness(PARAMS)
    harness.run(0.4, ship=SHIP)
    assert harness.received["/tether/state"], "node did not start"
    yield harness
    harness.close()


def still_running(h, since):
    """TetherStates keep coming after ``since`` with finite values and monotonic stamps."""
    later = h.received["/tether/state"][since:]
    stamps = [m.header.stamp.sec + 1e-9 * m.header.stamp.nanosec for m in later]
    assert len(later) >= 5 and np.all(np.diff(stamps) > 0)
    assert all(math.isfinite(m.ship_end_tension) and all(map(math.isfinite, m.tension)) for m in later)
    return later


def ship_input_status(h):
    diag = [d for d in h.received["/diagnostics"] if status(d, "ship input")]
    return status(diag[-1], "ship input")


def ship_end_x(state):
    return state.position[0].x


def send_bad(h, msg, reason):
    """Publish one bad ship sample and spin (clock still) until the node has seen it."""
    before = h.node.inputs["ship"].rejected[reason]
    h.pose_pubs["ship"].publish(msg)
    for _ in range(200):  # best-effort delivery: wait for it, with no other pose to crowd it out
        h.spin(1)
        if h.node.inputs["ship"].rejected[reason] > before:
            return
    raise AssertionError(f"the node never received the bad sample ({reason})")


@pytest.mark.parametrize("position, orientation, reason", [
    ((math.nan, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), "non-finite"),
    ((0.0, math.inf, 0.0), (0.0, 0.0, 0.0, 1.0), "non-finite"),
    ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 0.0), "bad quaternion"),
    ((50.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), "jump"),  # 50 m in 0.02 s
])
def test_bad_pose_values_are_rejected(h, position, orientation, reason):
    n = len(h.received["/tether/state"])
    send_bad(h, h.pose_msg(h.time + 0.01, position, orientation), reason)
    h.run(h.time + 1.2, ship=SHIP)
    later = still_running(h, n)
    assert max(abs(ship_end_x(m)) for m in later) < 1e-6  # the bad sample never reached the solver
    st = ship_input_status(h)
    assert int(values(st)[f"rejected_{reason}"]) == 1


def test_stamp_going_backwards_is_rejected(h):
    n = len(h.received["/tether/state"])
    send_bad(h, h.pose_msg(h.time - 5.0, (1.0, 0.0, 0.0)), "stamp not increasing")
    h.run(h.time + 1.2, ship=SHIP)
    later = still_running(h, n)
    assert max(abs(ship_end_x(m)) for m in later) < 1e-6
    assert int(values(ship_input_status(h))["rejected_stamp not increasing"]) == 1


def test_pose_in_a_foreign_frame_is_rejected(h):
    n = len(h.received["/tether/state"])
    send_bad(h, h.pose_msg(h.time + 0.01, (0.1, 0.0, 0.0), frame="odom"), "wrong frame")
    h.run(h.time + 1.2, ship=SHIP)
    still_running(h, n)
    assert int(values(ship_input_status(h))["rejected_wrong frame"]) == 1


def test_missing_input_is_reported_stale_and_the_simulation_goes_on(h):
    n = len(h.received["/tether/state"])
    h.run(h.time + 2.0)  # the ship pose stops
    still_running(h, n)
    st = ship_input_status(h)
    assert st.level == b"\x03" and "no valid ship pose" in st.message  # STALE


def test_diverging_solver_is_reported_and_recovered(h):
    solver = h.node.driver.solver
    original = solver.advance_to
    calls = {"n": 0}

    def diverge_once(t):
        calls["n"] += 1
        if calls["n"] == 1:
            raise SolverDivergedError("state became non-finite (injected)")
        return original(t)

    solver.advance_to = diverge_once
    n = len(h.received["/tether/state"])
    h.run(h.time + 1.2, ship=SHIP)
    still_running(h, n)
    assert h.node.driver.divergences == 1
    errors = [status(d, "simulation") for d in h.received["/diagnostics"] if status(d, "simulation").level == b"\x02"]
    assert errors and "injected" in errors[0].message
    # recovered from the last good snapshot (taken every 0.2 s), not rebuilt
    assert h.node.driver.last_recovery == "snapshot"


def test_clock_jumping_back_like_a_looping_replay(h):
    # /clock and the poses go from 1.2 s back to 0.5 s: pose histories are reset, outputs follow
    # the new clock (stamps = clock - node.input_delay = clock - 0.2 s)
    h.run(1.2, ship=SHIP)
    n = len(h.received["/tether/state"])
    h.time = 0.5
    h.run(1.3, ship=SHIP)
    later = h.received["/tether/state"][n:]
    stamps = [m.header.stamp.sec + 1e-9 * m.header.stamp.nanosec for m in later]
    jump = next(i for i, t in enumerate(stamps) if t < 0.9)  # (a state of 1.0 s may arrive late)
    assert len(stamps) - jump >= 30 and np.all(np.diff(stamps[jump:]) > 0) and stamps[-1] == pytest.approx(1.1)
    # poses that arrive before the /clock jump are still judged against the old history; after it
    # the history is reset and the new poses are accepted again
    assert h.node.inputs["ship"].last_stamp == pytest.approx(1.3)


def test_one_node_through_future_and_zero_stamps_a_failing_tick_and_an_undeclared_parameter(h):
    # one pose stamped an hour ahead is rejected for what it is and does not
    # disable the input (the node of 2026-11-21 then rejected every later pose and never reported it stale)
    n = len(h.received["/tether/state"])
    send_bad(h, h.pose_msg(h.time + 3600.0, (1.0, 0.0, 0.0)), "stamp in the future")
    accepted = h.node.inputs["ship"].accepted
    h.run(h.time + 1.2, ship=SHIP)
    still_running(h, n)
    assert h.node.inputs["ship"].accepted >= accepted + 30 and not h.node.inputs["ship"].is_stale(h.time)
    st = ship_input_status(h)
    assert int(values(st)["rejected_stamp in the future"]) == 1 and st.level != b"\x03"  # not STALE
    # a zero stamp is taken at the node's clock
    accepted = h.node.inputs["ship"].accepted
    h.pose_pubs["ship"].publish(h.pose_msg(0.0, SHIP))
    for _ in range(200):
        h.spin(1)
        if h.node.inputs["ship"].accepted > accepted:
            break
    assert h.node.inputs["ship"].last_stamp == pytest.approx(h.time)
    # an exception in a tick (not a divergence) is reported as what it is; the node goes on
    original = h.node.driver.tick
    calls = {"n": 0}

    def fail_once(now):
        calls["n"] += 1
        if calls["n"] == 1:
            raise KeyError("injected")
        return original(now)

    h.node.driver.tick = fail_once
    n = len(h.received["/tether/state"])
    h.run(h.time + 1.2, ship=SHIP)
    still_running(h, n)
    sims = [status(d, "simulation") for d in h.received["/diagnostics"]]
    failed = [s for s in sims if "tick(s) failed" in s.message]
    assert failed and "KeyError" in failed[-1].message and not any("diverged" in s.message for s in sims)
    assert h.node.driver.divergences == 0
    # an undeclared parameter is named (rclpy alone answers "undeclared parameter(s): []")
    from rclpy.exceptions import ParameterNotDeclaredException
    from rclpy.parameter import Parameter

    with pytest.raises(ParameterNotDeclaredException, match=r"'cable\.EAA' \(did you mean 'cable\.EA'\?\)"):
        h.node.set_parameters([Parameter("cable.EAA", value=1.0)])


def test_use_sim_time_cannot_change_while_running_and_the_node_goes_on(h):
    # (switching it on a running node used to be accepted: then no state, no /diagnostics, no log)
    from rclpy.parameter import Parameter

    n = len(h.received["/tether/state"])
    result = h.node.set_parameters([Parameter("use_sim_time", Parameter.Type.BOOL, False)])[0]
    assert not result.successful
    assert "use_sim_time cannot change while the node runs" in result.reason and "restart" in result.reason
    assert h.node.get_parameter("use_sim_time").value is True and h.node.get_clock().ros_time_is_active
    h.run(h.time + 0.6, ship=SHIP)
    still_running(h, n)
    assert h.node.set_parameters([Parameter("use_sim_time", Parameter.Type.BOOL, True)])[0].successful  # unchanged


def test_a_solver_that_cannot_keep_up_with_the_wall_clock_is_refused_at_start_up():
    """The node times its warmed-up solver in CPU time; on the wall clock a solver slower than
    1 / node.tick_budget is refused with the measured speed and a coarser mesh (it would only ever
    re-synchronise), unless node.require_real_time is false. node.tick_budget 0.05 asks for 20 x
    real time, which a 12-element P = 4 mesh of this 55 m tether does not reach (3.7 x per CPU
    second, 2026-11-26; N = 6, P = 3: 54 x)."""
    import rclpy
    from rclpy.parameter import Parameter

    from tether_sim.errors import ConfigError
    from tether_sim.ros.sim_node import TetherSimNode

    flat = {**PARAMS, "dg.n_elements": 12, "dg.order": 4, "node.tick_budget": 0.05}
    params = [Parameter(k, value=list(v) if isinstance(v, tuple) else v) for k, v in flat.items()]
    for require, refused in ((True, True), (False, False)):
        context = rclpy.Context()
        rclpy.init(context=context)
        try:
            overrides = params + [Parameter("node.require_real_time", value=require)]
            if refused:
                with pytest.raises(ConfigError) as err:
                    TetherSimNode(context=context, parameter_overrides=overrides)
                text = str(err.value)
                assert "x real time per CPU second" in text and "needs 20 x" in text
                assert "-p dg.resolution:=manual -p dg.n_elements:=" in text and "node.require_real_time:=false" in text
            else:
                TetherSimNode(context=context, parameter_overrides=overrides).destroy_node()
        finally:
            rclpy.shutdown(context=context)


# what the node logs as the reason of a degraded state (sim_node._handle_report)
DEGRADED_REASONS = ("marked degraded", "blended onto its pose input", "re-synchronised", "clock jumped backwards",
                    "solver diverged", "solver restarted")


class Recorder:
    """The node's log lines and its /tether/state publications, in the order they happen: ("log",
    text) and ("state", the degraded flag the message carries)."""

    def __init__(self, node):
        self.events, self.node, self.logger = [], node, node.get_logger()
        node.get_logger = lambda: self
        self.pub = node.pubs["/tether/state"]
        node.pubs["/tether/state"] = self

    def __getattr__(self, name):  # the logger's other levels
        return getattr(self.logger, name)

    def warning(self, text, **kwargs):
        self.events.append(("log", text))
        return self.logger.warning(text, **kwargs)

    def error(self, text, **kwargs):
        self.events.append(("log", text))
        return self.logger.error(text, **kwargs)

    def publish(self, data):
        self.events.append(("state", bool(self.node.driver.degraded)))
        return self.pub.publish(data)

    def get_subscription_count(self):
        return self.pub.get_subscription_count()


def test_a_degraded_state_and_the_log_agree_through_every_kind_of_fault(monkeypatch):
    """The log said "marked degraded" while the published state had degraded false (2 of 3 late soak
    states): every tick that logs it publishes a degraded state, and every run of degraded states
    starts at a tick that logs its reason (the node's warning throttle set to 0 here: in service the
    repeats of one kind are rate-limited). Faults: start from rest, a dropout of the pose input, the
    node behind (a 0.3 s /clock step with at most 60 substeps a tick: capped, late, catching up), a
    1.5 s step (beyond node.max_lag: re-synchronised) and /clock jumping back."""
    import tether_sim.ros.sim_node as sim_node

    monkeypatch.setattr(sim_node, "WARN_PERIOD", 0.0)
    h = SimHarness({**PARAMS, "node.max_substeps_per_tick": 60})  # 31 substeps a tick keep up; a jump does not
    try:
        rec = Recorder(h.node)
        h.run(1.0, ship=SHIP)  # started from rest: blended
        h.run(2.0)  # no ship pose for 1 s (node.input_timeout 0.5 s): input lost, held
        h.run(3.0, ship=SHIP)  # input resumed: blended
        h.step(3.3, ship=SHIP)  # 0.3 s at once: capped ticks, late until caught up
        h.run(4.5, ship=SHIP)
        h.step(6.0, ship=SHIP)  # 1.5 s at once: beyond max_lag, re-synchronised
        h.run(7.0, ship=SHIP)
        h.time = 5.0  # /clock jumps back 2 s
        h.run(7.0, ship=SHIP)
        events = rec.events
        states = [flag for kind, flag in events if kind == "state"]
        assert len(states) > 200 and sum(states) > 20 and not all(states)
        logs = [text for kind, text in events if kind == "log"]
        for reason in DEGRADED_REASONS[:4]:  # each fault happened and was logged
            assert any(reason in text for text in logs), reason
        # "marked degraded" logged -> the state published in that tick is degraded
        late = [i for i, (kind, text) in enumerate(events) if kind == "log" and "marked degraded" in text]
        assert len(late) >= 3
        for i in late:
            following = next((e for e in events[i + 1:] if e[0] == "state"), None)
            assert following == ("state", True), f"logged {events[i][1]!r}, published degraded false"
        # a run of degraded states starts at a tick that logged a reason
        since, was_degraded, runs = 0, False, 0
        for i, (kind, flag) in enumerate(events):
            if kind != "state":
                continue
            if flag and not was_degraded:
                runs += 1
                said = [text for k, text in events[since:i] if k == "log"]
                assert any(r in text for text in said for r in DEGRADED_REASONS), f"degraded without a reason: {said}"
            since, was_degraded = i, flag
        assert runs >= 3  # (the dropout and its resume are one run)
        # the published messages carry the same flags
        received = [m.degraded for m in h.received["/tether/state"]]
        assert sum(received) > 0 and received == states[:len(received)]
    finally:
        h.close()
