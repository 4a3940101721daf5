"""tether-sim-study stopped by a signal (a real process tree, a real signal): the finished case stays
in the results (tables and its MCAP readable), the case in flight is dropped and said so (its
incomplete MCAP removed; it runs when the study is started again), no worker survives, no traceback,
exit code 128 + the signal number.

Two cases on two worker processes: case 0 simulates 2 s (finishes), case 1 a million seconds (cannot
finish: this coarse mesh runs at a few hundred times real time on a fast machine, so an hour of simulated
time could end before the first progress line is read).
SIGINT goes to the whole process group, as a terminal's Ctrl-C does; SIGTERM to the parent only, as
a process manager does (the parent must end its workers itself)."""

import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
import yaml

from tether_sim.studies.results import read_results

HERE = Path(__file__).resolve().parent
PROGRAM = str(Path(sys.executable).with_name("tether-sim-study"))


def write_study(path):
    study = yaml.safe_load((HERE / "tiny_study.yaml").read_text())
    study["base"] = str((HERE / study["base"]).resolve())
    study["vary"] = {"zip": {"duration": [2.0, 1.0e6]}}
    study["set"] = {k: v for k, v in study["set"].items() if k not in ("duration", "vehicle_end.direction")}
    study["set"].update({"motion.frequency": 0.2, "motion.amplitude": 0.1})
    study["keep"] = {"mcap": True, "events": True}
    path.write_text(yaml.safe_dump(study))
    return path


def alive(pgid) -> bool:
    try:
        os.killpg(pgid, 0)
    except ProcessLookupError:
        return False
    return True


@pytest.mark.parametrize("sig, to_group", [(signal.SIGINT, True), (signal.SIGTERM, False)])
def test_a_signal_keeps_finished_cases_and_says_what_was_dropped(tmp_path, sig, to_group):
    study, out = write_study(tmp_path / "study.yaml"), tmp_path / "results"
    proc = subprocess.Popen([PROGRAM, str(study), "--out", str(out), "--workers", "2"], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, start_new_session=True,
                            env={**os.environ, "PYTHONUNBUFFERED": "1"})
    err = []
    try:
        deadline = time.monotonic() + 900.0  # two spawned workers import and load the numba cache (minutes at load 12)
        for line in proc.stderr:  # progress lines: wait for the first finished case
            err.append(line)
            if line.startswith("[study] 1/2 cases") or time.monotonic() > deadline:
                break
        assert any(x.startswith("[study] 1/2 cases (1 ok") for x in err), "".join(err)
        (os.killpg(proc.pid, sig) if to_group else proc.send_signal(sig))
        stdout, rest = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
    stderr = "".join(err) + rest
    assert proc.returncode == 128 + sig, (stdout, stderr)
    assert "Traceback" not in stderr and "KeyboardInterrupt" not in stderr, stderr
    assert re.search(rf"stopped by {sig.name}: 1 case\(s\) finished and kept in the results, 1 in flight dropped "
                     r"and 0 not started", stderr), stderr
    deadline = time.monotonic() + 10.0
    while alive(proc.pid) and time.monotonic() < deadline:  # the workers end with their parent
        time.sleep(0.1)
    assert not alive(proc.pid), "a worker process outlived the study"
    rows = read_results(out)
    assert [(r["index"], r["status"], r["sim_s"]) for r in rows] == [(0, "ok", 2.0)]
    kept = sorted((out / "mcap").glob("*.mcap"))
    assert [p.name for p in kept] == [Path(rows[0]["mcap"]).name]  # case 1's incomplete file is gone
    from tether_sim.io.mcap_log import read_messages

    states = [1 for topic, *_ in read_messages(str(kept[0])) if topic == "/tether/state"]
    assert len(states) == 2 * 10 + 1  # 10 Hz outputs over 2 s and the initial state
