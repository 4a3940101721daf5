"""RosMcapWriter / readers: rosbag2 layout, three independent decoders, crash and corruption cases.

CDR payloads come from rosbags' serializer; .msg files are laid out in a temporary ament-style
prefix (share/<pkg>/msg/), the standard ones split out of rosbags' Jazzy definitions and a custom
test package written here with comments, constants and arrays, as real interface packages have.
"""

import subprocess
import sys
import textwrap
import warnings
from pathlib import Path

import pytest
import yaml
from mcap.reader import SeekingReader
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

from tether_sim.io.mcap_log import (McapLogError, MessageDefinitionError, RosMcapWriter, iter_raw,
                                    read_messages, read_summary)
from tether_sim.io.mcap_scan import TruncatedMcapWarning
from tether_sim.io.msg_definitions import SEPARATOR, MessageDefinitions, export_rosbags_definitions

REPO = Path(__file__).resolve().parents[2]
SAMPLE_MSG = "# One sample along the cable.\nfloat64 s  # arclength [m]\nfloat32 tension  # [N]\nint64[] ids\n"
PROBE_MSG = textwrap.dedent("""\
    # A probe of the tether (test-only custom message).
    uint8 KIND_NONE=0  # constants are not fields
    uint8 KIND_SNAP=1

    std_msgs/Header header
    Sample[] samples   # bare name: same package
    float64[3] force   # [N]
    geometry_msgs/Point origin
    string label
    bool ok
    """)
STANDARD_TYPES = ["geometry_msgs/msg/PoseStamped", "geometry_msgs/msg/WrenchStamped",
                  "std_msgs/msg/String"]


@pytest.fixture(scope="module")
def prefix(tmp_path_factory):
    """An ament-style prefix holding the .msg files of the types used here."""
    root = tmp_path_factory.mktemp("prefix")
    export_rosbags_definitions(root, STANDARD_TYPES)
    custom = root / "share" / "tether_test_msgs" / "msg"
    custom.mkdir(parents=True)
    (custom / "Sample.msg").write_text(SAMPLE_MSG)
    (custom / "Probe.msg").write_text(PROBE_MSG)
    return root


@pytest.fixture(scope="module")
def typestore():
    store = get_typestore(Stores.ROS2_JAZZY)
    store.register(get_types_from_msg(SAMPLE_MSG, "tether_test_msgs/msg/Sample"))
    store.register(get_types_from_msg(PROBE_MSG, "tether_test_msgs/msg/Probe"))
    return store


def _header(store, t_ns, frame="map"):
    Time = store.types["builtin_interfaces/msg/Time"]
    return store.types["std_msgs/msg/Header"](stamp=Time(sec=t_ns // 10**9, nanosec=t_ns % 10**9),
                                              frame_id=frame)


def make_messages(store, n=40):
    """[(topic, type, log_ns, publish_ns, cdr, expected dict)] over four topics and four QoS kinds."""
    import numpy as np
    T = store.types
    out = []
    for i in range(n):
        t = 1_700_000_000_000_000_000 + i * 50_000_000
        pose = T["geometry_msgs/msg/PoseStamped"](header=_header(store, t), pose=T["geometry_msgs/msg/Pose"](
            position=T["geometry_msgs/msg/Point"](x=1.0 * i, y=-2.0, z=-100.0 - i),
            orientation=T["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0)))
        out.append(("/ship/pose", "geometry_msgs/msg/PoseStamped", t, t - 1000,
                    store.serialize_cdr(pose, "geometry_msgs/msg/PoseStamped"), {"z": -100.0 - i}))
        wrench = T["geometry_msgs/msg/WrenchStamped"](header=_header(store, t, "rov/tether_attach"),
                                                      wrench=T["geometry_msgs/msg/Wrench"](
            force=T["geometry_msgs/msg/Vector3"](x=0.5, y=0.0, z=-1000.0 - 10 * i),
            torque=T["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.0)))
        out.append(("/tether/vehicle_wrench", "geometry_msgs/msg/WrenchStamped", t + 1, t,
                    store.serialize_cdr(wrench, "geometry_msgs/msg/WrenchStamped"), {"fz": -1000.0 - 10 * i}))
        samples = [T["tether_test_msgs/msg/Sample"](s=float(k), tension=np.float32(10.0 * k + i),
                                                    ids=np.arange(k, dtype=np.int64)) for k in range(3)]
        probe = T["tether_test_msgs/msg/Probe"](header=_header(store, t), samples=samples,
                                                force=np.array([1.0, 2.0, 3.0 + i]),
                                                origin=T["geometry_msgs/msg/Point"](x=0.0, y=0.0, z=-5.0),
                                                label=f"probe{i}", ok=bool(i % 2))
        out.append(("/tether/probe", "tether_test_msgs/msg/Probe", t + 2, t,
                    store.serialize_cdr(probe, "tether_test_msgs/msg/Probe"), {"label": f"probe{i}"}))
    desc = T["std_msgs/msg/String"](data="cable L=200 m")
    out.insert(0, ("/tether/description", "std_msgs/msg/String", out[0][2] - 5, out[0][2] - 5,
                   store.serialize_cdr(desc, "std_msgs/msg/String"), {"data": "cable L=200 m"}))
    return out


QOS_OF = {"/ship/pose": "best_effort", "/tether/vehicle_wrench": "reliable", "/tether/probe": "reliable",
          "/tether/description": "latched"}


def write_file(path, prefix, messages, chunk_size=4096):
    with RosMcapWriter(path, msg_search_path=[prefix], chunk_size=chunk_size) as writer:
        for topic, type_name, log_ns, pub_ns, cdr, _ in messages:
            writer.add_topic(topic, type_name, QOS_OF[topic])
            writer.write(topic, cdr, log_ns, pub_ns)
    return path


def test_schema_text_is_rosbag2_concatenation(prefix):
    defs = MessageDefinitions([prefix])
    share = prefix / "share"
    raw = {name: (share / name.split("/")[0] / "msg" / f"{name.split('/')[1]}.msg").read_text()
           for name in ["geometry_msgs/PoseStamped", "geometry_msgs/Pose", "geometry_msgs/Point",
                        "geometry_msgs/Quaternion", "std_msgs/Header", "builtin_interfaces/Time"]}
    # rosbag2: root text, then sorted dependencies depth-first, each once, behind the delimiter.
    order = ["geometry_msgs/Pose", "geometry_msgs/Point", "geometry_msgs/Quaternion",
             "std_msgs/Header", "builtin_interfaces/Time"]
    expected = raw["geometry_msgs/PoseStamped"] + "".join(
        f"\n{SEPARATOR}\nMSG: {name}\n{raw[name]}" for name in order)
    assert defs.schema("geometry_msgs/msg/PoseStamped") == ("ros2msg", expected)
    encoding, text = defs.schema("tether_test_msgs/msg/Probe")
    assert text.startswith(PROBE_MSG)  # raw root file, comments and constants kept
    assert [line[5:] for line in text.split("\n") if line.startswith("MSG: ")] == [
        "geometry_msgs/Point", "std_msgs/Header", "builtin_interfaces/Time", "tether_test_msgs/Sample"]
    with pytest.raises(MessageDefinitionError, match="no_such_msgs/msg/Thing"):
        defs.schema("no_such_msgs/msg/Thing")


def test_round_trip_with_three_readers(tmp_path, prefix, typestore):
    messages = make_messages(typestore)
    path = write_file(tmp_path / "run.mcap", prefix, messages)
    by_topic = {}
    for m in messages:
        by_topic.setdefault(m[0], []).append(m)

    # 1) the mcap library, chunk CRCs checked, rosbag2 layout field by field
    with open(path, "rb") as handle:
        reader = SeekingReader(handle, validate_crcs=True)
        assert reader.get_header().profile == "ros2"
        summary = reader.get_summary()
        assert {c.compression for c in summary.chunk_indexes} == {"zstd"} and len(summary.chunk_indexes) > 1
        assert {s.encoding for s in summary.schemas.values()} == {"ros2msg"}
        jazzy = get_typestore(Stores.ROS2_JAZZY)
        for channel in summary.channels.values():
            schema = summary.schemas[channel.schema_id]
            assert channel.message_encoding == "cdr"
            (qos,) = yaml.safe_load(channel.metadata["offered_qos_profiles"])
            kind = QOS_OF[channel.topic]
            assert qos["reliability"] == ("best_effort" if kind == "best_effort" else "reliable")
            assert qos["durability"] == ("transient_local" if kind == "latched" else "volatile")
            store = typestore if schema.name.startswith("tether_test") else jazzy
            assert channel.metadata["topic_type_hash"] == store.hash_rihs01(schema.name)
            assert summary.statistics.channel_message_counts[channel.id] == len(by_topic[channel.topic])
        stored = [(c.topic, m.log_time, m.publish_time, m.data) for _, c, m in reader.iter_messages()]
        (meta,) = [m for m in reader.iter_metadata() if m.name == "rosbag2"]
    assert stored == [(t, log, pub, cdr) for t, _, log, pub, cdr, _ in sorted(messages, key=lambda m: m[2])]
    bag = yaml.safe_load(meta.metadata["serialized_metadata"])
    assert bag["version"] == 9 and bag["storage_identifier"] == "mcap"
    assert bag["message_count"] == len(messages)
    assert {t["topic_metadata"]["name"]: t["message_count"] for t in bag["topics_with_message_count"]} == \
        {t: len(v) for t, v in by_topic.items()}

    # 2) the mcap ROS 2 decoder through read_messages
    decoded = {}
    for topic, type_name, _, msg in read_messages(path):
        decoded.setdefault(topic, []).append(msg)
    assert [m.pose.position.z for m in decoded["/ship/pose"]] == [e["z"] for *_, e in by_topic["/ship/pose"]]
    assert [m.wrench.force.z for m in decoded["/tether/vehicle_wrench"]] == \
        [e["fz"] for *_, e in by_topic["/tether/vehicle_wrench"]]
    probe = decoded["/tether/probe"][3]
    assert probe.label == "probe3" and list(probe.force) == [1.0, 2.0, 6.0]
    assert list(probe.samples[2].ids) == [0, 1] and probe.samples[2].tension == pytest.approx(23.0)
    assert decoded["/tether/description"][0].data == "cable L=200 m"

    # 3) rosbags with an EMPTY typestore: types come only from the schema text in the file
    from rosbags.highlevel import AnyReader
    with AnyReader([path], default_typestore=get_typestore(Stores.EMPTY)) as anyreader:
        got = {}
        for conn, _, raw in anyreader.messages():
            got.setdefault(conn.topic, []).append(anyreader.deserialize(raw, conn.msgtype))
    assert [m.label for m in got["/tether/probe"]] == [e["label"] for *_, e in by_topic["/tether/probe"]]
    assert [m.wrench.force.z for m in got["/tether/vehicle_wrench"]] == \
        [e["fz"] for *_, e in by_topic["/tether/vehicle_wrench"]]
    assert got["/tether/description"][0].data == "cable L=200 m"
    info = read_summary(path)
    assert info.complete and info.topics["/tether/description"].latched
    assert not info.topics["/ship/pose"].latched and info.rosbag2_metadata["message_count"] == len(messages)


def test_direct_chunk_append_writes_the_bytes_of_the_mcap_writer(tmp_path, prefix, typestore, monkeypatch):
    """The writer appends each Message record to the open chunk itself (one struct pack, its own index
    and time bookkeeping); the file is byte for byte the one mcap's Writer.add_message writes, over
    several chunks (a chunk of 1 kB) with log times out of order (the description first, stamped
    earlier than the message before it)."""
    import tether_sim.io.mcap_log as mcap_log

    messages = make_messages(typestore, n=60)
    messages.insert(5, messages.pop(0))  # an earlier log time after later ones
    (tmp_path / "fast").mkdir()
    (tmp_path / "slow").mkdir()  # the same file name: the rosbag2 metadata record holds it
    fast = write_file(tmp_path / "fast" / "run.mcap", prefix, messages, chunk_size=1024)
    monkeypatch.setattr(mcap_log._ChunkAppender, "of", classmethod(lambda cls, writer, size: None))
    slow = write_file(tmp_path / "slow" / "run.mcap", prefix, messages, chunk_size=1024)
    with open(fast, "rb") as handle:
        assert len(SeekingReader(handle, validate_crcs=True).get_summary().chunk_indexes) > 5
    assert fast.read_bytes() == slow.read_bytes()


def test_chunks_are_zstd_level_1_and_other_writers_keep_their_level(tmp_path, prefix, typestore):
    """Every chunk is compressed at zstd level 1 (mcap's C++ writer's default level, the CPU of
    level 3 roughly halved); mcap's own Writer, used outside RosMcapWriter, still compresses at its
    level 3 (the level is set only while this writer closes a chunk)."""
    import io

    import mcap.writer
    import zstandard
    from mcap.records import Chunk
    from mcap.stream_reader import StreamReader

    path = write_file(tmp_path / "run.mcap", prefix, make_messages(typestore, n=80), chunk_size=1024)
    chunks = [r for r in StreamReader(io.BytesIO(path.read_bytes()), emit_chunks=True).records if isinstance(r, Chunk)]
    assert len(chunks) > 3
    for chunk in chunks:
        raw = zstandard.ZstdDecompressor().decompress(chunk.data, max_output_size=chunk.uncompressed_size)
        assert chunk.compression == "zstd" and chunk.data == zstandard.compress(raw, level=1)
        assert chunk.data != zstandard.compress(raw, level=3)  # (the check tells the levels apart here)
    assert mcap.writer.zstandard is zstandard
    out = io.BytesIO()
    plain = mcap.writer.Writer(out)
    plain.start()
    channel = plain.register_channel("/x", "cdr", 0)
    for k in range(50):
        plain.add_message(channel, k, bytes(range(200)) * (k % 7 + 1), k)
    plain.finish()
    (chunk,) = [r for r in StreamReader(io.BytesIO(out.getvalue()), emit_chunks=True).records if isinstance(r, Chunk)]
    raw = zstandard.ZstdDecompressor().decompress(chunk.data, max_output_size=chunk.uncompressed_size)
    assert chunk.data == zstandard.compress(raw, level=3)


def test_write_many_is_write_one_message_after_the_other(tmp_path, prefix, typestore):
    """A tick's outputs written in one call (one stamp) make the file that write() makes with them one
    after the other (a memoryview payload taken as its bytes); an unknown topic or a short payload is
    refused as write() refuses it."""
    messages = make_messages(typestore, n=30)
    paths = []
    for name in ("one", "many"):
        (tmp_path / name).mkdir()
        path = tmp_path / name / "run.mcap"
        with RosMcapWriter(path, msg_search_path=[prefix], chunk_size=2048) as writer:
            for topic, type_name, *_ in messages:
                writer.add_topic(topic, type_name, QOS_OF[topic])
            for k in range(0, len(messages), 3):
                group = [(m[0], memoryview(m[4]) if k % 2 else m[4]) for m in messages[k:k + 3]]
                t = messages[k][2]
                if name == "one":
                    for topic, cdr in group:
                        writer.write(topic, cdr, t, t)
                else:
                    writer.write_many(group, t)
            if name == "many":
                with pytest.raises(KeyError, match="/nowhere"):
                    writer.write_many([("/nowhere", messages[0][4])], t)
                with pytest.raises(ValueError, match="4-byte"):
                    writer.write_many([(messages[0][0], b"\x00\x01")], t)
        paths.append(path)
    assert paths[0].read_bytes() == paths[1].read_bytes()


def test_writer_rejects_bad_input(tmp_path, prefix, typestore):
    writer = RosMcapWriter(tmp_path / "bad.mcap", msg_search_path=[prefix])
    with pytest.raises(ValueError, match="absolute"):
        writer.add_topic("tether/state", "std_msgs/msg/String")
    with pytest.raises(ValueError, match="qos"):
        writer.add_topic("/a", "std_msgs/msg/String", qos="fast")
    with pytest.raises(MessageDefinitionError, match="nope_msgs/msg/X"):
        writer.add_topic("/a", "nope_msgs/msg/X")
    writer.add_topic("/a", "std_msgs/msg/String")
    with pytest.raises(ValueError, match="already added"):
        writer.add_topic("/a", "geometry_msgs/msg/PoseStamped")
    with pytest.raises(KeyError, match="/b"):
        writer.write("/b", b"\x00\x01\x00\x00", 1)
    with pytest.raises(ValueError, match="encapsulation"):
        writer.write("/a", b"\x00", 1)
    writer.close()
    writer.close()  # idempotent
    with pytest.raises(ValueError, match="closed"):
        writer.write("/a", b"\x00\x01\x00\x00", 1)


KILL_SCRIPT = """
import sys, time
sys.path.insert(0, {repo!r})
from tether_sim.io.mcap_log import RosMcapWriter
w = RosMcapWriter({path!r}, msg_search_path=[{prefix!r}], chunk_size=1 << 20)
w.add_topic("/chatter", "std_msgs/msg/String", "reliable")
def cdr(i):
    text = ("message %05d" % i).encode() + b"\\0"
    return b"\\x00\\x01\\x00\\x00" + len(text).to_bytes(4, "little") + text
for i in range(300):
    w.write("/chatter", cdr(i), 1000 + i)
    if i % 100 == 99:
        w.flush()          # three complete chunks: 0-99, 100-199, 200-299
for i in range(300, 350):  # an open chunk that never completes
    w.write("/chatter", cdr(i), 1000 + i)
print("READY", flush=True)
time.sleep(60)
"""


def test_sigkill_mid_write_keeps_complete_chunks(tmp_path, prefix):
    path = tmp_path / "killed.mcap"
    script = KILL_SCRIPT.format(repo=str(REPO), path=str(path), prefix=str(prefix))
    proc = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True)
    try:
        assert proc.stdout.readline().strip() == "READY"
    finally:
        proc.kill()  # SIGKILL: no close(), no footer
        proc.wait(timeout=10)
    with pytest.warns(TruncatedMcapWarning):
        got = [(log, msg.data) for _, _, log, msg in read_messages(path)]
    assert got == [(1000 + i, "message %05d" % i) for i in range(300)]
    with pytest.warns(TruncatedMcapWarning):
        info = read_summary(path)
    assert not info.complete and info.profile == "ros2" and info.topics["/chatter"].message_count == 300
    assert "kept 3 complete chunk(s)" in info.damage.describe()
    # mcap's own reader and rosbags refuse the cut file ...
    from mcap.reader import make_reader
    from rosbags.highlevel import AnyReader

    with pytest.raises(Exception), open(path, "rb") as handle:  # noqa: B017 - any refusal will do
        list(make_reader(handle).iter_messages())
    # ... tether-sim-recover rewrites it into a complete MCAP both open, losing only the open chunk
    from tether_sim.io.mcap_recover import main as recover_main, recover

    result = recover(path)
    # (the open chunk lived in the writer's memory: nothing of it reached the file)
    assert result.messages == 300 and not result.damage.complete
    out = Path(result.output)
    with open(out, "rb") as handle:
        reader = make_reader(handle)
        summary = reader.get_summary()
        assert summary.statistics.message_count == 300 and len(summary.chunk_indexes) >= 1
        got = [m.data[8:-1].decode() for _, _, m in reader.iter_messages(log_time_order=True)]
        assert got == ["message %05d" % i for i in range(300)]
        meta = {m.name: m.metadata for m in reader.iter_metadata()}
    bag = yaml.safe_load(meta["rosbag2"]["serialized_metadata"])
    assert bag["message_count"] == 300 and bag["topics_with_message_count"][0]["message_count"] == 300
    assert out.read_bytes()[-8:] == b"\x89MCAP0\r\n"  # end magic
    with AnyReader([out], default_typestore=get_typestore(Stores.ROS2_JAZZY)) as bag_reader:
        texts = [bag_reader.deserialize(raw, c.msgtype).data for c, _, raw in bag_reader.messages()]
    assert texts == ["message %05d" % i for i in range(300)]
    assert read_summary(out).complete and read_summary(out).damage is None
    assert recover_main([str(path), str(tmp_path / "again.mcap")]) == 0
    assert recover_main([str(tmp_path / "missing.mcap")]) == 2


def test_truncated_file_reads_up_to_last_complete_chunk(tmp_path, prefix, typestore):
    messages = make_messages(typestore)
    path = write_file(tmp_path / "full.mcap", prefix, messages, chunk_size=2048)
    with open(path, "rb") as handle:
        chunks = SeekingReader(handle).get_summary().chunk_indexes
    data = path.read_bytes()
    last = chunks[-2]
    cut = last.chunk_start_offset + last.chunk_length // 2  # inside the second-to-last chunk
    short = tmp_path / "cut.mcap"
    short.write_bytes(data[:cut])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        got = [(r.topic, r.log_time_ns, r.data) for r in iter_raw(short)]
    assert any(issubclass(w.category, TruncatedMcapWarning) for w in caught)
    complete = [c for c in chunks if c.chunk_start_offset + c.chunk_length <= cut]
    expected = sorted((m for m in messages if any(c.message_start_time <= m[2] <= c.message_end_time
                                                  for c in complete)), key=lambda m: m[2])
    assert len(got) == len(expected) > 0
    assert got == [(m[0], m[2], m[4]) for m in expected]


def test_corrupt_or_foreign_files_raise_clear_errors(tmp_path, prefix, typestore):
    with pytest.raises(McapLogError, match="no such MCAP file"):
        list(read_messages(tmp_path / "missing.mcap"))
    for name, content in [("empty.mcap", b""), ("text.mcap", b"hello, not an mcap file\n" * 10)]:
        (tmp_path / name).write_bytes(content)
        with pytest.raises(McapLogError, match=f"{name}: not an MCAP file"):
            list(read_messages(tmp_path / name))
    path = write_file(tmp_path / "good.mcap", prefix, make_messages(typestore), chunk_size=2048)
    with open(path, "rb") as handle:
        chunk = SeekingReader(handle).get_summary().chunk_indexes[1]
    data = bytearray(path.read_bytes())
    middle = chunk.chunk_start_offset + chunk.chunk_length - chunk.compressed_size // 2
    data[middle:middle + 8] = bytes(b ^ 0xFF for b in data[middle:middle + 8])
    bad = tmp_path / "flipped.mcap"
    bad.write_bytes(bytes(data))
    with pytest.raises(McapLogError, match="flipped.mcap"):
        list(read_messages(bad))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TruncatedMcapWarning)
        bad.write_bytes(bytes(data[: chunk.chunk_start_offset + chunk.chunk_length]))  # also no footer
        with pytest.raises(McapLogError, match="corrupt record"):
            list(read_messages(bad))


def _flip_in_chunk(path, k, n_bytes=64):
    """Flip ``n_bytes`` bytes in the compressed data of chunk ``k`` of a complete file; (chunks, bad copy)."""
    with open(path, "rb") as handle:
        chunks = SeekingReader(handle).get_summary().chunk_indexes
    chunk = chunks[k]
    data = bytearray(path.read_bytes())
    middle = chunk.chunk_start_offset + chunk.chunk_length - chunk.compressed_size // 2
    data[middle:middle + n_bytes] = bytes(b ^ 0xA5 for b in data[middle:middle + n_bytes])
    bad = path.with_name("bad_" + path.name)
    bad.write_bytes(bytes(data))
    return chunks, bad


@pytest.mark.parametrize("which", [-1, 1])
def test_recover_keeps_every_intact_chunk_around_a_corrupt_one(tmp_path, prefix, typestore, capsys, which):
    """64 corrupted bytes in one chunk (the last, or one in the middle) of a complete file: recovery keeps
    the messages of every other chunk, names the dropped chunk and counts the messages it held."""
    from tether_sim.io.mcap_recover import main as recover_main
    from tether_sim.io.mcap_scan import CorruptMcapWarning

    messages = make_messages(typestore, n=60)
    path = write_file(tmp_path / "run.mcap", prefix, messages, chunk_size=2048)
    chunks, bad = _flip_in_chunk(path, which)
    assert len(chunks) >= 4
    with pytest.raises(McapLogError, match="corrupt"):  # plain reading still refuses: nothing is lost silently
        list(read_messages(bad))
    out = tmp_path / "fixed.mcap"
    assert recover_main([str(bad), str(out)]) == 0
    said = capsys.readouterr().out
    dead = chunks[which]
    in_dead = [m for m in messages if dead.message_start_time <= m[2] <= dead.message_end_time]
    kept = sorted((m for m in messages if m not in in_dead), key=lambda m: m[2])
    assert f"dropped 1 corrupt record(s), {len(in_dead)} message(s) lost" in said
    assert f"bytes {dead.chunk_start_offset}-{dead.chunk_start_offset + dead.chunk_length}" in said
    assert "already complete" not in said
    got = [(r.topic, r.log_time_ns, r.data) for r in iter_raw(out)]
    assert got == [(m[0], m[2], m[4]) for m in kept] and len(kept) == len(messages) - len(in_dead)
    from rosbags.highlevel import AnyReader

    with AnyReader([out], default_typestore=get_typestore(Stores.EMPTY)) as bag_reader:  # rosbags opens the result
        assert sum(1 for _ in bag_reader.messages()) == len(kept)
    # reading with skip_corrupt gives the same intact messages, with a warning and the damage
    damage = []
    with pytest.warns(CorruptMcapWarning, match="dropped 1 corrupt"):
        again = [(r.topic, r.log_time_ns, r.data) for r in iter_raw(bad, skip_corrupt=True, damage=damage)]
    assert again == got and damage[0].complete and len(damage[0].corrupt) == 1
