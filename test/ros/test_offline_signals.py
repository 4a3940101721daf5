"""tether-sim-offline stopped by SIGINT / SIGTERM (a real process, a real signal): the MCAP it was
writing is closed as at a normal end and readable by an independent reader, its last state is the
one the one-line account names, no traceback, exit code 128 + the signal number."""

import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

pytest.importorskip("rclpy")
pytest.importorskip("tether_sim_msgs")

from tether_sim.io.mcap_log import read_messages  # noqa: E402

from test_offline import write_params  # noqa: E402

pytestmark = pytest.mark.ros

PROGRAM = str(Path(sys.executable).with_name("tether-sim-offline"))


def start_long_run(tmp_path):
    """A run of an hour of simulated time (it cannot end by itself within the test); returns
    (process, output path) once the output file exists, i.e. once the solver has started and a
    signal only asks the loop to stop (the file is opened after the start-up)."""
    params = write_params(tmp_path / "p.yaml", duration=3600.0,
                          motion={"kind": "heave", "amplitude": 0.5, "frequency": 0.2})
    out = tmp_path / "run.mcap"
    proc = subprocess.Popen([PROGRAM, "--params", params, "--output", str(out), "--no-progress"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 300.0  # start-up: imports and the numba cache, minutes on a loaded machine
    while not out.exists():
        assert proc.poll() is None, proc.communicate()
        assert time.monotonic() < deadline, "the offline run did not open its output"
        time.sleep(0.05)
    time.sleep(1.0)  # some ticks into the file
    return proc, out


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_a_signal_closes_the_file_and_says_what_was_written(tmp_path, sig):
    proc, out = start_long_run(tmp_path)
    proc.send_signal(sig)
    stdout, stderr = proc.communicate(timeout=60)
    assert proc.returncode == 128 + sig, (stdout, stderr)
    assert "Traceback" not in stderr and "KeyboardInterrupt" not in stderr, stderr
    m = re.search(rf"stopped by {sig.name} at ([0-9.e+]+) s of 3600 s simulated \((\d+) ticks\)", stderr)
    assert m, stderr
    simulated, ticks = float(m.group(1)), int(m.group(2))
    # (0 ticks is possible on a loaded machine: the signal may come before the first tick is done)
    assert 0 <= simulated < 3600 and ticks == round(simulated * 20.0)  # output_rate 20 Hz
    assert f"wrote {out}" in stdout
    # the file: footer and summary written (our reader and rosbags), every tick in it, the last at the
    # time the account names
    states = [(ns, msg) for topic, _t, ns, msg in read_messages(str(out)) if topic == "/tether/state"]
    assert len(states) == ticks + 1  # the initial state and one per tick
    assert states[-1][0] == pytest.approx(simulated * 1e9, abs=1.0)
    from rosbags.highlevel import AnyReader
    from rosbags.typesys import Stores, get_typestore

    with AnyReader([out], default_typestore=get_typestore(Stores.EMPTY)) as reader:
        n_states = sum(1 for c, _, raw in reader.messages() if c.topic == "/tether/state"
                       and reader.deserialize(raw, c.msgtype) is not None)
    assert n_states == ticks + 1

