"""Fault injection: bad inputs and faults against the stepping driver with the real DG
solver, and a few against one running node. Each checks: alive (keeps advancing), finite outputs,
the right diagnostics, no invented snap event.

Where the other rows of the issue are tested: a node slower than its clock, a resume after a gap
and a forced divergence with the ROPOS tether in test_overload.py; 1 kHz pose history and clock
checks of the stamps in test/io/test_inputs.py; recorder SIGKILL, recovery and the replay of cut
files in test_recorder_replay.py and test/io/test_mcap_log.py; a truncated report in
test/test_report.py; NaN/inf, bad quaternion, jump, backwards stamp, wrong frame, stale input and
clock jumps against a running node in test_bad_inputs.py.
"""

import math
import subprocess
import sys

import numpy as np
import pytest

from tether_sim.io.inputs import EndPoseInput
from tether_sim.io.params import from_flat
from tether_sim.physics.snap import SnapEvent
from tether_sim.ros.driver import SimulationDriver

RATE = 50.0
# 55 m DG tether between a heaving ship and a fixed point 50 m away (taut: static ~0.6 kN), cheap
FLAT = {"cable.length": 55.0, "cable.EA": 1.0e6, "cable.damping": 1.0e3,
        "ship_end.kind": "prescribed", "ship_end.position": (0.0, 0.0, 0.0),
        "vehicle_end.kind": "fixed", "vehicle_end.position": (30.0, 0.0, -40.0),
        "dg.n_elements": 6, "dg.order": 3, "node.output_rate": RATE, "node.max_end_speed": 10.0}


def heave(t):  # 0.3 m at 0.2 Hz
    return np.array([0.0, 0.0, 0.3 * math.sin(2 * math.pi * 0.2 * t)])


class Rig:
    """A driver with the node's input settings; ``run`` advances the clock feeding good poses
    (20 Hz) plus whatever ``inject(now)`` offers, and checks every tick."""

    def __init__(self):
        self.config = from_flat(FLAT)
        node = self.config.node
        self.inp = EndPoseInput.for_node("ship", node)
        self.inp.add_pose(0.0, heave(0.0), (0, 0, 0, 1), now=0.2)
        self.driver = SimulationDriver(self.config, {"ship": self.inp})
        self.driver.start(0.2)
        self.now, self.reports, self.next_pose = 0.2, [], 0.05

    def run(self, seconds, inject=None, poses=True):
        for _ in range(int(round(seconds * RATE))):
            self.now += 1.0 / RATE
            while self.next_pose <= self.now + 1e-9:
                if poses:
                    self.inp.add_pose(self.next_pose, heave(self.next_pose), (0, 0, 0, 1), now=self.now)
                self.next_pose += 0.05
            if inject is not None:
                inject(self.now)
            stamp = self.driver.stamp
            report = self.driver.tick(self.now)
            assert report.stamp > stamp  # alive: the state advances every tick
            state = self.driver.solver.state()
            assert np.all(np.isfinite(state.position)) and np.all(np.isfinite(state.tension))
            self.reports.append(report)
        return self

    def snaps(self):
        return [e for r in self.reports for e in r.events if isinstance(e, SnapEvent)]

    def end_error(self):
        """Largest distance of the ship end from the heave at its stamp, outside blends."""
        z = self.driver.solver.state(np.array([0.0])).position[0]
        return float(np.linalg.norm(z - heave(self.driver.stamp)))


@pytest.mark.parametrize("position, orientation, reason", [
    ((math.nan, 0.0, 0.0), (0, 0, 0, 1), "non-finite"),
    ((0.0, math.inf, 0.0), (0, 0, 0, 1), "non-finite"),
    ((0.0, 0.0, 0.0), (0, 0, 0, math.nan), "non-finite"),
    ((0.0, 0.0, 0.0), (0, 0, 0, 0), "bad quaternion"),
    ((0.0, 0.0, 0.0), (0, 0, 0, 2.0), "bad quaternion"),
    ((40.0, 0.0, 0.0), (0, 0, 0, 1), "jump"),
])
def test_bad_pose_values_never_reach_the_cable(position, orientation, reason):
    rig = Rig().run(1.0)
    bad = lambda now: rig.inp.add_pose(now + 1e-3, position, orientation, now=now)  # noqa: E731
    rig.run(2.0, inject=bad)
    assert rig.inp.rejected[reason] == 100 and not rig.snaps()
    assert rig.end_error() < 1e-6  # the ship end is on the true heave


@pytest.mark.parametrize("offset, reason", [(-0.5, "stamp not increasing"), (3600.0, "stamp in the future"),
                                            (-10.0, "stamp too old")])
def test_bad_stamps_are_rejected_with_their_own_reason_and_never_block_the_input(offset, reason):
    rig = Rig().run(1.0)
    rig.run(2.0, inject=lambda now: rig.inp.add_pose(now + offset, (5.0, 0.0, 0.0), (0, 0, 0, 1), now=now))
    assert rig.inp.rejected[reason] == 100 and sum(rig.inp.rejected.values()) == 100
    assert not rig.inp.is_stale(rig.now) and rig.end_error() < 1e-6 and not rig.snaps()


def test_a_flood_of_poses_keeps_memory_bounded_and_the_motion_true():
    rig = Rig().run(0.5)
    rig.inp.max_samples = 5000  # (25 kHz x the 2.2 s span = 55000 samples: the cap is what holds)
    state = {"t": 0.0}

    def flood(now):  # 500 valid poses per tick (25 kHz) on the true heave, just before the clock
        ts = now - 0.02 + np.arange(500) * 4e-5
        for t in ts[ts > max(rig.inp.last_stamp, state["t"])]:
            rig.inp.add_pose(t, heave(t), (0, 0, 0, 1), now=now)
        state["t"] = ts[-1]

    rig.run(1.0, inject=flood, poses=False)
    health = rig.inp.health(rig.now)
    assert health["history_samples"] <= 5000 + 63 and rig.inp.accepted > 20000
    assert rig.end_error() < 1e-6 and not rig.snaps()


def test_dropout_then_resume_is_stale_then_blended_without_snap():
    rig = Rig().run(1.5)
    rig.run(2.5, poses=False)  # silence
    assert rig.inp.is_stale(rig.now)
    assert any(reason == "input lost" for r in rig.reports for *_, reason in r.blends)
    rig.next_pose = rig.now  # the stream comes back where the heave is now
    rig.run(6.0)
    assert any(reason == "input resumed" for r in rig.reports for *_, reason in r.blends)
    assert not rig.snaps() and not rig.reports[-1].degraded and rig.end_error() < 1e-6


def test_diagnostics_never_hide_cannot_keep_up_behind_a_snap():
    pytest.importorskip("rclpy")
    from tether_sim.ros import convert

    sim = {"running": True, "snaps": 3, "snaps_recent": 2, "behind": True, "lag": 0.8, "degraded": True, "resyncs_recent": 0,
           "tick_errors_recent": 1, "last_tick_error": "KeyError: 'x'", "slack": {"ship": False}}
    st = convert.diagnostics(1.0, "tether_sim", sim, {}).status[0]
    assert st.level == convert.LEVEL_ERROR
    assert "cannot keep up" in st.message and "snap load" in st.message and "tick(s) failed" in st.message
    assert "diverged" not in st.message  # an exception in a tick is not a divergence


def test_help_prints_usage_and_starts_no_node():
    out = subprocess.run([sys.executable, "-m", "tether_sim.ros.sim_node", "--help"], capture_output=True,
                         text=True, timeout=60)
    assert out.returncode == 0 and out.stdout.startswith("usage: tether-sim") and "warmed up" not in out.stderr


def test_clock_jump_back_holds_the_end_smoothly_and_marks_every_bridged_state_degraded():
    """/clock jumps back 30 s (use_sim_time): the pose history (old clock) is dropped, the end is
    brought to rest smoothly instead of stopped dead, and every state until the end is back on its
    input is marked degraded, with snap detection suspended; afterwards the end follows the input."""
    rig = Rig().run(3.0)
    static = rig.driver.static_tensions[0]
    rig.now -= 30.0
    rig.next_pose = rig.now - 0.1
    reports, tension = [], []
    for _ in range(int(8.0 * RATE)):
        rig.now += 1.0 / RATE
        while rig.next_pose <= rig.now + 1e-9:
            rig.inp.add_pose(rig.next_pose, heave(rig.next_pose), (0, 0, 0, 1), now=rig.now)
            rig.next_pose += 0.05
        reports.append(rig.driver.tick(rig.now))
        tension.append(float(rig.driver.solver.state(np.array([0.0])).tension[0]))
    assert reports[0].clock_jump and any("clock jumped back" in b[2] for b in reports[0].blends)
    # degraded from the jump on, without a gap, until the resumed blend has ended; then clean
    flags = [r.degraded for r in reports]
    first_clean = flags.index(False)
    assert all(flags[:first_clean]) and not any(flags[first_clean:])
    assert any(reason == "input resumed" for r in reports[:first_clean] for *_, reason in r.blends)
    assert not [e for r in reports for e in r.events if isinstance(e, SnapEvent)]
    # the ship end was never stopped dead (a velocity step on a taut cable: 0.50-1.36 x static
    # before); the heave alone swings it 0.95-1.10 x, the smooth hold and blend stay within 0.75-1.3 x
    assert 0.75 * static < min(tension) and max(tension) < 1.3 * static
    assert rig.end_error() < 1e-6


def test_a_first_pose_between_start_and_first_tick_is_blended_not_stepped():
    """The node started without a ship pose (configured position held); the first pose arrives
    before the first tick, a few cm off (within what node.max_end_speed allows in a tick, so no
    restart): the end is blended onto it and the blended states are marked degraded."""
    config = from_flat(FLAT)
    node = config.node
    inp = EndPoseInput.for_node("ship", node)
    driver = SimulationDriver(config, {"ship": inp})
    driver.start(0.2)  # no data: the configured ship position (0, 0, 0), held
    offset = np.array([0.0, 0.0, 0.05])
    for k in range(6):
        inp.add_pose(0.15 + 0.05 * k, offset, (0, 0, 0, 1), now=0.2)
    reports = [driver.tick(0.2 + k / RATE) for k in range(1, 4 * int(RATE))]
    assert reports[0].restart is None
    assert any(reason == "input resumed" for r in reports for *_, reason in r.blends)
    z = [float(driver.solver.state(np.array([0.0])).position[0][2])]
    assert reports[0].degraded and z[0] == pytest.approx(0.05, abs=1e-6)  # on the input after the blend


def ropos_driven_by(sends, late=None, seconds=12.0):
    """The ROPOS tether with its README mesh (N = 2, P = 4) under the node's pose-input settings, its
    ship end driven by ``sends``: (stamp, time the position was read, arrival) of a 0.5 m, 0.1 Hz
    heave (peak speed 0.314 m/s; the tether never goes slack). Ticks every 20 ms (phase 0.7 ms),
    none while the simulated instant lies in the interval ``late``. Returns (events, largest
    commanded ship speed, end tensions / static after 5 s)."""
    from pathlib import Path

    from tether_sim.io.params import load_config

    config = load_config(Path(__file__).resolve().parents[2] / "config" / "ropos_L200.yaml")
    node = config.node
    inp = EndPoseInput.for_node("ship", node)
    w = 2 * math.pi * 0.1
    sends = sorted(sends, key=lambda s: s[2])
    driver, now, fed, events, speed, tensions = None, 0.2007, 0, [], [], []
    while now < seconds:
        now += 1.0 / RATE
        while fed < len(sends) and sends[fed][2] <= now:
            stamp, read, _ = sends[fed]
            assert inp.add_pose(stamp, (0.0, 0.0, 0.5 * math.sin(w * read)), (0, 0, 0, 1), now=now) is None
            fed += 1
        if driver is None:
            driver = SimulationDriver(config, {"ship": inp})
            driver.start(now)
            static = np.array(driver.static_tensions)
            continue
        if late is not None and late[0] < now - node.input_delay < late[1]:
            continue
        events += driver.tick(now).events
        speed.append(float(np.linalg.norm(driver._end_state["ship"][1])))
        if now > 5.0:  # (after the start-up blend)
            f = driver.solver.end_forces()
            tensions.append(np.array([f.ship_tension, f.vehicle_tension]) / static)
    return events, max(speed), np.array(tensions)


def regular(t0, t1):
    """20 Hz sends from t0 to t1: stamped when read, arriving at once."""
    return [(0.05 * k, 0.05 * k, 0.05 * k) for k in range(int(round(t0 / 0.05)), int(round(t1 / 0.05)))]


def assert_nothing_happened(events, speed, tensions, max_speed=0.32, spread=0.2):
    from tether_sim.physics.snap import NumericalSnapWarning, SlackStarted

    assert not [e for e in events if isinstance(e, (SlackStarted, NumericalSnapWarning, SnapEvent))], events
    assert speed < max_speed
    assert tensions.min() > 1.0 - spread and tensions.max() < 1.0 + spread, (tensions.min(), tensions.max())


def test_a_jittered_catch_up_burst_of_poses_makes_no_slack_and_no_snap():
    """The false snap of the one-hour soak (docs/node.md), reproduced offline. A pose publisher
    stalls and catches up: three poses 2 ms apart at 10 s, the middle one's position read 30 ms before
    its stamp (it was preempted between reading its clock and its position: 9 mm at the heave's
    0.31 m/s). A finite difference over 2 ms makes that 4.7 m/s; the node's tick, 0.2 s late,
    commands the ship end with it. Before the fix (every sample a knot) the tether went slack at both
    ends, the vehicle end re-tensioned in 4.3 ms (112 kN, rejected as numerical) and the ship end in
    19.3 ms (75 kN, rejected); commanded ship speed 6.1 m/s. With knots half an output period apart
    the commanded speed stays the heave's (0.314 m/s) and the end tensions within 0.8-1.2 x static
    (the heave and the cage's inertia move them by a few kN)."""
    burst = [(10.0, 10.0, 10.0), (10.002, 10.002 - 0.030, 10.002), (10.004, 10.004, 10.004)]
    assert_nothing_happened(*ropos_driven_by(regular(0.0, 10.0) + burst + regular(10.05, 13.0),
                                             late=(9.8, 10.0)))  # (the next tick: 10.0007 s)


def test_an_extrapolation_overtaken_by_late_samples_is_blended_not_stepped():
    """Found by benchmarks/jitter_soak.py (seed 1, 2120 s): the pose due at 9.95 s is stamped 30 ms
    late (9.98 s); with the next one (10.0 s), 20 ms apart in stamp (two knots), a one-sided velocity
    over the newest interval is 0.78 m/s (the heave's is 0.31). Then the publisher stalls until
    10.365 s and sends the overdue poses back to back. The node extrapolates from 10.0 s for up to
    node.max_extrapolation; when the stalled poses arrive, the stream where the end already is
    differs. Before, extrapolating with 0.78 m/s and stepping onto the revised stream within one
    20 ms chunk, the tether went slack at both ends and the ship end's re-tensioning was rejected
    (rise 4.8 ms). Now the newest knot's velocity spans two output periods (0.314 m/s here), and a
    revision of more than 1 mm would be blended onto ("input revised"), not stepped."""
    stall = [(9.98, 9.95, 9.98), (10.0, 10.0, 10.0)]
    stall += [(10.365 + 0.0005 * k, 10.365 + 0.0005 * k, 10.365 + 0.0005 * k) for k in range(8)]
    events, speed, tensions = ropos_driven_by(regular(0.0, 9.95) + stall + regular(10.4, 13.0))
    # the jittered pose stays a knot (20 ms from the next): the Hermite through it reaches 0.41 m/s
    # and the end tensions 0.94-1.25 x static (measured); before: 0.78 m/s for 0.18 s, then slack
    assert_nothing_happened(events, speed, tensions, max_speed=0.45, spread=0.3)


def test_resynchronisations_faster_than_blends_finish_keep_the_end_on_its_input():
    """A node that re-synchronises again before the blend of the last one has ended: each skip adds a
    decaying offset that ends on its own (tether_sim/ros/bridging.py). Before, each re-synchronisation
    restarted one blend whose held trajectory carried the end's velocity on until its weight grew (a
    blend takes 7.5 dv / a, 15 s for 1 m/s): on this elastic string (fixed far end, 100 m, EA 1 MN)
    with the ship input 1.5 m at 0.1 Hz and a 1.2 s stall every 1.5 s the end coasted to x = -3.1 and
    +3.6 m in 40 s, beyond anything its input does. Now it stays within the input's range widened by
    the input's travel over one skip (0.94 m/s x 1.2 s), and once the stalls stop it is back on its
    input, exactly, within the longest offset (7.5 x 1.9 m/s / 0.5 m/s^2 = 28.5 s)."""
    from test_driver import ElasticString, make_config

    amp, omega, stall = 1.5, 2 * math.pi * 0.1, 1.2
    inp = EndPoseInput("ship", history_span=5.0)
    fed = [0]

    def feed(now):
        while fed[0] / RATE <= now:
            t = fed[0] / RATE
            assert inp.add_pose(t, (amp * math.sin(omega * t), 0.0, 0.0), (0, 0, 0, 1)) is None
            fed[0] += 1

    feed(0.0)
    driver = SimulationDriver(make_config(max_lag=1.0), {"ship": inp}, solver_factory=ElasticString)
    driver.start(0.0)
    k, next_stall, rows = 0, 1.5, []
    while k / RATE < 75.0:
        k += 1
        if k / RATE >= next_stall and k / RATE < 30.0:
            k += int(round(stall * RATE))
            next_stall = k / RATE + 1.5
        now = k / RATE
        feed(now)
        report = driver.tick(now)
        x = driver.solver.ends["ship"][0]
        rows.append((now, x, abs(x - amp * math.sin(omega * driver.stamp)), report.degraded))
    rows = np.array(rows)
    assert driver.resyncs >= 10
    assert np.max(np.abs(rows[:, 1])) <= amp + amp * omega * stall
    settled = rows[rows[:, 0] > 30.0 + 30.0]
    assert np.max(settled[:, 2]) < 1e-9 and not np.any(settled[:, 3])  # on its input, not degraded
