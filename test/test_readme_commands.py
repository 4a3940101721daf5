"""Every command in README.md's ```bash blocks runs as written, with short durations:

- ``tether-sim`` lines: all started together (as the README's two-tethers example starts them), the
  ``tether_sim.ros.watch`` line run against them until it prints the end tensions of the namespace
  it watches; each node must warm up, start its solver and stop cleanly on SIGINT;
- ``tether-sim-offline``: 0.2 s of simulated time instead of the README's 60 s, into a temporary
  file that the ``tether-sim-report`` line then reads;
- other ``.venv/bin/python`` programs (the papers' scenarios, benchmarks, studies: minutes each,
  and they rewrite the figures in docs/): ``--help`` only;
- the offline runner, the report, the ``--help`` runs and the Python example run in this
  interpreter (entry point / ``runpy``), which saves an interpreter start-up each; the nodes and
  the watcher are real processes (namespaces, signals);
- skipped, with the reason in SKIPPED: ``make run`` / ``make test`` (CI runs them) and the colcon
  block (it needs a ROS 2 install).

A README command that fits none of these fails the test, so a new command must come with a way to
run it. The Python example of "Use it from Python without ROS" runs as written.
"""

import ast
import importlib
import os
import re
import runpy
import shlex
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text()
VENV_BIN = Path(sys.executable).parent
SKIPPED = {  # first word(s) of a command -> why the test does not run it
    "make run": "the main job, ~10 min; CI runs `make run` itself",
    "make test": "the test suite this test belongs to",
    "source": "colcon block: needs a ROS 2 Jazzy install (/opt/ros/jazzy)",
    "mkdir": "colcon block", "cd": "colcon block", "git clone": "colcon block", "ln": "colcon block",
    "rosdep": "colcon block", "pip install": "colcon block", "colcon": "colcon block",
    "ros2": "colcon block: no ros2 CLI here", "rviz2": "colcon block: no RViz here",
}


def readme_commands(text: str = README) -> list:
    """The commands of the ```bash blocks, comments and blank lines dropped."""
    out = []
    for block in re.findall(r"```bash\n(.*?)```", text, re.S):
        for line in block.replace("\\\n", " ").splitlines():
            words = shlex.split(line, comments=True)
            if words:
                out.append(words)
    return out


def python_example(text: str = README) -> str:
    section = text.split("## Use it from Python without ROS", 1)[1].split("\n## ", 1)[0]
    return re.search(r"```python\n(.*?)```", section, re.S).group(1)


def classify(words):
    joined = " ".join(words)
    for prefix, reason in SKIPPED.items():
        if joined == prefix or joined.startswith(prefix + " "):
            return "skip", reason
    exe = words[0]
    if exe == ".venv/bin/tether-sim":
        return "node", None
    if exe in (".venv/bin/tether-sim-offline", ".venv/bin/tether-sim-report"):
        return "pipeline", None
    if exe == ".venv/bin/python" and words[1:3] == ["-m", "tether_sim.ros.watch"]:
        return "watch", None
    if exe == ".venv/bin/python" or exe == ".venv/bin/tether-sim-study":  # studies: hours of CPU
        return "help", None
    if exe == ".venv/bin/tether-sim-poses":  # runs until stopped; test/ros/test_pose_source.py drives a node with it
        return "help", None
    return "unknown", None


def here(words):
    """The command with the repository's .venv/bin replaced by this interpreter's folder."""
    return [str(VENV_BIN / w[len(".venv/bin/"):]) if w.startswith(".venv/bin/") else w for w in words]


def test_every_readme_command_is_covered():
    kinds = [classify(w)[0] for w in readme_commands()]
    unknown = [" ".join(w) for w, k in zip(readme_commands(), kinds) if k == "unknown"]
    assert not unknown, f"README commands this test does not know how to run: {unknown}"
    assert {"node", "pipeline", "watch", "help", "skip"} <= set(kinds)


def entry_points() -> dict:
    """console script name -> (module, function), from setup.py."""
    tree = ast.parse((ROOT / "setup.py").read_text())
    for node in ast.walk(tree):
        if isinstance(node, ast.Dict):
            for key, value in zip(node.keys, node.values):
                if isinstance(key, ast.Constant) and key.value == "console_scripts":
                    pairs = (ast.literal_eval(e).split("=") for e in value.elts)
                    return {k.strip(): tuple(v.strip().split(":")) for k, v in pairs}
    raise AssertionError("no console_scripts in setup.py")


def run_in_process(words, monkeypatch, capsys) -> tuple:
    """(exit code, output) of a README command run in this interpreter: a console script calls its
    entry point, ``python -m mod`` / ``python script.py`` run as __main__ (what the interpreter
    would do, without the start-up of a new one: the programs' imports are shared)."""
    monkeypatch.chdir(ROOT)
    exe = words[0].rsplit("/", 1)[-1]
    if exe == "python":
        target, rest = (words[2], words[3:]) if words[1] == "-m" else (words[1], words[2:])
        monkeypatch.setattr(sys, "argv", [target] + rest)
        run = (lambda: runpy.run_module(target, run_name="__main__", alter_sys=True)) if words[1] == "-m" \
            else (lambda: runpy.run_path(str(ROOT / target), run_name="__main__"))
    else:
        module, func = entry_points()[exe]
        monkeypatch.setattr(sys, "argv", [exe] + words[1:])
        run = lambda: sys.exit(getattr(importlib.import_module(module), func)(words[1:]))  # noqa: E731
    try:
        run()
        code = 0
    except SystemExit as exc:
        code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
    out = capsys.readouterr()
    return code, out.out + out.err


def test_help_of_the_long_programs(monkeypatch, capsys):
    for words in (w for w in readme_commands() if classify(w)[0] == "help"):
        code, out = run_in_process(words + ["--help"], monkeypatch, capsys)
        assert code == 0 and "usage" in out.lower(), f"{' '.join(words)} --help:\n{out}"


def test_offline_run_and_report(tmp_path, monkeypatch, capsys):
    mcap = tmp_path / "L200.mcap"
    for words in (w for w in readme_commands() if classify(w)[0] == "pipeline"):
        words = [str(mcap) if w == "out/L200.mcap" else str(tmp_path / w[len("out/"):]) if w.startswith("out/")
                 and w.endswith(".mcap") else w for w in words]  # every README MCAP into tmp_path
        if "--duration" in words:
            words[words.index("--duration") + 1] = "0.2"
        code, out = run_in_process(words + (["--no-progress"] if "offline" in words[0] else []), monkeypatch, capsys)
        assert code == 0, f"{' '.join(words)}\n{out}"
    assert (tmp_path / "figures" / "report.md").is_file()


@pytest.mark.ros
def test_nodes_and_watch(tmp_path):
    pytest.importorskip("rclpy")
    pytest.importorskip("tether_sim_msgs")
    nodes = [w for w in readme_commands() if classify(w)[0] == "node"]
    watch = next(w for w in readme_commands() if classify(w)[0] == "watch")
    logs = [tmp_path / f"node{k}.log" for k in range(len(nodes))]
    procs = [subprocess.Popen(here(w), cwd=ROOT, stdout=open(log, "w"), stderr=subprocess.STDOUT,
                              env=dict(os.environ, PYTHONUNBUFFERED="1")) for w, log in zip(nodes, logs)]
    watched = next((w.split(":=", 1)[1] for w in watch if w.startswith("__ns:=")), "/")
    try:
        deadline, stopped = time.monotonic() + 120, set()
        while time.monotonic() < deadline and not all("solver started" in log.read_text() for log in logs):
            for k, (words, proc, log) in enumerate(zip(nodes, procs, logs)):
                if k in stopped:
                    continue
                assert proc.poll() is None, log.read_text()
                if "solver started" in log.read_text() and f"__ns:={watched}" not in words:
                    proc.send_signal(signal.SIGINT)  # started: done; leave the CPU to the watched one
                    stopped.add(k)
            time.sleep(0.3)
        i = watch.index("--ros-args")
        viewer = subprocess.Popen(here(watch[:i]) + ["--duration", "60"] + watch[i:], cwd=ROOT, text=True,
                                  stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
        seen = []
        for line in viewer.stdout:  # until the first line with the end tensions (or --duration)
            seen.append(line)
            if "ship end" in line:
                break
        viewer.send_signal(signal.SIGINT)
        seen.append(viewer.communicate(timeout=30)[0])
    finally:
        for p in procs:
            if p.poll() is None:
                p.send_signal(signal.SIGINT)
        codes = [p.wait(timeout=30) for p in procs]
    texts = [log.read_text() for log in logs]
    assert codes == [0] * len(procs), texts
    assert all("warmed up" in t and "solver started" in t for t in texts), texts
    out = "".join(seen)
    assert viewer.returncode == 0, out
    assert "watching /rov1/tether/*" in out and "ship end" in out, out


def test_python_example_runs(monkeypatch, capsys):
    monkeypatch.chdir(ROOT)
    exec(compile(python_example(), "README.md (Use it from Python without ROS)", "exec"), {})  # noqa: S102
    out = capsys.readouterr().out
    assert "static: ship" in out and "tension at 5 points" in out, out
