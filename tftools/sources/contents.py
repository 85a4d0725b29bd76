"""What a recording holds and where it came from (files, a live system or a buffer), its sensor data's
headers, and tf's topics."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import field
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np

from tftools.core.arrays import BoolArray, FloatArray, Int32Array, Int64Array
from tftools.core.batch import TransformBatch, concat_batches
from tftools.core.frames import Names
from tftools.values import record, value

if TYPE_CHECKING:
    from tftools.core._kernels import Spare

#: The topics read unless told otherwise.
DEFAULT_TOPICS = ("/tf", "/tf_static")
#: Topics never read as sensor data: the transforms and the clock themselves.
NOT_SENSOR_DATA = frozenset({*DEFAULT_TOPICS, "/clock"})


def global_name(topic: str) -> str:
    """``topic`` as a node in the root namespace resolves it: a relative name (``tf``, as a writer may store
    it in a bag) is ``/tf``, which is what ``ros2 bag play`` and ``rosbag play`` publish it as."""
    return topic if topic.startswith("/") else "/" + topic


def is_static_topic(topic: str) -> bool:
    """Transforms on ``/tf_static`` (or a namespaced ``.../tf_static``) hold at every time."""
    return topic.rstrip("/").endswith("tf_static")


@value
class Recorded:
    """A channel as the recording describes it: what a copy needs to write its messages as they are,
    their type known to tftools or not."""

    topic: str
    type_name: str  # as the recording names it ("std_msgs/String", "std_msgs/msg/String")
    encoding: str  # "ros1", "cdr", "json"...
    definition: str = ""  # its type's message definition ("": the recording does not give it)
    digest: str = ""  # a ROS 1 md5sum, a ROS 2 type hash (RIHS01_...), "" when the recording does not say
    publisher: str = ""  # a ROS 1 connection's callerid
    latching: bool = False  # a ROS 1 connection's
    qos: str = ""  # the offered QoS profiles, as the ROS 2 recording writes them (YAML)


class MessageSink(Protocol):
    """What a recording being copied is handed: each channel as it is met, then each message with its
    channel, record time (ns) and payload as recorded."""

    def channel(self, recorded: Recorded) -> None: ...

    def message(self, recorded: Recorded, time: int, payload: memoryview) -> None: ...


@value
class ClockSamples:
    """The recorded /clock: when each message was recorded and the time it carried."""

    topic: str  # "" when the recording has no /clock
    record_time: Int64Array  # ns, record (receive) time of each message, sorted as recorded
    clock: Int64Array  # ns, the message's clock value

    @classmethod
    def empty(cls) -> ClockSamples:
        return cls("", np.zeros(0, np.int64), np.zeros(0, np.int64))

    def __len__(self) -> int:
        return len(self.record_time)

    def continued(self, later: ClockSamples) -> ClockSamples:
        """The samples ``later`` (recorded next) after the last of these: enough for ``clock_at`` over them."""
        if not len(later):
            return self
        return ClockSamples(
            later.topic,
            np.concatenate([self.record_time[-1:], later.record_time]),
            np.concatenate([self.clock[-1:], later.clock]),
        )


@value
class StampedMessages:
    """One topic's messages with a header: when each arrived, its stamp and frame (index into ``frame_ids``)."""

    topic: str
    type: str
    record_time: Int64Array
    stamp: Int64Array
    frame: Int32Array
    frame_ids: Sequence[str]
    #: Per message, how many transforms of the recording were read before it: where it stands among
    #: them, messages recorded at the same instant in the order the recording replays them; empty where
    #: that order is not known (a live capture). Counted in the read that read the messages: a ROS 1 bag
    #: read with its headers has its ties in rosbag play's order, so the buffer to place them in is that
    #: read's (``stamped_of(recording.contents.files)``), not one read apart without them.
    tf_before: Int64Array = field(default_factory=lambda: np.zeros(0, np.int64))
    #: Of messages that state a transform beside their header (nav_msgs/Odometry: from the header's frame to
    #: its child_frame_id), per message its child (an index into ``child_ids``, -1 where not read) and the
    #: transform's value (N x 7: x y z qx qy qz qw, NaN where not read); empty for any other type.
    child: Int32Array = field(default_factory=lambda: np.zeros(0, np.int32))
    pose: FloatArray = field(default_factory=lambda: np.zeros((0, 7)))
    child_ids: Sequence[str] = ()

    def __len__(self) -> int:
        return len(self.record_time)

    @property
    def states_transforms(self) -> bool:
        """Whether each message states a transform (``child``, ``pose``): an Odometry's."""
        return len(self.child) == len(self.record_time) > 0

    @property
    def ordered(self) -> bool:
        """Whether ``tf_before`` places every message among the transforms."""
        return len(self.tf_before) == len(self.record_time)


@value
class WholeMessages:
    """One topic's messages read whole (a robot's joint states, its description): when each arrived, and
    its value (``codecs.robot``)."""

    topic: str
    type: str
    record_time: Int64Array
    values: Sequence[Any]

    def __len__(self) -> int:
        return len(self.record_time)


@value
class SentMessages:
    """The tf messages that held a transform, one row each in record order, as the source told them apart
    (a message of several transforms is one, whatever tf2 then kept of it): whose it was (an index into
    ``authorities``, which name publishers as a batch's do: the publisher, else the topic), whether it came on
    /tf_static, when it was recorded (0: unknown), and its first transform's stamp (which stands for its
    arrival where that is unknown, as a transform's stamp does)."""

    authorities: Sequence[str]
    authority: Int32Array
    static: BoolArray
    record_time: Int64Array
    stamp: Int64Array

    def __len__(self) -> int:
        return len(self.record_time)

    @classmethod
    def empty(cls) -> SentMessages:
        none = np.zeros(0, np.int64)
        return cls([], none.astype(np.int32), none.astype(bool), none, none)

    def taken(self, rows: slice | Int64Array) -> SentMessages:
        """The messages at ``rows``, sharing the string table."""
        return SentMessages(
            self.authorities, self.authority[rows], self.static[rows], self.record_time[rows], self.stamp[rows]
        )

    def recorded_up_to(self, time: int) -> int:
        """How many of the messages were recorded at or before ``time`` (record times sorted)."""
        return int(np.searchsorted(self.record_time, time, side="right"))


def concat_sent(parts: Sequence[SentMessages]) -> SentMessages:
    """One table of the messages of ``parts`` (each in record order), in record order (ties keep their order)."""
    parts = [p for p in parts if len(p)]
    if len(parts) < 2:
        return parts[0] if parts else SentMessages.empty()
    names = Names()
    authority = np.concatenate(
        [np.array([names.intern(n) for n in p.authorities], np.int32)[p.authority] for p in parts]
    )
    record_time = np.concatenate([p.record_time for p in parts])
    order = np.argsort(record_time, kind="stable")
    return SentMessages(
        names.names,
        authority[order],
        np.concatenate([p.static for p in parts])[order],
        record_time[order],
        np.concatenate([p.stamp for p in parts])[order],
    )


#: ``SourceInfo.format`` of a buffer checked as it is (``recording_of_buffer``).
BUFFER_FORMAT = "buffer"


@value
class Fetched:
    """What reading a remote recording fetched: bytes received of its files' ``size``; ``whole`` when
    a file had to be fetched whole (a .db3: SQLite reads only a local file)."""

    received: int
    size: int
    whole: bool = False

    def describe(self) -> str:
        share = self.received / self.size if self.size else 0.0
        line = f"fetched {_megabytes(self.received)} of {_megabytes(self.size)} ({share:.1%})"
        return line + (", .db3 files whole (SQLite reads a local file)" if self.whole else "")


#: Where a ROS 2 recording keeps its topics' offered QoS profiles, one per publisher (``OfferedQos.source``):
#: its metadata.yaml, or without one (a file given alone, a recording cut short) its files' own.
IN_METADATA = "metadata.yaml"
IN_DB3 = "the .db3's topics table"
IN_MCAP = "the MCAP's channel metadata"


@value
class OfferedQos:
    """The QoS profiles each static topic's publishers offered, as a ROS 2 bag's metadata.yaml (or, without
    one, its files: ``source``) says: what ``ros2 bag play`` publishes it with (and every topic's counts);
    ``problem``: why it does not say ("": it does); ``metadata``: False for a bag without one (a bare .db3 or
    .mcap file) whose files hold no static topic."""

    profiles: dict[str, list[object]]
    problem: str = ""
    metadata: bool = True
    #: Per topic, its messages and its publishers (offered QoS profiles), as ``source`` counts them.
    counts: dict[str, tuple[int, int]] = field(default_factory=dict)
    source: str = IN_METADATA  # where the profiles are kept, in words: "metadata.yaml lists 2 publishers"


def _megabytes(n: int) -> str:
    return f"{n / 1e6:.2f} MB" if n >= 10_000 else f"{n} bytes"


@record
class SourceInfo:
    """One source as read: a file (or ROS 2 bag directory), a live system listened to, or a buffer."""

    path: str  # the file, or the live system (``LiveSource.describe``: "ROS1 master http://...")
    format: str  # "ros1", "ros1-mcap", "rosbag2-sqlite3", "rosbag2-mcap", "mcap"; "ros1-live", "ros2-live"; "buffer"
    start: int  # first message's record (receive) time (ns), every topic counted
    end: int  # last message's record time (ns)
    message_count: int  # messages of every topic
    topics: dict[str, str] = field(default_factory=dict)  # topic -> message type, all topics
    transform_count: int = 0  # transforms read from this source
    problems: list[str] = field(default_factory=list)  # damage: what could not be read, one line each
    # Topics asked for (or foxglove transform channels) of a type or encoding tfx does not read,
    # one line each: a healthy file, nothing to repair.
    unread: list[str] = field(default_factory=list)
    fetched: Fetched | None = None  # a recording read by URL: what of it was fetched
    #: Per tf topic read, its messages and how many held no transform, as read (a file's, not metadata.yaml's).
    tf_messages: dict[str, tuple[int, int]] = field(default_factory=dict)
    #: Per tf topic read, the publishers of its messages that held no transform and how many, where the file names
    #: them (a ROS 1 bag's connections); empty otherwise.
    tf_empty_from: dict[str, dict[str, int]] = field(default_factory=dict)
    # False: a file read whole, for want of an index (a bag never closed, an MCAP without summary, a
    # file compressed whole, a damaged .db3): a record-time window of it costs the whole file.
    windowed: bool = True
    #: Record-time spans (ns, first and last) of the parts whose messages were lost or read from damaged bytes:
    #: a pause of tf there is the file's, not the robot's.
    damaged: list[tuple[int, int]] = field(default_factory=list)

    @property
    def live(self) -> bool:
        return self.format.endswith("-live")

    @property
    def names_publishers(self) -> bool:
        """Whether each transform's authority is its publisher: ROS 1 bags (and MCAP files of the ros1
        profile), live systems and buffers name the node; ROS 2 bags and other MCAP files only the topic."""
        return not self.format.startswith(("rosbag2", "mcap"))


@value
class StampedRead:
    """Each topic's stamped messages, and what could not be read of them (one line a topic)."""

    streams: list[StampedMessages] = field(default_factory=list)
    problems: list[str] = field(default_factory=list)


@record
class RecordingContents:
    """Every transform read, in record-time order (in consecutive parts, as decoded), a description of
    each source it came from, and what else the read took: the recorded clock, the sensor data's
    headers, the messages read whole and the ROS 2 bags' offered QoS."""

    parts: list[TransformBatch]
    files: list[SourceInfo]  # the files read, or the live system heard
    topics: tuple[str, ...]
    clock: ClockSamples = field(default_factory=ClockSamples.empty, repr=False, compare=False)  # the files' merged
    stamped: StampedRead = field(default_factory=StampedRead, repr=False, compare=False)  # headers read
    whole: list[WholeMessages] = field(default_factory=list, repr=False, compare=False)  # messages read whole
    #: Each ROS 2 bag's offered QoS, by its path (``SourceInfo.path``); none for other sources.
    qos: dict[str, OfferedQos] = field(default_factory=dict, repr=False, compare=False)
    #: The tf messages that held a transform; None where the source did not tell them apart (a buffer).
    sent: SentMessages | None = field(default=None, repr=False, compare=False)
    #: The buffer's block for the transforms, brought in while they were read (``Spare``): a whole file's.
    room: Spare | None = field(default=None, repr=False, compare=False)

    @property
    def transforms(self) -> TransformBatch:
        """Every transform, in one batch (a copy, unless there is one part); none once a
        ``Recording`` took the parts (its ``transforms`` gives them back)."""
        return concat_batches(self.parts)

    @property
    def start(self) -> int:
        return min((f.start for f in self.files if f.message_count), default=0)

    @property
    def end(self) -> int:
        return max((f.end for f in self.files if f.message_count), default=0)

    @property
    def live(self) -> bool:
        return any(f.live for f in self.files)

    @property
    def unread(self) -> list[str]:
        """Topics of a type or encoding tfx does not read, one line each (no repeats)."""
        return list(dict.fromkeys(line for f in self.files for line in f.unread))

    @property
    def problems(self) -> list[str]:
        """Everything to warn about: the topics not read, then each file's damage."""
        return self.unread + [p for f in self.files for p in f.problems]
