"""Study files -> cases (no simulation): blocks, samples, seeds, expressions, errors, shipped files."""

import math
from pathlib import Path

import numpy as np
import pytest

from tether_sim.io.params import load_config
from tether_sim.studies.expressions import ExpressionError, evaluate, phases
from tether_sim.studies.spec import StudyError, load_study

ROOT = Path(__file__).resolve().parents[2]
STUDIES = ROOT / "config" / "studies"


def write(tmp_path, text, name="s.yaml"):
    path = tmp_path / name
    path.write_text(text)
    return path


BASE = f"base: {ROOT / 'config' / 'ropos_L200.yaml'}\n"


def test_pe2020_sec62_has_the_papers_48_cases():
    study = load_study(STUDIES / "pe2020_sec62.yaml")
    cases = study.cases()
    assert len(cases) == 48
    combos = {(c.variables["L"], c.variables["alpha"], c.variables["f"]) for c in cases}
    # [PE2020 Eq. 47-48 and Sec. 6.2]: L x alpha x f, a = 2 m circular orbit
    assert combos == {(L, a, f) for L in (200, 500, 975, 1730) for a in (0, 1, 10, 100) for f in (0.1, 0.2, 0.25)}
    for c in cases:
        L, alpha, f = c.variables["L"], c.variables["alpha"], c.variables["f"]
        assert c.base.name == f"ropos_L{L}_paper.yaml" and c.base.is_file()
        o = c.overrides
        assert o["cable.EI"] == pytest.approx(alpha * 2.62e3, rel=1e-12)
        assert (o["motion.kind"], o["motion.amplitude"], o["motion.frequency"]) == ("circle", 2.0, f)
        assert o["duration"] == pytest.approx(12.0 / f) and o["motion.ramp_time"] == pytest.approx(1.0 / f)
    for c in cases:  # the public loader accepts every case; the paper's mesh N = 20, P = 4 [PE2020 App. A]
        cfg = load_config(c.base, c.overrides)
        assert (cfg.cable.length, cfg.dg.n_elements, cfg.dg.order) == (c.variables["L"], 20, 4)
    assert (cfg.cable.length, cfg.cable.EI, cfg.motion.frequency) == (1730.0, 262e3, 0.25)


def test_pe2020_sec62_N40_is_the_long_lengths_on_a_finer_mesh():
    """The 24 cases at L = 975 and 1730 m of pe2020_sec62.yaml, each resolved the same but on N = 40 elements."""
    main = {tuple(c.variables.values()): c for c in load_study(STUDIES / "pe2020_sec62.yaml").cases()}
    cases = load_study(STUDIES / "pe2020_sec62_N40.yaml").cases()
    assert len(cases) == 24
    assert {c.variables["L"] for c in cases} == {975, 1730}
    for c in cases:
        twin = main[tuple(c.variables.values())]
        assert c.base == twin.base
        assert {k: v for k, v in c.overrides.items() if k != "dg.n_elements"} == twin.overrides
        cfg = load_config(c.base, c.overrides)
        assert (cfg.dg.n_elements, cfg.dg.order) == (40, 4)


@pytest.mark.parametrize("name, n", [("heave_sweep.yaml", 30), ("heave_irregular_seeds.yaml", 20)])
def test_shipped_studies_load(name, n):
    cases = load_study(STUDIES / name).cases()
    assert len(cases) == n
    for c in cases:
        load_config(c.base, c.overrides)


def test_blocks_cross_and_seeds(tmp_path):
    study = load_study(write(tmp_path, BASE + """
vary:
  - grid: {motion.amplitude: [1, 2], f: [0.1, 0.2, 0.3]}
  - zip: {dg.n_elements: [3, 4], dg.order: [2, 3]}
seeds: [7, 8]
set:
  motion.frequency: "= f"
  motion.sine_phases: "= phases(seed, 2)"
"""))
    cases = study.cases()
    assert len(cases) == 2 * 3 * 2 * 2
    assert [c.index for c in cases] == list(range(24))
    # first block varies slowest, seeds fastest
    assert [c.variables["seed"] for c in cases[:4]] == [7, 8, 7, 8]
    assert {(c.overrides["dg.n_elements"], c.overrides["dg.order"]) for c in cases} == {(3, 2), (4, 3)}
    assert cases[0].overrides["motion.sine_phases"] == phases(7, 2) != phases(8, 2)


@pytest.mark.parametrize("kind", ["lhs", "random"])
def test_samples_are_seeded_and_in_range(tmp_path, kind):
    text = BASE + f"""
vary:
  {kind}: {{n: 10, seed: 3, ranges: {{motion.amplitude: [0.5, 3.0], motion.frequency: [0.05, 0.5, log]}}}}
"""
    a = [c.overrides for c in load_study(write(tmp_path, text, "a.yaml")).cases()]
    b = [c.overrides for c in load_study(write(tmp_path, text, "b.yaml")).cases()]
    assert a == b and len(a) == 10  # same seed, same samples
    amp = np.array([o["motion.amplitude"] for o in a])
    freq = np.array([o["motion.frequency"] for o in a])
    assert amp.min() >= 0.5 and amp.max() <= 3.0 and freq.min() >= 0.05 and freq.max() <= 0.5
    if kind == "lhs":  # Latin hypercube: exactly one sample in each of the 10 strata of each variable
        assert sorted(np.floor((amp - 0.5) / 2.5 * 10).astype(int)) == list(range(10))
        u = np.log(freq / 0.05) / np.log(10.0)
        assert sorted(np.floor(u * 10).astype(int)) == list(range(10))


def test_expressions():
    assert evaluate("12 / f", {"f": 0.25}) == 48.0
    assert evaluate("[a, 2 * a] if a > 1 else [a]", {"a": 2}) == [2, 4]
    assert evaluate("sqrt(2) * pi", {}) == pytest.approx(math.sqrt(2) * math.pi)
    for bad in ("__import__('os')", "f.real", "[1][0]", "open('x')", "lambda: 1"):
        with pytest.raises(ExpressionError):
            evaluate(bad, {"f": 1.0})


@pytest.mark.parametrize("text, message", [
    ("vary: {grid: {cable.lenght: [1, 2]}}", "neither a parameter"),
    ("vary: {grid: {x: [1, 2]}}", "neither parameters nor used"),
    ("vary: {grid: {f: [1]}}\nset: {motion.frequency: '= g2 * f'}", "unknown name 'g2'"),
    ("vary: {zip: {motion.amplitude: [1, 2], motion.frequency: [1]}}", "equal lengths"),
    ("vary: {lhs: {n: 0, ranges: {motion.amplitude: [0, 1]}}}", "positive integer"),
    ("vary: {grid: {dg.n_elements: [2.5]}}", "expected an integer"),
    ("set: {cable.nope: 1}", "unknown parameter"),
    ("colour: red", "unknown entries"),
    ("vary: {grid: {f: [1]}}\nset: {motion.frequency: '= f'}\nunits: {motion.amplitude: m}", "has its own unit"),
    ("vary: {grid: {f: [1]}}\nset: {motion.frequency: '= f'}\nunits: {g: m}", "not a study variable"),
    ("vary: {grid: {f: [1]}}\nset: {motion.frequency: '= f'}\nunits: {f: 3}", "expected a unit as text"),
    ("vary: {grid: {f: [1]}}\nset: {motion.frequency: '= f'}\nunits: {f: s}", "gives it the unit of motion.frequency"),
])
def test_bad_study_files_name_the_problem(tmp_path, text, message):
    path = write(tmp_path, BASE + text)
    with pytest.raises(StudyError, match=message) as info:
        load_study(path)
    assert str(path) in str(info.value)


def test_the_study_variables_carry_their_units(tmp_path):
    """A study's own variable has the unit its file declares, or else that of the parameter it is set
    to as it is; an expression gives none (its unit is not the parameter's)."""
    study = load_study(write(tmp_path, BASE + "vary: {grid: {f: [0.1, 0.2], a: [1, 2], k: [1, 2], n: [3]}}\n"
                             "set: {motion.frequency: '= f', motion.amplitude: '= a * k', duration: '= n / f'}\n"
                             "units: {k: '1'}"))
    assert study.column_units() == {"var.f": "Hz", "var.k": "1"}
    pe2020 = load_study(STUDIES / "pe2020_sec62.yaml")
    assert pe2020.column_units() == {"var.L": "m", "var.alpha": "1", "var.f": "Hz"}
    assert load_study(STUDIES / "heave_sweep.yaml").column_units() == {"var.f": "Hz"}
    assert load_study(STUDIES / "heave_irregular_seeds.yaml").column_units() == {"var.level": "1"}


def test_a_network_study_varies_network_keys_and_drives_the_ship():
    """config/studies/ropos_tms_cage.yaml: network keys take the kind and unit of the key they stand
    for; the motion keys stay the drive; a case's task is a network task keyed on its parameters."""
    from tether_sim.studies.case import code_version, make_task

    study = load_study(STUDIES / "ropos_tms_cage.yaml")
    cases = study.cases()
    assert len(cases) == 4
    assert cases[3].overrides["network.bodies.cage.mass"] == 7500.0 and cases[3].overrides["motion.amplitude"] == 2.0
    assert study.base.endswith("ropos_tms.yaml")
    tasks = [make_task(c, study, code_version(), "/tmp/unused") for c in cases]
    assert all(t["network"] for t in tasks) and len({t["key"] for t in tasks}) == 4
    from tether_sim.studies.spec import study_keys

    keys = study_keys()
    assert keys["network.bodies.cage.mass"].unit == "kg" and keys["network.lines.excursion.cable.length"].unit == "m"
    assert "network.lines.excursion.cable.lenght" not in keys and "network.bogus" not in keys
