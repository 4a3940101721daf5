"""The set-up helpers in tools/: CMake include-path fix and data-file links (on scratch folders)."""

import runpy
import sys
import sysconfig
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
FOREIGN = ("/opt/python/cp311-cp311/include/python3.11;"
           "/opt/python/cp311-cp311/lib/python3.11/site-packages/numpy/_core/include")


@pytest.fixture(scope="module")
def fixer():
    pytest.importorskip("numpy")
    return runpy.run_path(str(ROOT / "tools" / "fix_cmake_paths.py"))["fix_cmake_exports"]


def test_foreign_include_paths_are_rewritten_once(tmp_path, fixer):
    import numpy

    export = tmp_path / "share" / "geometry_msgs" / "cmake" / "export_geometry_msgs__rosidl_generator_pyExport.cmake"
    export.parent.mkdir(parents=True)
    export.write_text(f'set_target_properties(x PROPERTIES\n  INTERFACE_INCLUDE_DIRECTORIES "{FOREIGN}"\n)\n')
    untouched = tmp_path / "share" / "std_msgs" / "cmake" / "other.cmake"
    untouched.parent.mkdir(parents=True)
    untouched.write_text("set(A /usr/include)\n")

    assert fixer(tmp_path) == [export]
    text = export.read_text()
    assert "/opt/python" not in text
    assert f'"{sysconfig.get_paths()["include"]};{numpy.get_include()}"' in text
    assert fixer(tmp_path) == []  # idempotent
    assert untouched.read_text() == "set(A /usr/include)\n"


def test_the_project_venv_has_no_foreign_include_paths():
    """In the make environment (.venv), no wheel CMake export still names /opt/python."""
    prefix = Path(sys.prefix)
    if prefix != (ROOT / ".venv").resolve() and prefix != ROOT / ".venv":
        pytest.skip("not running in the project's .venv")
    exports = list(prefix.glob("share/*/cmake/*.cmake"))
    assert len(exports) > 100
    assert not [p for p in exports if "/opt/python/" in p.read_text()]


def test_data_files_are_linked_and_stale_links_removed(tmp_path):
    link = runpy.run_path(str(ROOT / "tools" / "link_data_files.py"))["link_data_files"]
    repo, prefix = tmp_path / "repo", tmp_path / "prefix"
    (repo / "config").mkdir(parents=True)
    (repo / "resource").mkdir()
    (repo / "resource" / "demo").write_text("")
    (repo / "config" / "a.yaml").write_text("a: 1\n")
    (repo / "config" / "b.yaml").write_text("b: 2\n")
    (repo / "setup.py").write_text(
        "from glob import glob\nfrom setuptools import setup\n"
        "setup(name='demo', data_files=[('share/ament_index/resource_index/packages', ['resource/demo']),\n"
        "                               ('share/demo/config', sorted(glob('config/*.yaml')))],\n"
        "      entry_points={'console_scripts': ['demo-run = demo.main:main']})\n")
    (prefix / "bin").mkdir(parents=True)
    (prefix / "bin" / "demo-run").write_text("#!/bin/sh\n")

    made = link(repo, prefix)
    assert len(made) == 4
    # the console script where ros2 run / launch_ros look for it: <prefix>/lib/<package>/<name>
    script = prefix / "lib" / "demo" / "demo-run"
    assert script.is_symlink() and script.resolve() == (prefix / "bin" / "demo-run").resolve()
    a = prefix / "share" / "demo" / "config" / "a.yaml"
    assert a.is_symlink() and a.read_text() == "a: 1\n"
    assert (prefix / "share" / "ament_index" / "resource_index" / "packages" / "demo").exists()

    (repo / "config" / "b.yaml").unlink()  # a removed config file loses its link on the next run
    made = link(repo, prefix)
    assert len(made) == 3
    assert not (prefix / "share" / "demo" / "config" / "b.yaml").is_symlink()
    assert a.is_symlink()


def test_each_process_holds_its_own_ros_domain(ros_domain_id, isolated_ros_env):
    """The conftest reserved this process's domain with a lock no second claimant can take."""
    import fcntl
    import os
    import tempfile

    assert os.environ["ROS_DOMAIN_ID"] == str(ros_domain_id)
    assert os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] == "LOCALHOST"
    other = int(isolated_ros_env["ROS_DOMAIN_ID"])
    assert other != ros_domain_id and 1 <= other <= 101
    for domain in (ros_domain_id, other):
        with open(Path(tempfile.gettempdir()) / f"tether_sim_ros_domain_{domain}.lock", "a+") as handle:
            with pytest.raises(BlockingIOError):  # held by this process's earlier open file
                fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
