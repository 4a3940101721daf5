"""Two MCAP files of the same run (e.g. ``tether-sim-offline`` of this tree and of another checkout),
message by message: the same topics in the same order at the same log times, each payload equal
as bytes or else deserialized and equal field by field with the wall-clock fields set to zero
(TetherState.real_time_factor; the /diagnostics values real_time_factor, tick_load, tick_max_ms).
Prints the counts and the first differences; exit code 1 when any message differs.

Usage: .venv/bin/python benchmarks/compare_mcap_outputs.py A.mcap B.mcap
"""

import sys

from mcap.reader import make_reader
from rclpy.serialization import deserialize_message
from rosidl_runtime_py.utilities import get_message

WALL_CLOCK_VALUES = ("real_time_factor", "tick_load", "tick_max_ms")


def messages(path):
    with open(path, "rb") as f:
        reader = make_reader(f)
        for schema, channel, message in reader.iter_messages(log_time_order=False):
            yield channel.topic, schema.name, message.log_time, bytes(message.data)


def _plain(msg):
    """A message as nested dicts and lists of plain values."""
    if hasattr(msg, "get_fields_and_field_types"):
        return {k: _plain(getattr(msg, k)) for k in msg.get_fields_and_field_types()}
    if isinstance(msg, (list, tuple)) or type(msg).__name__ == "ndarray" or type(msg).__name__ == "array":
        return [_plain(v) for v in msg]
    return msg


def _clean(value):
    if isinstance(value, dict):
        if "key" in value and "value" in value and value["key"] in WALL_CLOCK_VALUES:
            return dict(value, value="")
        return {k: (0.0 if k == "real_time_factor" else _clean(v)) for k, v in value.items()}
    if isinstance(value, list):
        return [_clean(v) for v in value]
    return value


def fields(type_name, data):
    return _clean(_plain(deserialize_message(data, get_message(type_name))))


def main(argv=None):
    a, b = (argv or sys.argv[1:])[:2]
    left, right = list(messages(a)), list(messages(b))
    differ, shown, same_bytes = 0, 0, 0
    if len(left) != len(right):
        print(f"message counts differ: {len(left)} against {len(right)}")
        differ += 1
    for x, y in zip(left, right):
        if x == y:
            same_bytes += 1
            continue
        if x[:3] != y[:3] or fields(x[1], x[3]) != fields(y[1], y[3]):
            differ += 1
            if shown < 5:
                shown += 1
                print(f"differs: {x[0]} at {x[2]} ns against {y[0]} at {y[2]} ns")
    print(f"{len(left)} / {len(right)} messages; {same_bytes} equal bytes; {differ} differing")
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
