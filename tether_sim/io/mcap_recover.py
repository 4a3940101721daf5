"""Recover an MCAP file cut by a crash, SIGKILL or power loss (console script ``tether-sim-recover``).

    tether-sim-recover IN [OUT]      # OUT defaults to IN with the suffix .recovered.mcap

A recorder killed mid-write leaves the header, the schemas and channels, and every chunk it closed;
the chunk it was filling is cut and the summary, the rosbag2 metadata record and the footer are
missing, so mcap's ``make_reader`` and rosbags refuse the file. This rewrites every complete record
(schemas, channels, messages of every complete chunk with its CRC checked, metadata) into a new,
complete MCAP: chunked (zstd), with summary, statistics, chunk and message indexes, footer and end
magic, plus the ``rosbag2`` metadata record (BagMetadata v9) recomputed from the recovered
messages when the original had none. A chunk that fails its CRC (bit rot, a bad sector) is dropped and
named, with its byte range, its time span and the number of messages lost; the intact chunks before
and after it are kept. Nothing of the input is changed; the output is written
beside it and renamed into place only when complete. No rclpy.
"""

from __future__ import annotations

import argparse
import os
import sys
from dataclasses import dataclass
from pathlib import Path

import yaml
from mcap.records import Channel, Header, Message, Metadata, Schema
from mcap.writer import CompressionType, Writer

from tether_sim.io.mcap_scan import Damage, McapLogError, _complete_summary, _open_mcap, _qos_list, _scan_records


@dataclass
class Recovery:
    """What :func:`recover` kept and lost."""

    output: str
    damage: Damage
    messages: int
    topics: dict  # topic -> message count
    start_ns: int
    end_ns: int

    def describe(self) -> str:
        span = (self.end_ns - self.start_ns) * 1e-9 if self.messages else 0.0
        return (f"{self.damage.describe()}\nwrote {self.output}: {self.messages} message(s) on "
                f"{len(self.topics)} topic(s), {span:.3f} s")


def default_output(path) -> Path:
    path = Path(path)
    stem = path.name[:-5] if path.name.endswith(".mcap") else path.name
    return path.with_name(f"{stem}.recovered.mcap")


def _bag_metadata(name, topics, channels, schemas, start, end, count) -> str:
    """BagMetadata v9 YAML (as rosbag2 writes it at close) for the recovered messages."""
    entries = []
    for cid, channel in channels.items():
        schema = schemas.get(channel.schema_id)
        entries.append({"topic_metadata": {"name": channel.topic, "type": schema.name if schema else "",
                                           "serialization_format": channel.message_encoding,
                                           "offered_qos_profiles": _qos_list(channel),
                                           "type_description_hash": channel.metadata.get("topic_type_hash", "")},
                        "message_count": topics.get(channel.topic, 0)})
    duration = max(0, end - start)
    data = {"version": 9, "storage_identifier": "mcap", "duration": {"nanoseconds": duration},
            "starting_time": {"nanoseconds_since_epoch": start}, "message_count": count,
            "topics_with_message_count": entries, "compression_format": "", "compression_mode": "",
            "relative_file_paths": [name],
            "files": [{"path": name, "starting_time": {"nanoseconds_since_epoch": start},
                       "duration": {"nanoseconds": duration}, "message_count": count}],
            "custom_data": None, "ros_distro": os.environ.get("ROS_DISTRO") or "jazzy"}
    return yaml.safe_dump(data, sort_keys=False, default_flow_style=False).strip()


def recover(path, output=None, *, chunk_size: int = 1 << 20) -> Recovery:
    """Rewrite the complete records of ``path`` into a complete MCAP ``output`` (see module doc).

    A corrupt record (a chunk failing its CRC) is dropped and listed in the returned damage (with the
    number of messages it held when the input's summary counted them); every intact chunk is kept.
    Raises McapLogError when ``path`` is not an MCAP file."""
    path = Path(path)
    output = Path(output) if output else default_output(path)
    if output.resolve() == path.resolve():
        raise McapLogError(f"{path}: the output must be a different file from the input")
    handle = _open_mcap(path)  # not MCAP -> McapLogError
    try:
        summary = _complete_summary(handle)  # a complete file's own count, to say how many messages a corrupt chunk held
    finally:
        handle.close()
    counted = summary.statistics.message_count if summary is not None and summary.statistics else None
    tmp = output.with_name(output.name + ".part")
    damage, schemas, channels, topics = [], {}, {}, {}
    schema_ids, channel_ids, metadata_names = {}, {}, set()
    count, start, end = 0, None, 0
    with open(tmp, "wb") as handle:
        writer = Writer(handle, chunk_size=chunk_size, compression=CompressionType.ZSTD, enable_crcs=True)
        started = seeded = False
        orphans = 0
        for record in _scan_records(path, damage, warn=False, skip_corrupt=True):
            if isinstance(record, Header):
                writer.start(profile=record.profile, library=record.library or "tether-sim-recover")
                started = True
                continue
            if not started:
                writer.start(profile="ros2", library="tether-sim-recover")
                started = True
            if summary is not None and not seeded:  # a corrupt chunk may hold the only Schema/Channel record
                seeded = True
                for sid, schema in sorted(summary.schemas.items()):
                    schemas[sid] = schema
                    schema_ids[sid] = writer.register_schema(schema.name, schema.encoding, schema.data)
                for cid, channel in sorted(summary.channels.items()):
                    channels[cid] = channel
                    channel_ids[cid] = writer.register_channel(channel.topic, channel.message_encoding,
                                                               schema_ids.get(channel.schema_id, 0),
                                                               dict(channel.metadata))
            if isinstance(record, Schema) and record.id not in schema_ids:
                schemas[record.id] = record
                schema_ids[record.id] = writer.register_schema(record.name, record.encoding, record.data)
            elif isinstance(record, Channel) and record.id not in channel_ids:
                channels[record.id] = record
                channel_ids[record.id] = writer.register_channel(
                    record.topic, record.message_encoding, schema_ids.get(record.schema_id, 0), dict(record.metadata))
            elif isinstance(record, Message):
                if record.channel_id not in channel_ids:  # its channel was defined in a dropped chunk
                    orphans += 1
                    continue
                writer.add_message(channel_ids[record.channel_id], record.log_time, record.data,
                                   record.publish_time, record.sequence)
                topic = channels[record.channel_id].topic
                topics[topic] = topics.get(topic, 0) + 1
                count += 1
                start = record.log_time if start is None else min(start, record.log_time)
                end = max(end, record.log_time)
            elif isinstance(record, Metadata):
                metadata_names.add(record.name)
                writer.add_metadata(record.name, dict(record.metadata))
        if not started:
            writer.start(profile="ros2", library="tether-sim-recover")
        if "rosbag2" not in metadata_names:
            writer.add_metadata("rosbag2", {"serialized_metadata": _bag_metadata(
                output.name, topics, channels, schemas, start or 0, end, count)})
        writer.finish()
    os.replace(tmp, output)
    if damage[0].corrupt and counted is not None:
        damage[0].messages_lost = max(0, counted - count)
    elif orphans:
        damage[0].messages_lost = orphans
    return Recovery(str(output), damage[0], count, topics, start or 0, end)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="tether-sim-recover", description=__doc__.split("\n\n")[0])
    ap.add_argument("input", help="MCAP file cut by a crash")
    ap.add_argument("output", nargs="?", help="complete MCAP to write (default: INPUT.recovered.mcap)")
    args = ap.parse_args(argv)
    try:
        result = recover(args.input, args.output)
    except McapLogError as exc:
        print(f"tether-sim-recover: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:
        print(f"tether-sim-recover: cannot write {args.output or default_output(args.input)}: "
              f"{exc.strerror or exc}", file=sys.stderr)
        return 2
    print(result.describe())
    if result.damage.complete and not result.damage.corrupt:
        print("(the input was already complete; the output is a rewritten copy)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
