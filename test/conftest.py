"""Test-session set-up shared by the whole suite: ROS 2 isolation and the ``ros`` marker.

ROS isolation (applied when this file is imported, before any test imports rclpy; every pytest
process, including each pytest-xdist worker, does it for itself):

- ``ROS_DOMAIN_ID``: a domain id of this process's own, claimed with an exclusive lock file
  (``<tmp>/tether_sim_ros_domain_<id>.lock``, held until the process exits; the kernel drops
  the lock even when the process is killed), so concurrent test runs on one machine, and the
  workers of one run, never share a domain.
- ``ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST``: discovery never leaves the machine (Jazzy).
- ``FASTRTPS_DEFAULT_PROFILES_FILE``: tools/fastdds_test.xml (UDP on 127.0.0.1 + shared
  memory, unicast discovery to 127.0.0.1, so no socket is opened on an external interface; and
  Fast DDS's well-known ports moved by half a domain, so ROS 2 processes outside the tests, which
  use the usual ports and know nothing of the lock files, are never discovered whatever their
  domain: a user's node in the test's domain cannot feed it poses or a clock).
  Set ``TETHER_SIM_TEST_FASTDDS_PROFILE=none`` to run with Fast DDS defaults instead (then only
  the domain id keeps the tests apart from other ROS 2 traffic).

Child processes started by tests inherit all of it through ``os.environ``; the fixture
``isolated_ros_env`` gives a copy of the environment with another reserved domain id, for a
group of processes that must not see this process's nodes.

Tests under ``test/ros/`` are marked ``ros``. Without rclpy (e.g. a plain dev venv) they are
skipped, unless ``TETHER_SIM_REQUIRE_ROS=1`` (set by ``make test``) turns that into a failure.
"""

import errno
import fcntl
import os
import random
import tempfile
from pathlib import Path

import pytest

REPO_ROOT = Path(__file__).resolve().parent.parent
FASTDDS_PROFILE = REPO_ROOT / "tools" / "fastdds_test.xml"
# the profile's ports are 7525 + 250 * domain + up to ~250, which stays below 32768 for domain <= 99
DOMAIN_IDS = range(1, 100)

_domain_locks = {}  # domain id -> open lock file: the domain ids this process holds


def claim_ros_domain_id() -> int:
    """Reserve a new ROS domain id that no other process on this machine holds, until exit."""
    ids = list(DOMAIN_IDS)
    start = random.SystemRandom().randrange(len(ids))
    for domain in ids[start:] + ids[:start]:
        path = Path(tempfile.gettempdir()) / f"tether_sim_ros_domain_{domain}.lock"
        handle = open(path, "a+")
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as exc:
            handle.close()
            if exc.errno in (errno.EWOULDBLOCK, errno.EACCES):
                continue
            raise
        _domain_locks[domain] = handle
        return domain
    raise RuntimeError(f"no free ROS domain id: all {len(DOMAIN_IDS)} are held by running test processes")


def release_ros_domain_id(domain: int) -> None:
    """Give back a domain id reserved with :func:`claim_ros_domain_id` (closing drops the lock)."""
    handle = _domain_locks.pop(domain, None)
    if handle is not None:
        handle.close()


def _isolate_ros() -> None:
    os.environ["ROS_DOMAIN_ID"] = str(claim_ros_domain_id())
    os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
    os.environ.pop("ROS_LOCALHOST_ONLY", None)  # deprecated on Jazzy; conflicts with the above
    os.environ.pop("ROS_STATIC_PEERS", None)
    if os.environ.get("TETHER_SIM_TEST_FASTDDS_PROFILE", "") != "none":
        os.environ["FASTRTPS_DEFAULT_PROFILES_FILE"] = str(FASTDDS_PROFILE)
    os.environ.setdefault("RMW_IMPLEMENTATION", "rmw_fastrtps_cpp")
    os.environ.setdefault("MPLBACKEND", "Agg")


_isolate_ros()


def _rclpy_available() -> bool:
    try:
        import rclpy  # noqa: F401
    except ImportError:
        return False
    return True


def pytest_collection_modifyitems(config, items):
    ros_dir = REPO_ROOT / "test" / "ros"
    have_rclpy = None
    for item in items:
        if ros_dir in Path(str(item.fspath)).parents:
            item.add_marker(pytest.mark.ros)
        if item.get_closest_marker("ros") is None:
            continue
        if have_rclpy is None:
            have_rclpy = _rclpy_available()
        if not have_rclpy and os.environ.get("TETHER_SIM_REQUIRE_ROS") != "1":
            item.add_marker(pytest.mark.skip(reason="rclpy not importable (run `make test` for the ROS tests)"))


@pytest.fixture(scope="session")
def ros_domain_id() -> int:
    """The ROS domain id reserved for this test process."""
    return int(os.environ["ROS_DOMAIN_ID"])


@pytest.fixture
def isolated_ros_env():
    """Environment for a group of child processes in a domain of their own (reserved for the test)."""
    domain = claim_ros_domain_id()
    env = dict(os.environ)
    env["ROS_DOMAIN_ID"] = str(domain)
    yield env
    release_ros_domain_id(domain)


@pytest.fixture
def ros_context(ros_domain_id):
    """An initialised rclpy Context of its own (in this process's domain), shut down afterwards."""
    import rclpy
    from rclpy.context import Context

    context = Context()
    rclpy.init(args=None, context=context, domain_id=ros_domain_id)
    try:
        yield context
    finally:
        if context.ok():
            rclpy.shutdown(context=context)
