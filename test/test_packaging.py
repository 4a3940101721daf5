"""package.xml, setup.py, tools/requirements.txt and the code agree (name, version, dependencies).

colcon reads package.xml, pip reads setup.py and `make` installs tools/requirements.txt; a
dependency declared in one but not the others breaks one of those three installs.
"""

import ast
import os
import re
import runpy
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
import setuptools

ROOT = Path(__file__).resolve().parent.parent
PACKAGE = "tether_sim"

# Python distribution (setup.py install_requires) -> rosdep key in package.xml
# (mcap has no key of its own: mcap-ros2-support's key installs it as a pip dependency)
ROSDEP_KEY = {
    "numpy": "python3-numpy",
    "scipy": "python3-scipy",
    "matplotlib": "python3-matplotlib",
    "PyYAML": "python3-yaml",
    "tqdm": "python3-tqdm",
    "numba": "python3-numba",
    "mcap": "mcap-ros2-support",
    "mcap-ros2-support": "mcap-ros2-support",
    "rosbags": "python3-rosbags-pip",
}
# keys that rosdistro's rosdep database defines (rosdep/python.yaml of ros/rosdistro at commit
# 8468e88c, 2026-08-22, read 2026-11-26): `rosdep install` fails on a key not in it
ROSDISTRO_KEYS = {"python3-numpy", "python3-scipy", "python3-matplotlib", "python3-yaml", "python3-tqdm",
                  "python3-numba", "mcap-ros2-support", "python3-rosbags-pip", "python3-pytest"}
# import name -> distribution, where they differ
DISTRIBUTION_OF_IMPORT = {"yaml": "PyYAML", "mcap_ros2": "mcap-ros2-support"}
# modules provided by ROS packages (declared as exec_depend in package.xml instead)
ROS_MODULE = re.compile(r"^(rclpy|ament_index_python|rosidl_\w+|\w+_interfaces|\w+_msgs)$")

CONSOLE_SCRIPTS = {  # CONTRACTS.md
    "tether-sim": "tether_sim.ros.sim_node:main",
    "tether-sim-offline": "tether_sim.ros.offline:main",
    "tether-sim-record": "tether_sim.ros.recorder_node:main",
    "tether-sim-replay": "tether_sim.ros.replay_node:main",
    "tether-sim-report": "tether_sim.report:main",
    "tether-sim-study": "tether_sim.studies.cli:main",
    "tether-sim-recover": "tether_sim.io.mcap_recover:main",
    "tether-sim-poses": "tether_sim.ros.pose_source:main",
    "tether-sim-vehicle": "tether_sim.ros.vehicle_node:main",
    "tether-sim-rov-demo": "tether_sim.ros.rov_demo:main",
}


def setup_kwargs(path: Path) -> dict:
    """The keyword arguments setup.py passes to setuptools.setup (setup.py is run, not installed)."""
    captured = {}
    real = setuptools.setup
    setuptools.setup = lambda **kwargs: captured.update(kwargs)
    cwd = Path.cwd()
    try:
        os.chdir(path.parent)
        try:
            runpy.run_path(str(path), run_name="__main__")
        finally:
            os.chdir(cwd)
    finally:
        setuptools.setup = real
    return captured


def manifest(path: Path) -> ET.Element:
    return ET.parse(path).getroot()


def deps(root: ET.Element, *tags) -> set:
    return {e.text.strip() for tag in tags for e in root.findall(tag)}


@pytest.fixture(scope="module")
def setup_py():
    return setup_kwargs(ROOT / "setup.py")


@pytest.fixture(scope="module")
def package_xml():
    return manifest(ROOT / "package.xml")


def _requirement_name(spec: str) -> str:
    return re.split(r"[\s\[<>=!~;]", spec.strip(), maxsplit=1)[0]


def test_name_and_version_agree(setup_py, package_xml):
    import tether_sim

    assert package_xml.get("format") == "3"
    assert package_xml.findtext("name") == setup_py["name"] == PACKAGE
    assert package_xml.findtext("version") == setup_py["version"] == tether_sim.__version__
    assert package_xml.find("export/build_type").text == "ament_python"
    assert package_xml.findtext("license") == setup_py["license"]


def test_manifests_pass_catkin_pkg_validation():
    """colcon and rosdep parse package.xml with catkin_pkg, which rejects e.g. bad e-mails."""
    catkin_pkg = pytest.importorskip("catkin_pkg.package")
    for path in (ROOT / "package.xml", ROOT / "msg_defs" / "package.xml"):
        pkg = catkin_pkg.parse_package(str(path))
        pkg.validate()
        assert pkg.package_format == 3


def test_python_dependencies_agree(setup_py, package_xml):
    required = {_requirement_name(r) for r in setup_py["install_requires"]} - {"setuptools"}
    assert required == set(ROSDEP_KEY), "setup.py install_requires and ROSDEP_KEY differ"
    python_keys = {d for d in deps(package_xml, "exec_depend", "depend")
                   if d.startswith("python3-") or d in ROSDEP_KEY.values()}
    assert python_keys == {ROSDEP_KEY[r] for r in required}


def test_rosdep_keys_exist_in_rosdistro(package_xml):
    """Every non-ROS-package key of package.xml is a key of rosdistro's database (a checked list)."""
    keys = {d for d in deps(package_xml, "exec_depend", "depend", "test_depend", "build_depend")
            if d.startswith("python3-") or d in ROSDEP_KEY.values()}
    assert keys <= ROSDISTRO_KEYS, keys - ROSDISTRO_KEYS


def _imports_of(path: Path) -> set:
    tree = ast.parse(path.read_text(), filename=str(path))
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names.update(a.name.split(".")[0] for a in node.names)
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names.add(node.module.split(".")[0])
    return names


def test_every_imported_library_is_declared(setup_py, package_xml):
    """Third-party imports in tether_sim/ appear in install_requires (or its extras), ROS ones in package.xml."""
    required = {_requirement_name(r) for r in setup_py["install_requires"]}
    required |= {_requirement_name(r) for extra in setup_py.get("extras_require", {}).values() for r in extra}
    ros_deps = deps(package_xml, "exec_depend", "depend")
    missing = []
    for path in sorted((ROOT / PACKAGE).rglob("*.py")):
        for name in _imports_of(path) - set(sys.stdlib_module_names) - {PACKAGE}:
            if ROS_MODULE.match(name):
                if name not in ros_deps:
                    missing.append(f"{path.relative_to(ROOT)}: {name} (package.xml exec_depend)")
            elif DISTRIBUTION_OF_IMPORT.get(name, name) not in required:
                missing.append(f"{path.relative_to(ROOT)}: {name} (setup.py install_requires)")
    assert not missing, "undeclared dependencies:\n" + "\n".join(missing)


def test_ros_dependencies_are_in_the_make_environment(package_xml):
    """Every ROS package that package.xml needs at run time is installed by tools/requirements.txt."""
    lines = (ROOT / "tools" / "requirements.txt").read_text().splitlines()
    wheels = {_requirement_name(x) for x in lines if x.strip() and not x.startswith("#")}
    for dep in deps(package_xml, "exec_depend", "depend"):
        if dep.startswith("python3-") or dep in ROSDEP_KEY.values() or dep in ("tether_sim_msgs", "tf2_msgs"):
            continue  # the two interface packages are built from msg_defs/ by tools/setup_env.sh
        assert f"ros-jazzy-{dep.replace('_', '-')}" in wheels, f"{dep} is not in tools/requirements.txt"
    for name in ROSDEP_KEY:
        assert name in wheels, f"{name} is not in tools/requirements.txt"


def test_console_scripts_follow_the_contract(setup_py):
    scripts = dict(
        (k.strip(), v.strip()) for k, v in (e.split("=", 1) for e in setup_py["entry_points"]["console_scripts"])
    )
    assert scripts == CONSOLE_SCRIPTS


def test_data_files_install_the_ament_index_marker_and_manifest(setup_py):
    data = {target: list(sources) for target, sources in setup_py["data_files"]}
    assert data["share/ament_index/resource_index/packages"] == [f"resource/{PACKAGE}"]
    assert (ROOT / "resource" / PACKAGE).is_file()
    assert data[f"share/{PACKAGE}"] == ["package.xml"]
    assert sorted(data[f"share/{PACKAGE}/config"]) == sorted(
        str(p.relative_to(ROOT)) for p in [*(ROOT / "config").glob("*.yaml"), *(ROOT / "config").glob("*.txt")])
    # every folder of config/ is installed; the study files next to the files their `base:` names
    folders = sorted(p.name for p in (ROOT / "config").iterdir() if p.is_dir())
    assert folders == ["studies"]
    assert sorted(data[f"share/{PACKAGE}/config/studies"]) == sorted(
        str(p.relative_to(ROOT)) for p in (ROOT / "config" / "studies").glob("*.yaml"))
    packages = set(setup_py["packages"])
    assert PACKAGE in packages and not any(p.startswith("test") for p in packages)


def test_interface_package_declares_what_its_messages_use():
    """msg_defs/: package.xml depends, CMake DEPENDENCIES and the .msg field types agree."""
    root = manifest(ROOT / "msg_defs" / "package.xml")
    assert root.findtext("name") == "tether_sim_msgs"
    assert root.findtext("member_of_group") == "rosidl_interface_packages"
    assert root.find("export/build_type").text == "ament_cmake"
    declared = deps(root, "depend")
    cmake = (ROOT / "msg_defs" / "CMakeLists.txt").read_text()
    cmake_deps = set(re.search(r"DEPENDENCIES\s+([^)]*)\)", cmake).group(1).split())
    used = set()
    for msg in (ROOT / "msg_defs" / "msg").glob("*.msg"):
        assert f'"msg/{msg.name}"' in cmake, f"{msg.name} is not generated by CMakeLists.txt"
        for line in msg.read_text().splitlines():
            kind = line.partition("#")[0].split()
            if kind and "/" in kind[0]:
                used.add(kind[0].split("/")[0])
    assert used == declared == cmake_deps
