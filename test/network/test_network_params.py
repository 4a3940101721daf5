"""Network parameter files (tether_sim/network/params.py): the TMS file loads; bad files name the key."""

from pathlib import Path

import pytest

from tether_sim.errors import ConfigError
from tether_sim.io.params import read_param_file
from tether_sim.network.params import file_is_network, load_network, load_network_files, unflatten

ROOT = Path(__file__).resolve().parents[2]
TMS = ROOT / "config" / "ropos_tms.yaml"


def test_tms_file_loads_as_a_two_line_network_with_two_winches():
    assert file_is_network(TMS) and not file_is_network(ROOT / "config" / "ropos_L200.yaml")
    spec, cfg = load_network_files([TMS])
    assert set(spec.lines) == {"tether", "excursion"} and set(spec.bodies) == {"cage"}
    tether, exc = spec.lines["tether"], spec.lines["excursion"]
    assert [e.target for e in tether.ends] == ["ship", "cage"] and [e.target for e in exc.ends] == ["cage", "vehicle"]
    assert tether.config.cable.length == 1730.0 and tether.config.cable.EA == 45.5e6  # PE2020 Table 3
    assert exc.config.cable.length == 30.0
    assert tether.config.winch.enabled and exc.config.winch.enabled and exc.config.winch.end == "ship"  # TMS drum
    assert spec.bodies["cage"].props.mass == 4995.0
    assert cfg.node.output_rate == 50.0


def test_unflatten_inverts_the_flat_keys():
    assert unflatten({"a.b.c": 1, "a.b.d": 2, "e": 3}) == {"a": {"b": {"c": 1, "d": 2}}, "e": 3}


@pytest.mark.parametrize("edit, key", [
    (("network.lines.excursion.to", "vehicel"), "network.lines.excursion.to"),
    (("network.lines.excursion.cable.lenght", 30.0), "cable.lenght"),
    (("cable.length", 30.0), "cable.length"),
    (("network.bodies.cage.mass", -1.0), "body.mass"),
    (("network.lines.tether.ship_end.kind", "fixed"), "network.lines.tether.ship_end.kind"),
    (("node.output_rate", "fast"), "node.output_rate"),
])
def test_bad_network_files_name_the_key(edit, key):
    flat = read_param_file(TMS)
    flat[edit[0]] = edit[1]
    with pytest.raises(ConfigError) as err:
        load_network(flat, where=str(TMS))
    assert key in str(err.value) and str(TMS) in str(err.value)


def test_a_dangling_line_end_names_the_key():
    flat = {k: v for k, v in read_param_file(TMS).items() if k != "network.lines.excursion.to"}
    with pytest.raises(ConfigError, match=r"network\.lines\.excursion\.to: missing"):
        load_network(flat)
