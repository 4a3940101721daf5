"""Parameter declaration of the simulation node: descriptors, file validation, live changes."""

import pytest

rclpy = pytest.importorskip("rclpy")
from rclpy.node import Node  # noqa: E402
from rclpy.parameter import Parameter  # noqa: E402

from tether_sim.errors import ConfigError  # noqa: E402
from tether_sim.ros import node_params  # noqa: E402

pytestmark = pytest.mark.ros


def make_node(tmp_path, text, extra=()):
    path = tmp_path / "params.yaml"
    path.write_text(text)
    ctx = rclpy.Context()
    rclpy.init(args=["--ros-args", "--params-file", str(path), *extra], context=ctx)
    return Node("tether_sim", context=ctx), ctx, str(path)


@pytest.fixture
def node_factory(tmp_path):
    made = []

    def factory(text, extra=()):
        node, ctx, path = make_node(tmp_path, text, extra)
        made.append((node, ctx))
        return node, path

    yield factory
    for node, ctx in made:
        node.destroy_node()
        rclpy.shutdown(context=ctx)


GOOD = """
tether_sim:
  ros__parameters:
    cable:
      length: 150.0
      EA: 45500000          # an integer for a double key is accepted
    body:
      attachment: [0, 0, 2]  # integers in a double array too
    snap:
      monitor_arc_lengths: []
"""


def test_every_key_is_declared_with_unit_range_and_read_only(node_factory):
    node, path = node_factory(GOOD)
    config = node_params.declare_all(node, path)
    assert config.cable.length == 150.0 and config.cable.EA == 45.5e6
    assert config.body.attachment == (0.0, 0.0, 2.0)
    d = node.describe_parameter("cable.EA")
    assert "axial stiffness" in d.description and "[N]" in d.description
    assert d.read_only and d.floating_point_range[0].to_value == 1e12
    assert not node.describe_parameter("snap.slack_fraction").read_only
    assert node.describe_parameter("dg.order").integer_range[0].from_value == 1
    assert "dg, hybrid" in node.describe_parameter("solver").additional_constraints


@pytest.mark.parametrize("text, needle", [
    ("tether_sim:\n  ros__parameters:\n    cable:\n      EAA: 1.0\n", "cable.EAA"),
    ("tether_sim:\n  ros__parameters:\n    cable:\n      length: -5.0\n", "cable.length"),
    ("tether_sim:\n  ros__parameters:\n    solver: fem\n", "solver"),
])
def test_bad_keys_in_the_file_name_the_key_and_the_file(node_factory, text, needle):
    node, path = node_factory(text)
    with pytest.raises(ConfigError) as err:
        node_params.declare_all(node, path)
    assert needle in str(err.value) and path in str(err.value)


def test_live_keys_change_and_other_keys_are_refused_with_a_reason(node_factory):
    node, path = node_factory(GOOD)
    config = node_params.declare_all(node, path)
    seen = {}

    def callback(params):
        result, new = node_params.check_live_change(params, seen.get("config", config))
        if new is not None:
            seen["config"] = new
        return result

    node.add_on_set_parameters_callback(callback)
    ok = node.set_parameters([Parameter("snap.slack_fraction", Parameter.Type.DOUBLE, 0.15)])[0]
    assert ok.successful and seen["config"].snap.slack_fraction == 0.15
    refused = node.set_parameters([Parameter("cable.EA", Parameter.Type.DOUBLE, 1.0e6)])[0]
    assert not refused.successful and "read-only" in refused.reason
    # the callback itself refuses non-live keys with the reason (also when read_only is bypassed)
    result, new = node_params.check_live_change([Parameter("cable.EA", Parameter.Type.DOUBLE, 1.0e6)], config)
    assert not result.successful and "restart" in result.reason and new is None
    out_of_range = node.set_parameters([Parameter("snap.slack_fraction", Parameter.Type.DOUBLE, 3.0)])[0]
    assert not out_of_range.successful


def test_command_line_override_is_validated_too(node_factory):
    node, path = node_factory(GOOD, extra=["-p", "dg.order:=99"])
    with pytest.raises(ConfigError, match="dg.order"):
        node_params.declare_all(node, path)


AUTO = """
tether_sim:
  ros__parameters:
    cable:
      length: 200.0
      EA: 45500000.0
    dg:
      resolution: auto
"""


def test_resolution_auto_declares_the_chosen_mesh(node_factory):
    """The node's parameters (and so /tether/description) carry the mesh the rule chose, not the defaults."""
    from tether_sim.solvers.resolution import choose

    node, path = node_factory(AUTO)
    config = node_params.declare_all(node, path)
    chosen = choose(200.0, 0.01)
    assert node.get_parameter("dg.n_elements").value == chosen.n_elements == config.dg.n_elements
    assert node.get_parameter("dg.cfl").value == chosen.cfl == config.dg.cfl
    assert node_params.read_config(node) == config


def test_resolution_auto_refuses_an_explicit_mesh(node_factory):
    node, path = node_factory(AUTO, extra=("-p", "dg.n_elements:=20"))
    with pytest.raises(ConfigError, match="dg.n_elements = 20 is set while dg.resolution is auto"):
        node_params.declare_all(node, path)


def test_a_bad_command_line_override_is_blamed_on_the_override_not_the_file(node_factory):
    from tether_sim.ros.node_cli import cli_param_keys

    argv = ["tether-sim", "--ros-args", "--params-file", "x.yaml", "-p", "dg.order:=99"]
    assert cli_param_keys(argv) == {"dg.order"}
    node, path = node_factory(GOOD, extra=["-p", "dg.order:=99"])
    with pytest.raises(ConfigError, match="command-line -p override") as err:
        node_params.declare_all(node, path, cli_keys=cli_param_keys(argv))
    assert path not in str(err.value)


def test_command_line_manual_mesh_rescues_a_file_the_automatic_choice_refuses(node_factory, tmp_path):
    """A file whose cable is outside the measured range of the automatic mesh choice: the node starts
    with ``-p dg.resolution:=manual`` (and ``-p dg.n_elements:=4`` on top), the file needs no edit."""
    from tether_sim.ros.node_cli import check_params_files, cli_param_values

    text = AUTO.replace("EA: 45500000.0", "EA: 1000000.0")
    path = tmp_path / "soft.yaml"
    path.write_text(text)
    with pytest.raises(ConfigError, match="outside the measured"):
        check_params_files([str(path)])
    argv = ["tether-sim", "--ros-args", "--params-file", str(path), "-p", "dg.resolution:=manual",
            "-p", "dg.n_elements:=4"]
    assert cli_param_values(argv) == {"dg.resolution": "manual", "dg.n_elements": 4}
    check_params_files([str(path)], cli_param_values(argv))  # no error
    node, node_path = node_factory(text, extra=["-p", "dg.resolution:=manual", "-p", "dg.n_elements:=4"])
    config = node_params.declare_all(node, node_path, cli_keys={"dg.resolution", "dg.n_elements"})
    assert (config.dg.resolution, config.dg.n_elements, config.cable.EA) == ("manual", 4, 1.0e6)
    # a bad -p value is still blamed on the command line
    with pytest.raises(ConfigError, match="command-line -p override"):
        check_params_files([str(path)], {"dg.n_elements": 0})


def test_a_live_change_that_breaks_a_cross_check_is_refused_with_the_reason(node_factory):
    node, path = node_factory(GOOD)
    config = node_params.declare_all(node, path)
    result, new = node_params.check_live_change(
        [Parameter("snap.retension_fraction", Parameter.Type.DOUBLE, 0.05)], config)
    assert not result.successful and new is None
    assert "snap.retension_fraction = 0.05 must be above snap.slack_fraction" in result.reason


def _overrides(argv) -> dict:
    """The parameter overrides rcl gives a node named tether_sim started with ``argv``."""
    ctx = rclpy.Context()
    rclpy.init(args=argv, context=ctx)
    try:
        node = Node("tether_sim", context=ctx, automatically_declare_parameters_from_overrides=True)
        try:
            return {name: p.value for name, p in node._parameters.items()}
        finally:
            node.destroy_node()
    finally:
        rclpy.shutdown(context=ctx)


def test_shipped_sections_apply_in_any_namespace_and_a_plain_section_is_renamed(tmp_path):
    """The shipped files use rcl's own `/**/tether_sim:` (applied in /rov1 by rcl itself); a file
    with a plain `tether_sim:` section is not applied there by rcl, and retarget() fixes that."""
    from pathlib import Path

    import yaml

    from tether_sim.ros.namespacing import retarget

    config = Path(__file__).resolve().parents[2] / "config"
    for path in sorted(config.glob("*.yaml")):
        assert all(str(k).startswith("/**/") for k in yaml.safe_load(path.read_text())), path
    ns = ["--ros-args", "-r", "__ns:=/rov1"]
    shipped = _overrides(ns + ["--params-file", str(config / "ropos_L200.yaml")])
    assert shipped["cable.length"] == 200.0 and shipped["dg.resolution"] == "auto"
    assert _overrides(["--ros-args", "--params-file", str(config / "ropos_L200.yaml")])["cable.length"] == 200.0  # root
    plain = tmp_path / "mine.yaml"
    plain.write_text("tether_sim:\n  ros__parameters:\n    cable:\n      length: 123.0\n")
    argv = ns + ["--params-file", str(plain)]
    assert "cable.length" not in _overrides(argv)  # rcl alone: /tether_sim only
    logged = []
    assert _overrides(retarget(argv, log=logged.append, tmpdir=tmp_path))["cable.length"] == 123.0
    assert logged == [f"{plain}: section 'tether_sim' applied to this node, /rov1/tether_sim"]
    assert retarget(ns + ["--params-file", str(config / "ropos_L200.yaml")]) == \
        ns + ["--params-file", str(config / "ropos_L200.yaml")]  # nothing to rename in a shipped file
