"""Hostile study files: the evaluator bounds its work and memory, every bad file is one line, exit 2.

The bad files run through ``tether-sim-study --list`` in one child process with a timeout, so an
evaluator that hangs (``10**10**10``) fails the test instead of hanging the suite.
"""

import json
import random
import subprocess
import sys
from pathlib import Path

import pytest

from tether_sim.studies.expressions import MAX_CHARS, MAX_INT_BITS, MAX_ITEMS, ExpressionError, evaluate
from tether_sim.studies.runner import plan
from tether_sim.studies.spec import MAX_CASES, StudyError, load_study

ROOT = Path(__file__).resolve().parents[2]
BASE = f"base: {ROOT / 'config' / 'ropos_L200.yaml'}\n"
VARY = "vary: {grid: {f: [0.1, 0.2]}}\n"

# (study file text after the base line, words the one-line error must hold: key and limit)
HOSTILE = {
    "power_tower": (VARY + "set: {duration: '= 10**10**10 + f'}", ["set.duration", f"limit of {MAX_INT_BITS}"]),
    "string_repeat": (VARY + "set: {node.world_frame: \"= 'a'*10**10 if f else 'b'\"}", ["set.node.world_frame", f"limit of {MAX_ITEMS}"]),
    "list_repeat": (VARY + "set: {motion.sine_phases: '= [f]*10**10'}", ["set.motion.sine_phases", f"limit of {MAX_ITEMS}"]),
    "linspace": (VARY + "set: {motion.sine_phases: '= linspace(0, f, 1e9)'}", ["set.motion.sine_phases", "linspace", f"limit of {MAX_ITEMS}"]),
    "phases": (VARY + "set: {motion.sine_phases: '= phases(f, 1e9)'}", ["set.motion.sine_phases", "phases", f"limit of {MAX_ITEMS}"]),
    "long_sum": (VARY + "set: {duration: '= f" + "+1" * 30000 + "'}", ["set.duration", f"limit of {MAX_CHARS}"]),
    "format_width": (VARY + "set: {node.world_frame: \"= '%0999999999d' % f\"}", ["set.node.world_frame", "formatting"]),
    "million_cases": ("vary: {grid: {motion.amplitude: " + str([0.1 * (i + 1) for i in range(1000)]) + ", f: "
                      + str([0.01 * (i + 1) for i in range(1000)]) + "}}\nset: {motion.frequency: '= f'}",
                      ["vary.grid", "1000000 cases", f"limit of {MAX_CASES}"]),
    "many_seeds": (VARY + "set: {motion.frequency: '= f'}\nseeds: 1000000", ["seeds", f"limit of {MAX_CASES}"]),
}


def _run_all(files, timeout=120):
    """``tether-sim-study FILE --list`` for each file, in one child process: [(rc, stderr), ...]."""
    script = (
        "import contextlib, io, json, sys\n"
        "from tether_sim.studies.cli import main\n"
        "out = []\n"
        "for f in sys.argv[1:]:\n"
        "    err = io.StringIO()\n"
        "    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):\n"
        "        try:\n"
        "            rc = main([f, '--list', '--out', f + '.out'])\n"
        "        except BaseException as exc:\n"
        "            rc, err = 'raised', io.StringIO(repr(exc)[:300])\n"
        "    out.append([rc, err.getvalue()])\n"
        "print(json.dumps(out))\n")
    proc = subprocess.run([sys.executable, "-c", script, *map(str, files)], capture_output=True, text=True,
                          timeout=timeout, cwd=ROOT)
    assert proc.returncode == 0, proc.stderr[-2000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


def test_hostile_study_files_end_in_one_line_exit_2(tmp_path):
    files = []
    for name, (text, _) in HOSTILE.items():
        files.append(tmp_path / f"{name}.yaml")
        files[-1].write_text(BASE + text)
    rng = random.Random(7)
    noise = tmp_path / "random_bytes.yaml"
    noise.write_bytes(bytes(rng.randrange(256) for _ in range(4096)))
    files.append(noise)
    results = _run_all(files)
    for path, (rc, err), words in zip(files, results, [w for _, w in HOSTILE.values()] + [["UTF-8"]]):
        lines = err.strip().splitlines()
        assert rc == 2, (path.name, rc, err[:500])
        assert len(lines) == 1 and lines[0].startswith(f"tether-sim-study: {path}:"), (path.name, err[:500])
        for word in words:
            assert word in lines[0], (path.name, word, lines[0])
        assert len(lines[0]) < 600


def test_evaluator_limits_hold_and_leave_ordinary_expressions_alone():
    assert evaluate("2 ** 100", {}) == 2 ** 100
    assert evaluate("[0] * 3 + linspace(0, 1, 3)", {}) == [0, 0, 0, 0.0, 0.5, 1.0]
    assert len(evaluate("phases(s, n)", {"s": 1, "n": MAX_ITEMS})) == MAX_ITEMS  # the limit itself is allowed
    for bad in ("(-3) ** 10000", "2 ** 4096 * 2", "'ab' * 60000", "-" * 50 + "1", "+".join(["1"] * 600),
                "int('9' * 5000)", "float('nan') ** 1e6 % 0"):
        with pytest.raises(ExpressionError):
            evaluate(bad, {})


@pytest.mark.parametrize("seed", range(3))
def test_random_and_mangled_study_files_are_study_errors(tmp_path, seed):
    """Random bytes and single-byte corruptions of a shipped study: a StudyError of one line, nothing else."""
    rng = random.Random(seed)
    src = (ROOT / "config" / "studies" / "heave_sweep.yaml").read_bytes()
    path = tmp_path / "s.yaml"
    for i in range(60):
        if i % 2:
            data = bytes(rng.randrange(256) for _ in range(rng.randrange(1, 300)))
        else:
            b = bytearray(src)
            for _ in range(rng.randrange(1, 6)):
                b[rng.randrange(len(b))] = rng.randrange(256)
            data = bytes(b)
        path.write_bytes(data)
        try:
            load_study(path)
        except StudyError as exc:
            assert "\n" not in str(exc) and str(path) in str(exc)


def test_resolving_reads_each_base_file_once(tmp_path, monkeypatch):
    """Planning a study resolves every case; the base file is read and checked once, not once a case."""
    path = tmp_path / "s.yaml"
    path.write_text(BASE + "vary: {grid: {motion.amplitude: [0.5, 1.0, 1.5, 2.0], f: [0.1, 0.2, 0.3, 0.4, 0.5]}}\n"
                    "seeds: 10\nset: {motion.frequency: '= f', motion.sine_phases: '= phases(seed, 3)'}\n")
    study = load_study(path)
    from tether_sim.io import params

    reads = []
    original = params.read_param_file
    monkeypatch.setattr(params, "read_param_file", lambda p: reads.append(p) or original(p))
    tasks, invalid, skipped, duplicates = plan(study, tmp_path / "out")
    assert len(tasks) == 200 and not invalid and not duplicates
    assert len(reads) == 1
    # the same keys as resolving each case on its own
    from tether_sim.studies.case import code_version, make_task

    for case in study.cases()[::37]:
        assert make_task(case, study, code_version(), tmp_path / "out")["key"] == tasks[case.index]["key"]



LARGE = (BASE + "vary: {grid: {motion.amplitude: " + str([round(0.01 * (i + 1), 2) for i in range(1000)])
         + ", f: [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0]}}\nseeds: 10\n"
         "set: {motion.frequency: '= f', motion.sine_phases: '= phases(seed, 3)'}\n")


def test_a_study_at_the_case_limit_starts_at_once_and_resolves_a_case_when_it_is_needed(tmp_path, monkeypatch):
    """10^5 cases (the limit): resolving them all before anything ran or was listed took 1-8 minutes
    (0.4-5 ms a case with the machine's load); now the file is checked on its first cases, and the
    cases are resolved one at a time as the workers (or --list) take them."""
    from tether_sim.studies import case as case_module
    from tether_sim.studies import runner

    path = tmp_path / "large.yaml"
    path.write_text(LARGE)
    resolved = []
    original = case_module.make_task
    monkeypatch.setattr(runner, "make_task", lambda c, *a, **k: resolved.append(c.index) or original(c, *a, **k))
    study = load_study(path)
    assert study.n_cases() == MAX_CASES
    lazy = runner.plan_lazy(study, tmp_path / "out")
    first = [next(lazy) for _ in range(3)]
    assert [(kind, index) for kind, index, *_ in first] == [("task", 0), ("task", 1), ("task", 2)] and resolved == [0, 1, 2]
    assert first[2][3] == {"motion.amplitude": 0.01, "f": 0.1, "seed": 2}
    # the same task as resolving that case alone
    from tether_sim.studies.case import code_version

    assert first[1][2]["key"] == original(study.case(1, first[1][3]), study, code_version(), tmp_path / "out")["key"]
    # a case further on whose expression fails is a failed row of its own, not the end of the study
    bad = tmp_path / "bad.yaml"
    bad.write_text(BASE + "vary: {grid: {f: [0.1, 0.2, 0.0]}}\nset: {motion.frequency: '= f', duration: '= 1 / f'}\n")
    with pytest.raises(StudyError, match="set.duration"):  # (within the first cases: refused up front)
        load_study(bad)
    monkeypatch.setattr("tether_sim.studies.spec.EAGER_CASES", 1)
    kinds = [(kind, index) for kind, index, *_ in runner.plan_lazy(load_study(bad), tmp_path / "out2")]
    assert kinds == [("task", 0), ("task", 1), ("invalid", 2)]


def test_listing_a_study_at_the_case_limit_prints_its_first_cases_at_once(tmp_path):
    path = tmp_path / "large.yaml"
    path.write_text(LARGE)
    proc = subprocess.Popen([sys.executable, "-m", "tether_sim.studies.cli", str(path), "--list", "--out",
                             str(tmp_path / "out")], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT)
    try:
        lines = [proc.stdout.readline() for _ in range(5)]  # (all 10^5 would take minutes)
    finally:
        proc.kill()
        proc.communicate(timeout=60)
    assert [line.split()[:3] for line in lines] == [[str(i), "to", "run"] for i in range(5)], lines
    assert "motion.amplitude=0.01, f=0.1, seed=4" in lines[4]
