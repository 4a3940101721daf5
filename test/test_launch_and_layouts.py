"""launch/tether_sim.launch.py, rviz/tether_sim.rviz and foxglove/tether_sim.json, checked without
ROS 2's launch, RViz or Foxglove (none runs here):

- the launch file runs through a model of what `ros2 launch` (launch 3.4 / launch_ros 0.26) does
  with it: the declarations in order, each default evaluated when its declaration runs (a default
  that reads an argument declared later fails, as launch fails), every substitution resolved,
  conditions parsed as launch parses them, parameter files opened, and each executable looked up
  in <prefix>/lib/tether_sim/ through the ament index (where launch_ros looks, not the venv's bin/);
  with no arguments, the README's arguments and a replay; where ROS 2's launch / launch_ros are
  importable, the same argument sets through them as well (skipped otherwise);
- the RViz config parses as YAML, uses RViz 2's default display classes, shows the tether marker,
  both wrenches and the snap markers on topics the node publishes, in the node's world frame;
- the Foxglove layout parses, its layout tree and panel configs agree, and every plotted path is a
  field of the message type the node publishes on that topic (from the msg_defs / ROS .msg text).
"""

import ast
import json
import math
import os
import sys
import types
from pathlib import Path

import pytest
import yaml

from tether_sim.config import NodeOptions

ROOT = Path(__file__).resolve().parents[1]
LAUNCH = ROOT / "launch" / "tether_sim.launch.py"
RVIZ = ROOT / "rviz" / "tether_sim.rviz"
FOXGLOVE = ROOT / "foxglove" / "tether_sim.json"
NODE_TOPICS = {  # what the node publishes (root namespace) -> message type (package/msg/Type)
    "/tether/state": "tether_sim_msgs/msg/TetherState", "/tether/marker": "visualization_msgs/msg/Marker",
    "/tether/path": "nav_msgs/msg/Path", "/tether/ship_wrench": "geometry_msgs/msg/WrenchStamped",
    "/tether/vehicle_wrench": "geometry_msgs/msg/WrenchStamped",
    "/tether/snap_events": "tether_sim_msgs/msg/SnapLoadEvent", "/tether/snap_markers": "visualization_msgs/msg/Marker",
    "/tether/slack_warnings": "tether_sim_msgs/msg/SlackWarning", "/vehicle/sim_pose": "geometry_msgs/msg/PoseStamped",
    "/tf": "tf2_msgs/msg/TFMessage", "/diagnostics": "diagnostic_msgs/msg/DiagnosticArray"}


# ------------------------------------------------------------------ launch file, through a model of launch
class LaunchError(Exception):
    """What launch raises; the messages follow launch 3.4 / launch_ros 0.26 (Jazzy)."""


class Context:
    def __init__(self, arguments):
        self.configs = dict(arguments)  # `ros2 launch ... name:=value` are set before the file runs
        self.started = []


def perform(item, context) -> str:
    """A launch 'SomeSubstitutionsType' (text, substitution or a list of both) as launch renders it."""
    if isinstance(item, (list, tuple)):
        return "".join(perform(v, context) for v in item)
    if isinstance(item, str):
        return item
    return item.perform(context)


class LaunchConfiguration:
    def __init__(self, name):
        self.name = name

    def perform(self, context):
        if self.name not in context.configs:
            raise LaunchError(f"launch configuration '{self.name}' does not exist")
        return context.configs[self.name]


class PathJoinSubstitution:
    def __init__(self, parts):
        self.parts = parts

    def perform(self, context):
        return os.path.join(*[perform(p, context) for p in self.parts])


class PythonExpression:
    def __init__(self, parts):
        self.parts = parts

    def perform(self, context):
        text = perform(self.parts, context)
        try:
            return str(eval(text, {"math": math}))  # noqa: S307 - what launch's PythonExpression does
        except Exception as error:  # noqa: BLE001 - launch reports every failure of the expression
            raise LaunchError(f"PythonExpression {text!r} failed: {error}") from error


class FindPackageShare:
    def __init__(self, package):
        self.package = package

    def perform(self, context):
        from ament_index_python.packages import PackageNotFoundError, get_package_share_directory
        try:
            return get_package_share_directory(self.package)
        except PackageNotFoundError as error:
            raise LaunchError(f"package '{self.package}' not found") from error


class IfCondition:
    def __init__(self, predicate):
        self.predicate = predicate

    def evaluate(self, context):
        text = perform(self.predicate, context).strip().lower()
        if text not in ("true", "false", "1", "0"):
            raise LaunchError(f"Unknown condition '{text}': expected true, false, 1 or 0")
        return text in ("true", "1")


class DeclareLaunchArgument:
    def __init__(self, name, default_value=None, description=None):
        self.name, self.default_value, self.description = name, default_value, description

    def execute(self, context):  # the default is evaluated here, in declaration order
        if self.name not in context.configs:
            if self.default_value is None:
                raise LaunchError(f"Required launch argument '{self.name}' was not provided")
            context.configs[self.name] = perform(self.default_value, context)


class Node:
    def __init__(self, *, package, executable, name=None, namespace=None, parameters=(), remappings=(),
                 condition=None, output=None, emulate_tty=False):
        self.package, self.executable, self.name, self.namespace = package, executable, name, namespace
        self.parameters, self.remappings, self.condition = list(parameters), list(remappings), condition

    def execute(self, context):
        if self.condition is not None and not self.condition.evaluate(context):
            return
        # launch_ros' ExecutableInPackage: <prefix of the package>/lib/<package>/<executable>
        from ament_index_python.packages import PackageNotFoundError, get_package_prefix
        try:
            prefix = get_package_prefix(self.package)
        except PackageNotFoundError as error:
            raise LaunchError(f"package '{self.package}' not found") from error
        libexec = os.path.join(prefix, "lib", self.package)
        path = os.path.join(libexec, self.executable)
        if not (os.path.isfile(path) and os.access(path, os.X_OK)):
            raise LaunchError(f"executable '{self.executable}' not found on the libexec directory '{libexec}'")
        parameters = []
        for item in self.parameters:
            if isinstance(item, dict):  # substitutions are evaluated, then read as YAML; plain values kept
                parameters.append({k: v if isinstance(v, (bool, int, float)) or
                                   (isinstance(v, list) and all(isinstance(x, str) for x in v))
                                   else yaml.safe_load(perform(v, context) or "''") for k, v in item.items()})
            else:
                file = perform(item, context)
                if not os.path.isfile(file):
                    raise LaunchError(f"Unable to find parameter file '{file}'")
                parameters.append(file)
        context.started.append({
            "executable": self.executable, "path": path, "name": self.name,
            "namespace": perform(self.namespace, context) if self.namespace is not None else "",
            "parameters": parameters,
            "remappings": {perform(a, context): perform(b, context) for a, b in self.remappings}})


def launch_module(monkeypatch):
    """The launch file's module, its `launch` / `launch_ros` imports bound to the model above."""
    modules = {
        "launch": {"LaunchDescription": lambda entities: list(entities)},
        "launch.actions": {"DeclareLaunchArgument": DeclareLaunchArgument},
        "launch.conditions": {"IfCondition": IfCondition},
        "launch.substitutions": {"LaunchConfiguration": LaunchConfiguration,
                                 "PathJoinSubstitution": PathJoinSubstitution, "PythonExpression": PythonExpression},
        "launch_ros": {}, "launch_ros.actions": {"Node": Node},
        "launch_ros.substitutions": {"FindPackageShare": FindPackageShare},
    }
    for name, attrs in modules.items():
        module = types.ModuleType(name)
        module.__dict__.update(attrs)
        monkeypatch.setitem(sys.modules, name, module)
    namespace = {}
    exec(compile(LAUNCH.read_text(), str(LAUNCH), "exec"), namespace)  # noqa: S102
    return namespace


def ros2_launch(entities, arguments=()) -> Context:
    """What `ros2 launch tether_sim tether_sim.launch.py a:=b ...` does: the entities in order."""
    context = Context(a.split(":=", 1) for a in arguments)
    for entity in entities:
        entity.execute(context)
    return context


@pytest.fixture
def launch(monkeypatch):
    pytest.importorskip("ament_index_python", reason="the executable lookup needs the ament index of the venv")
    from ament_index_python.packages import PackageNotFoundError, get_package_prefix
    try:
        get_package_prefix("tether_sim")
    except PackageNotFoundError:
        pytest.skip("tether_sim is not in the ament index here (set up by `make setup`)")
    return launch_module(monkeypatch)


def console_scripts():
    tree = ast.parse((ROOT / "setup.py").read_text())
    for node in ast.walk(tree):
        if isinstance(node, ast.Dict):
            for key, value in zip(node.keys, node.values):
                if isinstance(key, ast.Constant) and key.value == "console_scripts":
                    return {ast.literal_eval(e).split("=")[0].strip() for e in value.elts}
    raise AssertionError("no console_scripts in setup.py")


def readme_launch_arguments():
    """The arguments of the README's `ros2 launch tether_sim tether_sim.launch.py ...` line."""
    for line in (ROOT / "README.md").read_text().splitlines():
        words = line.split("#", 1)[0].split()
        if words[:4] == ["ros2", "launch", "tether_sim", "tether_sim.launch.py"]:
            return words[4:]
    raise AssertionError("no ros2 launch line in README.md")


def test_launch_file_runs_with_its_defaults_and_the_readme_arguments(launch):
    entities = launch["generate_launch_description"]()
    declarations = [e for e in entities if isinstance(e, DeclareLaunchArgument)]
    assert {d.name for d in declarations} == {"params_file", "namespace", "frame_prefix", "use_sim_time", "record",
                                              "output", "replay", "input", "rate"}
    assert all(d.description for d in declarations)
    nodes = [e for e in entities if isinstance(e, Node)]
    assert {n.executable for n in nodes} == {"tether-sim", "tether-sim-record", "tether-sim-replay"} <= console_scripts()

    # no argument at all: the node alone, on wall time, with the package's default parameter file
    context = ros2_launch(entities)
    (sim,) = context.started
    assert sim["executable"] == "tether-sim" and sim["namespace"] == ""
    assert Path(sim["parameters"][0]).resolve() == (ROOT / "config" / "ropos_L200.yaml").resolve()
    assert sim["parameters"][1] == {"use_sim_time": False, "node.frame_prefix": ""}
    # the README's line: node and recorder in /rov1, recording the config/recorder.yaml topics
    arguments = readme_launch_arguments()
    assert "namespace:=rov1" in arguments and "record:=true" in arguments
    context = ros2_launch(launch["generate_launch_description"](), arguments)
    started = {n["executable"]: n for n in context.started}
    assert set(started) == {"tether-sim", "tether-sim-record"}
    assert {n["namespace"] for n in started.values()} == {"rov1"}
    assert started["tether-sim"]["parameters"][1]["node.frame_prefix"] == "rov1/"  # frames apart per tether
    recorder = started["tether-sim-record"]["parameters"]
    # config/recorder.yaml's section must reach a recorder in /rov1: rcl matches /**/tether_sim_recorder
    assert "/**/tether_sim_recorder" in yaml.safe_load(Path(recorder[0]).read_text())
    assert recorder[1]["output"] == dict(a.split(":=") for a in arguments)["output"]
    # a replay: sim time for node and recorder, the replay's pose topics moved into the namespace
    context = ros2_launch(launch["generate_launch_description"](),
                          ["namespace:=/rov2/", "replay:=true", "record:=true", "input:=i.mcap", "rate:=0.5"])
    started = {n["executable"]: n for n in context.started}
    assert started["tether-sim"]["parameters"][1] == {"use_sim_time": True, "node.frame_prefix": "rov2/"}
    assert started["tether-sim-record"]["parameters"][1]["use_sim_time"] is True
    assert started["tether-sim-replay"]["remappings"] == {"/ship/pose": "/rov2/ship/pose",
                                                          "/vehicle/pose": "/rov2/vehicle/pose"}
    assert started["tether-sim-replay"]["parameters"][1] == {"input": "i.mcap", "rate": 0.5, "use_sim_time": False}
    context = ros2_launch(launch["generate_launch_description"](),
                          ["replay:=true", "use_sim_time:=false", "namespace:=rov3", "frame_prefix:=a/"])
    started = {n["executable"]: n for n in context.started}
    assert started["tether-sim"]["parameters"][1] == {"use_sim_time": False, "node.frame_prefix": "a/"}
    context = ros2_launch(launch["generate_launch_description"](), ["replay:=true"])
    started = {n["executable"]: n for n in context.started}
    assert started["tether-sim-replay"]["remappings"] == {"/ship/pose": "/ship/pose", "/vehicle/pose": "/vehicle/pose"}


def test_launch_model_catches_order_lookup_and_condition_errors(launch, tmp_path, monkeypatch):
    """The model fails where ros2 launch fails: the checks above can fail."""
    entities = launch["generate_launch_description"]()
    declarations = [e for e in entities if isinstance(e, DeclareLaunchArgument)]
    # a default reading an argument declared after it (this file's use_sim_time before replay)
    reordered = sorted(declarations, key=lambda d: d.name != "use_sim_time") + \
        [e for e in entities if not isinstance(e, DeclareLaunchArgument)]
    with pytest.raises(LaunchError, match="launch configuration 'replay' does not exist"):
        ros2_launch(reordered)
    ros2_launch(reordered, ["replay:=false"])  # given on the command line, the order does not matter
    with pytest.raises(LaunchError, match="Unknown condition 'yes'"):
        ros2_launch(launch["generate_launch_description"](), ["record:=yes"])
    with pytest.raises(LaunchError, match="Unable to find parameter file"):
        ros2_launch(launch["generate_launch_description"](), [f"params_file:={tmp_path / 'missing.yaml'}"])
    # an executable where pip puts it (<prefix>/bin) but not in <prefix>/lib/<package>
    prefix = tmp_path / "prefix"
    (prefix / "share" / "ament_index" / "resource_index" / "packages").mkdir(parents=True)
    (prefix / "share" / "ament_index" / "resource_index" / "packages" / "tether_sim").write_text("")
    (prefix / "share" / "tether_sim" / "config").mkdir(parents=True)
    (prefix / "share" / "tether_sim" / "config" / "ropos_L200.yaml").write_text("{}\n")
    (prefix / "bin").mkdir()
    (prefix / "bin" / "tether-sim").write_text("#!/bin/sh\n")
    (prefix / "bin" / "tether-sim").chmod(0o755)
    monkeypatch.setenv("AMENT_PREFIX_PATH", str(prefix))
    with pytest.raises(LaunchError, match="executable 'tether-sim' not found on the libexec directory"):
        ros2_launch(launch["generate_launch_description"]())


# ------------------------------------------------------------------ launch file, with launch itself
# Where ROS 2's own launch / launch_ros are importable (a ROS install, or their sources on PYTHONPATH)
# the file also runs through them, as `ros2 launch tether_sim tether_sim.launch.py ARGS` does it: a
# LaunchService with the file included, shut down once every expected process has started. The
# package registry has neither, so `make test` skips this and the model above stands in for it.
REAL_LAUNCH = """
import json, sys
import launch
from launch.actions import IncludeLaunchDescription, RegisterEventHandler, EmitEvent
from launch.event_handlers import OnProcessStart
from launch.events import Shutdown
from launch.launch_description_sources import PythonLaunchDescriptionSource
path, expected, *arguments = sys.argv[1:]
expected, started = set(expected.split(',')), []
def on_start(event, context):
    started.append(event.action.process_details['cmd'][0])
    names = {c.rsplit('/', 1)[-1] for c in started}
    return [EmitEvent(event=Shutdown(reason='all started'))] if names >= expected else None
include = IncludeLaunchDescription(PythonLaunchDescriptionSource(path),
                                   launch_arguments=[a.split(':=', 1) for a in arguments])
service = launch.LaunchService(argv=arguments, noninteractive=True)
service.include_launch_description(launch.LaunchDescription([
    RegisterEventHandler(OnProcessStart(on_start=on_start)), include]))
code = service.run()
print('RESULT ' + json.dumps({'code': code, 'started': started}), flush=True)
"""


def run_real_launch(path, expected, arguments=()):
    import subprocess

    done = subprocess.run([sys.executable, "-c", REAL_LAUNCH, str(path), ",".join(sorted(expected)), *arguments],
                          capture_output=True, text=True, timeout=120)
    results = [line for line in done.stdout.splitlines() if line.startswith("RESULT ")]
    assert results, done.stdout[-3000:] + done.stderr[-3000:]
    return json.loads(results[-1][len("RESULT "):]), done.stdout + done.stderr


def test_launch_file_with_ros2s_own_launch(tmp_path):
    import importlib.util

    # (the repository's launch/ folder alone would import as an empty namespace package `launch`)
    if importlib.util.find_spec("launch_ros") is None or importlib.util.find_spec("launch.launch_service") is None:
        pytest.skip("ROS 2's launch / launch_ros are not installed (neither is on the package registry)")
    from ament_index_python.packages import get_package_prefix

    prefix = Path(get_package_prefix("tether_sim"))
    for arguments, expected in (((), {"tether-sim"}),
                                (readme_launch_arguments(), {"tether-sim", "tether-sim-record"}),
                                (["namespace:=rov2", "replay:=true", "input:=i.mcap"], {"tether-sim", "tether-sim-replay"})):
        result, log = run_real_launch(LAUNCH, expected, arguments)
        assert result["code"] == 0, log[-3000:]
        # each executable where launch_ros looks for it: <prefix>/lib/tether_sim/
        assert {Path(c).name for c in result["started"]} == expected, log[-3000:]
        assert {Path(c).parent for c in result["started"]} == {prefix / "lib" / "tether_sim"}, log[-3000:]
    # and launch itself fails on a default that reads an argument declared after it
    text = LAUNCH.read_text()
    replay = '    ("replay", "false", "also start tether-sim-replay of \'input\', publishing /clock"),\n'
    assert replay in text
    reordered = tmp_path / "reordered.launch.py"
    reordered.write_text(text.replace(replay, "").replace('    ("record", "false"', replay + '    ("record", "false"'))
    result, log = run_real_launch(reordered, {"tether-sim"})
    assert result["code"] != 0 and "launch configuration 'replay' does not exist" in log, log[-3000:]


# ------------------------------------------------------------------ RViz
RVIZ_CLASSES = {"rviz_default_plugins/Grid", "rviz_default_plugins/TF", "rviz_default_plugins/Marker",
                "rviz_default_plugins/Wrench", "rviz_common/Displays", "rviz_common/Views"}


def test_rviz_config_shows_tether_wrenches_and_snaps():
    config = yaml.safe_load(RVIZ.read_text())
    manager = config["Visualization Manager"]
    assert manager["Global Options"]["Fixed Frame"] == NodeOptions().world_frame
    displays = manager["Displays"]
    assert {d["Class"] for d in displays} | {p["Class"] for p in config["Panels"]} <= RVIZ_CLASSES
    by_topic = {d["Topic"]["Value"]: d["Class"] for d in displays if "Topic" in d}
    assert by_topic == {"/tether/marker": "rviz_default_plugins/Marker",
                        "/tether/ship_wrench": "rviz_default_plugins/Wrench",
                        "/tether/vehicle_wrench": "rviz_default_plugins/Wrench",
                        "/tether/snap_markers": "rviz_default_plugins/Marker"}
    assert set(by_topic) <= set(NODE_TOPICS)
    for d in displays:  # the node publishes reliable: a reliable display matches it
        if "Topic" in d:
            assert d["Topic"]["Reliability Policy"] == "Reliable" and d["Enabled"] is True
    assert any(d["Class"] == "rviz_default_plugins/TF" for d in displays)


# ------------------------------------------------------------------ Foxglove
def msg_fields(type_name: str) -> dict:
    """{field: type} of a ROS 2 message from its .msg text (msg_defs/ or the venv's share/)."""
    pkg, _, name = type_name.split("/")
    candidates = [ROOT / "msg_defs" / "msg" / f"{name}.msg", ROOT / "msg_defs" / pkg / "msg" / f"{name}.msg",
                  Path(sys.prefix) / "share" / pkg / "msg" / f"{name}.msg"]
    path = next((p for p in candidates if p.is_file() and (pkg != "tether_sim_msgs" or "msg_defs/msg" in str(p))), None)
    if path is None:
        pytest.skip(f"no .msg text for {type_name} here")
    fields = {}
    for line in path.read_text().splitlines():
        line = line.split("#", 1)[0].strip()
        if not line or "=" in line.split()[1 if len(line.split()) > 1 else 0]:
            continue
        typ, field = line.split()[:2]
        typ = typ.split("[")[0]
        if "/" not in typ and typ[0].isupper():
            typ = f"{pkg}/{typ}"
        if typ == "Header":
            typ = "std_msgs/Header"
        fields[field] = typ if "/" not in typ else f"{typ.split('/')[0]}/msg/{typ.split('/')[-1]}"
    return fields


def resolve_path(path: str, topics=None):
    """The message type at a plotted path ``/topic.field.field`` of ``topics`` (default: the single-line node's)."""
    topic, _, rest = path.partition(".")
    typ = (topics or NODE_TOPICS)[topic]
    for part in rest.split("."):
        fields = msg_fields(typ)
        assert part in fields, (path, part, sorted(fields))
        typ = fields[part]
    return typ


def test_foxglove_layout_panels_and_paths():
    layout = json.loads(FOXGLOVE.read_text())
    configs = layout["configById"]

    def leaves(node):
        return [node] if isinstance(node, str) else leaves(node["first"]) + leaves(node["second"])

    assert sorted(leaves(layout["layout"])) == sorted(configs)
    kinds = {key.split("!")[0] for key in configs}
    assert {"3D", "Plot", "RawMessages", "DiagnosticSummary"} <= kinds
    three_d = next(v for k, v in configs.items() if k.startswith("3D!"))
    assert three_d["followTf"] == NodeOptions().world_frame
    assert {"/tether/marker", "/tether/snap_markers"} <= {t for t, c in three_d["topics"].items() if c["visible"]}
    assert set(three_d["topics"]) <= set(NODE_TOPICS)
    plotted = [p["value"] for k, v in configs.items() if k.startswith("Plot!") for p in v["paths"]]
    for needed in ("/tether/state.ship_end_tension", "/tether/state.vehicle_end_tension",
                   "/tether/snap_events.peak_tension", "/tether/vehicle_wrench.wrench.force.z"):
        assert needed in plotted
    for path in plotted:
        assert resolve_path(path) in ("float64", "float32"), path
    raw = [v["topicPath"] for k, v in configs.items() if k.startswith("RawMessages!")]
    assert raw == ["/tether/snap_events"]


# ------------------------------------------------------------------ the network's layouts (config/ropos_tms.yaml)
RVIZ_TMS = ROOT / "rviz" / "tether_sim_tms.rviz"
FOXGLOVE_TMS = ROOT / "foxglove" / "tether_sim_tms.json"


def tms_topics() -> dict:
    """What the network node publishes on config/ropos_tms.yaml (root namespace) -> message type:
    network_outputs.output_topics of the file's network, and /tf."""
    pytest.importorskip("rclpy")
    pytest.importorskip("tether_sim_msgs")
    from tether_sim.network.params import load_network_files
    from tether_sim.ros.network_outputs import output_topics

    spec, _ = load_network_files([str(ROOT / "config" / "ropos_tms.yaml")])
    winches = [n for n, ln in spec.lines.items() if ln.config.winch.enabled]
    return {**{t: typ for t, (typ, _) in output_topics(spec, winches).items()}, "/tf": "tf2_msgs/msg/TFMessage"}


def test_network_rviz_config_shows_every_line_the_cage_and_the_wrenches():
    topics = tms_topics()
    config = yaml.safe_load(RVIZ_TMS.read_text())
    manager = config["Visualization Manager"]
    assert manager["Global Options"]["Fixed Frame"] == NodeOptions().world_frame
    displays = manager["Displays"]
    assert {d["Class"] for d in displays} | {p["Class"] for p in config["Panels"]} <= RVIZ_CLASSES | {
        "rviz_default_plugins/Pose"}
    by_topic = {d["Topic"]["Value"]: d["Class"] for d in displays if "Topic" in d}
    expected = {"/tether/tether/marker": "rviz_default_plugins/Marker",
                "/tether/excursion/marker": "rviz_default_plugins/Marker",
                "/cage/sim_pose": "rviz_default_plugins/Pose",
                "/tether/cage_wrench": "rviz_default_plugins/Wrench",
                "/tether/ship_wrench": "rviz_default_plugins/Wrench",
                "/tether/vehicle_wrench": "rviz_default_plugins/Wrench"}
    assert by_topic == expected
    for topic, cls in by_topic.items():  # each on a topic the node publishes, with the display's type
        typ = {"rviz_default_plugins/Marker": "visualization_msgs/msg/Marker",
               "rviz_default_plugins/Pose": "geometry_msgs/msg/PoseStamped",
               "rviz_default_plugins/Wrench": "geometry_msgs/msg/WrenchStamped"}[cls]
        assert topics.get(topic) == typ, topic
    assert {f"/tether/{line}/marker" for line in ("tether", "excursion")} == {
        t for t in topics if t.endswith("/marker")}  # every line of the file
    for d in displays:
        if "Topic" in d:
            assert d["Topic"]["Reliability Policy"] == "Reliable" and d["Enabled"] is True
    assert any(d["Class"] == "rviz_default_plugins/TF" for d in displays)


def test_network_foxglove_layout_shows_every_line_and_the_cage():
    topics = tms_topics()
    layout = json.loads(FOXGLOVE_TMS.read_text())
    configs = layout["configById"]

    def leaves(node):
        return [node] if isinstance(node, str) else leaves(node["first"]) + leaves(node["second"])

    assert sorted(leaves(layout["layout"])) == sorted(configs)
    three_d = next(v for k, v in configs.items() if k.startswith("3D!"))
    assert three_d["followTf"] == NodeOptions().world_frame
    visible = {t for t, c in three_d["topics"].items() if c["visible"]}
    assert visible == {"/tether/tether/marker", "/tether/excursion/marker", "/cage/sim_pose"}
    assert set(three_d["topics"]) <= set(topics)
    plotted = [p["value"] for k, v in configs.items() if k.startswith("Plot!") for p in v["paths"]]
    for needed in ("/tether/tether/state.ship_end_tension", "/tether/tether/state.vehicle_end_tension",
                   "/tether/excursion/state.ship_end_tension", "/tether/excursion/state.vehicle_end_tension",
                   "/tether/vehicle_wrench.wrench.force.z", "/cage/sim_pose.pose.position.z",
                   "/cage/sim_twist.twist.linear.z", "/cage/sim_accel.accel.linear.z",
                   "/tether/cage_wrench.wrench.force.z", "/cage/hydro_wrench.wrench.force.z"):
        assert needed in plotted
    for path in plotted:  # every plotted path a float field of the type the node publishes there
        assert resolve_path(path, topics) in ("float64", "float32"), path
    raw = sorted(v["topicPath"] for k, v in configs.items() if k.startswith("RawMessages!"))
    assert raw == ["/tether/excursion/snap_events", "/tether/tether/snap_events"]
    assert all(t in topics for t in raw)
    assert any(k.startswith("DiagnosticSummary!") and v["topicToRender"] in topics for k, v in configs.items())
