"""Stamped messages, from bags and live alike: each message's ``std_msgs/Header`` (stamp and frame_id),
as the codecs parse it, gathered per topic."""

from __future__ import annotations

from collections.abc import Sequence
from itertools import groupby

import numpy as np

from tftools.core.frames import Names
from tftools.sources.codecs.decoded import Header
from tftools.sources.codecs.gather import first_and_inverse
from tftools.sources.contents import StampedMessages


class HeaderCollector:
    """One topic's headers as they are read, at most ``limit`` of them (None: all)."""

    __slots__ = ("damaged", "frame", "frame_ids", "left_out", "limit", "record_time", "stamp", "type")

    def __init__(self, type: str, limit: int | None = None) -> None:
        self.type = type
        self.limit = limit
        self.record_time: list[int] = []
        self.stamp: list[int] = []
        self.frame: list[int] = []
        self.frame_ids = Names()
        self.damaged = 0
        self.left_out = 0

    def add(self, record_time: int, header: Header | None) -> None:
        """A message that arrived at ``record_time``; ``header`` None: one too damaged for a header."""
        if header is None:
            self.damaged += 1
        elif self.limit is not None and len(self.record_time) >= self.limit:
            self.left_out += 1
        else:
            stamp, frame_id = header
            self.record_time.append(record_time)
            self.stamp.append(stamp)
            self.frame.append(self.frame_ids.intern(frame_id))

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
        return StampedMessages(
            topic,
            self.type,
            np.array(self.record_time, np.int64)[order],
            np.array(self.stamp, np.int64)[order],
            np.array(self.frame, np.int32)[order],
            list(self.frame_ids.names),
        )


def merged(streams: Sequence[StampedMessages]) -> list[StampedMessages]:
    """One stream per topic of several (a split recording's files), in topic order, each in record
    time order (ties keep their order) and naming only its messages' frames, as they first come."""
    merged = []
    for topic, parts in groupby(sorted(streams, key=lambda s: s.topic), key=lambda s: s.topic):
        pieces = list(parts)
        record_time = np.concatenate([p.record_time for p in pieces])
        order = np.argsort(record_time, kind="stable")
        offsets = np.cumsum([0] + [len(p.frame_ids) for p in pieces]).tolist()
        frame = np.concatenate([p.frame + offset for p, offset in zip(pieces, offsets, strict=False)])[order]
        every_name = [name for p in pieces for name in p.frame_ids]
        firsts, inverse = first_and_inverse(frame)
        names = Names()
        ids = np.array([names.intern(every_name[i]) for i in frame[np.sort(firsts)].tolist()], np.int32)
        renumbered = np.empty(len(firsts), np.int32)
        renumbered[np.argsort(firsts, kind="stable")] = ids
        stamp = np.concatenate([p.stamp for p in pieces])[order]
        ordered = all(p.ordered for p in pieces)
        before = np.concatenate([p.tf_before for p in pieces])[order] if ordered else np.zeros(0, np.int64)
        children = tuple(dict.fromkeys(c for p in pieces for c in p.children))
        merged.append(
            StampedMessages(
                topic, pieces[0].type, record_time[order], stamp, renumbered[inverse], names.names, before, children
            )
        )
    return merged
