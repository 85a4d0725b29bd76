"""Decoded blocks of transforms gathered into one ``TransformBatch`` in record order."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from tftools.core.batch import TransformBatch
from tftools.sources.bag.contents import is_static_topic
from tftools.sources.bag.decode.codec import Codec
from tftools.sources.bag.decode.template import Block, IntArray


@dataclass(frozen=True)
class Channel:
    """A topic read with a codec: its name is the rows' authority."""

    topic: str
    codec: Codec


class Rows:
    """Columns of decoded transforms; frame names interned as they come."""

    def __init__(
        self, channels: list[Channel], times: IntArray, channel_of: npt.NDArray[np.int32], rank: IntArray
    ) -> None:
        self.channels = channels
        self.times = times  # per message
        self.channel_of = channel_of  # per message
        self.rank = rank  # per message: its place in record order
        self.frames: dict[str, int] = {}
        self.messages: list[IntArray] = []
        self.parents: list[npt.NDArray[np.int32]] = []
        self.children: list[npt.NDArray[np.int32]] = []
        self.stamps: list[IntArray] = []
        self.values: list[npt.NDArray[np.float64]] = []

    def _ids(self, names: list[str]) -> npt.NDArray[np.int32]:
        return np.array([self.frames.setdefault(name, len(self.frames)) for name in names], np.int32)

    def add(self, messages: IntArray, block: Block) -> None:
        """The block's rows, ``messages`` being the message number of each of its rows."""
        n, k = block.stamps.shape
        if not n * k:
            return
        self.messages.append(np.repeat(messages, k))
        self.parents.append(np.tile(self._ids(block.parents), n))
        self.children.append(np.tile(self._ids(block.children), n))
        self.stamps.append(block.stamps.reshape(-1))
        self.values.append(block.values.reshape(-1, 7))

    def batch(self) -> TransformBatch:
        if not self.messages:
            return TransformBatch.empty()
        messages = np.concatenate(self.messages)
        order = np.argsort(self.rank[messages], kind="stable")
        messages = messages[order]
        values = np.concatenate(self.values)[order]
        authorities = list(dict.fromkeys(c.topic for c in self.channels))
        authority_of = np.array([authorities.index(c.topic) for c in self.channels], np.int32)
        static_of = np.array([is_static_topic(c.topic) for c in self.channels], bool)
        channel = self.channel_of[messages]
        return TransformBatch(
            frame_names=list(self.frames),
            authorities=authorities,
            parent=np.concatenate(self.parents)[order],
            child=np.concatenate(self.children)[order],
            stamp=np.concatenate(self.stamps)[order],
            translation=np.ascontiguousarray(values[:, :3]),
            rotation=np.ascontiguousarray(values[:, 3:]),
            static=static_of[channel],
            record_time=self.times[messages],
            authority=authority_of[channel],
        )
