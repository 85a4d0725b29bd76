"""A copy of a bag with static transforms added on ``/tf_static``, as if a static_transform_publisher
had run while it was recorded (``tfx static ... -b IN -o OUT``), or with its own static transforms
made safe to replay (``tfx static --repair``): read through tftools' reader, every message copied as
recorded (its type known or not), written with rosbags' writers. The input is never modified."""

from __future__ import annotations

import os
import re
import shutil
import sqlite3
import tempfile
from collections.abc import Mapping, Sequence
from contextlib import ExitStack, closing
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from tftools.analysis.wtf.replay import REPEATED_EVERY_S
from tftools.core.arrays import BoolArray, Int32Array, Int64Array
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform
from tftools.sinks.errors import CopyError
from tftools.sinks.static_held import HeldStatics, Messages, StaticRows
from tftools.sources.bag.contents import RecordWindow
from tftools.sources.bag.formats import MCAP, ROS1, Format, format_of
from tftools.sources.bag.mcap.index import chunks_compressed
from tftools.sources.bag.reader import BagReader
from tftools.sources.codecs import cdr
from tftools.sources.codecs.ros1 import encode_tf_message
from tftools.sources.codecs.types import TF_MESSAGE, ros1_message_type, rosidl_name, typestore
from tftools.sources.contents import Recorded, is_static_topic
from tftools.sources.errors import BagError
from tftools.sources.storage.locations import METADATA, only_bag_files

STATIC_TOPIC = "/tf_static"

#: The callerid of the connection carrying the added transforms in a ROS1 bag: their authority.
PUBLISHER = "/tfx_static"

#: At most this many repeats of the statics between two messages of the recording (an hour's at 10 s).
SILENCE_REPEATS = 360

#: A repaired copy repeats its static transforms this often (s of record time), so that playing it
#: from any point, splitting it or filtering it by time keeps them: as often as wtf's static_volatile
#: asks of statics re-sent through a recording.
REPAIR_EVERY_S = REPEATED_EVERY_S


@dataclass(frozen=True)
class _Plan:
    """What the copy adds: ``messages``, each (who sends it, its transforms), stamped at its start; or ``statics``, the
    recording's own, which it sends as tf2 holds them (``HeldStatics``) at its start and, with ``every`` (ns), again
    that often. ``durable``: every /tf_static connection latched (ROS 1) or offered transient local (ROS 2). A sender
    is who sent those transforms in the bag (its authority: a ROS 1 callerid, else the topic), so that the copy
    repeats them on that same connection and tfx sees the publishers it saw before; ``PUBLISHER``: tfx's own."""

    messages: Sequence[tuple[str, Sequence[Transform]]] = ()
    statics: StaticRows | None = None
    every: int = 0
    durable: bool = False
    #: The frames whose transforms are repeated only before a record time (ns) (``_repeated_until``): the others
    #: always are.
    until: Mapping[str, int] = field(default_factory=dict)

    def stamped(self, stamp: int) -> Messages:
        """``messages`` with their transforms stamped ``stamp``."""
        return [(sender, [replace(t, stamp=stamp) for t in transforms]) for sender, transforms in self.messages]

    def repeated(self, transforms: Sequence[Transform], time: int) -> list[Transform]:
        """Those of ``transforms`` repeated at record time ``time``."""
        return [t for t in transforms if time < self.until.get(t.child_frame_id, time + 1)]


@dataclass(frozen=True)
class Copied:
    """A copy written: where, and the types it holds messages of but no definition (``undescribed``): its
    recording held none (rosbag2 before Iron stored none in a .db3) and tfx knows none. Their messages are
    copied as recorded; a reader that decodes them needs their definitions from elsewhere."""

    path: Path
    undescribed: tuple[str, ...] = ()


def add_static_transforms(
    bag: str | os.PathLike[str],
    output: str | os.PathLike[str],
    transforms: Sequence[Transform],
    *,
    force: bool = False,
) -> Path:
    """Write ``output``: every connection and message of ``bag`` (a ROS1 .bag file, a ROS2 bag directory,
    a bare .db3, or a bare .mcap copied to a bare .mcap) plus one ``/tf_static`` message holding
    ``transforms``, stamped at the bag's start and recorded just before its first message. Refuses an
    existing ``output`` unless ``force``."""
    return copy_adding(bag, output, transforms, force=force).path


def copy_adding(
    bag: str | os.PathLike[str], output: str | os.PathLike[str], transforms: Sequence[Transform], *, force: bool
) -> Copied:
    """``add_static_transforms``, saying which types the copy holds no definition of."""
    return _write_copy(Path(bag), Path(output), _Plan([(PUBLISHER, transforms)]), force)


def repair_static_transforms(
    bag: str | os.PathLike[str], output: str | os.PathLike[str], *, force: bool = False
) -> tuple[Path, list[Transform]]:
    """Write ``output``: ``bag`` with its static transforms repeated (as tf2 holds them at each instant,
    ``HeldStatics``) at its start and every ``REPAIR_EVERY_S`` s, and ``/tf_static`` latched (ROS 1) or
    offered transient local (ROS 2), so that ``rosbag play`` / ``ros2 bag play`` give them to late subscribers
    and a copy from any point keeps them. Returns the copy and the transforms (the latest value of each)."""
    copied, statics = copy_repairing(bag, output, force=force)
    return copied.path, statics


def copy_repairing(
    bag: str | os.PathLike[str], output: str | os.PathLike[str], *, force: bool
) -> tuple[Copied, list[Transform]]:
    """``repair_static_transforms``, saying which types the copy holds no definition of."""
    source = Path(bag)
    rows, statics, until = _static_rows(source)  # read_recording says when there is no such bag
    plan = _Plan(statics=rows, every=round(REPAIR_EVERY_S * NS_PER_S), durable=True, until=until)
    return _write_copy(source, Path(output), plan, force), statics


#: ``_Plan.until`` of a frame whose static transform is never repeated: it came on /tf before /tf_static.
NEVER = -(2**63)


def _static_rows(source: Path) -> tuple[StaticRows, list[Transform], dict[str, int]]:
    """The recording's /tf_static transforms as tf2 takes them (``StaticRows``), the value tf2 keeps at the end of
    each static frame (in first-seen order), and ``_Plan.until`` (``_repeated_until``)."""
    from tftools.sources.recording import read_recording

    recording = read_recording([source])
    batch = recording.transforms
    rows = np.flatnonzero(batch.static)
    if not len(rows):
        damage = [line for file in recording.contents.files for line in file.problems]
        if damage:  # its statics may be in what was lost; and it could not be copied whole anyway
            raise CopyError(str(source), f"cannot be copied whole: {damage[0]}", "damaged")
        raise CopyError(str(source), "holds no static transforms", "no_statics")
    rows = rows[np.argsort(batch.record_time[rows], kind="stable")]  # each message keeps its own order
    names = batch.frame_names
    authority, times = batch.authority[rows].astype(np.int64), batch.record_time[rows]
    messages = np.cumsum(np.r_[False, (np.diff(authority) != 0) | (np.diff(times) != 0)])  # one sender, one instant
    starts = np.flatnonzero(np.r_[True, np.diff(messages) != 0])

    def transform(k: int) -> Transform:
        row = int(rows[k])
        value = (tuple(batch.translation[row].tolist()), tuple(batch.rotation[row].tolist()))
        stamp = int(batch.stamp[row])
        return Transform(value[0], value[1], stamp, names[int(batch.parent[row])], names[int(batch.child[row])])

    senders = [batch.authorities[int(a)] for a in authority[starts]]
    held = StaticRows(times, batch.child[rows], messages, senders, transform)
    latest = dict(zip(batch.child[rows].tolist(), range(len(rows)), strict=True))  # first seen, the last of each
    until = _repeated_until(batch.static, batch.child, batch.record_time, len(names))
    return held, [transform(k) for k in latest.values()], {names[c]: t for c, t in until.items()}


def _repeated_until(static: BoolArray, child: Int32Array, record_time: Int64Array, frames: int) -> dict[int, int]:
    """The frames (ids) sent on both /tf_static and /tf, and the record time from which the copy no longer repeats
    their static transforms: their first /tf sample, or ``NEVER`` where /tf came first. tf2 keeps one cache per
    frame: ROS 2's empties it each time the frame switches between /tf_static and /tf; ROS 1's keeps the kind its
    first sample made and lets every later sample replace a static value. Repeated after the frame's /tf samples
    began, a static transform emptied its history (ROS 2: the JetAcker's map -> odom, 44 samples to 3, and a
    `clock` error) or brought back the static parent (ROS 1: the Neato beside its driver, 1 change of parent to
    35); repeated only before them, tf2 holds what it held of the recording."""
    big = np.iinfo(np.int64).max
    first_tf, first_static = np.full(frames, big, np.int64), np.full(frames, big, np.int64)
    np.minimum.at(first_tf, child[~static], record_time[~static])
    np.minimum.at(first_static, child[static], record_time[static])
    both = np.flatnonzero((first_tf < big) & (first_static < big))
    return {int(c): int(first_tf[c]) if first_static[c] < first_tf[c] else NEVER for c in both}


#: The type hash a ROS 2 copy is written with where its recording gave none (ROS 2 bags before Iron have
#: none) and tfx has no definition of its own: rosbags' writer needs one; ``_Rosbag2Copy.finish`` leaves the
#: copy's hash empty there, as the recording's was.
UNKNOWN_TYPE_HASH = "RIHS01_" + "0" * 64


class _CopyError(Exception):
    """The writer failed on a message the reader handed on: said of the output, not of the input."""

    def __init__(self, error: BaseException) -> None:
        super().__init__(str(error))
        self.error = error

    def said_of(self, target: Path) -> BagError:
        """A ``BagError`` raised by the copier itself as it is; any other as the output's."""
        if isinstance(self.error, BagError):
            return self.error
        e = self.error
        why = e.strerror if isinstance(e, OSError) and e.strerror else f"{type(e).__name__}: {e}"
        return BagError(str(target), f"cannot be written ({why})")


def _write_copy(source: Path, target: Path, plan: _Plan, force: bool) -> Copied:
    fmt = format_of(source)  # the bag's own errors: missing, a FIFO, not a recording
    _never_over_the_input(source, target)
    if target.exists() or target.is_symlink():
        if not force:
            raise CopyError(str(target), "already exists", "exists")
        if not (target.is_file() or (target.is_dir() and only_bag_files(target))):
            raise CopyError(str(target), "is not a regular file or a bag directory", "not_replaceable")
    # Written beside the target under its own name (a ROS2 bag names its files after its
    # directory), then moved into place: an interrupted copy leaves no half bag at ``output``.
    try:
        scratch = Path(tempfile.mkdtemp(prefix=".tfx-static-", dir=target.parent))
    except OSError as error:
        raise BagError(str(target), f"cannot be written ({error.strerror})") from None
    partial = scratch / target.name
    try:
        written, undescribed = _copy(source, fmt, partial, plan)
        if target.is_dir() and not target.is_symlink():
            shutil.rmtree(target)
        else:
            target.unlink(missing_ok=True)
        written.rename(target)
    except _CopyError as failed:
        raise failed.said_of(target) from None
    except OSError as error:  # disk full, read-only folder...
        raise BagError(str(target), f"cannot be written ({error.strerror or error})") from None
    except BagError:  # the reader's: what is wrong with the input
        raise
    except Exception as error:  # rosbags' writer, closing the copy
        raise BagError(str(target), f"cannot be written ({type(error).__name__}: {error})") from None
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    return Copied(target, undescribed)


def _never_over_the_input(source: Path, target: Path) -> None:
    """Refuse an output that is the input, lies inside it (a ROS2 bag's file or metadata.yaml) or
    holds it: replacing it would destroy the recording."""
    given, written = source.resolve(), target.resolve()
    if written == given or given in written.parents or written in given.parents:
        raise BagError(str(target), "is the input bag, inside it or a folder holding it", "write the copy elsewhere")


def _copy(source: Path, fmt: Format, target: Path, plan: _Plan) -> tuple[Path, tuple[str, ...]]:
    """Copy ``source`` (of format ``fmt``) to ``target`` with ``plan``'s transforms; returns what was
    written (a bare .mcap is copied to a bare .mcap: the file inside the rosbag2 directory written), and the
    types it holds no definition of."""
    copy: _Copy = _Ros1Copy(target, plan) if fmt is ROS1 else _Rosbag2Copy(source, fmt, target, plan)
    with ExitStack() as stack:
        reader = stack.enter_context(BagReader([source], copy=copy))
        try:
            copy.open(stack)
        except Exception as error:
            raise _CopyError(error) from None
        # The descriptions only: every connection (those without messages too), and where the bag starts.
        head = reader.read(RecordWindow(0, 0)).files[0]
        try:
            if head.message_count:
                copy.start(head.start)
        except Exception as error:
            raise _CopyError(error) from None
        read = reader.read().files[0]
        if read.problems:
            raise CopyError(str(source), f"cannot be copied whole: {read.problems[0]}", "damaged")
        if copy.mark is None:  # no message at all: the plan's are all the copy holds
            copy.start(0)
    copy.finish()
    return (target / f"{target.name}.mcap" if fmt is MCAP else target), tuple(sorted(copy.undescribed))


class _Copy:
    """A copy being written: the messages handed on by the reader, and the plan's transforms at the
    start and every ``plan.every`` ns up to the last message, each on its sender's connection."""

    def __init__(self, target: Path, plan: _Plan) -> None:
        self.target = target
        self.plan = plan
        self.held = HeldStatics(plan.statics) if plan.statics is not None else None
        self.writer: Any = None
        self.connections: dict[tuple[str, ...], Any] = {}
        #: The record time of the plan's last messages; None before the copy's start is known.
        self.mark: int | None = None
        self.undescribed: set[str] = set()

    def open(self, stack: ExitStack) -> None:
        raise NotImplementedError

    def finish(self) -> None:
        """After the writer closed the copy."""

    def start(self, mark: int) -> int:
        """The plan's messages ahead of the copy's start, ``mark`` (record time, ns); returns ``mark``."""
        self.mark = mark
        if self.plan.statics is not None and all(t == mark for t in self.plan.statics.message_times()):
            return mark  # the recording begins with them: a repeat ahead of its messages gives tf2 nothing it lacks
        self._statics(mark, ahead=True)
        return mark

    def channel(self, recorded: Recorded) -> None:
        try:
            self._connection(recorded)
        except Exception as error:  # the writer's: not the reader's to judge
            raise _CopyError(error) from None

    def message(self, recorded: Recorded, time: int, payload: memoryview) -> None:
        try:
            # Where its description did not say where it starts (a damaged .db3), its first message does.
            mark = self.start(time) if self.mark is None else self.mark
            if self.plan.every and (time - mark) // self.plan.every > SILENCE_REPEATS:
                # A silence of hours, or a record time decades from the rest (a clock reset, a damaged file): the
                # repeats of its last stretch only; one every 10 s of it is a loop sized by a time read from the file.
                mark = time - (time - mark) % self.plan.every - SILENCE_REPEATS * self.plan.every
            while self.plan.every and time >= mark + self.plan.every:
                mark += self.plan.every
                self._statics(mark)
            self.mark = mark
            self.writer.write(self._connection(recorded), time, payload)
        except Exception as error:  # the writer's, or a disk full: not the reader's to judge
            raise _CopyError(error) from None

    def _statics(self, stamp: int, ahead: bool = False) -> None:
        """What the plan sends at record time ``stamp``, recorded a nanosecond apart from it on, or ``ahead`` of it
        (the copy's start, before the recording's first message): messages recorded at one instant on one topic
        read as one message, as tfx's own did beside the Webots e-puck's first /tf_static message (recorded at the
        copy's start), told a publisher of both. Added transforms are stamped ``stamp``; the recording's own are
        sent as tf2 holds them, with their own stamps (restamped, a repeat reads as another publisher's message
        where the recording names none: the real Neatos' repaired copies told 4 publishers of 2)."""
        messages = self.held.at(stamp) if self.held is not None else self.plan.stamped(stamp)
        first = max(stamp - len(messages), 0) if ahead else stamp  # no record time before 0 (ROS 1, MCAP)
        for k, (sender, transforms) in enumerate(messages):
            if sent := self.plan.repeated(transforms, first + k):
                self.writer.write(self._connection(self._sent_by(sender)), first + k, self._encode(sent))

    def _sent_by(self, sender: str) -> Recorded:
        raise NotImplementedError

    def _encode(self, transforms: Sequence[Transform]) -> bytes:
        raise NotImplementedError

    def _connection(self, recorded: Recorded) -> Any:
        raise NotImplementedError


class _Ros1Copy(_Copy):
    """A ROS 1 bag: one connection per topic, type and callerid, latched as recorded (every /tf_static
    one with ``plan.durable``)."""

    def open(self, stack: ExitStack) -> None:
        from rosbags.rosbag1 import Writer

        self.writer = stack.enter_context(Writer(self.target))

    def _sent_by(self, sender: str) -> Recorded:
        tf = ros1_message_type(TF_MESSAGE)
        topic, publisher = (sender, "") if is_static_topic(sender) else (STATIC_TOPIC, sender)
        return Recorded(topic, tf.name, "ros1", tf.definition, tf.md5sum, publisher, latching=True)

    def _encode(self, transforms: Sequence[Transform]) -> bytes:
        return encode_tf_message(transforms)

    def _connection(self, recorded: Recorded) -> Any:
        key = (recorded.topic, rosidl_name(recorded.type_name), recorded.publisher)
        if key not in self.connections:
            latching = recorded.latching or (self.plan.durable and is_static_topic(recorded.topic))
            self.connections[key] = self.writer.add_connection(
                recorded.topic,
                key[1],
                msgdef=recorded.definition,
                md5sum=recorded.digest or "*",  # ROS 1's "any type"
                callerid=recorded.publisher or None,
                latching=int(latching),
            )
        return self.connections[key]


class _Rosbag2Copy(_Copy):
    """A ROS 2 bag in the storage of the input (sqlite3 or mcap), compressed as it was: one connection
    per topic, type and encoding, with the QoS it was recorded with (tf2_ros' static QoS on every
    /tf_static topic with ``plan.durable``). CDR messages only."""

    def __init__(self, source: Path, fmt: Format, target: Path, plan: _Plan) -> None:
        super().__init__(target, plan)
        self.source = source
        self.mcap = fmt is MCAP or (source.is_dir() and any(source.glob("*.mcap*")))
        self.store = typestore("ros2_humble")
        self.hashes: dict[str, str] = {}

    def open(self, stack: ExitStack) -> None:
        from rosbags.rosbag2 import CompressionFormat, CompressionMode, StoragePlugin, Writer

        storage = StoragePlugin.MCAP if self.mcap else StoragePlugin.SQLITE3
        self.writer = Writer(self.target, version=8, storage_plugin=storage)
        mode, self.hashes = _metadata(self.source)
        if mode:
            self.writer.set_compression(CompressionMode[mode.upper()], CompressionFormat.ZSTD)
        elif self.mcap and any(chunks_compressed(f) for f in _mcap_files(self.source)):
            # CyberShip Voyager's MCAP (corpus ros2-cybership-voyager-mocap-basin-2025-mcap): zstd chunks,
            # 21.7 MB; copied uncompressed it was 101 MB
            self.writer.set_compression(CompressionMode.STORAGE, CompressionFormat.ZSTD)
        stack.enter_context(self.writer)

    def finish(self) -> None:
        """The copy describes each type as its recording did. A type whose recording gave no hash (ROS 2 bags
        before Iron), and tfx no definition of its own, is left without one: rosbags' writer gave it
        ``UNKNOWN_TYPE_HASH``, and rosbags' reader refused the whole copy, the hash of its definition not being
        that one (the CougUV AUV's .mcap, ros2_mcap_coug_auv_replayed: its schemas of frost_interfaces/msg/... and
        dvl_msgs/msg/... kept, their hashes zeros in metadata.yaml). A type of which the recording gave no
        definition either gets none in the copy's .db3, as in the recording (a Neato's neato2_interfaces/msg/Bump,
        Gazebo's PerformanceMetrics; an .mcap's channel names a schema: an empty one, as rosbag2 writes it)."""
        metadata = self.target / METADATA
        if metadata.is_file():
            text = metadata.read_text(encoding="utf-8")
            text = re.sub(rf"type_description_hash:\s+{UNKNOWN_TYPE_HASH}\b", "type_description_hash: ''", text)
            metadata.write_text(text, encoding="utf-8")
        for db3 in self.target.glob("*.db3"):
            with closing(sqlite3.connect(db3)) as db, db:
                db.execute("DELETE FROM message_definitions WHERE encoded_message_definition = ''")
                for table in ("message_definitions", "topics"):
                    db.execute(
                        f"UPDATE {table} SET type_description_hash = '' WHERE type_description_hash = ?",
                        (UNKNOWN_TYPE_HASH,),
                    )

    def _sent_by(self, sender: str) -> Recorded:
        return Recorded(sender if is_static_topic(sender) else STATIC_TOPIC, TF_MESSAGE, "cdr")

    def _encode(self, transforms: Sequence[Transform]) -> bytes:
        return cdr.encode_tf_message(transforms)

    def _connection(self, recorded: Recorded) -> Any:
        key = (recorded.topic, rosidl_name(recorded.type_name), recorded.encoding)
        if key not in self.connections:
            if recorded.encoding != "cdr":
                raise CopyError(
                    str(self.source),
                    f"{recorded.topic} is in {recorded.encoding or 'no'} encoding: a ROS 2 copy holds CDR messages",
                    "encoding",
                )
            definition, digest = self._described(key[1], recorded)
            self.connections[key] = self.writer.add_connection(
                recorded.topic,
                key[1],
                msgdef=definition,
                rihs01=digest,
                serialization_format=recorded.encoding,
                offered_qos_profiles=self._qos(recorded),
            )
        return self.connections[key]

    def _described(self, type_name: str, recorded: Recorded) -> tuple[str, str]:
        """The type's definition and hash: the recording's (an .mcap's schema as it is, a .db3's
        message_definitions, metadata.yaml's hash), else, where it gave no definition, those of the types tfx
        knows (ROS 2 Humble's; their hash is not said of another definition), else none (``UNKNOWN_TYPE_HASH``,
        ``undescribed``): its messages are copied all the same."""
        definition = recorded.definition
        digest = recorded.digest or self.hashes.get(recorded.type_name, "")
        digest = digest if digest.startswith("RIHS01_") else ""
        if not definition and type_name in self.store.fielddefs:
            definition, _ = self.store.generate_msgdef(type_name, ros_version=2)
            digest = digest or self.store.hash_rihs01(type_name)
        if not definition:
            self.undescribed.add(type_name)
        return definition, digest or UNKNOWN_TYPE_HASH

    def _qos(self, recorded: Recorded) -> list[Any]:
        """The QoS profiles the copy offers on ``recorded``'s topic: rosbag2 records one per publisher, which is how
        a ROS 2 recording counts them. The recording's; on /tf_static each made tf2_ros' static QoS with
        ``plan.durable``, and one more for tfx's own publisher of added transforms (the Webots e-puck's copy
        listed 5 publishers where 6 sent)."""
        from rosbags.rosbag2.metadata import parse_qos

        profiles = parse_qos(recorded.qos) if recorded.qos.strip() else []
        if not is_static_topic(recorded.topic):
            return profiles
        if self.plan.durable:
            profiles = [static_qos() for _ in profiles]
        added = any(sender == PUBLISHER for sender, _ in self.plan.messages)
        return [*profiles, static_qos()] if added or not profiles else profiles


def _mcap_files(source: Path) -> list[Path]:
    """The MCAP files of ``source``: itself, or those of its rosbag2 directory (uncompressed by file)."""
    return [source] if source.is_file() else sorted(source.glob("*.mcap"))


def _metadata(source: Path) -> tuple[str, dict[str, str]]:
    """How the ROS 2 bag at ``source`` is compressed ("message", "file", or ""), and its types' hashes,
    as its metadata.yaml says (an MCAP file holds no hashes): none when it has none, or it is unreadable
    (the reader says so)."""
    from tftools.sources import user_files

    if not (source / METADATA).is_file():
        return "", {}
    try:
        info = user_files.load(source / METADATA)["rosbag2_bagfile_information"]
        mode, fmt = str(info.get("compression_mode") or "").lower(), str(info.get("compression_format") or "")
        topics = [entry["topic_metadata"] for entry in info.get("topics_with_message_count") or []]
        hashes = {str(t["type"]): str(t.get("type_description_hash") or "") for t in topics}
    except (user_files.UserFileError, KeyError, TypeError, AttributeError):
        return "", {}
    return (mode if fmt.lower() == "zstd" and mode in ("message", "file") else ""), hashes


def static_qos() -> Any:
    """tf2_ros' static QoS: reliable, transient local, keep last 1 (StaticBroadcasterQoS)."""
    from rosbags.interfaces import Qos, QosDurability, QosHistory, QosLiveliness, QosReliability, QosTime

    never = QosTime(0, 0)
    return Qos(
        QosHistory.KEEP_LAST, 1, QosReliability.RELIABLE, QosDurability.TRANSIENT_LOCAL,
        never, never, QosLiveliness.SYSTEM_DEFAULT, never, False,
    )  # fmt: skip
