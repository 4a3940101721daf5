"""Helpers shared by the recorder and replay nodes: message classes, QoS <-> rosbag2 offers."""

from __future__ import annotations

import importlib
import signal

from rclpy.qos import (DurabilityPolicy, HistoryPolicy, LivelinessPolicy, QoSProfile,
                       ReliabilityPolicy)

from tether_sim.io.msg_definitions import split_type_name

_NS_PER_S = 1_000_000_000


def message_class(type_name: str):
    """'pkg/msg/Type' -> the generated Python class (ImportError/AttributeError names the type)."""
    pkg, namespace, name = split_type_name(type_name)
    try:
        return getattr(importlib.import_module(f"{pkg}.{namespace}"), name)
    except (ImportError, AttributeError) as exc:
        raise ImportError(f"message type {type_name} is not installed in this environment "
                          f"({exc})") from exc


def _duration_dict(duration) -> dict:
    ns = int(duration.nanoseconds)
    return {"sec": ns // _NS_PER_S, "nsec": ns % _NS_PER_S}


def offer_to_dict(qos: QoSProfile) -> dict:
    """A discovered publisher QoS as rosbag2 stores it (metadata v9: lower-case enum names)."""
    return {"history": qos.history.name.lower(), "depth": int(qos.depth),
            "reliability": qos.reliability.name.lower(),
            "durability": qos.durability.name.lower(),
            "deadline": _duration_dict(qos.deadline), "lifespan": _duration_dict(qos.lifespan),
            "liveliness": qos.liveliness.name.lower(),
            "liveliness_lease_duration": _duration_dict(qos.liveliness_lease_duration),
            "avoid_ros_namespace_conventions": bool(qos.avoid_ros_namespace_conventions)}


def adapted_subscription_qos(offers: list[dict], depth: int) -> QoSProfile:
    """rosbag2's rule: RELIABLE / TRANSIENT_LOCAL only when every publisher offers it."""
    reliable = bool(offers) and all(o["reliability"] == "reliable" for o in offers)
    latched = bool(offers) and all(o["durability"] == "transient_local" for o in offers)
    return QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=depth,
                      reliability=ReliabilityPolicy.RELIABLE if reliable else ReliabilityPolicy.BEST_EFFORT,
                      durability=DurabilityPolicy.TRANSIENT_LOCAL if latched else DurabilityPolicy.VOLATILE,
                      liveliness=LivelinessPolicy.AUTOMATIC)


def replay_qos(offers: list[dict], depth: int) -> QoSProfile:
    """Publisher QoS for a recorded topic: latched topics TRANSIENT_LOCAL depth 1, else the
    recorded reliability (RELIABLE when unknown) with the given depth."""
    latched = bool(offers) and all(o.get("durability") == "transient_local" for o in offers)
    if latched:
        return QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                          durability=DurabilityPolicy.TRANSIENT_LOCAL)
    best_effort = bool(offers) and all(o.get("reliability") == "best_effort" for o in offers)
    return QoSProfile(depth=depth, reliability=ReliabilityPolicy.BEST_EFFORT if best_effort
                      else ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.VOLATILE)


def clock_qos() -> QoSProfile:
    """/clock: best effort, depth 1 (what rclpy's TimeSource subscribes with)."""
    return QoSProfile(depth=1, reliability=ReliabilityPolicy.BEST_EFFORT)


def wait_for(predicate, timeout_s: float, spin_node=None, step_s: float = 0.05, context=None) -> bool:
    """Poll predicate() (spinning spin_node if given) until true, timeout or the shutdown of
    ``context`` (rclpy's default context if None); returns the result."""
    import time

    import rclpy

    deadline = time.monotonic() + timeout_s
    while True:
        if predicate():
            return True
        if time.monotonic() >= deadline or not rclpy.ok(context=context):
            return False
        if spin_node is not None:
            rclpy.spin_once(spin_node, timeout_sec=step_s)
        else:
            time.sleep(step_s)


def stop_on_signals(node) -> None:
    """SIGINT and SIGTERM set ``node.stopped`` so the node's own loop closes its file cleanly."""

    def request_stop(signum, _frame):
        node.stopped = True

    signal.signal(signal.SIGINT, request_stop)
    signal.signal(signal.SIGTERM, request_stop)
