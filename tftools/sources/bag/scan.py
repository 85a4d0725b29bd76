"""``FileScan``: what one bag file held, undecoded; ``file_result``: scans made a bag's result (``FileRead``)."""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from tftools.core.arrays import Int64Array
from tftools.core.batch import TransformBatch
from tftools.sources import user_files
from tftools.sources.bag.apart import TfTimes
from tftools.sources.bag.contents import BagFileInfo, in_record_order, merged_clock
from tftools.sources.bag.messages import MessageSet
from tftools.sources.codecs.select import Unread, unread_lines
from tftools.sources.contents import (
    ClockSamples,
    OfferedQos,
    SentMessages,
    StampedMessages,
    WholeMessages,
    concat_sent,
    is_static_topic,
)
from tftools.sources.headers import merged

if TYPE_CHECKING:
    from tftools.core._kernels import Spare


class FileRead:
    """What one bag (a file, or a ROS 2 bag directory) gave: its transforms in record order, its
    description, its recorded clock, its sensor data's headers (and one line per topic whose headers
    could not be read), the messages read whole and, for a ROS 2 bag, the QoS its publishers offered."""

    __slots__ = ("batches", "clock", "info", "qos", "room", "sent", "stamped", "stamped_problems", "tf_times", "whole")

    def __init__(
        self,
        batches: list[TransformBatch],
        info: BagFileInfo,
        clock: ClockSamples | None = None,
        stamped: list[StampedMessages] | None = None,
        stamped_problems: list[str] | None = None,
        whole: list[WholeMessages] | None = None,
        qos: OfferedQos | None = None,
        sent: SentMessages | None = None,
        room: Spare | None = None,
        tf_times: list[TfTimes] | None = None,
    ) -> None:
        self.batches = batches
        self.tf_times = [] if tf_times is None else tf_times  # ``MessageSet.tf_times``: for ``strays`` to count
        self.room = room  # the buffer's block for the transforms, brought in as they were read
        self.sent = SentMessages.empty() if sent is None else sent
        self.info = info
        self.clock = ClockSamples.empty() if clock is None else clock
        self.stamped = [] if stamped is None else stamped
        self.stamped_problems = [] if stamped_problems is None else stamped_problems
        self.whole = [] if whole is None else whole
        self.qos = qos


class FileScan:
    """One file's transform, clock and stamped messages (undecoded) and description."""

    __slots__ = (
        "damaged",
        "end",
        "lost_after",
        "message_count",
        "messages",
        "offered_qos",
        "problems",
        "skipped",
        "start",
        "topics",
        "windowed",
    )  # fmt: skip

    def __init__(self, messages: MessageSet) -> None:
        self.messages = messages
        self.start = 0  # record times over every topic (ns)
        self.end = 0
        self.message_count = 0  # every topic
        self.topics: dict[str, str] = {}
        #: Each topic's offered QoS profiles (YAML) as the file itself holds them: rosbag2's sqlite3 topics
        #: table (Foxy on), what ``ros2 bag reindex`` rebuilds metadata.yaml from.
        self.offered_qos: dict[str, str] = {}
        self.problems: list[str] = []  # damage: what was lost
        self.skipped: list[Unread] = []  # asked-for topics of types or encodings not read
        self.windowed = True  # False: read whole, without an index to find a record-time window by
        self.damaged: list[tuple[int, int]] = []  # record-time spans of the damaged parts (``SourceInfo.damaged``)
        self.lost_after: int | None = None  # the record time read last before messages were lost (``note_lost``)

    def note_times(self, first: int, last: int, count: int) -> None:
        """``count`` messages of any topic met, recorded from ``first`` to ``last`` (when no index
        or summary counts them)."""
        if self.lost_after is not None:  # the first read after a loss: the stretch between is the damaged part
            before, self.lost_after = self.lost_after, None
            self.damaged.append((min(before, first), max(before, first)))
        self.start = min(self.start, first) if self.message_count else first
        self.end = max(self.end, last) if self.message_count else last
        self.message_count += count

    def note_lost(self) -> None:
        """Messages lost here, in a file read record after record (damage met, without an index to say what was
        there): the stretch from the last record time read before to the first read after is a damaged part (none
        is known before the first or after the last read)."""
        if self.message_count and self.lost_after is None:
            self.lost_after = self.end

    def note_problem(self, line: str) -> None:
        if line and line not in self.problems:
            self.problems.append(line)

    def note_skipped(self, unread: Unread | None) -> None:
        if unread is not None:
            self.skipped.append(unread)


def file_result(path: Path, fmt: str, scans: Sequence[FileScan], labels: Sequence[str] = ()) -> FileRead:
    """The scans of one bag's files decoded into batches in record order, and the bag described;
    ``labels`` (one per scan, e.g. file names) prefix each file's problem lines."""
    batches: list[TransformBatch] = []
    clocks: list[ClockSamples] = []
    stamped: list[StampedMessages] = []
    whole: list[WholeMessages] = []
    problems: list[str] = []
    stamped_problems: list[str] = []
    tf_messages: dict[str, tuple[int, int]] = {}
    tf_empty_from: dict[str, dict[str, int]] = {}
    times: list[Int64Array] = []
    parts: list[list[StampedMessages]] = []
    for index, scan in enumerate(scans):
        decoded, clock, headers, undecodable = scan.messages.decode()
        if len(scans) > 1:  # to place each file's sensor messages among the others' transforms
            times.append(record_times(decoded))
        parts.append(headers)
        for topic, (messages, empty) in scan.messages.tf_messages.items():
            before = tf_messages.get(topic, (0, 0))
            tf_messages[topic] = (before[0] + messages, before[1] + empty)
        for topic, senders in scan.messages.tf_empty_from.items():
            mine = tf_empty_from.setdefault(topic, {})
            for publisher, empty in senders.items():
                mine[publisher] = mine.get(publisher, 0) + empty
        batches += decoded
        clocks.append(clock)
        whole += scan.messages.whole
        label = f"{labels[index]}: " if index < len(labels) and labels[index] else ""
        problems += [label + line for line in scan.problems + undecodable]
        stamped_problems += [label + line for line in scan.messages.headers_lost]
    batches = in_record_order(batches)
    stamped = [stream for part in (placed_among(times, parts) if len(scans) > 1 else parts) for stream in part]
    counted = [s for s in scans if s.message_count]
    topics = {name: type_name for scan in scans for name, type_name in scan.topics.items()}
    info = BagFileInfo(
        path=str(path),
        format=fmt,
        start=min((s.start for s in counted), default=0),
        end=max((s.end for s in counted), default=0),
        message_count=sum(s.message_count for s in counted),
        topics=topics,
        transform_count=sum(len(b) for b in batches),
        problems=problems,
        unread=unread_lines([u for scan in scans for u in scan.skipped]),
        windowed=all(s.windowed for s in scans),
        tf_messages=tf_messages,
        tf_empty_from=tf_empty_from,
        damaged=sorted(span for scan in scans for span in scan.damaged),
    )
    sent = concat_sent([scan.messages.sent for scan in scans])
    room = scans[0].messages.room if len(scans) == 1 else None  # several: each brought in a part of it
    tf_times = [times for scan in scans for times in scan.messages.tf_times]
    return FileRead(
        batches,
        info,
        merged_clock(clocks),
        merged(stamped),
        stamped_problems,
        whole,
        sent=sent,
        room=room,
        tf_times=tf_times,
    )


def record_times(batches: Sequence[TransformBatch]) -> Int64Array:
    """The record times of ``batches``' transforms, sorted."""
    return np.sort(np.concatenate([np.zeros(0, np.int64), *(b.record_time for b in batches)]))


def placed_among(
    times: Sequence[Int64Array], parts: Sequence[Sequence[StampedMessages]]
) -> list[list[StampedMessages]]:
    """Each part's stamped messages (a split bag's files', or several bags'), placed among its own transforms
    (``StampedMessages.tf_before``), placed among every part's (``times``: each part's ``record_times``) as
    ``in_record_order`` merges them: after those of the parts before it recorded up to their time, and of the
    parts after it recorded before it."""
    placed = []
    for k, streams in enumerate(parts):
        mine = []
        for stream in streams:
            before = stream.tf_before
            if stream.ordered:
                for j, others in enumerate(times):
                    if j != k:
                        before = before + np.searchsorted(others, stream.record_time, "right" if j < k else "left")
            mine.append(dataclasses.replace(stream, tf_before=before))
        placed.append(mine)
    return placed


def qos_in_files(scans: list[FileScan], source: str) -> OfferedQos | None:
    """Without metadata.yaml (a recording cut short, or a .db3 or .mcap copied alone), the offered QoS of the
    static topics as the files' own topics tables (a .db3's) or channels (an MCAP's) hold them (``source``:
    ``IN_DB3`` or ``IN_MCAP``), none for a static topic they keep no QoS for (a .db3's empty column, as
    metadata.yaml's ``offered_qos_profiles: ''``: what ``ros2 bag play`` plays with its default, volatile), and
    each topic's publishers (a profile each) and messages read, as metadata.yaml counts them; None where they
    hold no static topic. Called once the scans are decoded."""
    offered = {name: text for scan in scans for name, text in scan.offered_qos.items()}
    static_topics = [name for scan in scans for name in scan.topics if is_static_topic(name)]
    if not static_topics:
        return None
    try:
        profiles = {name: list(user_files.load_text(text) or []) for name, text in offered.items()}
    except user_files.UserFileError as error:
        return OfferedQos({}, f"unreadable QoS profiles ({error})", source=source)
    messages: dict[str, int] = {}
    for scan in scans:
        for topic, (count, _) in scan.messages.tf_messages.items():
            messages[topic] = messages.get(topic, 0) + count
    counts = {name: (messages.get(name, 0), len(offered_by)) for name, offered_by in profiles.items()}
    static = {name: profiles.get(name, []) for name in static_topics}
    return OfferedQos(static, counts=counts, source=source)
