"""The simulation node's published messages, this tree against another checkout, tick by tick.

Builds the node (``TetherSimNode`` from the parameter file) of this tree and of ``--baseline`` (a
renamed copy, as bench_tick.load_baseline) in one process, drives both by hand as
bench_node_tick.py does (the same simulated clock, the same ship poses on the file's motion, the
1 Hz diagnostics every output_rate ticks; no wall-clock budget per tick, so that the machine's load
cannot cut one node's tick short) with every publisher counted as subscribed, and records
what each publisher is handed. Per tick the two nodes' messages are compared topic by topic: equal
bytes, else deserialized and compared field by field with the wall-clock fields set to zero
(TetherState.real_time_factor; the /diagnostics values real_time_factor, tick_load, tick_max_ms).
Prints the counts and the first differences; exit code 1 when any message differs.

A line-network file (config/ropos_tms.yaml) builds the network node of each tree, the ship on the
fairlead circle of bench_node_tick.py, the other driven points held at their configured positions.

A topic this tree sends less often than the baseline (``node.visual_rate``: marker, path and /tf on
every fifth output by default) is compared where both sent it: each message this tree publishes must
equal the baseline's of the same tick, and the ticks the baseline alone published are counted
("left out"). A configuration key only one tree has (a new key) is left out of the comparison of
/tether/description's parameter list and named.

Usage: .venv/bin/python benchmarks/compare_node_outputs.py --baseline ../other-checkout
           [--params config/ropos_L1730.yaml ...] [--ticks 600] [-p node.tf_tether_frames:=3]
"""

import argparse
import os
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

WALL_CLOCK_VALUES = ("real_time_factor", "tick_load", "tick_max_ms")


class _Recorded:
    """One node of one tree, driven by hand; ``log[k]`` = [(topic, bytes)] published at tick k."""

    def __init__(self, pkg, params, overrides):
        import importlib

        from geometry_msgs.msg import PoseStamped

        from benchmarks.bench_node_tick import is_network, network_ship_motion

        sim_node = importlib.import_module(f"{pkg}.ros.sim_node")
        self.convert = importlib.import_module(f"{pkg}.ros.convert")
        build_motion = importlib.import_module(f"{pkg}.physics.motion").build_motion
        self.held = {}
        if is_network(params):  # a line network: its node, the ship on the live files' circle, the other points held
            network_node = importlib.import_module(f"{pkg}.ros.network_node")
            self.node = network_node.NetworkSimNode(files=[str(params)], overrides={p.name: p.value for p in overrides})
            self.motion = network_ship_motion(self.node.spec.points["ship"].position)
            self.held = {n: p.position for n, p in self.node.spec.points.items() if p.kind == "prescribed" and n != "ship"}
        else:
            self.node = sim_node.TetherSimNode(where=str(params), parameter_overrides=list(overrides))
            self.motion = build_motion(self.node.config.motion, self.node.config.ship_end.position)
        self.node.driver.wall_budget = None  # no tick cut short by the machine's load: both nodes step alike
        self.log, self.current = [], None
        for publisher in self.node.publishers:
            self._record(publisher)
        cfg = self.node.config
        self.period = 1.0 / cfg.node.output_rate
        self.clock = 100.0
        self.node._now = lambda: self.clock
        self.msg = PoseStamped()
        self.msg.header.frame_id = cfg.node.world_frame
        self.msg.pose.orientation.w = 1.0

    def _record(self, publisher):
        from rclpy.serialization import serialize_message

        topic = publisher.topic_name

        def publish(msg):
            data = msg if isinstance(msg, bytes) else serialize_message(msg)
            self.current.append((topic, data))
        publisher.publish = publish
        publisher.get_subscription_count = lambda: 1

    def tick(self, k):
        self.current = []
        self.log.append(self.current)
        self.clock += self.period
        p, _, _ = self.motion.at(self.clock - 100.0)
        self.msg.header.stamp = self.convert.time_msg(self.clock)
        for name, position in self.held.items():
            self.msg.pose.position.x, self.msg.pose.position.y, self.msg.pose.position.z = (float(v) for v in position)
            self.node._on_pose(name, self.msg)
        self.msg.pose.position.x, self.msg.pose.position.y, self.msg.pose.position.z = (float(v) for v in p)
        self.node._on_pose("ship", self.msg)
        self.node._on_tick()
        if k % round(self.node.config.node.output_rate) == 0:
            self.node._publish_diagnostics()


def _type_of(node, topic):
    for publisher in node.publishers:
        if publisher.topic_name == topic:
            return publisher.msg_type
    raise KeyError(topic)


MAY_LEAVE_OUT = ("/tether/marker", "/tether/path", "/tf")  # node.visual_rate; any other topic left out differs


def may_leave_out(topic) -> bool:
    """node.visual_rate's topics, a line network's lines' marker and path among them."""
    return topic in MAY_LEAVE_OUT or (topic.startswith("/tether/") and topic.endswith(("/marker", "/path")))
NEW_KEYS = set()  # configuration keys only one tree has (/tether/description), named in the summary


def _common_keys(ma, mb):
    """Both descriptions' parameter lists without the keys only one of them has (recorded in NEW_KEYS)."""
    ka, kb = {kv.key for kv in ma.parameters}, {kv.key for kv in mb.parameters}
    NEW_KEYS.update(ka ^ kb)
    ma.parameters = [kv for kv in ma.parameters if kv.key in kb]
    mb.parameters = [kv for kv in mb.parameters if kv.key in ka]


def _masked(msg):
    """The message with its wall-clock fields zeroed (module doc)."""
    if hasattr(msg, "real_time_factor"):
        msg.real_time_factor = 0.0
    for status in getattr(msg, "status", []):
        for kv in status.values:
            if kv.key in WALL_CLOCK_VALUES:
                kv.value = "0"
    return msg


def _fields(msg, prefix=""):
    """(field path, value) of every leaf field, for naming a difference."""
    if hasattr(msg, "get_fields_and_field_types"):
        for name in msg.get_fields_and_field_types():
            yield from _fields(getattr(msg, name), f"{prefix}.{name}" if prefix else name)
    elif isinstance(msg, (list, tuple)) and msg and hasattr(msg[0], "get_fields_and_field_types"):
        for i, item in enumerate(msg):
            yield from _fields(item, f"{prefix}[{i}]")
    else:
        yield prefix, msg


def compare(a, b, node, topic):
    """None when the two serialized messages are equal up to wall-clock fields, else the first differing field."""
    if a == b:
        return None
    from rclpy.serialization import deserialize_message

    msg_type = _type_of(node, topic)
    ma, mb = (_masked(deserialize_message(x, msg_type)) for x in (a, b))
    if hasattr(ma, "parameters") and hasattr(ma, "output_arc_length"):  # TetherDescription
        _common_keys(ma, mb)
    if ma == mb:
        return None
    for (name, va), (_, vb) in zip(_fields(ma), _fields(mb)):
        if list(va) != list(vb) if hasattr(va, "__len__") and not isinstance(va, str) else va != vb:
            return f"{name}: {va!r} != {vb!r}"[:300]
    return "messages differ"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--params", nargs="+", default=["config/ropos_L1730.yaml"])
    ap.add_argument("--ticks", type=int, default=600)
    ap.add_argument("--baseline", required=True, help="another checkout (its tether_sim, renamed)")
    ap.add_argument("-p", dest="extra", action="append", default=[], metavar="KEY:=VALUE",
                    help="a parameter of both nodes, e.g. node.tf_tether_frames:=3")
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        return child(args)
    env = dict(os.environ, ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST", ROS_DOMAIN_ID=str(100 + os.getpid() % 100))
    import subprocess

    failed = 0
    for params in args.params:  # a process of its own per file (one rclpy context, an isolated domain)
        cmd = [sys.executable, __file__, "--child", "--params", params, "--ticks", str(args.ticks),
               "--baseline", args.baseline] + [x for e in args.extra for x in ("-p", e)]
        failed |= subprocess.run(cmd, env=env, cwd=ROOT).returncode
    return failed


def child(args):
    import rclpy
    import yaml
    from rclpy.parameter import Parameter

    from benchmarks.bench_tick import load_baseline

    load_baseline(args.baseline, with_ros=True)
    params = args.params[0]
    rclpy.init(args=["tether_sim", "--ros-args", "--params-file", str(params)])
    overrides = [Parameter(key, value=yaml.safe_load(text)) for key, _, text in (e.partition(":=") for e in args.extra)]
    this, base = (_Recorded(pkg, params, overrides) for pkg in ("tether_sim", "tether_sim_base"))
    for k in range(args.ticks):
        this.tick(k)
        base.tick(k)
    counts, left_out, diffs = {}, {}, []
    for k, (mine, theirs) in enumerate(zip(this.log, base.log)):
        pending = list(theirs)  # the baseline's messages of tick k, in order; this tree's must be among them
        skipped = []
        for topic, a in mine:
            at = next((i for i, (t, _) in enumerate(pending) if t == topic), None)
            if at is None:
                diffs.append(f"tick {k}: {topic} published here, not by the baseline")
                continue
            skipped.extend(t for t, _ in pending[:at])  # sent by the baseline alone, before this one
            b = pending[at][1]
            pending = pending[at + 1:]
            counts[topic] = counts.get(topic, 0) + 1
            why = compare(a, b, this.node, topic)
            if why is not None:
                diffs.append(f"tick {k} {topic}: {why}")
        for t in skipped + [t for t, _ in pending]:
            left_out[t] = left_out.get(t, 0) + 1
            if not may_leave_out(t):
                diffs.append(f"tick {k}: {t} published by the baseline, not here")
    print(f"{Path(params).name}: {args.ticks} ticks, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}; messages "
          + ", ".join(f"{t} {n}" for t, n in sorted(counts.items()))
          + (("; sent by the baseline alone: " + ", ".join(f"{t} {n}" for t, n in sorted(left_out.items())))
             if left_out else "")
          + (f"; keys of one tree only (left out of the description's comparison): {', '.join(sorted(NEW_KEYS))}"
             if NEW_KEYS else "")
          + f"; snaps {this.node.snaps_published} / {base.node.snaps_published}; {len(diffs)} differing", flush=True)
    for line in diffs[:20]:
        print("  " + line)
    for r in (this, base):
        r.node.destroy_node()
    rclpy.shutdown()
    return 1 if diffs else 0


if __name__ == "__main__":
    sys.exit(main())
