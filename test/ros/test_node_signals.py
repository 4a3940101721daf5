"""The running node stopped by SIGINT (Ctrl-C, ROS launch) or SIGTERM (a process manager): it ends
within seconds with exit code 0 (what ROS launch expects of a node told to stop; the node writes no
file, so nothing can be lost), no traceback, and one line on what it did.

Ctrl-C on `ros2 launch` sends SIGINT twice: the terminal's to the whole process group, then launch's
own to each process it started (launch 3.4.3 logs "sending signal 'SIGINT' to process[...]"); the second
one lands while the node is already stopping and must not turn a clean stop into "process has died"."""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

pytest.importorskip("rclpy")
pytest.importorskip("tether_sim_msgs")

pytestmark = pytest.mark.ros
ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("sig, repeat, executor", [(signal.SIGINT, False, "single"), (signal.SIGTERM, False, "single"),
                                                   (signal.SIGINT, True, "single"), (signal.SIGINT, False, "events"),
                                                   (signal.SIGTERM, False, "events"), (signal.SIGINT, True, "events")],
                         ids=["SIGINT", "SIGTERM", "SIGINT-repeated-as-by-ros2-launch", "SIGINT-events-executor",
                              "SIGTERM-events-executor", "SIGINT-repeated-events-executor"])
def test_running_node_stops_cleanly_with_an_account(sig, repeat, executor):
    """(``node.executor``: rclpy's SingleThreadedExecutor or its EventsExecutor spins the node.)"""
    proc = subprocess.Popen([str(Path(sys.executable).with_name("tether-sim")), "--ros-args", "--params-file",
                             str(ROOT / "config/ropos_L200.yaml"), "-p", f"node.executor:={executor}"], cwd=ROOT, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True, env={**os.environ, "PYTHONUNBUFFERED": "1"})
    lines = []
    try:
        deadline = time.monotonic() + 180.0
        for line in proc.stdout:
            lines.append(line)
            if "solver started" in line or time.monotonic() > deadline:
                break
        assert any("solver started" in x for x in lines), "".join(lines)
        time.sleep(1.0)  # ticking
        proc.send_signal(sig)
        if repeat:  # more of the same every 10 ms while it stops (some land in the clean-up)
            deadline = time.monotonic() + 20.0
            while proc.poll() is None and time.monotonic() < deadline:
                time.sleep(0.01)
                if proc.poll() is None:
                    proc.send_signal(sig)
        rest = proc.communicate(timeout=20)[0]
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == 0, rest
    assert "Traceback" not in rest, rest
    account = [x for x in rest.splitlines() if x.startswith("tether-sim: stopped by")]
    # once ticking, the signal only sets the spin loop's flag: the account names it exactly
    assert len(account) == 1 and account[0].startswith(f"tether-sim: stopped by {sig.name}: "), rest
    assert "0 snap event(s) published, 0 failed tick(s)" in account[0], rest  # at rest: the tether hangs still
    ran = float(account[0].split("ran ", 1)[1].split(" s of clock time", 1)[0])
    assert ran >= 0.5, rest  # the timer ticked for the second it was given (any executor)


@pytest.mark.parametrize("program, args, ready", [
    ("tether-sim-poses", ["--params", "config/ropos_L200.yaml"], "publishing"),
    ("tether-sim-vehicle", ["--rate", "50"], "holding"),
], ids=["pose-source", "vehicle"])
@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_helper_nodes_stop_cleanly_on_a_signal(program, args, ready, sig):
    """The pose source and the vehicle simulator (run beside the node by the demos, stopped by SIGINT / SIGTERM):
    exit code 0 and no traceback, with signals repeated every 10 ms while they stop."""
    if program == "tether-sim-vehicle":
        pytest.importorskip("mujoco")
    proc = subprocess.Popen([str(Path(sys.executable).with_name(program)), *args], cwd=ROOT, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True, env={**os.environ, "PYTHONUNBUFFERED": "1"})
    lines = []
    try:
        deadline = time.monotonic() + 120.0
        for line in proc.stdout:
            lines.append(line)
            if ready in line or time.monotonic() > deadline:
                break
        assert any(ready in x for x in lines), "".join(lines)
        time.sleep(0.5)  # publishing
        proc.send_signal(sig)
        deadline = time.monotonic() + 20.0
        while proc.poll() is None and time.monotonic() < deadline:
            time.sleep(0.01)
            if proc.poll() is None:
                proc.send_signal(sig)
        rest = proc.communicate(timeout=20)[0]
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == 0, "".join(lines) + rest
    assert "Traceback" not in rest, rest
