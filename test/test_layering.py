"""The layering of tether_sim, checked on the source (ast; nothing is imported).

``physics``, ``numerics`` (leaves) <- ``solvers`` <- ``config`` <- ``io``, ``scenarios`` <- ``ros``;
``network`` (line networks over the solver interface) sits on ``io`` and below ``scenarios``, ``ros``.
Nothing outside ``tether_sim/ros/`` imports rclpy or a ROS message package, so the solvers,
the offline runner and the tests run without ROS. Imports inside functions and
``importlib.import_module("...")`` with a literal name count too.
"""

import ast
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PACKAGE = ROOT / "tether_sim"

ROS_MODULE = re.compile(r"^(rclpy|rosidl_\w+|\w+_interfaces|\w+_msgs)(\.|$)")
# subpackage -> tether_sim subpackages it must not import
FORBIDDEN = {
    "physics": ("solvers", "io", "ros", "scenarios", "config", "network"),
    "numerics": ("solvers", "io", "ros", "scenarios", "config", "network"),
    "solvers": ("io", "ros", "scenarios", "network"),
    "config": ("io", "ros", "scenarios", "network"),
    "io": ("ros", "network"),
    "network": ("ros", "scenarios"),
    "forecast": ("io", "ros", "scenarios", "network"),
    "scenarios": ("ros",),
    "spec": ("solvers", "io", "ros", "scenarios", "config", "physics", "numerics"),
    "errors": ("solvers", "io", "ros", "scenarios", "config", "physics", "numerics"),
    "paths": ("solvers", "io", "ros", "scenarios", "config", "physics", "numerics"),
}


def module_name(path: Path, root: Path = ROOT) -> str:
    parts = list(path.relative_to(root).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def imported_modules(source: str, module: str, is_package: bool = False) -> list:
    """Absolute names of every module that ``source`` (the module ``module``) imports."""
    tree = ast.parse(source)
    package = module if is_package else module.rpartition(".")[0]
    names = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names.extend(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - node.level + 1]
                prefix = ".".join(base + ([node.module] if node.module else []))
            else:
                prefix = node.module
            names.append(prefix)
            names.extend(f"{prefix}.{alias.name}" for alias in node.names if alias.name != "*")
        elif isinstance(node, ast.Call) and node.args and isinstance(node.args[0], ast.Constant):
            func = node.func
            called = func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", "")
            if called in ("import_module", "__import__") and isinstance(node.args[0].value, str):
                names.append(node.args[0].value)
    return names


def violations(source: str, module: str, is_package: bool = False) -> list:
    """Layering rules broken by ``source`` of the tether_sim module ``module``."""
    parts = module.split(".")
    layer = parts[1] if len(parts) > 1 else ""
    found = []
    for name in imported_modules(source, module, is_package):
        if layer != "ros" and ROS_MODULE.match(name):
            found.append(f"{module} imports {name} (ROS only in tether_sim.ros)")
        target = name.split(".")
        if target[0] == "tether_sim" and len(target) > 1 and target[1] in FORBIDDEN.get(layer, ()):
            found.append(f"{module} imports {name} ({layer} must not depend on {target[1]})")
    return found


def test_package_respects_the_layering():
    modules = sorted(PACKAGE.rglob("*.py"))
    assert len(modules) > 10
    found = []
    for path in modules:
        found += violations(path.read_text(), module_name(path), path.name == "__init__.py")
    assert not found, "\n".join(found)


@pytest.mark.parametrize("module, source", [
    ("tether_sim.physics.cable", "import rclpy"),
    ("tether_sim.io.mcap_log", "from geometry_msgs.msg import PoseStamped"),
    ("tether_sim.solvers.dg.solver", "def f():\n    from tether_sim.io.params import load_config"),
    ("tether_sim.solvers.dg.solver", "from ...io import params"),
    ("tether_sim.numerics.quadrature", "from tether_sim import config"),
    ("tether_sim.physics.bodies", "import importlib\nimportlib.import_module('tether_sim.ros.sim_node')"),
    ("tether_sim.scenarios.ropos", "from tether_sim.ros.convert import to_msg"),
    ("tether_sim.report", "from builtin_interfaces.msg import Time"),
    ("tether_sim.io.params", "from rcl_interfaces.msg import ParameterDescriptor"),
])
def test_checker_catches_forbidden_imports(module, source):
    assert violations(source, module)


@pytest.mark.parametrize("module, source", [
    ("tether_sim.ros.sim_node", "import rclpy\nfrom tether_sim_msgs.msg import TetherState\nfrom tether_sim.io import params"),
    ("tether_sim.physics.bodies", "from tether_sim.numerics.jit import jit\nfrom tether_sim.spec import param"),
    ("tether_sim.solvers.factory", "from .dg import solver\nfrom tether_sim.physics.cable import CableProperties"),
    ("tether_sim.io.params", "from tether_sim.config import SimConfig"),
])
def test_checker_allows_the_permitted_directions(module, source):
    assert violations(source, module) == []
