"""Other ROS 2 traffic on the machine does not reach the tests: a publisher started the way a
user's node is (the usual Fast DDS ports, LOCALHOST discovery) in this test process's own domain is
never received, while one started with the test environment (test/conftest.py, tools/fastdds_test.xml)
is. The same subscriber in the usual set-up receives the outside publisher, so the check can fail."""

import os
import subprocess
import sys
import time

import pytest

pytest.importorskip("rclpy")

pytestmark = pytest.mark.ros

PUBLISHER = """
import sys, time, rclpy
from std_msgs.msg import String
rclpy.init()
node = rclpy.create_node("isolation_probe_" + sys.argv[1])
pub = node.create_publisher(String, "/isolation_probe", 10)
end = time.monotonic() + float(sys.argv[2])
while time.monotonic() < end:
    pub.publish(String(data=sys.argv[1]))
    time.sleep(0.05)
"""


def received(listener_env: dict, publishers: dict, seconds: float = 5.0) -> dict:
    """Messages per publisher name received by a listener process started with ``listener_env``
    while each publisher runs with its own environment."""
    code = f"""
import collections, time, rclpy
from std_msgs.msg import String
rclpy.init()
node = rclpy.create_node("isolation_listener")
count = collections.Counter()
node.create_subscription(String, "/isolation_probe", lambda m: count.update([m.data]), 50)
end = time.monotonic() + {seconds}
while time.monotonic() < end:
    rclpy.spin_once(node, timeout_sec=0.05)
print(dict(count))
"""
    listener = subprocess.Popen([sys.executable, "-c", code], env=listener_env, stdout=subprocess.PIPE, text=True)
    time.sleep(0.3)
    procs = [subprocess.Popen([sys.executable, "-c", PUBLISHER, name, str(seconds - 1.0)], env=env)
             for name, env in publishers.items()]
    out, _ = listener.communicate(timeout=60 + seconds)
    for proc in procs:
        proc.wait(timeout=30)
    return eval(out.strip().splitlines()[-1])  # noqa: S307 - a dict this test printed


def test_outside_ros_traffic_in_the_tests_domain_is_not_received():
    test_env = dict(os.environ)  # as conftest set it: this process's domain, the test profile
    assert test_env["FASTRTPS_DEFAULT_PROFILES_FILE"].endswith("fastdds_test.xml"), \
        "run with the test profile (TETHER_SIM_TEST_FASTDDS_PROFILE unset)"
    outside = {k: v for k, v in test_env.items() if k != "FASTRTPS_DEFAULT_PROFILES_FILE"}  # a user's node
    counts = received(test_env, {"inside": test_env, "outside": outside})
    # (publishing at 20 Hz for 4 s; on a loaded machine discovery takes a second or two)
    assert counts.get("inside", 0) > 0 and counts.get("outside", 0) == 0, counts
    # control: a listener in the usual set-up, same domain, does receive the outside publisher
    counts = received(outside, {"outside": outside})
    assert counts.get("outside", 0) > 0, counts
