"""The watcher (python -m tether_sim.ros.watch) stopped by Ctrl-C at any moment ends with exit 0.

rclpy's SIGINT handler shuts the context down; when that happens between the loop's rclpy.ok() and
spin_once's wait, rclpy raises RCLError ("the given context is not valid") instead of KeyboardInterrupt.
The test makes that moment happen on purpose."""

import pytest

pytest.importorskip("rclpy")
pytest.importorskip("tether_sim_msgs")

import rclpy  # noqa: E402
from rclpy._rclpy_pybind11 import RCLError  # noqa: E402

from tether_sim.ros import watch  # noqa: E402

pytestmark = pytest.mark.ros


def test_a_stop_while_spin_once_sets_up_its_wait_is_a_clean_exit(monkeypatch):
    def stopped_inside(node, timeout_sec=None):
        rclpy.shutdown()  # as rclpy's signal handler does
        raise RCLError("failed to create timer: the given context is not valid")

    monkeypatch.setattr(watch.rclpy, "spin_once", stopped_inside)
    assert watch.main(["watch", "--duration", "5"]) == 0


def test_any_other_error_while_running_is_not_hidden(monkeypatch):
    def broken(node, timeout_sec=None):
        raise RuntimeError("a real error")

    monkeypatch.setattr(watch.rclpy, "spin_once", broken)
    with pytest.raises(RuntimeError, match="a real error"):
        watch.main(["watch", "--duration", "5"])
