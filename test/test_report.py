"""tether-sim-report on a synthetic output MCAP whose slack period and snap event are known exactly.

The MCAP is written with RosMcapWriter from CDR made by rosbags (types parsed from the shipped
msg_defs/), so the report reads it through the same decoder path as a recording.
"""

import io
import json
from pathlib import Path

import numpy as np
import pytest
from matplotlib.image import imread
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

from tether_sim.io.mcap_log import RosMcapWriter
from tether_sim.io.msg_definitions import export_rosbags_definitions
from tether_sim.report import ReportError, below_intervals, load_run, main, make_report

REPO = Path(__file__).resolve().parents[1]
MSG_DIR = REPO / "msg_defs" / "msg"
T0_NS = 50 * 10**9           # first state stamp: 50 s of sim time
DT = 0.1                     # 10 Hz output
N_T, N_S, L = 201, 11, 100.0
SLACK = (6.0, 7.0)           # vehicle end below the threshold on these samples (inclusive)
THRESHOLD, PEAK, T_PEAK = 100.0, 12_000.0, 7.3


@pytest.fixture(scope="module")
def store():
    ts = get_typestore(Stores.ROS2_JAZZY)
    for name in ("TetherState", "SnapLoadEvent", "SlackWarning"):
        ts.register(get_types_from_msg((MSG_DIR / f"{name}.msg").read_text(),
                                       f"tether_sim_msgs/msg/{name}"))
    return ts


def _stamp(ts, seconds):
    ns = T0_NS + int(round(seconds * 1e9))
    return ts.types["builtin_interfaces/msg/Time"](sec=ns // 10**9, nanosec=ns % 10**9)


def _header(ts, seconds):
    return ts.types["std_msgs/msg/Header"](stamp=_stamp(ts, seconds), frame_id="map")


def vehicle_tension(t):
    """Static 2000 N, a slack period on SLACK (50 N), then the snap peak at T_PEAK."""
    if SLACK[0] - 1e-9 <= t <= SLACK[1] + 1e-9:
        return 50.0
    return PEAK if abs(t - T_PEAK) < 1e-9 else 2000.0


def write_output(path, prefix, ts, chunk_size=1 << 20, lines=("",)):
    """The known run; ``lines``: one copy per line of a network recording (``/tether/<line>/...``,
    line k's snap peak PEAK + k N), "" = the single-line topics."""
    with RosMcapWriter(path, msg_search_path=[prefix], chunk_size=chunk_size) as w:
        for k, line in enumerate(lines):
            _write_line(w, ts, f"/tether/{line}/" if line else "/tether/", k)
    return path


def _write_line(w, ts, top, k_line):
    T = ts.types
    s = np.linspace(0.0, L, N_S)
    w.add_topic(f"{top}state", "tether_sim_msgs/msg/TetherState")
    w.add_topic(f"{top}snap_events", "tether_sim_msgs/msg/SnapLoadEvent")
    w.add_topic(f"{top}slack_warnings", "tether_sim_msgs/msg/SlackWarning")
    if top == "/tether/":
        w.add_topic("/tether/ship_wrench", "geometry_msgs/msg/WrenchStamped")
    for k in range(N_T):
        t = k * DT
        tv = vehicle_tension(t)
        ship = tv + 9.81 * 5.0 * L  # weight of 100 m of 5 kg/m cable in air, as a simple offset
        state = T["tether_sim_msgs/msg/TetherState"](
            header=_header(ts, t), solver="dg", arc_length=s,
            position=[T["geometry_msgs/msg/Point"](x=0.1 * t, y=0.0, z=-si) for si in s],
            velocity=[T["geometry_msgs/msg/Vector3"](x=0.1, y=0.0, z=0.0) for _ in s],
            tension=np.linspace(ship, tv, N_S), curvature=np.zeros(N_S),
            bending_moment=np.zeros(N_S), ship_end_tension=ship, vehicle_end_tension=tv,
            time_step=1e-3, real_time_factor=1.0, lag=0.0, degraded=False)
        log = T0_NS + k * 10**8
        w.write(f"{top}state", ts.serialize_cdr(state, "tether_sim_msgs/msg/TetherState"), log)
        if top != "/tether/":
            pass
        else:
            wrench = T["geometry_msgs/msg/WrenchStamped"](header=_header(ts, t), wrench=T["geometry_msgs/msg/Wrench"](
                force=T["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=-ship),
                torque=T["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.0)))
            w.write("/tether/ship_wrench", ts.serialize_cdr(wrench, "geometry_msgs/msg/WrenchStamped"), log)
        if abs(t - SLACK[0]) < 1e-9:
            warn = T["tether_sim_msgs/msg/SlackWarning"](header=_header(ts, t), end="vehicle",
                                                         arc_length=L, tension=50.0,
                                                         threshold=THRESHOLD, static_tension=2000.0)
            w.write(f"{top}slack_warnings", ts.serialize_cdr(warn, "tether_sim_msgs/msg/SlackWarning"), log)
        if abs(t - T_PEAK) < 1e-9:
            snap = T["tether_sim_msgs/msg/SnapLoadEvent"](
                header=_header(ts, t), end="vehicle", arc_length=L, peak_tension=PEAK + k_line,
                min_tension=50.0, slack_start=_stamp(ts, SLACK[0]), slack_duration=1.0,
                rise_time=0.3, static_tension=2000.0, amplification=PEAK / 2000.0,
                criterion="slack_threshold", lag=0.0, degraded=False)
            w.write(f"{top}snap_events", ts.serialize_cdr(snap, "tether_sim_msgs/msg/SnapLoadEvent"), log)


@pytest.fixture(scope="module")
def prefix(tmp_path_factory):
    root = tmp_path_factory.mktemp("prefix")
    export_rosbags_definitions(root, ["geometry_msgs/msg/WrenchStamped", "geometry_msgs/msg/Point",
                                      "geometry_msgs/msg/Vector3", "std_msgs/msg/Header"])
    return root


def test_below_intervals_exact():
    t = np.arange(10.0)
    v = np.array([5, 1, 1, 5, 5, 0, 5, 5, 1, 1.0])
    assert below_intervals(t, v, 2.0) == [(1.0, 2.0), (5.0, 5.0), (8.0, 9.0)]


def test_report_on_known_run(tmp_path, prefix, store):
    path = write_output(tmp_path / "out.mcap", prefix, store)
    result = make_report(path, tmp_path / "fig")
    run = result["run"]
    assert len(run.t) == N_T and run.t[0] == 0.0 and run.t[-1] == pytest.approx(20.0)
    # slack: samples 6.0..7.0 s are below the 100 N threshold the node reported; the event's own
    # slack interval (6.0 + 1.0 s) coincides, so exactly one period results.
    (period,) = result["periods"]["vehicle"]
    assert (period["start"], period["end"]) == pytest.approx(SLACK, abs=1e-6)
    assert period["min_tension"] == 50.0 and period["threshold"] == THRESHOLD
    assert result["periods"]["ship"] == []
    assert result["static"] == {"ship": pytest.approx(2000.0 + 9.81 * 500.0), "vehicle": 2000.0}
    (snap,) = run.snaps
    assert snap["t_peak"] == pytest.approx(T_PEAK) and snap["slack_start"] == pytest.approx(SLACK[0])
    md = result["markdown"]
    assert "| 1 | vehicle | 100.0 | 7.300 | 12000.0 | 2000.0 | 6.00 |" in md
    assert "| vehicle | 6.000 | 7.000 | 1.000 | 50.0 | 100.0 |" in md
    assert result["report_path"].read_text() == md
    for png in result["figures"].values():
        image = imread(png)
        assert image.shape[0] > 400 and image.shape[1] > 800
        assert image[..., :3].std() > 0.05  # not a blank canvas
    wrench_t, wrench_f = run.wrench["ship"]
    assert np.allclose(wrench_f, run.end_tension["ship"])
    # the envelope along the cable: tension is linear from the ship (tv + 4905 N) to the vehicle
    # (tv), so its largest value is at the ship end at the snap instant, its smallest at the vehicle
    # end in slack; no breaking load in this file, so no utilisation
    env = result["envelope"]
    ship_peak = PEAK + 9.81 * 5.0 * L
    assert env["largest"] == {"tension_N": pytest.approx(ship_peak), "arc_length_m": 0.0, "time_s": pytest.approx(T_PEAK)}
    assert env["max_N"] == pytest.approx(np.linspace(ship_peak, PEAK, N_S).tolist())
    assert env["min_N"][-1] == 50.0 and env["smallest_N"] == 50.0 and env["utilisation"] is None
    assert "Largest tension anywhere on the cable: **16905.0 N** at s = 0.0 m, t = 7.300 s" in md
    assert "not computed (`cable.breaking_load` not given" in md
    summary = json.loads(result["json_path"].read_text())  # report.json: the same numbers, units in names
    assert result["json_path"].parent == result["report_path"].parent
    assert summary["tension_envelope"]["largest_N"] == pytest.approx(ship_peak)
    assert summary["end_tension_N"]["vehicle"]["static"] == 2000.0 and summary["utilisation"] is None
    assert summary["slack_periods"]["vehicle"] == [{"start_s": pytest.approx(6.0), "end_s": pytest.approx(7.0),
                                                   "duration_s": pytest.approx(1.0), "min_tension_N": 50.0,
                                                   "threshold_N": THRESHOLD}]
    assert [e["peak_N"] for e in summary["snap_events"]] == [PEAK]


def test_utilisation_against_the_breaking_load_of_the_description(tmp_path, prefix, store):
    from tether_sim.report import envelope_markdown, load_run, tension_envelope

    run = load_run(write_output(tmp_path / "out.mcap", prefix, store))
    run.parameters = {"cable.breaking_load": "50000.0"}  # as TetherDescription.parameters carries it
    env = tension_envelope(run)
    assert env["utilisation"] == pytest.approx((PEAK + 9.81 * 5.0 * L) / 50000.0)
    assert "Utilisation: 33.8 % of the breaking load (`cable.breaking_load` 50000 N)." in envelope_markdown(env)


def test_network_recording_gets_one_report_per_line(tmp_path, prefix, store, capsys):
    """/tether/<line>/... topics: each line's report holds its own snap (peaks PEAK, PEAK + 1) and slack
    period, not the other line's; an index links them; --line picks one."""
    from tether_sim.report import make_network_report, network_lines

    path = write_output(tmp_path / "net.mcap", prefix, store, lines=("tether", "excursion"))
    assert network_lines(path) == ["excursion", "tether"]
    result = make_network_report(path, tmp_path / "fig")
    for k, line in enumerate(("tether", "excursion")):
        r = result["lines"][line]
        assert [e["peak"] for e in r["run"].snaps] == [PEAK + k]
        assert r["periods"]["vehicle"][0]["start"] == pytest.approx(SLACK[0])
        assert (tmp_path / "fig" / line / "end_tensions.png").is_file()
        assert f"line {line}" in r["markdown"]
    assert "`tether/report.md`" in result["markdown"] and "`excursion/report.md`" in result["markdown"]
    assert main([str(path), "--out-dir", str(tmp_path / "one"), "--line", "excursion"]) == 0
    assert (tmp_path / "one" / "excursion" / "report.md").is_file() and not (tmp_path / "one" / "tether").exists()
    assert main([str(path), "--out-dir", str(tmp_path / "bad"), "--line", "umbilical"]) == 2
    assert "no line 'umbilical'" in capsys.readouterr().err


def test_report_without_states_is_a_clear_error(tmp_path, prefix, store, capsys):
    path = tmp_path / "poses.mcap"
    with RosMcapWriter(path, msg_search_path=[prefix]) as w:
        w.add_topic("/ship/wrench", "geometry_msgs/msg/WrenchStamped")
    with pytest.raises(ReportError, match="no tether_sim_msgs/msg/TetherState topic"):
        make_report(path, tmp_path / "fig")
    assert main([str(path)]) == 2
    assert "poses.mcap" in capsys.readouterr().err
    assert main([str(tmp_path / "missing.mcap")]) == 2


def test_report_names_the_dg_mesh_from_the_description():
    from tether_sim.report import _mesh_line

    params = {"solver": "dg", "dg.n_elements": "3", "dg.order": "4", "dg.cfl": "0.8", "dg.resolution": "auto",
              "dg.snap_tolerance": "0.01"}
    assert _mesh_line(params) == (" DG mesh: N = 3, P = 4, dg.cfl 0.8 (dg.resolution auto, first-snap-peak "
                                  "tolerance 1 %).")
    assert _mesh_line({**params, "solver": "hybrid"}) == "" and _mesh_line({}) == ""
    fine = {**params, "dg.n_elements": 40, "dg.resolution": "manual", "cable.length": 200.0, "cable.EI": 2620.0}
    assert "Caution: bending" in _mesh_line(fine) and "Caution" not in _mesh_line({**fine, "cable.EI": 0.0})
def test_report_of_a_truncated_file_says_so(tmp_path, prefix, store, capsys):
    path = write_output(tmp_path / "out.mcap", prefix, store, chunk_size=16384)
    data = path.read_bytes()
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(data[: len(data) // 2])  # a crash half-way through the file
    with pytest.warns(UserWarning, match="truncated"):
        result = make_report(cut, tmp_path / "fig")
    assert 0 < len(result["run"].t) < N_T
    assert "**Truncated recording.**" in result["markdown"] and "complete chunk(s)" in result["markdown"]
    # a file cut before its first complete chunk: a clear error naming the truncation, exit 2
    single = write_output(tmp_path / "single.mcap", prefix, store)
    empty = tmp_path / "empty_cut.mcap"
    empty.write_bytes(single.read_bytes()[: single.stat().st_size // 2])
    assert main([str(empty), "--out-dir", str(tmp_path / "fig2")]) == 2
    assert "truncated" in capsys.readouterr().err


def test_report_of_a_file_with_a_corrupt_chunk_covers_the_intact_ones(tmp_path, prefix, store, capsys):
    """64 corrupted bytes in the last chunk with states of a complete recording: the report covers every intact
    chunk and says what was dropped (exit 0), instead of refusing the whole file."""
    from mcap.reader import SeekingReader

    from mcap.data_stream import ReadDataStream
    from mcap.records import Chunk, Message
    from mcap.stream_reader import breakup_chunk

    path = write_output(tmp_path / "out.mcap", prefix, store, chunk_size=16384)
    good = path.read_bytes()
    summary = SeekingReader(io.BytesIO(good)).get_summary()
    assert len(summary.chunk_indexes) >= 3
    state_channel = next(c.id for c in summary.channels.values() if c.topic == "/tether/state")

    def states_of(chunk):
        """The log times of the states in ``chunk``, read from the intact original."""
        record = good[chunk.chunk_start_offset + 9:chunk.chunk_start_offset + chunk.chunk_length]
        return {r.log_time for r in breakup_chunk(Chunk.read(ReadDataStream(io.BytesIO(record))))
                if isinstance(r, Message) and r.channel_id == state_channel}

    # the last chunk that holds states (where the chunks end depends on the schemas' text, written into them)
    last = next(c for c in reversed(summary.chunk_indexes) if states_of(c))
    data = bytearray(good)
    middle = last.chunk_start_offset + last.chunk_length - last.compressed_size // 2
    data[middle:middle + 64] = bytes(b ^ 0x5A for b in data[middle:middle + 64])
    bad = tmp_path / "bad.mcap"
    bad.write_bytes(bytes(data))
    assert main([str(bad), "--out-dir", str(tmp_path / "fig")]) == 0
    text = capsys.readouterr().out
    assert "**Damaged recording.**" in text and "dropped 1 corrupt record(s)" in text
    run = load_run(bad)
    lost = states_of(last)
    kept = [k for k in range(N_T) if T0_NS + k * 10**8 not in lost]
    assert lost and 0 < len(run.t) == len(kept) < N_T
    assert np.allclose(run.t, np.array(kept) * DT)


def test_threshold_series_follows_the_warnings_in_time():
    """A winch run's threshold changes with the length: each instant takes the latest warning's
    threshold (the first one before any), so a dip is judged against the threshold of its time."""
    from tether_sim.report import below_intervals, threshold_series

    t = np.arange(0.0, 10.0, 1.0)
    warned = [(7.0, 8000.0), (2.0, 5000.0)]  # unsorted on purpose
    thr = threshold_series(t, warned)
    np.testing.assert_array_equal(thr, [5000.0] * 7 + [8000.0] * 3)
    tension = np.array([9e3, 9e3, 4e3, 9e3, 9e3, 6e3, 9e3, 7e3, 7e3, 9e3])
    # 6 kN at t = 5 s is above that time's 5 kN threshold; 7 kN at 7-8 s is below the 8 kN then
    assert below_intervals(t, tension, thr) == [(2.0, 2.0), (7.0, 8.0)]
    np.testing.assert_array_equal(threshold_series(t, []), np.zeros(10))
