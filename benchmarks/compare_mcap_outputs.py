"""Two MCAP files of the same run (e.g. ``tether-sim-offline`` of this tree and of another checkout),
message by message: the same topics in the same order at the same log times, and every message
deserialized (rclpy's deserializer and the generated message classes, tether_sim.ros.bag_common)
and compared field by field, floats exactly (NaN equal to NaN), with the wall-clock fields set to
zero (TetherState.real_time_factor; the /diagnostics values real_time_factor, tick_load, tick_max_ms).
Prints the counts (messages, equal bytes, leaf fields compared) and the first differences named by
field; exit code 1 when any message differs.

Usage: .venv/bin/python benchmarks/compare_mcap_outputs.py A.mcap B.mcap
"""

import math
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from benchmarks.compare_node_outputs import _masked  # noqa: E402  (the wall-clock fields zeroed, as there)


def messages(path):
    """(topic, type name, log time ns, publish time ns, bytes) of every message in file order."""
    from mcap.reader import make_reader

    with open(path, "rb") as f:
        reader = make_reader(f)
        for schema, channel, message in reader.iter_messages(log_time_order=False):
            yield channel.topic, schema.name, message.log_time, message.publish_time, bytes(message.data)


def leaves(msg, prefix=""):
    """(field path, plain value) of every leaf field; arrays element by element."""
    if hasattr(msg, "get_fields_and_field_types"):
        for name in msg.get_fields_and_field_types():
            yield from leaves(getattr(msg, name), f"{prefix}.{name}" if prefix else name)
    elif isinstance(msg, (str, bytes)):
        yield prefix, msg
    elif hasattr(msg, "__len__"):
        for i, item in enumerate(msg):
            yield from leaves(item, f"{prefix}[{i}]")
    else:
        yield prefix, msg


def _same(a, b) -> bool:
    if isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b):
        return True
    return type(a) is type(b) and a == b or (isinstance(a, (int, float)) and isinstance(b, (int, float)) and a == b)


def decoded(type_name, data):
    from rclpy.serialization import deserialize_message

    from tether_sim.ros.bag_common import message_class

    return list(leaves(_masked(deserialize_message(data, message_class(type_name)))))


def compare(a, b, show=5, out=print):
    """(messages of a, of b, equal bytes, leaf fields compared, differing messages)."""
    left, right = list(messages(a)), list(messages(b))
    differ, same_bytes, n_fields, shown = 0, 0, 0, 0
    if len(left) != len(right):
        out(f"message counts differ: {len(left)} against {len(right)}")
        differ += abs(len(left) - len(right))
    for k, (x, y) in enumerate(zip(left, right)):
        same_bytes += x[4] == y[4]
        why = None
        if x[:4] != y[:4]:
            why = f"topic/type/time {x[:4]} against {y[:4]}"
        else:
            fa, fb = decoded(x[1], x[4]), decoded(y[1], y[4])
            n_fields += len(fa)
            if len(fa) != len(fb):
                why = f"field counts {len(fa)} against {len(fb)}"
            else:
                for (name, va), (_, vb) in zip(fa, fb):
                    if not _same(va, vb):
                        why = f"{name}: {va!r} != {vb!r}"[:300]
                        break
        if why is not None:
            differ += 1
            if shown < show:
                shown += 1
                out(f"message {k} ({x[0]} at {x[2]} ns) differs: {why}")
    out(f"{len(left)} / {len(right)} messages; {same_bytes} equal bytes; {n_fields} leaf fields compared; "
        f"{differ} differing")
    return len(left), len(right), same_bytes, n_fields, differ


def main(argv=None):
    a, b = (argv or sys.argv[1:])[:2]
    return 1 if compare(a, b)[4] else 0


if __name__ == "__main__":
    sys.exit(main())
