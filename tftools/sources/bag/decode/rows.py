"""Decoded blocks of transforms gathered into ``TransformBatch`` es in record order."""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from tftools.core.arrays import Int64Array as IntArray
from tftools.core.batch import TransformBatch
from tftools.sources.bag.columns import ColumnParts
from tftools.sources.codecs.decoded import Decoded, FrameNames
from tftools.sources.codecs.select import ClockCodec, Codec
from tftools.sources.contents import is_static_topic


@dataclass(frozen=True)
class Channel:
    """A topic read with a codec: its name is the rows' authority (a clock's channel has no rows)."""

    topic: str
    codec: Codec | ClockCodec


class Rows:
    """Columns of decoded transforms, part after part; frame names interned as they come.

    Parts come codec by codec; ``settle`` puts those added since the last call
    in message order, so that rows read in record order need no reordering of the whole batch.
    """

    def __init__(self, channels: list[Channel]) -> None:
        self.channels = channels
        self.frames = FrameNames()
        self.columns = ColumnParts(_COLUMNS)
        self.settled = 0  # parts of each column in message order

    def add(self, messages: IntArray, decoded: Decoded) -> None:
        """The decoded rows, ``messages`` being the message number of each (its frames in ``frames``)."""
        if not len(messages):
            return
        self.columns.add(
            message=messages,
            parent=decoded.parent,
            child=decoded.child,
            stamp=decoded.stamp,
            translation=np.ascontiguousarray(decoded.values[:, :3]),
            rotation=np.ascontiguousarray(decoded.values[:, 3:]),
        )

    def settle(self) -> None:
        """Merge the parts added since the last call into one, in message order (a few
        megabytes at most: reordered while in cache)."""
        added = {name: parts[self.settled :] for name, parts in self.columns.parts.items()}
        if len(added["message"]) > 1:
            messages = np.concatenate(added["message"])
            order = np.argsort(messages, kind="stable")
            for name, parts in added.items():
                self.columns.parts[name][self.settled :] = [np.concatenate(parts)[order]]
        self.settled = len(self.columns)

    def batches(self, times: IntArray, channel_of: npt.NDArray[np.int32], rank: IntArray) -> list[TransformBatch]:
        """The rows in record order, given each message's record time, channel and place in
        that order: the parts as settled when they are in that order already, else one batch
        made column after column, each freed as it is taken (one is held twice at most)."""
        self.settle()
        if not len(self.columns):
            return []
        authorities = list(dict.fromkeys(c.topic for c in self.channels if isinstance(c.codec, Codec)))
        authority_of = np.array(
            [authorities.index(c.topic) if isinstance(c.codec, Codec) else -1 for c in self.channels], np.int32
        )
        static_of = np.array([is_static_topic(c.topic) for c in self.channels], bool)
        names = self.frames.names

        def batch(columns: dict[str, npt.NDArray[Any]]) -> TransformBatch:
            messages = columns.pop("message")
            channel = channel_of[messages]
            return TransformBatch(
                frame_names=names,
                authorities=authorities,
                static=static_of[channel],
                record_time=times[messages],
                authority=authority_of[channel],
                **columns,
            )

        ranks = [rank[m] for m in self.columns.parts["message"]]
        if all(bool(np.all(r[1:] >= r[:-1])) for r in ranks) and all(
            a[-1] <= b[0] for a, b in itertools.pairwise(ranks)
        ):
            return [batch(columns) for columns in self.columns.take_parts()]
        order = np.argsort(np.concatenate(ranks), kind="stable")
        del ranks
        return [batch(self.columns.take_whole(order))]


_COLUMNS = ("message", "parent", "child", "stamp", "translation", "rotation")
