"""The repository as a colcon workspace, as the README's colcon block lays it out: `colcon list`
finds both packages (tether_sim at the root, tether_sim_msgs through the link to msg_defs/), and
`colcon build` builds both, the messages first, against the venv's ROS 2 Jazzy wheels.

colcon is installed by `make setup` into a venv of its own (.venv/colcon/, tools/colcon-requirements.txt);
without it these tests skip and say so. The build of both packages takes ~1.5 min of one core
(rosidl generates and compiles the type supports of six messages), so it runs once per session.
"""

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
COLCON = ROOT / ".venv" / "colcon" / "bin" / "colcon"
PREFIX = Path(sys.prefix)  # the venv: ament_cmake, rosidl and the message wheels
SCRIPTS = {"tether-sim", "tether-sim-offline", "tether-sim-record", "tether-sim-replay", "tether-sim-report",
           "tether-sim-study", "tether-sim-recover", "tether-sim-poses", "tether-sim-vehicle", "tether-sim-rov-demo"}

pytestmark = pytest.mark.skipif(not COLCON.is_file(), reason=f"colcon is not installed ({COLCON}; `make setup` installs it)")


def source_files() -> list:
    """The repository's files as a clone has them (tracked, plus new files not ignored)."""
    out = subprocess.run(["git", "ls-files", "-co", "--exclude-standard", "-z"], cwd=ROOT, check=True,
                         capture_output=True).stdout.decode()
    return [f for f in out.split("\0") if f and (ROOT / f).is_file()]


@pytest.fixture(scope="module")
def workspace(tmp_path_factory):
    """~/tether_ws of the README: src/tether_sim (the clone) and the link src/tether_sim_msgs."""
    if shutil.which("git") is None or not (ROOT / ".git").exists():
        pytest.skip("needs the repository's git checkout to lay out the workspace")
    ws = tmp_path_factory.mktemp("tether_ws")
    clone = ws / "src" / "tether_sim"
    for name in source_files():
        (clone / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(ROOT / name, clone / name)
    (ws / "src" / "tether_sim_msgs").symlink_to("tether_sim/msg_defs")  # the README's `ln -s` line
    return ws


def colcon(ws: Path, *args, timeout=60) -> str:
    libs = [str(PREFIX / "lib")] + [str(p) for p in sorted((PREFIX / "lib").glob("python3*/site-packages/ros_*.libs"))]
    env = dict(os.environ, AMENT_PREFIX_PATH=str(PREFIX), CMAKE_PREFIX_PATH=str(PREFIX),
               LD_LIBRARY_PATH=os.pathsep.join(libs + [os.environ.get("LD_LIBRARY_PATH", "")]),
               PATH=os.pathsep.join([str(COLCON.parent), str(PREFIX / "bin"), os.environ["PATH"]]),
               COLCON_HOME=str(ws / ".colcon"), COLCON_LOG_PATH=str(ws / "log"))
    done = subprocess.run([str(COLCON), *args], cwd=ws, env=env, capture_output=True, text=True, timeout=timeout)
    assert done.returncode == 0, f"colcon {' '.join(args)} failed:\n{done.stdout[-3000:]}\n{done.stderr[-3000:]}"
    return done.stdout


DEBIAN_COLCON = Path("/usr/bin/colcon")  # Debian's packages (apt install colcon python3-colcon-ros ...)


@pytest.mark.skipif(not DEBIAN_COLCON.is_file(), reason="Debian's colcon is not installed (/usr/bin/colcon)")
def test_debians_colcon_lists_both_packages_messages_first(workspace):
    """The same layout through the distribution's colcon (a different colcon-core and colcon-ros than the
    venv's): both packages, the messages first."""
    env = dict(os.environ, COLCON_HOME=str(workspace / ".colcon-debian"), COLCON_LOG_PATH=str(workspace / "log-debian"))
    done = subprocess.run([str(DEBIAN_COLCON), "list", "--topological-order"], cwd=workspace, env=env,
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr[-3000:]
    listed = [line.split("\t") for line in done.stdout.splitlines()]
    assert [(name, kind) for name, _, kind in listed] == [("tether_sim_msgs", "(ros.ament_cmake)"),
                                                          ("tether_sim", "(ros.ament_python)")]


def test_readme_block_makes_the_link(workspace):
    readme = (ROOT / "README.md").read_text()
    assert "ln -s tether_sim/msg_defs tether_sim_msgs" in readme
    assert not (ROOT / "msg_defs" / "COLCON_IGNORE").exists()


def test_colcon_lists_both_packages_messages_first(workspace):
    listed = [line.split("\t") for line in colcon(workspace, "list").splitlines()]
    assert {(name, kind) for name, _, kind in listed} == {("tether_sim", "(ros.ament_python)"),
                                                          ("tether_sim_msgs", "(ros.ament_cmake)")}
    order = colcon(workspace, "list", "--topological-order", "--names-only").split()
    assert order == ["tether_sim_msgs", "tether_sim"]
    # the alternative the README gives: no link, both base paths
    (workspace / "src" / "tether_sim_msgs").unlink()
    try:
        names = colcon(workspace, "list", "--names-only", "--base-paths", "src", "src/tether_sim/msg_defs").split()
        assert sorted(names) == ["tether_sim", "tether_sim_msgs"]
        assert colcon(workspace, "list", "--names-only").split() == ["tether_sim"]  # what was wrong before
    finally:
        (workspace / "src" / "tether_sim_msgs").symlink_to("tether_sim/msg_defs")


@pytest.mark.slow
def test_colcon_builds_both_packages(workspace):
    colcon(workspace, "build", "--event-handlers", "console_direct-", "--cmake-args",
           f"-DPython3_EXECUTABLE={PREFIX / 'bin' / 'python'}", "-DBUILD_TESTING=OFF", timeout=1200)
    install = workspace / "install"
    assert {p.name for p in (install / "tether_sim" / "lib" / "tether_sim").iterdir()} == SCRIPTS
    share = install / "tether_sim" / "share"
    assert (share / "ament_index" / "resource_index" / "packages" / "tether_sim").is_file()
    for item in ("package.xml", "launch/tether_sim.launch.py", "config/ropos_L200.yaml", "rviz/tether_sim.rviz"):
        assert (share / "tether_sim" / item).is_file(), item
    msgs = install / "tether_sim_msgs"
    assert (msgs / "share" / "ament_index" / "resource_index" / "packages" / "tether_sim_msgs").is_file()
    # the built messages (not the venv's own copy) serialize and deserialize through rclpy
    site = next(msgs.glob("lib/python3*/site-packages"))
    code = ("import tether_sim_msgs.msg as m, rclpy.serialization as s; x = m.TetherState(ship_end_tension=1.5);"
            "y = s.deserialize_message(s.serialize_message(x), m.TetherState); print(m.__file__, y.ship_end_tension)")
    env = dict(os.environ, PYTHONPATH=str(site),
               LD_LIBRARY_PATH=os.pathsep.join([str(msgs / "lib"), os.environ.get("LD_LIBRARY_PATH", "")]))
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr[-3000:]
    path, value = out.stdout.split()
    assert Path(path).is_relative_to(site) and float(value) == 1.5
