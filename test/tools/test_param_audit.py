"""Every key of the schema with values outside its documented range, non-finite and of the wrong
type (tools/audit_param_ranges.py --loader): each is refused by the loader with a ConfigError that
names the key, never accepted and never another exception."""

import math
import sys
from pathlib import Path

from tether_sim.io.schema import key_map

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
import audit_param_ranges  # noqa: E402


def test_bad_values_cover_range_type_and_non_finite():
    keys = key_map()
    labels = dict(audit_param_ranges.bad_values(keys["cable.EA"]))
    assert labels["below min"] < 0.0 and labels["above max"] > 1e12 and math.isnan(labels["nan"])
    assert {"inf", "-inf", "text", "list", "bool", "null"} <= set(labels)
    assert "not a choice" in dict(audit_param_ranges.bad_values(keys["solver"]))
    assert dict(audit_param_ranges.bad_values(keys["dg.n_elements"]))["fraction"] == 2.5


def test_every_bad_value_of_every_key_is_a_clear_error():
    lines = []
    faults = audit_param_ranges.audit_loader(list(key_map()), ROOT / "config" / "ropos_L200.yaml", out=lines.append)
    assert faults == [], "\n".join(lines)
