"""The same recording written again as real recorders and tools write it: other containers, compressions,
chunkings, a rosbag2 folder split into several files, record-time ties in another order. Built at test time from
a corpus recording (nothing of a recording is committed) with rosbags' and mcap's own writers.

Each variant holds the same messages, with the same record times, on the same topics, in the same order per
topic: what tfx finds in it must be what it finds in the original."""

from __future__ import annotations

import functools
import shutil
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from mcap.reader import make_reader
from mcap.writer import CompressionType, IndexType
from mcap.writer import Writer as McapWriter
from rosbags.interfaces import Qos
from rosbags.rosbag1 import Reader as Ros1Reader
from rosbags.rosbag1 import Writer as Ros1Writer
from rosbags.rosbag2 import CompressionFormat, CompressionMode, StoragePlugin
from rosbags.rosbag2 import Reader as Ros2Reader
from rosbags.rosbag2 import Writer as Ros2Writer
from rosbags.typesys import Stores, get_typestore
from ruamel.yaml import YAML

from tftools.sources.bag.ros1.view import view_order

_TYPES = get_typestore(Stores.ROS2_HUMBLE)
#: rosbag2's metadata.yaml with no type description hash (bags before Iron): rosbags' writer needs one.
_NO_HASH = "RIHS01_" + "0" * 64


@dataclass(frozen=True)
class Connection:
    """A connection (ROS 1) or topic (ROS 2) as its recording declares it."""

    topic: str
    msgtype: str
    msgdef: str
    digest: str  # ROS 1's md5sum, ROS 2's type description hash
    callerid: str = ""
    latching: int = 0
    serialization: str = "cdr"
    qos: tuple[Qos, ...] = ()


@dataclass(frozen=True)
class Contents:
    """A recording's connections and its messages (connection, record time ns, raw bytes) in its reader's order."""

    ros1: bool
    connections: dict[int, Connection]
    messages: list[tuple[int, int, bytes]]


@functools.cache
def read(path: Path) -> Contents:
    """A .bag's or a rosbag2 folder's connections and raw messages, as rosbags reads them (once per path)."""
    if path.is_file():
        with Ros1Reader(path) as bag:
            conns = {}
            for c in bag.connections:
                ros1: Any = c.ext
                conns[c.id] = Connection(
                    c.topic, c.msgtype, c.msgdef.data, c.digest, ros1.callerid or "", ros1.latching or 0
                )
            return Contents(True, conns, [(c.id, t, bytes(raw)) for c, t, raw in bag.messages()])
    with Ros2Reader(path) as bag:
        conns = {}
        for c in bag.connections:
            ext: Any = c.ext
            msgdef, digest = (c.msgdef.data if c.msgdef else ""), c.digest
            if not msgdef or not digest:  # a bag before Iron's: its metadata names types only
                try:
                    msgdef, digest = _TYPES.generate_msgdef(c.msgtype, ros_version=2)[0], _TYPES.hash_rihs01(c.msgtype)
                except Exception:  # a type the store does not know: kept without its definition
                    digest = digest or _NO_HASH
            conns[c.id] = Connection(
                c.topic,
                c.msgtype,
                msgdef,
                digest,
                serialization=ext.serialization_format,
                qos=tuple(ext.offered_qos_profiles),
            )
        return Contents(False, conns, [(c.id, t, bytes(raw)) for c, t, raw in bag.messages()])


def write_ros1(path: Path, contents: Contents, compression: str = "", chunk_bytes: int = 0) -> Path:
    """A ROS 1 bag as rosbag writes it: chunks compressed (``BZ2``, ``LZ4``) or not, of ``chunk_bytes``."""
    writer = Ros1Writer(path)
    if compression:
        writer.set_compression(Ros1Writer.CompressionFormat[compression])
    writer.open()
    if chunk_bytes:
        writer.chunk_threshold = chunk_bytes
    out = {
        key: writer.add_connection(
            c.topic, c.msgtype, msgdef=c.msgdef, md5sum=c.digest, callerid=c.callerid or None, latching=c.latching
        )
        for key, c in contents.connections.items()
    }
    for key, stamp, raw in contents.messages:
        writer.write(out[key], stamp, raw)
    writer.close()
    return path


def write_ros2(path: Path, contents: Contents, storage: str = "sqlite3", message_zstd: bool = False) -> Path:
    """A rosbag2 folder as ``ros2 bag record`` writes it (``-s mcap``; ``--compression-mode message``)."""
    writer = Ros2Writer(path, version=9, storage_plugin=StoragePlugin[storage.upper()])
    if message_zstd:
        writer.set_compression(CompressionMode.MESSAGE, CompressionFormat.ZSTD)
    writer.open()
    out = {
        key: writer.add_connection(
            c.topic,
            c.msgtype,
            msgdef=c.msgdef,
            rihs01=c.digest,
            serialization_format=c.serialization,
            offered_qos_profiles=c.qos,
        )
        for key, c in contents.connections.items()
    }
    for key, stamp, raw in contents.messages:
        writer.write(out[key], stamp, raw)
    writer.close()
    return path


def write_split(path: Path, contents: Contents, parts: int, storage: str = "sqlite3") -> Path:
    """A rosbag2 folder of ``parts`` files of equal spans of record time, each holding every topic, and one
    metadata.yaml listing them (``ros2 bag record --max-bag-duration``)."""
    times = [t for _, t, _ in contents.messages]
    first, last = min(times), max(times)
    bounds = [first + (last - first) * i // parts for i in range(1, parts)]
    split: list[list[tuple[int, int, bytes]]] = [[] for _ in range(parts)]
    for message in contents.messages:
        split[sum(message[1] >= b for b in bounds)].append(message)
    path.mkdir()
    yaml = YAML(typ="safe", pure=True)
    infos = []
    suffix = ".db3" if storage == "sqlite3" else ".mcap"
    for i, messages in enumerate(split):
        part = write_ros2(path / f"_part{i}", Contents(False, contents.connections, messages), storage)
        (part / f"_part{i}{suffix}").rename(path / f"{path.name}_{i}{suffix}")
        infos.append(yaml.load((part / "metadata.yaml").read_text())["rosbag2_bagfile_information"])
        shutil.rmtree(part)
    info = dict(infos[0])
    written = [x for x in infos if x["message_count"]]
    start = min(x["starting_time"]["nanoseconds_since_epoch"] for x in written)
    end = max(x["starting_time"]["nanoseconds_since_epoch"] + x["duration"]["nanoseconds"] for x in written)
    info["relative_file_paths"] = [f"{path.name}_{i}{suffix}" for i in range(parts)]
    info["files"] = [dict(x["files"][0], path=f"{path.name}_{i}{suffix}") for i, x in enumerate(infos)]
    info["message_count"] = sum(x["message_count"] for x in infos)
    info["starting_time"] = {"nanoseconds_since_epoch": start}
    info["duration"] = {"nanoseconds": end - start}
    info["topics_with_message_count"] = [
        dict(topic, message_count=sum(x["topics_with_message_count"][j]["message_count"] for x in infos))
        for j, topic in enumerate(info["topics_with_message_count"])
    ]
    with (path / "metadata.yaml").open("w") as out:
        yaml.dump({"rosbag2_bagfile_information": info}, out)
    return path


def write_mcap_ros1(path: Path, contents: Contents, chunked: bool = True) -> Path:
    """A ROS 1 bag as MCAP with Foxglove's ros1 profile (``mcap convert``): ``ros1msg`` schemas named as ROS 1
    names types, ``ros1`` messages (the bag's bytes), each channel's callerid and latching in its metadata."""
    with path.open("wb") as out:
        writer = McapWriter(out, use_chunking=chunked)
        writer.start(profile="ros1", library="tftools tests")
        schemas: dict[str, int] = {}
        channels: dict[int, int] = {}
        for key, c in contents.connections.items():
            name = c.msgtype.replace("/msg/", "/")
            if name not in schemas:
                schemas[name] = writer.register_schema(name=name, encoding="ros1msg", data=c.msgdef.encode())
            metadata = {"md5sum": c.digest, "callerid": c.callerid} | ({"latching": "1"} if c.latching else {})
            channels[key] = writer.register_channel(c.topic, "ros1", schemas[name], metadata)
        for sequence, (key, stamp, raw) in enumerate(contents.messages):
            writer.add_message(channels[key], log_time=stamp, data=raw, publish_time=stamp, sequence=sequence)
        writer.finish()
    return path


def replay_ordered(messages: Sequence[tuple[int, int, bytes]]) -> list[tuple[int, int, bytes]]:
    """A ROS 1 bag's messages in the order ``rosbag play`` (``rosbag::View``) gives them, ties of record time
    included: the order a converter that replays the bag writes, and the one tfx reads the bag in. A
    container without that order (MCAP: ties in file order) of the messages in another order holds other
    arrivals: a sensor message before or after the tf of its instant."""
    keys = sorted({key for key, _, _ in messages})
    times = [np.array([t for k, t, _ in messages if k == key], np.int64) for key in keys]
    places = view_order(times)
    placed: list[tuple[int, tuple[int, int, bytes]]] = []
    for key, place in zip(keys, places, strict=True):
        mine = [m for m in messages if m[0] == key]
        placed += zip(place.tolist(), mine, strict=True)
    return [m for _, m in sorted(placed, key=lambda p: p[0])]


def rewrite_mcap(
    source: Path, path: Path, channel_metadata: Callable[[dict[str, str]], dict[str, str]] | None = None, **options: Any
) -> Path:
    """An MCAP file's records written again by mcap's Writer with ``options`` (chunking, compression, index,
    summary): the same schemas, channels (their metadata as ``channel_metadata`` makes it) and messages."""
    with source.open("rb") as f, path.open("wb") as out:
        reader = make_reader(f)
        header = reader.get_header()
        writer = McapWriter(out, **options)
        writer.start(profile=header.profile, library=header.library)
        schemas: dict[int, int] = {}
        channels: dict[int, int] = {}

        def registered(schema: Any, channel: Any) -> None:
            if schema is not None and schema.id not in schemas:
                schemas[schema.id] = writer.register_schema(schema.name, schema.encoding, schema.data)
            if channel.id not in channels:
                schema_id = schemas.get(channel.schema_id, 0)
                metadata = channel.metadata if channel_metadata is None else channel_metadata(channel.metadata)
                channels[channel.id] = writer.register_channel(
                    channel.topic, channel.message_encoding, schema_id, metadata
                )

        summary = reader.get_summary()
        for channel in summary.channels.values() if summary is not None else ():  # those without messages too
            registered(summary.schemas.get(channel.schema_id) if summary is not None else None, channel)
        for schema, channel, message in reader.iter_messages(log_time_order=False):
            registered(schema, channel)
            writer.add_message(
                channels[channel.id], message.log_time, message.data, message.publish_time, message.sequence
            )
        writer.finish()
    return path


def ties_reordered(messages: Sequence[tuple[int, int, bytes]]) -> list[tuple[int, int, bytes]]:
    """Messages of one record time on several connections in the other connections' order, each connection's own
    messages kept in their order (a bag written again, by ``rosbag filter`` or a reindex, interleaves ties so)."""
    out: list[tuple[int, int, bytes]] = []
    i = 0
    while i < len(messages):
        j = i
        while j < len(messages) and messages[j][1] == messages[i][1]:
            j += 1
        out.extend(sorted(messages[i:j], key=lambda m: -m[0]))
        i = j
    return out


Variant = Callable[[Path, Path], Path]  # (the original, a new folder) -> the variant's path to open


def _ros1(name: str, **kw: Any) -> Variant:
    return lambda source, folder: write_ros1(folder / f"{name}.bag", read(source), **kw)


def _ties_ros1(source: Path, folder: Path) -> Path:
    contents = read(source)
    reordered = Contents(True, contents.connections, ties_reordered(contents.messages))
    return write_ros1(folder / "ties.bag", reordered, chunk_bytes=4096)


def _replayed(source: Path) -> Contents:
    contents = read(source)
    return Contents(True, contents.connections, replay_ordered(contents.messages))


def _mcap_of(source: Path, folder: Path) -> Path:
    """A ROS 2 recording's MCAP file: its own, or the bag written as MCAP."""
    own = sorted(source.glob("*.mcap")) if source.is_dir() else [source]
    if len(own) == 1:
        return own[0]
    return next(write_ros2(folder / "as_mcap", read(source), "mcap").glob("*.mcap"))


def _other_storage(source: Path, folder: Path) -> Path:
    contents = read(source)
    mcap = any(source.glob("*.mcap"))
    return write_ros2(folder / "other_storage", contents, "sqlite3" if mcap else "mcap")


def _mcap_rewritten(name: str, **options: Any) -> Variant:
    """The recording's MCAP written again with ``options``: in its bag directory, beside its metadata.yaml
    (``ros2 bag convert`` with a storage preset), or alone where it came alone."""

    def written(source: Path, folder: Path) -> Path:
        mcap = _mcap_of(source, folder)
        if not (mcap.parent / "metadata.yaml").exists():
            return rewrite_mcap(mcap, folder / f"{name}.mcap", **options)
        bag = folder / name
        bag.mkdir()
        shutil.copyfile(mcap.parent / "metadata.yaml", bag / "metadata.yaml")
        rewrite_mcap(mcap, bag / mcap.name, **options)
        return bag

    return written


ROS1_VARIANTS: dict[str, Variant] = {
    "bz2 chunks": _ros1("bz2", compression="BZ2"),
    "lz4 chunks": _ros1("lz4", compression="LZ4"),
    "1 KiB chunks": _ros1("tiny", chunk_bytes=1024),
    "ties reordered": _ties_ros1,
    "mcap ros1 profile": lambda source, folder: write_mcap_ros1(folder / "ros1.mcap", _replayed(source)),
    "mcap ros1 unchunked": lambda source, folder: write_mcap_ros1(folder / "ros1u.mcap", _replayed(source), False),
}
ROS2_VARIANTS: dict[str, Variant] = {
    "other storage": _other_storage,
    "messages zstd": lambda source, folder: write_ros2(folder / "zstd", read(source), message_zstd=True),
    "split in 3": lambda source, folder: write_split(folder / "split", read(source), 3),
    "split in 2 mcap": lambda source, folder: write_split(folder / "split_mcap", read(source), 2, "mcap"),
    "mcap unchunked": _mcap_rewritten("unchunked", use_chunking=False),
    "mcap lz4": _mcap_rewritten("lz4", compression=CompressionType.LZ4),
    "mcap without summary": _mcap_rewritten(
        "bare",
        index_types=IndexType.NONE,
        repeat_channels=False,
        repeat_schemas=False,
        use_statistics=False,
        use_summary_offsets=False,
    ),
}
#: A bare MCAP file (no rosbag2 folder): only its own records written again.
MCAP_VARIANTS: dict[str, Variant] = {
    name: variant for name, variant in ROS2_VARIANTS.items() if name.startswith("mcap")
}
