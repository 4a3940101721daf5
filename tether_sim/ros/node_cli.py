"""The command line of ``tether-sim`` before and after rclpy: its help, the ROS arguments it reads
(parameter files, ``-p`` values), their check before the node starts, and the quiet stop after a signal.
The node itself: :mod:`tether_sim.ros.sim_node`.
"""

import signal
import sys

import rclpy
import yaml

from tether_sim.errors import ConfigError
from tether_sim.io.params import check_values, load_config
from tether_sim.io.schema import key_map


USAGE = """usage: tether-sim [-h] [--ros-args [--params-file FILE] [-p KEY:=VALUE] [-r FROM:=TO] ...]

The real-time tether simulation node (docs/node.md). Every configuration key of
docs/parameters.md is a ROS parameter: give a parameter file (config/*.yaml) with --params-file
and single values with -p (e.g. -p use_sim_time:=true). Inputs /ship/pose, /vehicle/pose; outputs
/tether/state, /tether/marker, /tether/path, wrenches, snap events, slack warnings, /diagnostics.

  tether-sim --ros-args --params-file config/ropos_L200.yaml
"""


def wants_help(argv) -> bool:
    """-h/--help before any --ros-args section."""
    for a in argv[1:]:
        if a == "--ros-args":
            return False
        if a in ("-h", "--help"):
            return True
    return False


def _ros_arg_values(argv, flags):
    """The values that follow any of ``flags`` inside the ``--ros-args`` sections of ``argv``."""
    in_ros = False
    for i, a in enumerate(argv):
        if a == "--ros-args":
            in_ros = True
        elif a == "--":
            in_ros = False
        elif in_ros and a in flags and i + 1 < len(argv):
            yield argv[i + 1]


def _cli_params(argv):
    """(name, text) of each ``-p``/``--param NAME:=VALUE`` inside ``--ros-args`` (a ``node:`` prefix
    dropped from the name)."""
    for item in _ros_arg_values(argv, ("-p", "--param")):
        if ":=" in item:
            name, _, text = item.partition(":=")
            yield name.rsplit(":", 1)[-1], text


def cli_param_keys(argv) -> set:
    """Parameter names set with ``-p``/``--param NAME:=VALUE`` inside ``--ros-args``."""
    return {name for name, _ in _cli_params(argv)}


def params_files(argv) -> list:
    """The files given with ``--params-file`` inside ``--ros-args`` sections of ``argv``."""
    return list(_ros_arg_values(argv, ("--params-file",)))


def cli_param_values(argv) -> dict:
    """{name: value} of the ``-p NAME:=VALUE`` of ``argv`` that are tether_sim keys (values read as YAML,
    as ROS reads them)."""
    keys, out = key_map(), {}
    for name, text in _cli_params(argv):
        if name in keys:
            try:
                out[name] = yaml.safe_load(text) if text else ""
            except yaml.YAMLError:
                out[name] = text
    return out


def check_params_files(files, overrides=None) -> None:
    """Validate the tether_sim sections of parameter files with the command line's ``-p`` values over
    them (``-p dg.resolution:=manual`` rescues a file the automatic mesh choice refuses); a ConfigError
    names key and file."""
    if overrides:
        check_values(overrides, where="command-line -p override")
    for f in files:
        try:
            load_config(f, overrides)
        except ConfigError as exc:
            if "no 'tether_sim'" not in str(exc):  # a file for other nodes only is fine
                raise


def stop_flag() -> list:
    """SIGINT and SIGTERM from now on append their name to the returned list (once) instead of raising or
    shutting rclpy down: a node's loop reads it between its spin_once calls (see :func:`spin_until_signal`)."""
    got = []

    def request_stop(signum, _frame):
        if not got:
            got.append(signal.Signals(signum).name)

    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, request_stop)
    return got


def spin_until_signal(node, executor) -> str | None:
    """Spin ``node`` on ``executor`` until SIGINT / SIGTERM or an rclpy shutdown; the signal's name, or None.

    The signals only set a flag that this loop reads between callbacks: neither Python's KeyboardInterrupt nor
    rclpy's shutdown then lands inside rclpy's own code (a SIGINT raised while the executor builds a callback's
    task left that task half made, and its clean-up printed a traceback at exit). The wait is bounded (0.1 s), so
    a signal stops the node within one wait even when no timer is due."""
    got = stop_flag()
    executor.add_node(node)
    while not got and rclpy.ok():
        executor.spin_once(timeout_sec=0.1)
    return got[0] if got else None


def ignore_further_signals() -> None:
    """Once the node is stopping, more SIGINT/SIGTERM must not cut its clean-up short: Ctrl-C on
    ``ros2 launch`` reaches the node twice (the terminal's SIGINT to the process group, then launch's
    own), and launch follows with SIGTERM if the node is still alive after 5 s. Ignored at the OS level
    (SIG_IGN): Python keeps that through its own exit, where it resets a handler of its own to the
    default (killed by SIGINT, exit code -2, "process has died" in launch)."""
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, signal.SIG_IGN)


def say_stopped(node, how):
    """The one line on what a node stopped by a signal did (it writes no file: nothing to close; exit code 0,
    as ROS launch expects of a node told to stop)."""
    if hasattr(node, "account"):
        print(f"tether-sim: stopped by {how}: {node.account()}", file=sys.stderr)
