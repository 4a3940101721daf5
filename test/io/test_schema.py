"""The flat key list (tether_sim.io.schema) is complete, consistent, and documented in docs/parameters.md."""

import math
import runpy
from dataclasses import fields, is_dataclass
from pathlib import Path

import pytest

from tether_sim.config import SimConfig
from tether_sim.io.params import to_flat
from tether_sim.io.schema import all_keys, key_map, markdown_table

ROOT = Path(__file__).resolve().parents[2]
KINDS = {"float", "int", "bool", "str", "float_array", "str_array"}


def test_keys_match_the_dataclass_tree():
    assert [k.name for k in all_keys()] == list(to_flat(SimConfig()))
    assert len(key_map()) == len(all_keys())  # no duplicate names
    sections = {f.name for f in fields(SimConfig) if is_dataclass(getattr(SimConfig(), f.name))}
    assert {"cable", "environment", "ship_end", "vehicle_end", "dg", "hybrid", "snap", "node"} <= sections


@pytest.mark.parametrize("key", all_keys(), ids=lambda k: k.name)
def test_every_key_is_documented_and_its_default_valid(key):
    assert key.kind in KINDS
    assert key.doc.strip(), f"{key.name} has no description"
    assert "|" not in key.doc and "|" not in key.unit, "a '|' would break the markdown table"
    if key.kind in ("float", "int"):
        assert not (key.min is not None and key.max is not None and key.min > key.max)
        if key.kind == "float":
            assert math.isfinite(key.default)
        assert key.min is None or key.default >= key.min, f"{key.name} default below min"
        assert key.max is None or key.default <= key.max, f"{key.name} default above max"
    else:
        assert key.min is None and key.max is None, f"{key.name}: bounds on a {key.kind}"
    if key.choices:
        assert key.kind == "str" and key.default in key.choices


def test_key_defaults_are_the_config_defaults():
    """The documented (and ROS-declared) default of every key is what SimConfig() holds.

    Sections built with a default_factory (vehicle_end is a body end, ship_end a prescribed one)
    must report the factory's values, not the section class's own defaults.
    """
    defaults = to_flat(SimConfig())
    wrong = [f"{k.name}: schema {k.default!r} != SimConfig {defaults[k.name]!r}"
             for k in all_keys() if k.default != defaults[k.name]]
    assert not wrong, "\n".join(wrong)


def test_markdown_table_has_one_row_per_key():
    lines = markdown_table().splitlines()
    assert len(lines) == 2 + len(all_keys())
    for key, row in zip(all_keys(), lines[2:]):
        assert row.startswith(f"| `{key.name}` | {key.kind} |")
        assert row.count("|") == 8


def test_parameter_reference_is_up_to_date():
    """docs/parameters.md is generated; regenerate with `make docs` after changing a param()."""
    generator = runpy.run_path(str(ROOT / "tools" / "gen_param_docs.py"))
    current = (ROOT / "docs" / "parameters.md").read_text()
    assert current == generator["render"](), "docs/parameters.md is out of date: run `make docs`"
