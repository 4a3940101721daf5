"""Reading rosbag2-style MCAP files, tolerant of a tail cut off by a crash (no rclpy).

A complete file (footer + summary) is read through its chunk index in log-time order with chunk
CRCs checked. A file without a usable summary (the writer was killed) is scanned record by record
from the start; every complete record counts, the incomplete tail is dropped with a
:class:`TruncatedMcapWarning`. Anything else that is wrong (not an MCAP file, a CRC mismatch, a
record that does not parse) raises :class:`McapLogError` naming the file.
"""

from __future__ import annotations

import io
import struct
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import yaml
from mcap.data_stream import ReadDataStream
from mcap.opcode import Opcode
from mcap.reader import SeekingReader
from mcap.records import Channel, Chunk, Header, Message, Metadata, Schema
from mcap.stream_reader import breakup_chunk

from tether_sim.errors import TetherSimError

MCAP_MAGIC = b"\x89MCAP0\r\n"
_RECORD_PREFIX = 9  # opcode (1 byte) + record length (uint64)


class McapLogError(TetherSimError, ValueError):
    """An MCAP file cannot be read: missing, not MCAP, corrupt, or undecodable (names the file)."""


class TruncatedMcapWarning(UserWarning):
    """The file ends inside a record (the writer died); only its complete records were read."""


@dataclass(frozen=True)
class RawMessage:
    """One stored message: topic, type, times (ns), sequence and the CDR bytes as written."""

    topic: str
    type_name: str
    log_time_ns: int
    publish_time_ns: int
    sequence: int
    data: bytes
    channel: Channel
    schema: Schema | None


@dataclass
class TopicInfo:
    type_name: str
    message_encoding: str
    offered_qos_profiles: list = field(default_factory=list)
    type_hash: str = ""
    message_count: int = 0

    @property
    def latched(self) -> bool:
        """True when every offer was TRANSIENT_LOCAL (a 'latched' topic)."""
        offers = self.offered_qos_profiles
        return bool(offers) and all(str(q.get("durability")) in ("transient_local", "1")
                                    for q in offers)


@dataclass
class McapSummary:
    profile: str
    topics: dict[str, TopicInfo]
    message_count: int
    start_ns: int
    end_ns: int
    metadata: dict[str, dict]
    complete: bool
    damage: "Damage | None" = None  # what a crash cut off (None for a complete file)

    @property
    def rosbag2_metadata(self) -> dict | None:
        """The parsed 'rosbag2' serialized_metadata (BagMetadata) or None."""
        text = self.metadata.get("rosbag2", {}).get("serialized_metadata")
        return yaml.safe_load(text) if text else None


def _open_mcap(path: Path):
    if not path.is_file():
        raise McapLogError(f"{path}: no such MCAP file")
    handle = open(path, "rb")  # noqa: SIM115 - returned to the caller, who closes it
    if handle.read(len(MCAP_MAGIC)) != MCAP_MAGIC:
        handle.close()
        raise McapLogError(f"{path}: not an MCAP file (missing the MCAP magic bytes)")
    handle.seek(0)
    return handle


def _complete_summary(handle):
    """The summary of a complete file, or None when the footer/summary is missing or unusable."""
    try:
        summary = SeekingReader(handle).get_summary()
    except Exception:  # noqa: BLE001 - a truncated footer raises assorted errors; scan instead
        return None
    if summary is None or not summary.chunk_indexes:
        return None
    return summary


def _qos_list(channel: Channel) -> list:
    text = channel.metadata.get("offered_qos_profiles", "")
    try:
        value = yaml.safe_load(text) if text else []
    except yaml.YAMLError:
        return []
    return value if isinstance(value, list) else []


def _type_name(channel: Channel, schemas: dict) -> str:
    schema = schemas.get(channel.schema_id)
    return schema.name if schema is not None else ""


@dataclass
class Damage:
    """What a scan found at the end of a file: complete, or where and why it stops."""

    path: str
    size: int  # bytes
    good_end: int  # byte offset after the last complete record
    chunks: int  # complete chunks
    complete: bool  # footer reached
    corrupt: list = field(default_factory=list)  # [(byte offset, length, start ns, end ns, reason)] dropped
    messages_lost: int | None = None  # known when a summary counted the messages (recover, report)

    @property
    def lost_bytes(self) -> int:
        return self.size - self.good_end

    def describe_corrupt(self) -> str:
        """What was dropped as corrupt ('' when nothing)."""
        if not self.corrupt:
            return ""
        parts = []
        for offset, length, start, end, reason in self.corrupt:
            span = f", log time {start * 1e-9:.3f}-{end * 1e-9:.3f} s" if start is not None else ""
            parts.append(f"bytes {offset}-{offset + length} ({reason}{span})")
        lost = (f"{self.messages_lost} message(s)" if self.messages_lost is not None
                else "their messages")
        return (f"dropped {len(self.corrupt)} corrupt record(s), {lost} lost: " + "; ".join(parts))

    def describe(self) -> str:
        corrupt = self.describe_corrupt()
        if self.complete:
            return f"{self.path}: complete" + (f"; kept {self.chunks} intact chunk(s), {corrupt}" if corrupt else "")
        tail = (f"the last {self.lost_bytes} byte(s) (from byte {self.good_end} of {self.size}: the chunk being "
                f"written, its messages are lost)" if self.lost_bytes else "no footer, summary or end magic")
        return (f"{self.path}: truncated (the writer stopped without closing it); kept {self.chunks} complete "
                f"chunk(s), lost {tail}" + (f"; {corrupt}" if corrupt else ""))


class CorruptMcapWarning(UserWarning):
    """Corrupt records (a chunk failing its CRC) were skipped while reading with ``skip_corrupt``."""


def _scan_records(path: Path, damage: list | None = None, warn: bool = True, skip_corrupt: bool = False):
    """Yield every complete top-level record (chunks broken up); warn at a truncated tail; append a
    :class:`Damage` to ``damage`` when given. A corrupt record (CRC, zstd or struct error) raises
    :class:`McapLogError`, or with ``skip_corrupt`` is skipped (its bytes, its chunk's time span and the
    reason are listed in the Damage and a :class:`CorruptMcapWarning` is given) and the scan goes on."""
    data = path.read_bytes()
    pos, size, n_chunks, corrupt = len(MCAP_MAGIC), len(data), 0, []
    complete = False
    while pos < size:
        if pos + _RECORD_PREFIX > size:
            break
        opcode = data[pos]
        (length,) = struct.unpack_from("<Q", data, pos + 1)
        end = pos + _RECORD_PREFIX + length
        if end > size:
            break
        body = ReadDataStream(io.BytesIO(data[pos + _RECORD_PREFIX:end]))
        chunk = None
        try:
            if opcode == Opcode.FOOTER:
                complete = True
                break
            if opcode == Opcode.CHUNK:
                chunk = Chunk.read(body)
                records = breakup_chunk(chunk, validate_crc=True)
                n_chunks += 1
            elif opcode == Opcode.MESSAGE:
                records = [Message.read(body, length)]
            elif opcode == Opcode.SCHEMA:
                records = [Schema.read(body)]
            elif opcode == Opcode.CHANNEL:
                records = [Channel.read(body)]
            elif opcode == Opcode.METADATA:
                records = [Metadata.read(body)]
            elif opcode == Opcode.HEADER:
                records = [Header.read(body)]
            else:
                records = []
        except Exception as exc:  # noqa: BLE001 - CRC, zstd and struct errors all mean corrupt
            if not skip_corrupt:
                raise McapLogError(f"{path}: corrupt record (opcode {opcode:#04x}) at byte {pos}: "
                                   f"{exc}") from exc
            reason = " ".join(str(exc).split())[:120] or type(exc).__name__
            corrupt.append((pos, end - pos, chunk.message_start_time if chunk else None,
                            chunk.message_end_time if chunk else None,
                            f"{'chunk' if opcode == Opcode.CHUNK else f'opcode {opcode:#04x}'}: {reason}"))
            pos = end
            continue
        yield from records
        pos = end
    found = Damage(str(path), size, size if complete else pos, n_chunks, complete, corrupt)
    if damage is not None:
        damage.append(found)
    if warn and corrupt:
        warnings.warn(f"{path}: {found.describe_corrupt()}", CorruptMcapWarning, stacklevel=3)
    if warn and not complete:
        warnings.warn(found.describe(), TruncatedMcapWarning, stacklevel=3)


def inspect(path) -> Damage:
    """Scan a file to its end: complete (footer and a usable summary), or what a crash cut off."""
    path = Path(path)
    handle = _open_mcap(path)
    try:
        if _complete_summary(handle) is not None:
            size = path.stat().st_size
            return Damage(str(path), size, size, 0, True)
    finally:
        handle.close()
    damage = []
    for _ in _scan_records(path, damage, warn=False):
        pass
    return damage[0]


def iter_raw(path, topics=None, *, skip_corrupt=False, damage=None):
    """Yield :class:`RawMessage` (log-time order), reading a crash-truncated file up to its tail.

    A corrupt record raises :class:`McapLogError`; with ``skip_corrupt`` the file is scanned record by
    record, every intact chunk is read, the corrupt ones are skipped with a :class:`CorruptMcapWarning`,
    and ``damage`` (a list, when given) receives the :class:`Damage` saying what was dropped."""
    path = Path(path)
    wanted = None if topics is None else {topics} if isinstance(topics, str) else set(topics)
    handle = _open_mcap(path)
    try:
        summary = _complete_summary(handle)
        if summary is None or skip_corrupt:
            schemas, channels, found = {}, {}, []
            if summary is not None:  # a corrupt chunk may hold the only Schema/Channel record
                schemas, channels = dict(summary.schemas), dict(summary.channels)
            for record in _scan_records(path, damage, skip_corrupt=skip_corrupt):
                if isinstance(record, Schema):
                    schemas[record.id] = record
                elif isinstance(record, Channel):
                    channels[record.id] = record
                elif isinstance(record, Message):
                    channel = channels.get(record.channel_id)
                    if channel is None and skip_corrupt:
                        continue  # its channel was defined in a dropped chunk (counted as lost by the caller)
                    if channel is None:
                        raise McapLogError(f"{path}: message on unknown channel {record.channel_id}")
                    if wanted is None or channel.topic in wanted:
                        found.append((record, channel, schemas.get(channel.schema_id)))
            found.sort(key=lambda item: item[0].log_time)
            items = found
        else:
            handle.seek(0)
            reader = SeekingReader(handle, validate_crcs=True)
            items = ((m, c, s) for s, c, m in reader.iter_messages(topics=wanted,
                                                                   log_time_order=True))
        try:
            for message, channel, schema in items:
                yield RawMessage(channel.topic, schema.name if schema else "", message.log_time,
                                 message.publish_time, message.sequence, message.data, channel,
                                 schema)
        except McapLogError:
            raise
        except Exception as exc:  # noqa: BLE001 - CRC, zstd and struct errors all mean corrupt
            raise McapLogError(f"{path}: corrupt MCAP data: {exc}") from exc
    finally:
        handle.close()


def read_summary(path) -> McapSummary:
    """Profile, topics (type, QoS offers, hash, count), time range and metadata records."""
    path = Path(path)
    handle = _open_mcap(path)
    try:
        summary = _complete_summary(handle)
        if summary is not None:
            handle.seek(0)
            reader = SeekingReader(handle)
            try:
                header = reader.get_header()
                metadata = {m.name: dict(m.metadata) for m in reader.iter_metadata()}
            except Exception as exc:  # noqa: BLE001
                raise McapLogError(f"{path}: corrupt MCAP summary: {exc}") from exc
            stats = summary.statistics
            counts = stats.channel_message_counts if stats else {}
            topics = {c.topic: TopicInfo(_type_name(c, summary.schemas), c.message_encoding,
                                         _qos_list(c), c.metadata.get("topic_type_hash", ""),
                                         counts.get(c.id, 0))
                      for c in summary.channels.values()}
            return McapSummary(header.profile, topics, stats.message_count if stats else 0,
                               stats.message_start_time if stats else 0,
                               stats.message_end_time if stats else 0, metadata, True)
        profile, schemas, channels, metadata, topics = "", {}, {}, {}, {}
        times, damage = [], []
        for record in _scan_records(path, damage):
            if isinstance(record, Schema):
                schemas[record.id] = record
            elif isinstance(record, Channel):
                channels[record.id] = record
                topics[record.topic] = TopicInfo(_type_name(record, schemas),
                                                 record.message_encoding, _qos_list(record),
                                                 record.metadata.get("topic_type_hash", ""))
            elif isinstance(record, Message) and record.channel_id in channels:
                topics[channels[record.channel_id].topic].message_count += 1
                times.append(record.log_time)
            elif isinstance(record, Metadata):
                metadata[record.name] = dict(record.metadata)
            elif isinstance(record, Header):
                profile = record.profile
        return McapSummary(profile, topics, len(times), min(times, default=0),
                           max(times, default=0), metadata, False, damage[0] if damage else None)
    finally:
        handle.close()
