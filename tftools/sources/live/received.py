"""Transform messages as a live source receives them, decoded many at a time by the bulk decoder bags use.

A message decoded alone costs its decoder's set-up (a frame table, the batch's columns): ~0.4 ms for one of 100
transforms, which at 1 kHz is the better part of a core. Decoded together, the messages of one wake-up cost what
their bytes cost, and a live reader keeps up with a busy robot where tf2_ros's keep-last-100 history would
otherwise drop what waited while the previous ones were decoded.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from tftools.core.batch import TransformBatch
from tftools.sources.codecs.decoded import BulkDecoder, FrameNames
from tftools.sources.contents import SentMessages, is_static_topic


@dataclass(frozen=True)
class Received:
    """One tf message received: the topic it came on (e.g. "/tf"), its serialized bytes, its publisher (the
    authority) and when it was received (ns, on the source's clock)."""

    topic: str
    data: bytes
    authority: str
    record_time: int


@dataclass(frozen=True)
class DecodedArrivals:
    """Messages received, decoded: the transforms of the well-formed ones in arrival order, those that held a
    transform (as ``SentMessages``, in record order), how many were well-formed, and each other one with why."""

    batch: TransformBatch
    sent: SentMessages
    readable: int
    unreadable: list[tuple[Received, str]]


def decode_received(decode: BulkDecoder, messages: Sequence[Received]) -> DecodedArrivals:
    """``messages`` decoded in one call of ``decode``; a message that is not well-formed gives no transform."""
    if not messages:
        return DecodedArrivals(TransformBatch.empty(), SentMessages.empty(), 0, [])
    lengths = np.array([len(m.data) for m in messages], np.int64)
    starts = np.zeros(len(messages), np.int64)
    np.cumsum(lengths[:-1], out=starts[1:])
    frames = FrameNames()
    decoded = decode(np.frombuffer(b"".join(m.data for m in messages), np.uint8), starts, lengths, frames)
    rows = decoded.message
    firsts = np.flatnonzero(np.diff(rows, prepend=-1))  # each message's first row (rows are in message order)
    held = rows[firsts]  # the messages that held a transform: theirs alone are the batch's authorities
    index: dict[str, int] = {}
    authority_of = np.zeros(len(messages), np.int32)
    authority_of[held] = [index.setdefault(messages[m].authority, len(index)) for m in held.tolist()]
    authorities = list(index)
    static_of = np.array([is_static_topic(m.topic) for m in messages], bool)
    record_time_of = np.array([m.record_time for m in messages], np.int64)
    batch = TransformBatch(
        frame_names=frames.names,
        authorities=authorities,
        parent=decoded.parent,
        child=decoded.child,
        stamp=decoded.stamp,
        translation=decoded.translation,
        rotation=decoded.rotation,
        static=static_of[rows],
        record_time=record_time_of[rows],
        authority=authority_of[rows],
    )
    order = np.argsort(record_time_of[held], kind="stable")
    sent = SentMessages(
        authorities,
        authority_of[held][order],
        static_of[held][order],
        record_time_of[held][order],
        decoded.stamp[firsts][order],
    )
    unreadable = [(messages[m], reason) for m, reason in decoded.failures]
    return DecodedArrivals(batch, sent, len(messages) - len(unreadable), unreadable)
