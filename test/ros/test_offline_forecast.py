"""tether-sim-offline with forecast.enabled: the node's SnapForecast messages in the MCAP (inline, on the
runner's tick grid, so an exact forecast repeats the run), and the report's forecast timeline and skill."""

import math

import pytest
import yaml

pytest.importorskip("rclpy")
pytest.importorskip("tether_sim_msgs")

from tether_sim.io.mcap_log import read_messages  # noqa: E402
from tether_sim.report import make_report  # noqa: E402
from tether_sim.ros.offline import main  # noqa: E402

pytestmark = pytest.mark.ros


def params(tmp_path, **forecast):
    """The 1730 m live mesh on the A-frame in a regular wave (H 6 m, T 9 s): one cage snap per wave."""
    with open("config/ropos_aframe_jonswap.yaml") as f:
        doc = yaml.safe_load(f)
    p = next(iter(doc.values()))["ros__parameters"]  # the file's one node section
    p.update(duration=24.0, node={"output_rate": 10.0},
             waves={"kind": "regular", "height": 6.0, "period": 9.0, "direction": 195.0},
             forecast={"enabled": True, "horizon": 10.0, **forecast})
    p["motion"]["ramp_time"] = 5.0
    path = tmp_path / "p.yaml"
    path.write_text(yaml.safe_dump(doc))
    return str(path)


def test_offline_run_writes_forecasts_that_match_its_snaps_and_the_report_scores_them(tmp_path, capsys):
    out = tmp_path / "run.mcap"
    assert main(["--params", params(tmp_path, members=1, sea_error=0.0), "--output", str(out), "--no-progress"]) == 0
    assert "38 snap forecasts on /tether/snap_forecast" in capsys.readouterr().out
    forecasts, snaps = [], []
    for topic, _type, log_ns, msg in read_messages(str(out), ["/tether/snap_forecast", "/tether/snap_events"]):
        stamp = msg.header.stamp.sec + 1e-9 * msg.header.stamp.nanosec
        assert log_ns == round(stamp * 1e9)
        (forecasts if topic == "/tether/snap_forecast" else snaps).append((stamp, msg))
    assert len(forecasts) == 38 and len(snaps) >= 2  # one per end per second from the end of the 5 s ramp-in
    for stamp, f in forecasts:
        assert f.source == "known_sea" and f.members == 1 and not f.degraded and f.header.frame_id == "map"
        later = [(t, s) for t, s in snaps if s.end == f.end and t >= stamp]
        if later and later[0][0] <= stamp + f.horizon:
            t, s = later[0]
            assert f.probability == 1.0
            assert stamp + f.time_to_snap == pytest.approx(t, abs=1e-6)  # the stamps are rounded to 1 ns
            assert f.predicted_peak == pytest.approx(s.peak_tension, rel=1e-9)
        elif stamp + f.horizon + 2.0 <= 24.0:
            assert f.probability == 0.0 and math.isnan(f.time_to_snap)
    result = make_report(out, tmp_path / "figures")
    assert (tmp_path / "figures" / "snap_forecast.png").is_file()
    md = result["markdown"]
    assert "## Snap forecast" in md
    rows = [[c.strip() for c in line.strip("|").split("|")] for line in md.splitlines()
            if line.startswith("| vehicle | ") and "%" in line]
    assert [r[1] for r in rows] == ["0.5", "0.75 (alarm)"]  # the definition's threshold and the run's alarm
    for cells in rows:
        assert cells[3].endswith("(100 %)") and cells[5] == "0"  # every scored snap warned, no false alarm
