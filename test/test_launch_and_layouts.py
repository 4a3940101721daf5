"""launch/tether_sim.launch.py, rviz/tether_sim.rviz and foxglove/tether_sim.json, checked without
ROS 2's launch, RViz or Foxglove (none runs here):

- the launch file is executed against stand-ins of the launch / launch_ros classes that record
  what they are given: every argument it uses is declared, the executables are console scripts of
  setup.py, the config files exist, its recorder topics equal config/recorder.yaml's, and its
  namespace / sim-time expressions evaluate as intended;
- the RViz config parses as YAML, uses RViz 2's default display classes, shows the tether marker,
  both wrenches and the snap markers on topics the node publishes, in the node's world frame;
- the Foxglove layout parses, its layout tree and panel configs agree, and every plotted path is a
  field of the message type the node publishes on that topic (from the msg_defs / ROS .msg text).
"""

import ast
import json
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


# ------------------------------------------------------------------ launch file, with stand-ins
class Sub:
    """A substitution stand-in: ``render(values)`` gives the string launch would produce."""

    def __init__(self, kind, value):
        self.kind, self.value = kind, value

    def render(self, values):
        if self.kind == "arg":
            return values[self.value]
        parts = "".join(render(v, values) for v in self.value)
        if self.kind == "join":
            return "/".join(render(v, values) for v in self.value)
        if self.kind == "python":
            return str(eval(parts))  # noqa: S307 - the launch file's own expression, as launch does
        return parts


def render(item, values):
    if isinstance(item, Sub):
        return item.render(values)
    if isinstance(item, (list, tuple)):
        return "".join(render(v, values) for v in item)
    return str(item)


@pytest.fixture
def launch_description(monkeypatch):
    made = {"args": [], "nodes": [], "used": set()}

    def configuration(name):
        made["used"].add(name)
        return Sub("arg", name)

    class Node:
        def __init__(self, **kwargs):
            made["nodes"].append(kwargs)

    modules = {
        "launch": {"LaunchDescription": lambda entities: entities},
        "launch.actions": {"DeclareLaunchArgument": lambda name, **kw: made["args"].append((name, kw))},
        "launch.conditions": {"IfCondition": lambda predicate: ("if", predicate)},
        "launch.substitutions": {"LaunchConfiguration": configuration,
                                 "PathJoinSubstitution": lambda parts: Sub("join", parts),
                                 "PythonExpression": lambda parts: Sub("python", parts)},
        "launch_ros.actions": {"Node": Node},
        "launch_ros.substitutions": {"FindPackageShare": lambda pkg: Sub("text", [f"<share:{pkg}>"])},
    }
    for name, attrs in modules.items():
        module = types.ModuleType(name)
        module.__dict__.update(attrs)
        monkeypatch.setitem(sys.modules, name, module)
    monkeypatch.setitem(sys.modules, "launch_ros", types.ModuleType("launch_ros"))
    namespace = {}
    exec(compile(LAUNCH.read_text(), str(LAUNCH), "exec"), namespace)  # noqa: S102
    entities = namespace["generate_launch_description"]()
    return made, entities, namespace


def console_scripts():
    tree = ast.parse((ROOT / "setup.py").read_text())
    for node in ast.walk(tree):
        if isinstance(node, ast.Dict):
            for key, value in zip(node.keys, node.values):
                if isinstance(key, ast.Constant) and key.value == "console_scripts":
                    return {ast.literal_eval(e).split("=")[0].strip() for e in value.elts}
    raise AssertionError("no console_scripts in setup.py")


def test_launch_file_arguments_executables_and_files(launch_description):
    made, entities, namespace = launch_description
    declared = {name for name, _ in made["args"]}
    assert declared == {"params_file", "namespace", "use_sim_time", "record", "output", "replay", "input", "rate"}
    assert made["used"] <= declared, made["used"] - declared
    assert all(kw.get("description") for _, kw in made["args"])
    nodes = {n["executable"]: n for n in made["nodes"]}
    assert set(nodes) == {"tether-sim", "tether-sim-record", "tether-sim-replay"}
    assert set(nodes) <= console_scripts()
    assert all(n["package"] == "tether_sim" for n in made["nodes"])
    values = {"params_file": "p.yaml", "namespace": "rov1", "use_sim_time": "true", "record": "true",
              "output": "o.mcap", "replay": "true", "input": "i.mcap", "rate": "0.5"}
    for n in made["nodes"]:  # every config file the launch file names exists in config/
        for p in n.get("parameters", []):
            if isinstance(p, Sub) and p.kind == "join":
                path = render(p, values).split("<share:tether_sim>/", 1)[-1]
                assert (ROOT / path).is_file(), path
    default = dict(made["args"])["params_file"]["default_value"]
    assert (ROOT / render(default, values).split("<share:tether_sim>/", 1)[-1]).is_file()
    recorder_yaml = yaml.safe_load((ROOT / "config/recorder.yaml").read_text())
    assert namespace["RECORDED_TOPICS"] == recorder_yaml["tether_sim_recorder"]["ros__parameters"]["topics"]
    # the sim-time switch and the replay's remap into the namespace
    sim = nodes["tether-sim"]["parameters"][1]["use_sim_time"]
    assert render(sim, values) == "True" and render(sim, dict(values, use_sim_time="false")) == "False"
    remaps = dict((render(a, values), render(b, values)) for a, b in nodes["tether-sim-replay"]["remappings"])
    assert remaps == {"/ship/pose": "/rov1/ship/pose", "/vehicle/pose": "/rov1/vehicle/pose"}
    remaps = dict((render(a, values), render(b, dict(values, namespace=""))) for a, b in
                  nodes["tether-sim-replay"]["remappings"])
    assert remaps == {"/ship/pose": "/ship/pose", "/vehicle/pose": "/vehicle/pose"}
    assert render(nodes["tether-sim"]["namespace"], values) == "rov1"


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


def resolve_path(path: str):
    topic, _, rest = path.partition(".")
    typ = NODE_TOPICS[topic]
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
