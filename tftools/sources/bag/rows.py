"""Decoded transforms gathered column by column, and made ``TransformBatch`` es in record order."""

from __future__ import annotations

import itertools
from collections.abc import Iterator
from typing import Any

import numpy as np
import numpy.typing as npt

from tftools.core.arrays import Int32Array, Int64Array
from tftools.core.batch import TransformBatch
from tftools.sources.codecs import _wire
from tftools.sources.codecs.decoded import Decoded, FrameNames
from tftools.sources.codecs.select import AnyCodec, Codec
from tftools.sources.contents import SentMessages, is_static_topic
from tftools.values import value

Column = npt.NDArray[Any]


@value
class Channel:
    """A topic read with a codec (a clock's or stamped messages' channel has no rows), as one publisher recorded it."""

    topic: str
    codec: AnyCodec
    publisher: str = ""  # a ROS1 connection's callerid; "" when the recording does not say
    tie: int = 0  # messages of equal record time and channels of unequal ``tie``: the lower first

    @property
    def authority(self) -> str:
        """Whose transforms they are: the publisher, else the topic."""
        return self.publisher or self.topic


class Rows:
    """Columns of decoded transforms, part after part; frame names interned as they come.

    Parts come codec by codec; ``settle`` puts those added since the last call in message order,
    so that rows read in record order need no reordering of the whole batch.
    """

    def __init__(self, channels: list[Channel]) -> None:
        self.channels = channels
        self.frames = FrameNames()
        self.parts: dict[str, list[Column]] = {name: [] for name in _COLUMNS}
        self.messages: list[Int64Array] = []  # of each part added since ``settle``: each row's message number
        #: Of each part settled: its messages, and how many rows each has there (8 bytes a row less).
        self.runs: list[tuple[Int64Array, Int64Array]] = []
        self.held = 0  # rows added so far

    def add_rows(self, message: Int64Array, decoded: Decoded) -> None:
        """The rows ``decoded`` (frame ids in ``frames``): ``message`` being each one's message number."""
        if not len(message):  # messages that held no transform (an empty TFMessage): no run to keep
            return
        self.messages.append(message)
        self.held += len(message)
        columns: list[Column] = [getattr(decoded, name) for name in _COLUMNS]
        for name, column in zip(_COLUMNS, columns, strict=True):
            self.parts[name].append(column)

    def messages_with_rows(self) -> Iterator[Int64Array]:
        """The numbers of the messages settled that held a transform, part after part."""
        return (messages for messages, _ in self.runs)

    def settle(self) -> None:
        """Merge the parts added since the last call into one, in message order (a few
        megabytes at most: reordered while in cache)."""
        if not self.messages:
            return
        message = self.messages[0]
        if len(self.messages) > 1:
            order = np.argsort(np.concatenate(self.messages), kind="stable")
            message = np.concatenate(self.messages)[order]
            for parts in self.parts.values():
                parts[len(self.runs) :] = [np.concatenate(parts[len(self.runs) :])[order]]
        self.messages = []
        first = np.empty(len(message), bool)  # where a message's rows begin: compared, not subtracted (no
        first[0] = True  # int64 steps made and faulted in, a part after another)
        np.not_equal(message[1:], message[:-1], out=first[1:])
        firsts = np.flatnonzero(first)
        self.runs.append((message[firsts], np.diff(firsts, append=len(message))))

    def sent(self, times: Int64Array, channel_of: Int32Array, rank: Int64Array) -> SentMessages:
        """The messages settled that held a transform, in record order (``rank``), with their first row's stamp."""
        self.settle()
        if not self.runs:
            return SentMessages.empty()
        messages = np.concatenate([m for m, _ in self.runs])
        stamps = np.concatenate([s[np.cumsum(n) - n] for s, (_, n) in zip(self.parts["stamp"], self.runs, strict=True)])
        ranks = rank[messages]
        if not bool(np.all(ranks[1:] >= ranks[:-1])):  # read out of record order: sorted (usually they are)
            order = np.argsort(ranks, kind="stable")
            messages, stamps = messages[order], stamps[order]
        channel = channel_of[messages]
        transforms = [c for c in self.channels if isinstance(c.codec, Codec)]
        authorities = list(dict.fromkeys(c.authority for c in transforms))
        authority_of = np.array([authorities.index(c.authority) if c in transforms else -1 for c in self.channels])
        static_of = np.array([is_static_topic(c.topic) for c in self.channels], bool)
        return SentMessages(
            authorities, authority_of[channel].astype(np.int32), static_of[channel], times[messages], stamps
        )

    def batches(self, times: Int64Array, channel_of: Int32Array, rank: Int64Array) -> list[TransformBatch]:
        """The rows in record order, given each message's record time, channel and place in
        that order: the parts as settled when they are in that order already, else one batch
        made column after column, each freed as it is taken (one is held twice at most)."""
        self.settle()
        if not self.runs:
            return []
        transforms = [c for c in self.channels if isinstance(c.codec, Codec)]
        authorities = list(dict.fromkeys(c.authority for c in transforms))
        authority_of = np.array(
            [authorities.index(c.authority) if c in transforms else -1 for c in self.channels], np.int32
        )
        static_of = np.array([is_static_topic(c.topic) for c in self.channels], bool)

        def batch(messages: Int64Array, rows: Int64Array, columns: dict[str, Column]) -> TransformBatch:
            """The rows of ``messages``, ``rows[i]`` of message ``messages[i]``, in that order."""
            record_time, static, authority = _wire.per_row(messages, rows, times, channel_of, static_of, authority_of)
            return TransformBatch(
                frame_names=self.frames.names,
                authorities=authorities,
                static=static,
                record_time=record_time,
                authority=authority,
                **columns,
            )

        runs, self.runs = self.runs, []
        ranks = [rank[messages] for messages, _ in runs]
        if all(bool(np.all(r[1:] >= r[:-1])) for r in ranks) and all(
            a[-1] <= b[0] for a, b in itertools.pairwise(ranks)
        ):
            parts = [dict(zip(_COLUMNS, part, strict=True)) for part in zip(*self.parts.values(), strict=True)]
            self.parts = {name: [] for name in _COLUMNS}
            return [batch(*run, columns) for run, columns in zip(runs, parts, strict=True)]
        message = np.concatenate([np.repeat(*run) for run in runs])
        order = np.argsort(rank[message], kind="stable")
        del ranks, runs
        ones = np.ones(len(message), np.int64)
        return [batch(message[order], ones, {name: self._whole(name)[order] for name in _COLUMNS})]

    def _whole(self, name: str) -> Column:
        """A column whole, its parts freed as it is taken: only one column is ever held twice."""
        parts = self.parts.pop(name)
        self.parts[name] = []
        return parts[0] if len(parts) == 1 else np.concatenate(parts)


#: The translation (N, 3) and rotation (N, 4) each contiguous, as the decoders write them and the core takes them.
_COLUMNS = ("parent", "child", "stamp", "translation", "rotation")
