"""main_job fails loudly, naming the missing piece, and never starts processes without them."""

import shutil
from pathlib import Path

import pytest

from tether_sim.ros import main_job
from tether_sim.ros.processes import StepFailed, command_for, isolated_env

REPO = Path(__file__).resolve().parents[2]


def test_missing_record_and_params_are_named(tmp_path):
    with pytest.raises(StepFailed) as info:
        main_job.preflight(tmp_path)
    text = str(info.value)
    assert "data/ropos_ship_heave.mcap" in text and "config/ropos_validation.yaml" in text


def test_broken_record_is_a_clear_failure(tmp_path):
    (tmp_path / "data").mkdir()
    (tmp_path / "config").mkdir()
    shutil.copy(REPO / "config" / "ropos_validation.yaml", tmp_path / "config")
    (tmp_path / "data" / "ropos_ship_heave.mcap").write_bytes(b"not an mcap file")
    with pytest.raises(StepFailed, match="not an MCAP file"):
        main_job.preflight(tmp_path)


def test_main_returns_nonzero_with_the_reason(tmp_path, monkeypatch, capsys):
    import os
    for name in ("ROS_DOMAIN_ID", "ROS_AUTOMATIC_DISCOVERY_RANGE", "PYTHONUNBUFFERED"):
        if name in os.environ:  # main() joins its private domain; restore ours afterwards
            monkeypatch.setenv(name, os.environ[name])
        else:
            monkeypatch.delenv(name, raising=False)
    monkeypatch.setattr(main_job, "REPO", tmp_path)
    monkeypatch.chdir(tmp_path)
    (tmp_path / "config").mkdir()
    assert main_job.main(["--out", str(tmp_path / "out"), "--domain-id", "97"]) == 1
    out = capsys.readouterr().out
    assert "FAILED" in out and "ship-motion record" in out
    assert not (tmp_path / "out" / "logs" / "tether_sim.log").exists()  # nothing was started


def test_children_get_a_private_localhost_domain():
    env = isolated_env(42)
    assert env["ROS_DOMAIN_ID"] == "42" and env["ROS_AUTOMATIC_DISCOVERY_RANGE"] == "LOCALHOST"
    argv = command_for("tether-sim-record")
    assert argv[0].endswith("tether-sim-record") or argv[-1] == "tether-sim-record"


def test_replay_rate_follows_the_measured_capacity():
    """Half the measured capacity when the node kept up, 70 % of what it kept when it fell behind."""
    from tether_sim.ros.main_job import replay_rate

    assert replay_rate(0.99, 0.05) == 1.0  # 20x capacity: real time
    assert replay_rate(1.0, 0.8) == 0.6  # 1.25x capacity: 0.625 -> 0.6
    assert replay_rate(0.5, 0.9) == 0.35  # behind the clock: 0.7 x 0.5
    assert replay_rate(None, None) == 1.0
    assert replay_rate(0.01, None) == 0.05  # never below 0.05


def test_a_job_stops_its_children_however_it_ends(tmp_path):
    """run_job (make run and the vehicle demo): 0 / 1 / 130 for a finished, failed and interrupted body
    (SIGTERM raised inside it), the reason said, every child stopped, the SIGTERM handler given back."""
    import os
    import signal
    import sys

    from tether_sim.ros.processes import StepFailed, run_job

    said = []
    before = signal.getsignal(signal.SIGTERM)
    children = []

    def body(end):
        def job(group):
            children.append(group.start("sleeper", [sys.executable, "-c", "import time; time.sleep(60)"]))
            if end == "fail":
                raise StepFailed("the sleeper was told to fail")
            if end == "sigterm":
                os.kill(os.getpid(), signal.SIGTERM)
        return job

    env = dict(os.environ)
    codes = [run_job(env, tmp_path / "logs", tmp_path, body(end), said.append) for end in ("done", "fail", "sigterm")]
    assert codes == [0, 1, 130]
    assert said == ["FAILED: the sleeper was told to fail", "interrupted"]
    assert all(child.proc.poll() is not None for child in children)
    assert signal.getsignal(signal.SIGTERM) is before
