"""A copy of a bag with static transforms added on ``/tf_static``, as if a static_transform_publisher
had run while it was recorded (``tfx static ... -b IN -o OUT``), or with its own static transforms
made safe to replay (``tfx static --repair``). The input is never modified."""

from __future__ import annotations

import os
import shutil
import tempfile
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, BinaryIO

import numpy as np

from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform
from tftools.sources.bag.damage import DamageError
from tftools.sources.bag.formats import ROS1, is_format
from tftools.sources.bag.unpack import Budget, zstd_file, zstd_messages
from tftools.sources.codecs import cdr
from tftools.sources.codecs.decoded import TransformEncoder
from tftools.sources.codecs.ros1 import encode_tf_message
from tftools.sources.codecs.types import TF_MESSAGE, ros1_message_type, typestore
from tftools.sources.contents import is_static_topic
from tftools.sources.errors import BagError, BagNotFoundError, UnknownBagFormatError
from tftools.sources.storage.locations import only_bag_files

STATIC_TOPIC = "/tf_static"

#: The callerid of the connection carrying the added transforms in a ROS1 bag: their authority.
PUBLISHER = "/tfx_static"

#: A repaired copy repeats its static transforms this often (s of record time), so that playing it
#: from any point, splitting it or filtering it by time keeps them.
REPAIR_EVERY_S = 5.0


@dataclass(frozen=True)
class _Plan:
    """What the copy adds: ``transforms`` at the start and, with ``every`` (ns), again that often;
    ``durable``: every /tf_static connection latched (ROS 1) or offered transient local (ROS 2);
    ``senders``: per transform, the /tf_static connection (a ROS 1 callerid, a ROS 2 topic) that sent
    it in the bag, so that it keeps its publisher; none: tfx's own (``PUBLISHER``)."""

    transforms: Sequence[Transform]
    every: int = 0
    durable: bool = False
    senders: Sequence[str] = ()

    def by_sender(self, stamp: int) -> dict[str, list[Transform]]:
        """The transforms stamped ``stamp``, one message per sender."""
        groups: dict[str, list[Transform]] = {}
        for i, t in enumerate(self.transforms):
            groups.setdefault(self.senders[i] if self.senders else PUBLISHER, []).append(replace(t, stamp=stamp))
        return groups


def add_static_transforms(
    bag: str | os.PathLike[str],
    output: str | os.PathLike[str],
    transforms: Sequence[Transform],
    *,
    force: bool = False,
) -> Path:
    """Write ``output``: every connection and message of ``bag`` (a ROS1 .bag file or a ROS2 bag
    directory) plus one ``/tf_static`` message holding ``transforms``, stamped and recorded at the
    bag's start. Refuses an existing ``output`` unless ``force``."""
    return _write_copy(Path(bag), Path(output), _Plan(transforms), force)


def repair_static_transforms(
    bag: str | os.PathLike[str], output: str | os.PathLike[str], *, force: bool = False
) -> tuple[Path, list[Transform]]:
    """Write ``output``: ``bag`` with its static transforms complete (the latest value of each, all in
    one message) at its start and every ``REPAIR_EVERY_S`` s, and ``/tf_static`` latched (ROS 1) or
    offered transient local (ROS 2), so that ``rosbag play`` / ``ros2 bag play`` give them to late
    subscribers and a copy from any point keeps them. Returns the copy and the transforms."""
    source = Path(bag)
    statics, senders = _latest_statics(source)  # read_recording says when there is no such bag
    plan = _Plan(statics, every=round(REPAIR_EVERY_S * NS_PER_S), durable=True, senders=senders)
    return _write_copy(source, Path(output), plan, force), statics


def _latest_statics(source: Path) -> tuple[list[Transform], list[str]]:
    """The latest value of each static transform of the recording at ``source`` (in first-seen
    order), and who sent it (``_Plan.senders``)."""
    from tftools.sources.recording import read_recording

    batch = read_recording([source]).transforms
    latest: dict[tuple[int, int], int] = {}
    for row in np.flatnonzero(batch.static).tolist():
        latest[(int(batch.parent[row]), int(batch.child[row]))] = row
    if not latest:
        raise BagError(str(source), "holds no static transforms", "add them with tfx static X Y Z ... -b IN -o OUT")
    names = batch.frame_names
    senders = [batch.authorities[int(batch.authority[row])] for row in latest.values()]
    statics = [
        Transform(tuple(batch.translation[row].tolist()), tuple(batch.rotation[row].tolist()), 0, names[p], names[c])
        for (p, c), row in latest.items()
    ]
    return statics, senders


def _write_copy(source: Path, target: Path, plan: _Plan, force: bool) -> Path:
    if not source.exists():
        raise BagNotFoundError(str(source))
    _never_over_the_input(source, target)
    if target.exists():
        if not force:
            raise BagError(str(target), "already exists", "choose another output path, or --force to replace it")
        if target.is_dir() and not only_bag_files(target):
            raise BagError(str(target), "is a folder that is not a ROS2 bag", "--force replaces only an earlier output")
    if not (source.is_dir() or is_format(source, ROS1)):
        raise UnknownBagFormatError(
            str(source), "static transforms are added to ROS1 .bag files and ROS2 bag directories"
        )
    # Written beside the target under its own name (a ROS2 bag names its files after its
    # directory), then moved into place: an interrupted copy leaves no half bag at ``output``.
    try:
        scratch = Path(tempfile.mkdtemp(prefix=".tfx-static-", dir=target.parent))
    except OSError as error:
        raise BagError(str(target), f"cannot be written ({error.strerror})") from None
    partial = scratch / target.name
    try:
        (_copy_rosbag2 if source.is_dir() else _copy_ros1)(source, partial, plan)
        if target.is_dir():
            shutil.rmtree(target)
        else:
            target.unlink(missing_ok=True)
        partial.rename(target)
    except OSError as error:  # disk full, read-only folder...
        raise BagError(str(target), f"cannot be written ({error.strerror or error})") from None
    except Exception as error:  # rosbags' reader and writer errors
        raise BagError(str(source), f"could not be copied ({type(error).__name__}: {error})") from None
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    return target


def _never_over_the_input(source: Path, target: Path) -> None:
    """Refuse an output that is the input, lies inside it (a ROS2 bag's file or metadata.yaml) or
    holds it: replacing it would destroy the recording."""
    given, written = source.resolve(), target.resolve()
    if written == given or given in written.parents or written in given.parents:
        raise BagError(str(target), "is the input bag, inside it or a folder holding it", "write the copy elsewhere")


def _copy_ros1(source: Path, target: Path, plan: _Plan) -> None:
    from rosbags.interfaces import ConnectionExtRosbag1
    from rosbags.rosbag1 import Reader, Writer

    with Reader(source) as reader, Writer(target) as writer:
        connections, static = {}, {}
        for c in reader.connections:
            ext = c.ext if isinstance(c.ext, ConnectionExtRosbag1) else ConnectionExtRosbag1(None, None)
            latching = 1 if plan.durable and is_static_topic(c.topic) else ext.latching
            connections[c.id] = writer.add_connection(
                c.topic, c.msgtype, msgdef=c.msgdef.data, md5sum=c.digest, callerid=ext.callerid, latching=latching
            )
            if _sends_statics(c):
                static[ext.callerid or ""] = connections[c.id]
        tf_type = ros1_message_type(TF_MESSAGE)
        own = None
        if set(plan.by_sender(0)) - set(static):  # transforms of no publisher in the bag: tfx's own connection
            own = writer.add_connection(
                STATIC_TOPIC,
                TF_MESSAGE,
                msgdef=tf_type.definition,
                md5sum=tf_type.md5sum,
                callerid=PUBLISHER,
                latching=1,
            )
        _copy_messages(plan, reader, writer, connections, static, own, encode_tf_message)


@contextmanager
def _budgeted_zstd(source: Path) -> Iterator[None]:
    """While rosbags reads a compressed ROS 2 bag, its zstd decompression goes through tftools' budgeted
    one (``unpack``), the same as when the bag is read for its transforms: a message or file that would
    decompress past its share of the budget stops the copy with an error, instead of filling memory or
    the temporary folder (rosbags decompresses without a bound)."""
    import rosbags.rosbag2.reader as rosbag2_reader

    size = sum(p.stat().st_size for p in source.iterdir() if p.is_file())
    real = rosbag2_reader.zstd  # type: ignore[attr-defined]
    message = zstd_messages(size)
    budget = Budget(size)

    class Budgeted:
        @staticmethod
        def decompress(data: bytes) -> bytes:
            return message(bytes(data))

        @staticmethod
        @contextmanager
        def open(file: BinaryIO, _mode: str = "rb") -> Iterator[BinaryIO]:
            with tempfile.TemporaryDirectory(prefix="tftools-") as folder:
                plain = Path(folder) / "plain"
                loss = zstd_file(file, plain, budget)
                if loss:
                    raise DamageError(loss)
                with plain.open("rb") as decompressed:
                    yield decompressed

    rosbag2_reader.zstd = Budgeted  # type: ignore[attr-defined,assignment]
    try:
        yield
    finally:
        rosbag2_reader.zstd = real  # type: ignore[attr-defined]


def _copy_rosbag2(source: Path, target: Path, plan: _Plan) -> None:
    from rosbags.interfaces import ConnectionExtRosbag2
    from rosbags.rosbag2 import CompressionFormat, CompressionMode, Reader, StoragePlugin, Writer

    store = typestore("ros2_humble")
    plugin = StoragePlugin.MCAP if any(source.glob("*.mcap")) else StoragePlugin.SQLITE3
    with _budgeted_zstd(source), Reader(source) as reader:
        writer = Writer(target, version=8, storage_plugin=plugin)
        if reader.compression_mode and reader.compression_format:
            writer.set_compression(
                CompressionMode[reader.compression_mode.upper()], CompressionFormat[reader.compression_format.upper()]
            )
        with writer:
            connections = {}
            for c in reader.connections:
                ext = c.ext if isinstance(c.ext, ConnectionExtRosbag2) else ConnectionExtRosbag2("cdr", [])
                connections[c.id] = writer.add_connection(
                    c.topic,
                    c.msgtype,
                    msgdef=c.msgdef.data,
                    rihs01=c.digest if c.digest.startswith("RIHS01_") else None,
                    serialization_format=ext.serialization_format,
                    offered_qos_profiles=[static_qos()]
                    if plan.durable and is_static_topic(c.topic)
                    else ext.offered_qos_profiles,
                    typestore=store,
                )
            existing = [c for c in reader.connections if c.topic == STATIC_TOPIC and c.msgtype == TF_MESSAGE]
            added = (
                connections[existing[0].id]
                if existing
                else writer.add_connection(
                    STATIC_TOPIC, TF_MESSAGE, typestore=store, offered_qos_profiles=[static_qos()]
                )
            )
            static = {c.topic: connections[c.id] for c in reader.connections if _sends_statics(c)}
            _copy_messages(plan, reader, writer, connections, static, added, cdr.encode_tf_message)


def _copy_messages(
    plan: _Plan,
    reader: Any,
    writer: Any,
    connections: dict[int, Any],
    static: dict[str, Any],
    own: Any,
    encode: TransformEncoder,
) -> None:
    """Every message of ``reader`` on its copy in ``connections``, and the plan's transforms at the
    bag's start, then every ``plan.every`` ns up to the last message: each on its sender's connection
    in ``static``, else on ``own``."""

    def add(stamp: int) -> None:
        for sender, transforms in plan.by_sender(stamp).items():
            writer.write(static.get(sender, own), stamp, encode(transforms))

    mark = reader.start_time if reader.message_count else 0
    add(mark)
    for connection, timestamp, data in reader.messages():
        while plan.every and timestamp >= mark + plan.every:
            mark += plan.every
            add(mark)
        writer.write(connections[connection.id], timestamp, data)


def _sends_statics(connection: Any) -> bool:
    return bool(is_static_topic(connection.topic) and connection.msgtype == TF_MESSAGE)


def static_qos() -> Any:
    """tf2_ros' static QoS: reliable, transient local, keep last 1 (StaticBroadcasterQoS)."""
    from rosbags.interfaces import Qos, QosDurability, QosHistory, QosLiveliness, QosReliability, QosTime

    never = QosTime(0, 0)
    return Qos(
        QosHistory.KEEP_LAST, 1, QosReliability.RELIABLE, QosDurability.TRANSIENT_LOCAL,
        never, never, QosLiveliness.SYSTEM_DEFAULT, never, False,
    )  # fmt: skip
