"""Stamped messages, from bags and live alike: each message's ``std_msgs/Header`` (stamp and frame_id),
as the codecs parse it, gathered per topic."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from itertools import groupby

import numpy as np

from tftools.core.arrays import Int32Array, Int64Array
from tftools.core.frames import Names
from tftools.sources.codecs.decoded import Header, Stated
from tftools.sources.contents import StampedMessages


class HeaderCollector:
    """One topic's headers as they are read, at most ``limit`` of them (None: all)."""

    __slots__ = (
        "children",
        "damaged",
        "frame",
        "frame_ids",
        "left_out",
        "limit",
        "poses",
        "record_time",
        "stamp",
        "type",
    )

    def __init__(self, type: str, limit: int | None = None) -> None:
        self.type = type
        self.limit = limit
        self.record_time: list[int] = []
        self.stamp: list[int] = []
        self.frame: list[int] = []
        self.frame_ids = Names()
        self.damaged = 0
        self.left_out = 0
        self.children: list[str | None] = []  # of each message kept, the child of the transform it states
        self.poses: list[tuple[float, ...]] = []

    def add(self, record_time: int, header: Header | None, stated: Stated | None = None) -> None:
        """A message that arrived at ``record_time``; ``header`` None: one too damaged for a header; ``stated``:
        the transform it states beside it (an Odometry's)."""
        if header is None:
            self.damaged += 1
        elif self.limit is not None and len(self.record_time) >= self.limit:
            self.left_out += 1
        else:
            stamp, frame_id = header
            self.record_time.append(record_time)
            self.stamp.append(stamp)
            self.frame.append(self.frame_ids.intern(frame_id))
            self.children.append(stated[0] if stated is not None else None)
            self.poses.append(stated[1] if stated is not None else (math.nan,) * 7)

    def problems(self, topic: str) -> list[str]:
        """What was not kept of the topic, in a line each."""
        said = []
        if self.damaged:
            s = "s" if self.damaged > 1 else ""
            said.append(f"{topic}: {self.damaged} message{s} too short for a header, skipped")
        if self.left_out:
            said.append(
                f"{topic}: {self.left_out} messages after the first {self.limit} (tfx's limit per topic) not checked"
            )
        return said

    def done(self, topic: str) -> StampedMessages:
        order = np.argsort(np.array(self.record_time, np.int64), kind="stable")
        stream = StampedMessages(
            topic,
            self.type,
            np.array(self.record_time, np.int64)[order],
            np.array(self.stamp, np.int64)[order],
            np.array(self.frame, np.int32)[order],
            list(self.frame_ids.names),
        )
        if not any(child is not None for child in self.children):
            return stream
        names = Names()
        child = np.array([names.intern(c) if c is not None else -1 for c in self.children], np.int32)[order]
        pose = np.array(self.poses, np.float64).reshape(-1, 7)[order]
        return dataclasses.replace(stream, child=child, pose=pose, child_ids=list(names.names))


def merged(streams: Sequence[StampedMessages]) -> list[StampedMessages]:
    """One stream per topic of several (a split recording's files), in topic order, each in record
    time order (ties keep their order) and naming only its messages' frames (and children), as they first come."""
    merged = []
    for topic, parts in groupby(sorted(streams, key=lambda s: s.topic), key=lambda s: s.topic):
        pieces = list(parts)
        record_time = np.concatenate([p.record_time for p in pieces])
        order = np.argsort(record_time, kind="stable")
        frame, frame_ids = _as_they_come([p.frame for p in pieces], [p.frame_ids for p in pieces], order)
        stamp = np.concatenate([p.stamp for p in pieces])[order]
        ordered = all(p.ordered for p in pieces)
        before = np.concatenate([p.tf_before for p in pieces])[order] if ordered else np.zeros(0, np.int64)
        stream = StampedMessages(topic, pieces[0].type, record_time[order], stamp, frame, frame_ids, before)
        if all(p.states_transforms or not len(p) for p in pieces) and any(p.states_transforms for p in pieces):
            child, child_ids = _as_they_come([p.child for p in pieces], [p.child_ids for p in pieces], order)
            pose = np.concatenate([p.pose for p in pieces])[order]
            stream = dataclasses.replace(stream, child=child, pose=pose, child_ids=child_ids)
        merged.append(stream)
    return merged


def _as_they_come(
    ids: Sequence[Int32Array], tables: Sequence[Sequence[str]], order: Int64Array
) -> tuple[Int32Array, list[str]]:
    """Each piece's ``ids`` (indices into its own of ``tables``, -1 for none), joined in ``order`` and numbered
    in one table of the names they use, as they first come: a reader may hand over its file's whole frame table."""
    offsets = np.cumsum([0] + [len(t) for t in tables[:-1]]).tolist()
    joined = np.concatenate([np.where(i >= 0, i + offset, -1) for i, offset in zip(ids, offsets, strict=True)])
    joined = joined[order]
    named = joined >= 0
    used = joined[named]
    first = np.full(sum(len(t) for t in tables), len(used), np.int64)
    np.minimum.at(first, used, np.arange(len(used)))  # no sort of every message: the tables are small
    seen = np.flatnonzero(first < len(used))
    every_name = [name for table in tables for name in table]
    names = Names()
    renumbered = np.full(len(first), -1, np.int32)
    for k in seen[np.argsort(first[seen], kind="stable")].tolist():
        renumbered[k] = names.intern(every_name[k])
    numbered = np.full(len(joined), -1, np.int32)
    numbered[named] = renumbered[used]
    return numbered, list(names.names)
