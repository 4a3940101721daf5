"""Parameter files -> SimConfig (tether_sim.io.params): layouts, error messages, round trips."""

from dataclasses import replace
from pathlib import Path

import math
import pytest
import yaml

from tether_sim.config import SimConfig
from tether_sim.errors import ConfigError
from tether_sim.io.params import flatten, from_flat, load_config, read_param_file, to_flat


def write(tmp_path, text, name="params.yaml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def unflatten(flat: dict) -> dict:
    tree = {}
    for name, value in flat.items():
        *sections, key = name.split(".")
        node = tree
        for section in sections:
            node = node.setdefault(section, {})
        node[key] = list(value) if isinstance(value, tuple) else value
    return tree


def test_nested_yaml_sets_the_fields(tmp_path):
    path = write(tmp_path, """
tether_sim:
  ros__parameters:
    solver: hybrid
    cable:
      length: 975.0
      EA: 1.2e+8
    node:
      output_points: 101
      ship_attachment: [1.0, 0.0, -2.5]
""")
    config = load_config(path)
    assert config.solver == "hybrid"
    assert config.cable.length == 975.0 and config.cable.EA == 1.2e8
    assert config.node.output_points == 101
    assert config.node.ship_attachment == (1.0, 0.0, -2.5)
    assert config.cable.gamma0 == SimConfig().cable.gamma0  # untouched keys keep their defaults


def test_flat_dotted_keys_and_wildcard_section(tmp_path):
    path = write(tmp_path, """
/**:
  ros__parameters:
    use_sim_time: true
    cable.length: 500.0
other_node:
  ros__parameters:
    not_ours: 1
""")
    config = load_config(path)
    assert config.cable.length == 500.0


def test_node_section_overrides_wildcard_in_file_order(tmp_path):
    path = write(tmp_path, """
/**:
  ros__parameters:
    cable: {length: 500.0, EA: 1.0e+6}
/tether_sim:
  ros__parameters:
    cable: {length: 750.0}
""")
    config = load_config(path)
    assert (config.cable.length, config.cable.EA) == (750.0, 1.0e6)


def test_exponent_without_sign_is_a_float(tmp_path):
    """45.5e6 is a YAML 1.2 float (as for rcl's parser); PyYAML's 1.1 rules alone would give a string."""
    config = load_config(write(tmp_path, "tether_sim:\n  ros__parameters:\n    cable: {EA: 45.5e6, gamma0: 3e0}\n"))
    assert config.cable.EA == 45.5e6 and config.cable.gamma0 == 3.0


def test_integers_are_accepted_for_floats(tmp_path):
    config = load_config(write(tmp_path, "tether_sim:\n  ros__parameters:\n    cable: {length: 300}\n"))
    assert config.cable.length == 300.0 and isinstance(config.cable.length, float)


def test_misspelt_key_names_key_file_and_suggestion(tmp_path):
    path = write(tmp_path, "tether_sim:\n  ros__parameters:\n    cable:\n      lenght: 200.0\n", "ropos.yaml")
    with pytest.raises(ConfigError) as err:
        load_config(path)
    text = str(err.value)
    assert "cable.lenght" in text and str(path) in text and "cable.length" in text


@pytest.mark.parametrize("body, words", [
    ("cable: {length: -5.0}", ("cable.length", "below the minimum", "m")),
    ("snap: {slack_fraction: 1.5}", ("snap.slack_fraction", "above the maximum")),
    ("cable: {EA: stiff}", ("cable.EA", "expected a number")),
    ("cable: {EA: true}", ("cable.EA", "expected a number")),
    ("cable: {EA: .nan}", ("cable.EA", "finite")),
    ("node: {output_points: 4.5}", ("node.output_points", "expected an integer")),
    ("solver: fem", ("solver", "not one of", "dg", "hybrid")),
    ("node: {ship_attachment: [1.0, 2.0]}", ("node.ship_attachment", "expected 3 values")),
    ("node: {ship_attachment: 1.0}", ("node.ship_attachment", "expected a list")),
    ("node: {world_frame: 3}", ("node.world_frame", "expected a string")),
])
def test_bad_values_are_named(tmp_path, body, words):
    path = write(tmp_path, f"tether_sim:\n  ros__parameters:\n    {body}\n")
    with pytest.raises(ConfigError) as err:
        load_config(path)
    for word in words + (str(path),):
        assert word in str(err.value), f"{word!r} missing from {err.value}"


@pytest.mark.parametrize("text, words", [
    ("tether_sim: [1, 2]\n", ("ros__parameters",)),
    ("some_other_node:\n  ros__parameters: {a: 1}\n", ("no 'tether_sim'",)),
    ("tether_sim:\n  ros__parameters: [1, 2]\n", ("must be a mapping",)),
    ("tether_sim: {ros__parameters: {cable: {length: [}}\n", ("malformed YAML",)),
    ("- just\n- a list\n", ("mapping at the top level",)),
])
def test_malformed_files_are_errors(tmp_path, text, words):
    path = write(tmp_path, text)
    with pytest.raises(ConfigError) as err:
        load_config(path)
    for word in words + (str(path),):
        assert word in str(err.value)


def test_missing_file_is_a_config_error(tmp_path):
    with pytest.raises(ConfigError, match="cannot read"):
        read_param_file(tmp_path / "absent.yaml")


def test_overrides_apply_over_the_file(tmp_path):
    path = write(tmp_path, "tether_sim:\n  ros__parameters:\n    cable: {length: 300.0}\n")
    config = load_config(path, overrides={"cable.length": 310.0, "dg.order": SimConfig().dg.order})
    assert config.cable.length == 310.0


def test_flatten_nested_mapping():
    assert flatten({"a": {"b": 1, "c": {"d": 2}}, "e": 3}) == {"a.b": 1, "a.c.d": 2, "e": 3}


def test_round_trip_flat_and_config():
    default = SimConfig()
    assert from_flat(to_flat(default)) == default
    changed = replace(default, solver="hybrid", cable=replace(default.cable, length=1730.0, EA=2.0e8))
    flat = to_flat(changed)
    assert flat["cable.length"] == 1730.0 and flat["solver"] == "hybrid"
    assert from_flat(flat) == changed
    assert set(flat) == set(to_flat(default))


def test_round_trip_through_a_written_file(tmp_path):
    default = SimConfig()
    changed = replace(default, cable=replace(default.cable, length=1730.0, EA=2.0e8),
                      node=replace(default.node, vehicle_attachment=(0.1, 0.0, 0.7)))
    document = {"tether_sim": {"ros__parameters": unflatten(to_flat(changed))}}
    path = write(tmp_path, yaml.safe_dump(document))
    assert load_config(path) == changed


def test_frame_names_prefix_and_attachment_frames():
    """node.frame_prefix moves every frame but the world's; attachment frames are named apart from
    the body frames; two parameters naming one frame are an error naming both keys."""
    node = from_flat({"node.frame_prefix": "rov1/"}).node
    assert (node.body_frame("ship"), node.body_frame("vehicle")) == ("rov1/ship/base_link", "rov1/rov/base_link")
    assert (node.attachment_frame("ship"), node.attachment_frame("vehicle")) == \
        ("rov1/ship/tether_sheave", "rov1/rov/tether_attach")
    assert node.tether_frame(3) == "rov1/tether/3" and node.world_frame == "map"
    node = from_flat({"node.vehicle_frame": "cage", "node.vehicle_attachment_frame": "cage/bail",
                      "node.ship_attachment_frame": "a_frame/sheave"}).node
    assert (node.attachment_frame("vehicle"), node.attachment_frame("ship")) == ("cage/bail", "a_frame/sheave")
    assert from_flat({"node.ship_frame": "boat"}).node.attachment_frame("ship") == "boat_tether_sheave"
    with pytest.raises(ConfigError, match="node.vehicle_attachment_frame and node.vehicle_frame"):
        from_flat({"node.vehicle_attachment_frame": "rov/base_link"})
    with pytest.raises(ConfigError, match="node.vehicle_frame and node.ship_frame"):
        from_flat({"node.vehicle_frame": "ship/base_link"})
    with pytest.raises(ConfigError, match="node.ship_frame: frame name"):
        from_flat({"node.ship_frame": "ship base"})


ROPOS = Path(__file__).resolve().parents[2] / "config" / "ropos_L200.yaml"
MANUAL = {"dg.resolution": "manual", "dg.n_elements": 3, "dg.order": 2}


@pytest.mark.parametrize("overrides, words", [
    ({"snap.retension_fraction": 0.05}, ["snap.retension_fraction = 0.05", "snap.slack_fraction = 0.1"]),
    ({"snap.retension_fraction": 0.1}, ["must be above"]),  # equal: no hysteresis either
    ({"cable.EA": 0.0, "dg.resolution": "manual"}, ["cable.EA = 0", "solver: hybrid"]),
    # (these two passed the loader and failed when the solver was built)
    ({"dg.resolution": "manual", "dg.n_elements": 3, "dg.element_lengths": [1.0, 2.0]},
     ["dg.element_lengths has 2 weights", "dg.n_elements = 3"]),
    ({"cable.material": "table", "cable.table_strain": [0.0, 0.01], "cable.table_tension": [0.0]},
     ["cable.table_strain / cable.table_tension"]),
    # the range end cable.density 0.001 kg/m^3 (A = 3010 m^2 on a 3 cm cable: the hybrid solver's Newton failed
    # at t = 0) and the density in g/cm^3 (every key in range, the buoyancy 470 x too large)
    ({"cable.density": 0.001}, ["cable.gamma0 / cable.density = 3.01 / 0.001", "2 x cable.diameter^2 = 0.0018 m^2"]),
    ({"cable.density": 7.153}, ["cable.gamma0 / cable.density = 3.01 / 7.153 = 0.421 m^2"]),
    ({**MANUAL, "dg.fixed_time_step": 10.0}, ["dg.fixed_time_step = 10 s exceeds the stability limit 0.00273 s"]),
])
def test_related_keys_are_cross_checked_at_load(overrides, words):
    """Each value inside its documented range, the pair not: refused at load, naming both keys and the file
    (before: 6 'snaps' at 1.01-1.03 x static in a run that never went slack; numpy divisions by EA = 0)."""
    with pytest.raises(ConfigError) as err:
        load_config(ROPOS, overrides)
    assert str(ROPOS) in str(err.value)
    for w in words:
        assert w in str(err.value)


def test_cross_checks_leave_valid_combinations_alone():
    # an absolute slack threshold replaces slack_fraction: the fractions are then not compared
    cfg = load_config(ROPOS, {"snap.retension_fraction": 0.05, "snap.slack_threshold": 500.0})
    assert cfg.snap.retension_fraction == 0.05
    # EA = 0 is the hybrid solver's inextensible rod (the Goyal-Perkins file)
    gp = load_config(ROPOS.parent / "goyal_perkins.yaml")
    assert gp.solver == "hybrid" and gp.cable.EA == 0.0


@pytest.mark.parametrize("overrides, words", [
    # the mesh: 2000 elements of 0.1 m with the ROPOS axial damping, a 1.3e-8 s substep (before: accepted, a
    # 0.3 s run still going after 15 min)
    ({**MANUAL, "dg.n_elements": 2000}, ["dg.n_elements = 2000", "cable.damping = 45500", "1.28e-08 s",
                                         "axial material damping", "dg.damping: implicit"]),
    # material damping and bending damping at their range ends (h^-2, h^-4 terms of the substep rule)
    ({**MANUAL, "cable.damping": 1e12}, ["cable.damping = 1e+12", "axial material damping"]),
    ({**MANUAL, "dg.n_elements": 20, "cable.bending_damping": 1e12}, ["cable.bending_damping = 1e+12", "bending damping"]),
    # the axial wave speed sqrt(EA / gamma0) = 3e10 m/s (both in range)
    ({**MANUAL, "cable.EA": 1e12, "cable.gamma0": 1e-9, "cable.damping": 0.0}, ["cable.EA = 1e+12", "cable.gamma0 = 1e-09",
                                                                                "axial waves"]),
    # the shortest cable: 1 mm in three elements
    ({**MANUAL, "cable.length": 0.001}, ["elements down to 0.000333 m"]),
    ({**MANUAL, "dg.fixed_time_step": 1e-12}, ["dg.fixed_time_step = 1e-12 s"]),
    ({"solver": "hybrid", "hybrid.n_segments": 100000, "hybrid.time_step": 1e-7}, ["hybrid.n_segments = 100000",
                                                                                    "hybrid.time_step = 1e-07 s"]),
])
def test_a_run_that_could_never_finish_is_refused_at_load_naming_its_keys_and_the_limit(overrides, words):
    """Every key inside its documented range, the run not doable: one simulated second estimated above
    work_limit CPU seconds (tether_sim/solvers/work.py) is a ConfigError naming the keys that set the
    substep and the limit; work_limit 0 lifts it (the configuration then loads)."""
    with pytest.raises(ConfigError) as err:
        load_config(ROPOS, overrides)
    text = str(err.value)
    assert str(ROPOS) in text and "work_limit = 1000 s" in text, text
    for w in words:
        assert w in text, (w, text)
    assert load_config(ROPOS, {**overrides, "work_limit": 0.0}).work_limit == 0.0


def test_the_work_estimate_uses_the_solvers_own_substep_and_passes_the_shipped_files():
    from tether_sim.solvers.factory import build_solver
    from tether_sim.solvers.work import estimate

    for overrides in ({}, {**MANUAL, "cable.EI": 2620.0, "cable.bending_damping": 10.0},
                      {**MANUAL, "dg.element_lengths": [1.0, 3.0, 1.0], "environment.seabed": True,
                       "environment.seabed_z": -190.0}):
        config = load_config(ROPOS, overrides)
        assert estimate(config).substep == pytest.approx(build_solver(config).stable_time_step(), rel=1e-12)
    from tether_sim.network.params import file_is_network

    checked = 0
    for path in sorted(ROPOS.parent.glob("*.yaml")):
        if "tether_sim:" in path.read_text() and not file_is_network(path):
            # far below the limit (the dearest: Koh's swinging cable, implicit bending damping, ~30 CPU s per
            # simulated s; measured 27 with bench_work_estimate.py, 2026-11-27)
            assert estimate(load_config(path)).cpu < 100.0, path
            checked += 1
    assert checked >= 15


def test_the_work_estimate_prices_an_implicit_damping_solve_by_its_kind():
    """An implicit damping substep costs more than an explicit one: the axial solve ~2x, the bending-damping
    (general) block solve ~75x (bench_work_estimate.py, 2026-11-27): Koh's swinging cable was estimated at
    0.39 CPU s per simulated s and took 27."""
    from tether_sim.solvers import work

    koh = load_config(Path(__file__).resolve().parents[2] / "config" / "koh_swinging_cable.yaml")
    assert koh.dg.damping == "implicit" and koh.cable.bending_damping > 0.0
    w = work.estimate(koh)
    assert w.cpu == pytest.approx(w.count * work.DG_IMPLICIT_GENERAL_CPU) and w.cpu > 10.0
    axial = load_config(PAPER_200, {"dg.damping": "implicit"})
    assert axial.cable.bending_damping == 0.0 and axial.cable.damping > 0.0
    assert work.estimate(axial).cpu == pytest.approx(work.estimate(axial).count * work.DG_IMPLICIT_AXIAL_CPU)
    explicit = load_config(PAPER_200)
    assert work.estimate(explicit).cpu == pytest.approx(work.estimate(explicit).count * work.DG_UPDATE_CPU)


PAPER_200 = Path(__file__).resolve().parents[2] / "config" / "ropos_L200_paper.yaml"


@pytest.mark.parametrize("EI, refused", [(2620.0, True), (26200.0, True), (262000.0, False), (0.0, False)])
def test_implicit_damping_is_refused_where_slack_phases_reach_the_compression_cap(EI, refused):
    """ROPOS 200 m on the paper's mesh (N = 20, P = 4; cage submerged weight 43.1 kN plus the cable's 5.9 kN):
    the cap EI (pi P / h)^2 is 4.1 kN at bending factor 1 and 41 kN at 10, below the 49 kN the cable carries,
    and there the implicit damping step gave cage snaps of 93-384 kN against 210 kN explicit; at factor 100
    (414 kN) it matched explicit damping within 1.4e-5. Without bending (no cap) and with explicit damping
    nothing is refused; nor is the Koh swinging cable (cap 232 N, weight 14 N)."""
    overrides = {"dg.damping": "implicit", "cable.EI": EI, "cable.compression": "buckling"}
    # without the cap (cable.compression none, the default: Eq. 22 as printed) nothing is refused
    assert load_config(PAPER_200, {"dg.damping": "implicit", "cable.EI": EI}).dg.damping == "implicit"
    if refused:
        with pytest.raises(ConfigError) as err:
            load_config(PAPER_200, overrides)
        assert "dg.damping implicit" in str(err.value) and "dg.damping explicit" in str(err.value)
        assert f"{math.pi ** 2 * EI * 0.16:.4g} N" in str(err.value)  # EI (pi 4 / 10)^2
    else:
        assert load_config(PAPER_200, overrides).dg.damping == "implicit"
    assert load_config(PAPER_200, {"cable.EI": EI}).dg.damping == "explicit"
    assert load_config(PAPER_200.parent / "koh_swinging_cable.yaml").dg.damping == "implicit"


def test_the_work_estimate_of_a_winch_run_is_taken_where_the_winch_can_take_the_cable():
    """The DG elements scale with the length a winch gives the cable, so hauling in shortens them
    and the substep falls (the solver's own rule while the winch moves: dg/winch_driver.py); a command
    on the winch topic may ask for winch.min_length at any time, so the estimate is taken there. The
    hybrid solver adds a segment per 4 m paid out: its count is taken at winch.max_length."""
    from tether_sim.solvers.dg import layout as Y
    from tether_sim.solvers.factory import build_solver
    from tether_sim.solvers.work import estimate

    mesh = {"dg.resolution": "manual", "dg.n_elements": 20, "dg.order": 4, "winch.enabled": True}
    # hauled in to 20 m the 20 elements are 1 m long: 2.1e-7 s substeps, ~210 CPU s per simulated s (accepted)
    config = load_config(ROPOS, {**mesh, "winch.min_length": 20.0})
    work = estimate(config)
    assert 100.0 < work.cpu < 1000.0 and "winch.min_length = 20 m" in work.cause
    solver = build_solver(config)  # the solver's substep at that length, hauling in at winch.max_speed
    solver.ws.prm[[Y.P_WL, Y.P_WR0, Y.P_WR1]] = 20.0, -2.0, -2.0
    assert work.substep == pytest.approx(solver._winch_substep(0.0), rel=1e-9)
    assert estimate(replace(config, winch=replace(config.winch, enabled=False))).cpu < 3.0  # at 200 m
    # down to 1 m (the default winch.min_length): 0.05 m elements, 5e-10 s substeps: refused, named
    with pytest.raises(ConfigError) as err:
        load_config(ROPOS, mesh)
    assert "hauled in to winch.min_length = 1 m" in str(err.value) and "a longer winch.min_length" in str(err.value)
    assert load_config(ROPOS, {**mesh, "winch.min_length": 150.0}).winch.min_length == 150.0
    # hybrid at 2e-5 s steps: 50 segments (37.5 CPU s per s) accepted; paying out to 10 km, 2500 of them: refused
    hybrid = ROPOS.with_name("ropos_L200_hybrid.yaml")
    fine = {"hybrid.time_step": 2e-5}
    assert load_config(hybrid, fine).hybrid.time_step == 2e-5
    with pytest.raises(ConfigError, match="2500 segments when the winch has paid out to winch.max_length = 10000 m"):
        load_config(hybrid, {**fine, "winch.enabled": True})
    assert load_config(hybrid, {**fine, "winch.enabled": True, "winch.max_length": 1000.0}).winch.enabled
