"""MCAP files exactly as rosbag2 (Jazzy) writes them, and a tolerant reader (no rclpy).

Layout [ros2-conventions 1.7]: header profile ``ros2``; one ``ros2msg`` schema per type, its text
from the ``.msg`` files (:mod:`tether_sim.io.msg_definitions`); channels with ``cdr`` encoding and
metadata ``offered_qos_profiles`` (metadata-v9 YAML, lower-case enums) and ``topic_type_hash``
(RIHS01); message data = the CDR bytes as given (4-byte encapsulation header included); zstd
chunks with CRCs (zstd level 1, the level of mcap's C++ writer by default, which rosbag2's MCAP storage
uses; :func:`_zstd_level`); the ``rosbag2`` metadata record (``serialized_metadata`` = BagMetadata v9 YAML)
written at close. Every byte the MCAP writer emits goes straight to the OS (no user-space buffer),
and a chunk is closed when it is full or ``flush_interval_s`` has passed, so a process killed
mid-write leaves a file whose complete chunks still read (:func:`iter_raw` scans such files).
"""

from __future__ import annotations

import os
import struct
import threading
import time
from contextlib import contextmanager
from pathlib import Path

import mcap.writer as _mcap_writer
import yaml
from mcap.opcode import Opcode
from mcap.records import MessageIndex
from mcap.writer import CompressionType, Writer

from tether_sim.io.mcap_scan import McapLogError, RawMessage, iter_raw, read_summary
from tether_sim.io.msg_definitions import MessageDefinitionError, MessageDefinitions

__all__ = ["RosMcapWriter", "read_messages", "iter_raw", "read_summary", "McapLogError",
           "RawMessage", "qos_profile", "QOS_PRESETS", "MessageDefinitionError"]

METADATA_VERSION = 9
INFINITE_DURATION = {"sec": 9223372036, "nsec": 854775807}
QOS_PRESETS = {  # name -> (reliability, durability)
    "reliable": ("reliable", "volatile"),
    "best_effort": ("best_effort", "volatile"),
    "latched": ("reliable", "transient_local"),
}


def qos_profile(reliability: str = "reliable", durability: str = "volatile",
                history: str = "unknown", depth: int = 0) -> dict:
    """One offered QoS profile as rosbag2 stores a discovered offer (v9 enums, infinite durations)."""
    return {"history": history, "depth": int(depth), "reliability": reliability,
            "durability": durability, "deadline": dict(INFINITE_DURATION),
            "lifespan": dict(INFINITE_DURATION), "liveliness": "automatic",
            "liveliness_lease_duration": dict(INFINITE_DURATION),
            "avoid_ros_namespace_conventions": False}


def _dump_yaml(data) -> str:
    return yaml.safe_dump(data, sort_keys=False, default_flow_style=False).strip()


class _UnbufferedFile:
    """Pass-through to an unbuffered file so each MCAP record reaches the OS when it is written.

    mcap's Writer wraps an ``io.RawIOBase`` in a BufferedWriter, so this deliberately is not one."""

    def __init__(self, path: Path):
        self._raw = open(path, "wb", buffering=0)  # noqa: SIM115 - closed in close()

    def write(self, data) -> int:
        view, written = memoryview(data), 0
        while written < len(view):
            written += self._raw.write(view[written:])
        return written

    def tell(self) -> int:
        return self._raw.tell()

    def flush(self) -> None:
        """Nothing is buffered here."""

    def close(self) -> None:
        self._raw.close()


_MESSAGE_RECORD = struct.Struct("<BQHIQQ")  # opcode, record length, channel id, sequence, log time, publish time
_OP_MESSAGE = 0x05
_MESSAGE_FIELDS = 22  # bytes of the record after its length, before the data


class _MessageIndex(MessageIndex):
    """mcap's MessageIndex record (channel id, byte length of the pairs, (log time, offset) pairs)
    with its pairs packed in one call: mcap's ``write`` packs each number alone (two calls per
    message when the chunk closes). The same bytes (test/io/test_mcap_log.py)."""

    def write(self, stream):
        n = len(self.records)
        stream.start_record(Opcode.MESSAGE_INDEX)
        stream.write(struct.pack(f"<HI{2 * n}Q", self.channel_id, 16 * n, *(x for pair in self.records for x in pair)))
        stream.finish_record()


ZSTD_LEVEL = 1  # mcap's C++ writer: CompressionLevel::Default is zstd level 1 (mcap's Python writer: 3)


class _Zstd:
    """What mcap's Python writer calls to compress a chunk (``zstandard.compress(data)``, zstd's
    default level 3), at :data:`ZSTD_LEVEL`: about half the CPU of level 3 on this writer's chunks,
    the file a little larger (docs/network.md, "The output cost: chunk compression")."""

    def __init__(self, zstandard, level):
        self._zstandard, self.level = zstandard, level

    def compress(self, data):
        return self._zstandard.compress(data, level=self.level)


_SWAP = threading.Lock()


@contextmanager
def _zstd_level():
    """Within: mcap's writer compresses chunks at :data:`ZSTD_LEVEL` (its module's ``zstandard`` is
    stood in for, under a lock, and put back after). A no-op when that writer has no such name."""
    module = getattr(_mcap_writer, "zstandard", None)
    if module is None or isinstance(module, _Zstd):
        yield
        return
    with _SWAP:
        _mcap_writer.zstandard = _Zstd(module, ZSTD_LEVEL)
        try:
            yield
        finally:
            _mcap_writer.zstandard = module


class _ChunkAppender:
    """What ``mcap.writer.Writer.add_message`` does with chunking on, in one ``struct`` pack: the
    file's statistics, the open chunk's time range and message index, and the Message record
    (opcode, length, channel, sequence, log time, publish time, data) appended to the chunk, which
    is closed when it is full. The file's bytes are the same as through ``add_message``
    (``test/io/test_mcap_log.py``); its Python record objects cost ~10x more per message (a network
    file writes about 13 messages a tick). Built on mcap 1.x's writer internals: when they are not
    there, :meth:`of` returns None and the writer goes through ``add_message``."""

    __slots__ = ("stats", "chunk", "finalize", "chunk_size")

    def __init__(self, writer: Writer, chunk_size: int):
        self.stats = writer._Writer__statistics
        self.chunk = writer._Writer__chunk_builder
        self.finalize = writer._Writer__finalize_chunk
        self.chunk_size = chunk_size
        for name in ("num_messages", "message_start_time", "message_end_time", "message_indices", "record_writer"):
            getattr(self.chunk, name)
        self.chunk.record_writer._buffer.tell()
        for name in ("message_count", "message_start_time", "message_end_time", "channel_message_counts"):
            getattr(self.stats, name)

    @classmethod
    def of(cls, writer: Writer, chunk_size: int):
        try:
            return cls(writer, chunk_size)
        except AttributeError:
            return None

    def add(self, channel: int, log_time: int, data, publish_time: int, sequence: int) -> None:
        st = self.stats
        if st.message_count == 0 or log_time < st.message_start_time:
            st.message_start_time = log_time
        if log_time > st.message_end_time:
            st.message_end_time = log_time
        st.channel_message_counts[channel] += 1
        st.message_count += 1
        ch = self.chunk
        if ch.num_messages == 0 or log_time < ch.message_start_time:
            ch.message_start_time = log_time
        if log_time > ch.message_end_time:
            ch.message_end_time = log_time
        buf = ch.record_writer._buffer
        index = ch.message_indices.get(channel)
        if index is None:
            index = ch.message_indices[channel] = _MessageIndex(channel_id=channel, records=[])
        index.records.append((log_time, buf.tell()))
        ch.num_messages += 1
        buf.write(_MESSAGE_RECORD.pack(_OP_MESSAGE, _MESSAGE_FIELDS + len(data), channel, sequence, log_time,
                                       publish_time))
        buf.write(data)
        if buf.tell() > self.chunk_size:
            with _zstd_level():
                self.finalize()


class RosMcapWriter:
    """rosbag2-compatible MCAP writer of given CDR payloads; a context manager, close() idempotent.

    Parameters: ``path``; ``msg_search_path`` extra prefixes for .msg files; ``chunk_size`` bytes of
    uncompressed messages per chunk; ``flush_interval_s`` closes the open chunk at least that often
    (recorders); ``ros_distro`` stored in the metadata record.
    """

    def __init__(self, path, *, msg_search_path=None, chunk_size: int = 1 << 20,
                 flush_interval_s: float | None = None, ros_distro: str | None = None):
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._definitions = MessageDefinitions(msg_search_path)
        self._file = _UnbufferedFile(self.path)
        self._writer = Writer(self._file, chunk_size=int(chunk_size),
                              compression=CompressionType.ZSTD, enable_crcs=True)
        self._writer.start(profile="ros2", library="tether_sim rosbag2-compatible writer")
        self._append = _ChunkAppender.of(self._writer, int(chunk_size))
        self._schemas: dict[str, int] = {}
        self._topics: dict[str, dict] = {}
        self._flush_interval = flush_interval_s
        self._last_flush = time.monotonic()
        self._ros_distro = ros_distro or os.environ.get("ROS_DISTRO") or "jazzy"
        self._t_min: int | None = None
        self._t_max = 0
        self.closed = False

    def __enter__(self):
        return self

    def __exit__(self, *exc_info):
        self.close()

    @property
    def message_count(self) -> int:
        return sum(t["count"] for t in self._topics.values())

    def add_topic(self, topic: str, type_name: str, qos: str = "reliable", *,
                  offered_qos_profiles: list | None = None, type_hash: str | None = None) -> int:
        """Register a topic (schema once per type); returns its channel id. Re-adding is a no-op.

        ``qos`` is one of ``QOS_PRESETS``; a recorder passes the discovered ``offered_qos_profiles``
        (list of :func:`qos_profile` dicts) and ``type_hash`` instead."""
        self._check_open()
        if not topic.startswith("/"):
            raise ValueError(f"topic {topic!r} must be an absolute name starting with '/'")
        if topic in self._topics:
            known = self._topics[topic]["type"]
            if known != type_name:
                raise ValueError(f"topic {topic} already added with type {known}, not {type_name}")
            return self._topics[topic]["channel"]
        if offered_qos_profiles is None:
            if qos not in QOS_PRESETS:
                raise ValueError(f"qos {qos!r} for {topic}: expected one of {sorted(QOS_PRESETS)}")
            offered_qos_profiles = [qos_profile(*QOS_PRESETS[qos])]
        if type_name not in self._schemas:
            encoding, text = self._definitions.schema(type_name)
            with _zstd_level():  # (a schema or channel record may close the chunk)
                self._schemas[type_name] = self._writer.register_schema(
                    name=type_name, encoding=encoding, data=text.encode("utf-8"))
        if type_hash is None:
            type_hash = self._definitions.type_hash(type_name)
        metadata = {"offered_qos_profiles": _dump_yaml(list(offered_qos_profiles)),
                    "topic_type_hash": type_hash}
        with _zstd_level():
            channel = self._writer.register_channel(topic=topic, message_encoding="cdr",
                                                    schema_id=self._schemas[type_name],
                                                    metadata=metadata)
        self._topics[topic] = {"type": type_name, "channel": channel, "count": 0, "seq": 0,
                               "qos": list(offered_qos_profiles), "hash": type_hash}
        return channel

    def write(self, topic: str, cdr: bytes, log_time_ns: int, publish_time_ns: int | None = None,
              *, sequence: int | None = None) -> None:
        """Append one message: ``cdr`` = serialized bytes incl. the 4-byte encapsulation header."""
        self._check_open()
        info = self._topics.get(topic)
        if info is None:
            raise KeyError(f"topic {topic} was not added to {self.path} (call add_topic first)")
        if not isinstance(cdr, (bytes, bytearray, memoryview)) or len(cdr) < 4:
            raise ValueError(f"{topic}: CDR payload must be bytes with a 4-byte encapsulation header")
        log_time_ns = int(log_time_ns)
        publish_time_ns = log_time_ns if publish_time_ns is None else int(publish_time_ns)
        if log_time_ns < 0 or publish_time_ns < 0:
            raise ValueError(f"{topic}: negative timestamp ({log_time_ns}, {publish_time_ns})")
        info["seq"] = info["seq"] + 1 if sequence is None else int(sequence)
        info["count"] += 1
        self._t_min = log_time_ns if self._t_min is None else min(self._t_min, log_time_ns)
        self._t_max = max(self._t_max, log_time_ns)
        if self._append is not None:
            if isinstance(cdr, memoryview):
                cdr = cdr.tobytes()
            self._append.add(info["channel"], log_time_ns, cdr, publish_time_ns, info["seq"] & 0xFFFFFFFF)
        else:
            with _zstd_level():
                self._writer.add_message(channel_id=info["channel"], log_time=log_time_ns,
                                         data=bytes(cdr), publish_time=publish_time_ns,
                                         sequence=info["seq"] & 0xFFFFFFFF)
        if self._flush_interval is not None and \
                time.monotonic() - self._last_flush >= self._flush_interval:
            self.flush()

    def write_many(self, messages, log_time_ns: int) -> None:
        """``write(topic, cdr, log_time_ns)`` for each (topic, cdr) of ``messages``, in order: the
        outputs of one tick, all stamped ``log_time_ns`` (log time = publish time), the per-call
        checks and bookkeeping done once. The file is the same as through ``write`` (test)."""
        self._check_open()
        t = int(log_time_ns)
        if t < 0:
            raise ValueError(f"negative timestamp ({t})")
        append = self._append
        if append is None:
            for topic, cdr in messages:
                self.write(topic, cdr, t, t)
            return
        topics = self._topics
        written = False
        for topic, cdr in messages:
            info = topics.get(topic)
            if info is None:
                raise KeyError(f"topic {topic} was not added to {self.path} (call add_topic first)")
            if type(cdr) is not bytes:
                if not isinstance(cdr, (bytes, bytearray, memoryview)):
                    raise ValueError(f"{topic}: CDR payload must be bytes with a 4-byte encapsulation header")
                cdr = bytes(cdr)
            if len(cdr) < 4:
                raise ValueError(f"{topic}: CDR payload must be bytes with a 4-byte encapsulation header")
            info["seq"] = seq = info["seq"] + 1
            info["count"] += 1
            append.add(info["channel"], t, cdr, t, seq & 0xFFFFFFFF)
            written = True
        if written:
            self._t_min = t if self._t_min is None else min(self._t_min, t)
            self._t_max = max(self._t_max, t)
        if self._flush_interval is not None and \
                time.monotonic() - self._last_flush >= self._flush_interval:
            self.flush()

    def flush(self) -> None:
        """Close the open chunk (if it holds messages) and hand it to the OS."""
        self._check_open()
        with _zstd_level():
            self._writer.flush()
        self._last_flush = time.monotonic()

    def bag_metadata(self) -> dict:
        """BagMetadata (v9) as rosbag2 serializes it into the 'rosbag2' metadata record."""
        start = self._t_min or 0
        duration = max(0, self._t_max - start) if self._t_min is not None else 0
        count = self.message_count
        return {
            "version": METADATA_VERSION,
            "storage_identifier": "mcap",
            "duration": {"nanoseconds": duration},
            "starting_time": {"nanoseconds_since_epoch": start},
            "message_count": count,
            "topics_with_message_count": [
                {"topic_metadata": {"name": topic, "type": t["type"],
                                    "serialization_format": "cdr",
                                    "offered_qos_profiles": t["qos"],
                                    "type_description_hash": t["hash"]},
                 "message_count": t["count"]}
                for topic, t in self._topics.items()],
            "compression_format": "",
            "compression_mode": "",
            "relative_file_paths": [self.path.name],
            "files": [{"path": self.path.name,
                       "starting_time": {"nanoseconds_since_epoch": start},
                       "duration": {"nanoseconds": duration},
                       "message_count": count}],
            "custom_data": None,
            "ros_distro": self._ros_distro,
        }

    def close(self) -> None:
        """Write the metadata record, the summary and the footer; safe to call twice."""
        if self.closed:
            return
        self.closed = True
        try:
            self._writer.add_metadata("rosbag2", {"serialized_metadata": _dump_yaml(self.bag_metadata())})
            with _zstd_level():
                self._writer.finish()
        finally:
            self._file.close()

    def _check_open(self) -> None:
        if self.closed:
            raise ValueError(f"{self.path} is closed")


def read_messages(path, topics=None, *, skip_corrupt=False, damage=None):
    """Yield (topic, type_name, log_time_ns, decoded_msg) with the mcap_ros2 decoder.

    Log-time order for complete files; a file cut off by a crash yields its complete chunks (with a
    warning). Unreadable or corrupt files raise :class:`McapLogError` naming the file; with
    ``skip_corrupt`` the intact chunks are read and ``damage`` receives what was dropped (:func:`iter_raw`)."""
    from mcap_ros2.decoder import DecoderFactory

    factory = DecoderFactory()
    decoders = {}
    for raw in iter_raw(path, topics, skip_corrupt=skip_corrupt, damage=damage):
        key = raw.schema.id if raw.schema is not None else None
        if key not in decoders:
            try:
                decoders[key] = factory.decoder_for(raw.channel.message_encoding, raw.schema)
            except Exception as exc:  # noqa: BLE001 - the schema parser raises assorted errors
                raise McapLogError(f"{path}: cannot parse the schema of {raw.topic} "
                                   f"({raw.type_name}): {exc}") from exc
            if decoders[key] is None:
                raise McapLogError(f"{path}: {raw.topic} is not a ros2msg/cdr channel "
                                   f"(schema encoding {raw.schema.encoding if raw.schema else None})")
        try:
            msg = decoders[key](raw.data)
        except Exception as exc:  # noqa: BLE001 - malformed CDR raises assorted errors
            raise McapLogError(f"{path}: cannot decode a {raw.type_name} message on {raw.topic} "
                               f"at log time {raw.log_time_ns} ns: {exc}") from exc
        yield raw.topic, raw.type_name, raw.log_time_ns, msg

