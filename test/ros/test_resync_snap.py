"""A re-synchronisation does not hide a snap: the node behind the clock publishes the snap load its
cable went through, as degraded, instead of a state at several times the static tension with no event.

The case: the hybrid solver on config/ropos_L200_hybrid.yaml (ROPOS tether, cage) with the fairlead on
the PE2020 circle (2 m, 0.2 Hz) ramped in over 1 s, hybrid.time_step 0.02 s: the tether goes slack
at t = 0.7 s and snaps at t = 3.5 s (271.2 kN at the ship, 5.64 x static). A stall of the node's clock of 1.5 s (beyond
node.max_lag) in the middle of the slack makes the driver re-synchronise. Detection used to be
suspended across a re-synchronisation and restarted with a fresh detector after its blend: a slack
period that began before was lost (its snap unreported, or reported with a wrong slack start and a
second slack warning), and a node behind the clock, re-synchronising every few seconds, was blind.

1. The ship in solver time (``SolverTimeMotion``, as the node's RAO ship): a re-synchronisation changes
   nothing in the cable (no blend), so the events must be those of the run without it, shifted by
   the dropped clock time, and marked degraded (their slack ran across the skip).
2. The ship on a pose input: the re-synchronisation blends the end onto its input; the snap that
   ends the slack is published, marked degraded.
3. The ship's input drops out during the slack period: the end is blended to rest ("input lost")
   and back ("input resumed"); detection goes on across both blends (it used to be suspended from
   the blend's start and restarted fresh after it, dropping the slack period and its snap).
"""

from pathlib import Path

import numpy as np

from tether_sim.io.inputs import EndPoseInput
from tether_sim.io.params import load_config
from tether_sim.physics.motion import build_motion
from tether_sim.physics.snap import SlackStarted, SnapEvent
from tether_sim.ros import convert
from tether_sim.ros.driver import SimulationDriver
from tether_sim.ros.end_commands import SolverTimeMotion

ROOT = Path(__file__).resolve().parents[2]
RATE = 50.0  # Hz, the node's output rate
STALL = 1.5  # s of clock the node does not tick (node.max_lag is 1 s)


def _config():
    return load_config(ROOT / "config" / "ropos_L200_hybrid.yaml", {"motion.ramp_time": 1.0, "hybrid.time_step": 0.02})


def _run(cfg, source, stall_at=None, end=5.0, dropout=None):
    """Tick at RATE until clock ``end`` (plus the stall); ([(event, its message, tick report)], reports, driver)."""
    motion = build_motion(cfg.motion, np.asarray(cfg.ship_end.position, float))
    box = {}
    if source == "solver time":
        src, feed = SolverTimeMotion(motion, lambda: box.get("driver")), None
    else:
        src, fed = EndPoseInput("ship", history_span=3.0), [0]

        def feed(now):  # 50 Hz poses of the circle, each arriving when the clock reaches its stamp
            while fed[0] / 50.0 <= now:
                t = fed[0] / 50.0
                if dropout is None or not dropout[0] <= t < dropout[1]:
                    assert src.add_pose(t, motion.at(t)[0], (0, 0, 0, 1)) is None
                fed[0] += 1

        feed(0.0)
    driver = box["driver"] = SimulationDriver(cfg, {"ship": src}, start_blend=False)
    driver.start(0.0)
    events, reports, k, now, stalled = [], [], 0, 0.0, stall_at is None
    while now < end + (0.0 if stall_at is None else STALL):
        k += 1
        if not stalled and k / RATE >= stall_at:
            k += int(round(STALL * RATE))
            stalled = True
        now = k / RATE
        if feed is not None:
            feed(now)
        report = driver.tick(now)
        reports.append(report)
        messages = {id(ev): msg for ev, (_, msg) in zip([e for e in report.events if isinstance(e, (SnapEvent, SlackStarted))],
                                                           convert.event_outputs(report.events, driver))}
        events += [(ev, messages.get(id(ev)), report) for ev in report.events]
    return events, reports, driver


def _snaps(events):
    """(event, message) of the snap events, by location."""
    return sorted([(ev, msg) for ev, msg, _ in events if isinstance(ev, SnapEvent)], key=lambda x: x[0].location)


def test_a_resynchronisation_in_a_slack_period_keeps_its_snap():
    cfg = _config()
    reference, _, _ = _run(cfg, "solver time")
    resynced, _, driver = _run(cfg, "solver time", stall_at=2.0)
    assert driver.resyncs == 1
    dropped = driver.dropped_total
    assert dropped > 1.0
    ref_snaps, snaps = _snaps(reference), _snaps(resynced)
    assert [ev.location for ev, _ in ref_snaps] == ["ship", "vehicle"]
    assert max(ev.amplification for ev, _ in ref_snaps) > 4.0  # the snap the node must not hide
    assert [ev.location for ev, _ in snaps] == [ev.location for ev, _ in ref_snaps]
    for (ref, ref_msg), (ev, msg) in zip(ref_snaps, snaps):
        # the same cable history in simulated time: the same snap, stamped on the clock after the skip
        assert abs(ev.peak_tension / ref.peak_tension - 1.0) < 1e-9
        assert abs(ev.slack_duration - ref.slack_duration) < 1e-6
        assert abs(ev.time - (ref.time + dropped)) < 1e-6
        assert not ref_msg.degraded and msg.degraded  # its slack ran across the skipped clock time
    # one slack warning per end for the one slack period (a fresh detector used to warn again)
    first_snap = min(ev.time for ev, _ in snaps)
    slack = [ev.location for ev, _, _ in resynced if isinstance(ev, SlackStarted) and ev.time < first_snap]
    assert sorted(slack) == ["ship", "vehicle"]


def test_a_snap_during_a_resynchronisation_blend_is_published_degraded():
    """The ship on its pose input re-synchronised at 3.0 s: it keeps its motion and catches up with the
    input over 62 s (a velocity change of 4.6 m/s at 0.5 m/s^2); the slack that began at 0.87 s ends
    below the snap level, the next one (5.5 s) in snaps at 8.2 s (2.5 and 2.4 x static), published
    degraded (until 2026-11-27 the end coasted straight on and snapped at 3.5 s, also degraded)."""
    cfg = _config()
    events, reports, driver = _run(cfg, "pose input", stall_at=3.0, end=8.0)
    assert driver.resyncs == 1
    resync_report = next(r for r in reports if r.dropped > 0.0)
    assert [b[2] for b in resync_report.blends] == ["re-synchronised"]
    snaps = _snaps(events)
    assert {ev.location for ev, _ in snaps} == {"ship", "vehicle"}
    for ev, msg in snaps:
        assert ev.amplification > 2.0
        assert driver.bridged(ev) and msg.degraded and msg.peak_tension == ev.peak_tension



def test_an_input_dropout_in_a_slack_period_keeps_its_snap():
    """The ship's poses stop at 2.9 s (slack since 0.87 s) and come back at 4.2 s: beyond
    node.max_extrapolation the end is blended to rest, and onto the stream when it resumes. The
    re-tensioning at 3.6 s happens during that blend: 190 kN at the cage end and 197 kN at the ship
    (4.4 and 4.1 x static; the ship no longer on its circle, so less than the 261 / 271 kN without the
    dropout). Before, the blend suspended detection and a fresh detector started after it: both snaps
    went unreported."""
    cfg = _config()
    events, reports, driver = _run(cfg, "pose input", end=5.0, dropout=(2.9, 4.2))
    blends = [b[2] for r in reports for b in r.blends]
    assert "input lost" in blends and "input resumed" in blends and driver.resyncs == 0
    snaps = _snaps(events)
    assert [ev.location for ev, _ in snaps] == ["ship", "vehicle"]
    for ev, msg in snaps:
        assert ev.amplification > 3.0 and ev.slack_start < 1.0  # the slack period that began at 0.87 s
        assert driver.bridged(ev) and msg.degraded and msg.peak_tension == ev.peak_tension
    first_snap = min(ev.time for ev, _ in snaps)
    slack = [ev.location for ev, _, _ in events if isinstance(ev, SlackStarted) and ev.time < first_snap]
    assert sorted(slack) == ["ship", "vehicle"]
