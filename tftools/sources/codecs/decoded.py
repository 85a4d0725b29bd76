"""What every decoder gives: rows of transforms, message by message, their frame names interned
once per source; clocks; and the one-message use of a bulk decoder."""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from tftools.core.arrays import BoolArray, FloatArray, Int32Array, Int64Array, UInt8Array
from tftools.core.batch import TransformBatch
from tftools.core.frames import Names
from tftools.core.transform import Transform

#: A payload: bytes as received, a view into a file, or a numpy array of them.
BytesLike = bytes | memoryview | UInt8Array
#: A message's header: its stamp (ns) and frame_id.
Header = tuple[int, str]


class DecodeError(ValueError):
    """A payload that is not a well-formed message of its type."""


class FrameNames(Names):
    """Frame names interned once for a whole source, from decoded names or from the bytes that
    hold them."""

    def intern_all(self, raw: UInt8Array, starts: Int64Array, lengths: Int64Array) -> tuple[Int32Array, BoolArray]:
        """The ids of the names ``raw[starts[i] : starts[i] + lengths[i]]`` (a message's few, or the
        distinct names of many messages), and which are not UTF-8."""
        data = raw.data
        found = []
        for start, length in zip(starts.tolist(), lengths.tolist(), strict=True):
            try:
                found.append(self.intern(str(data[start : start + length], "utf-8")))
            except UnicodeDecodeError:
                found.append(-1)
        ids = np.array(found, np.int32)
        return np.maximum(ids, 0), ids < 0


class Decoded:
    """Transforms of decoded messages, message by message in order: ``message`` is each row's
    message (an index into the payloads given), ``parent`` and ``child`` ids of a ``FrameNames``;
    ``failures`` the (message, reason) of payloads that are not well-formed messages. Each row's
    translation (N, 3) and rotation (N, 4) are apart, each contiguous, as the core takes them."""

    __slots__ = ("child", "failures", "message", "parent", "rotation", "stamp", "translation")

    def __init__(
        self,
        message: Int64Array,
        parent: Int32Array,
        child: Int32Array,
        stamp: Int64Array,
        translation: FloatArray,
        rotation: FloatArray,
        failures: list[tuple[int, str]] | None = None,
    ) -> None:
        self.message = message
        self.parent = parent
        self.child = child
        self.stamp = stamp
        self.translation = translation  # (N, 3): x y z
        self.rotation = rotation  # (N, 4): qx qy qz qw
        self.failures = [] if failures is None else failures

    @classmethod
    def of_values(
        cls,
        message: Int64Array,
        parent: Int32Array,
        child: Int32Array,
        stamp: Int64Array,
        values: FloatArray,
        failures: list[tuple[int, str]] | None = None,
    ) -> Decoded:
        """Rows whose ``values`` are (N, 7): x y z qx qy qz qw."""
        translation, rotation = np.ascontiguousarray(values[:, :3]), np.ascontiguousarray(values[:, 3:])
        return cls(message, parent, child, stamp, translation, rotation, failures)

    @property
    def values(self) -> FloatArray:
        """Each row's 7 values (N, 7): x y z qx qy qz qw (a copy)."""
        return np.concatenate([self.translation, self.rotation], axis=1)

    @classmethod
    def empty(cls, failures: Sequence[tuple[int, str]] = ()) -> Decoded:
        none, ids = np.zeros(0, np.int64), np.zeros(0, np.int32)
        return cls(none, ids, ids, none, np.zeros((0, 3)), np.zeros((0, 4)), list(failures))

    @classmethod
    def joined(cls, parts: Sequence[Decoded]) -> Decoded:
        """The parts' rows as one, in message order (rows of a message keep their order)."""
        if len(parts) == 1:
            return parts[0]
        if not parts:
            return cls.empty()
        columns = [np.concatenate([getattr(p, name) for p in parts]) for name in _COLUMNS]
        if np.any(columns[0][1:] < columns[0][:-1]):
            order = np.argsort(columns[0], kind="stable")
            columns = [column[order] for column in columns]
        message, parent, child, stamp, translation, rotation = columns
        failures = sorted(f for p in parts for f in p.failures)
        return cls(message, parent, child, stamp, translation, rotation, failures)

    def renumbered(self, numbers: Int64Array) -> Decoded:
        """The same rows and failures, message ``i`` renumbered ``numbers[i]``."""
        failures = [(int(numbers[message]), reason) for message, reason in self.failures]
        return Decoded(
            numbers[self.message], self.parent, self.child, self.stamp, self.translation, self.rotation, failures
        )

    def batch(self, frames: FrameNames, *, static: bool, authority: str, record_time: int) -> TransformBatch:
        """The rows as one source's batch, every row from ``authority`` at ``record_time``."""
        n = len(self.message)
        return TransformBatch(
            frame_names=frames.names,
            authorities=[authority],
            parent=self.parent,
            child=self.child,
            stamp=self.stamp,
            translation=self.translation,
            rotation=self.rotation,
            static=np.full(n, static),
            record_time=np.full(n, record_time, np.int64),
        )


_COLUMNS = ("message", "parent", "child", "stamp", "translation", "rotation")


class Headers:
    """The headers of decoded messages, in message order: ``message`` is each one's message (an index
    into the payloads given), ``frame`` ids of a ``FrameNames``; ``failures`` the (message, reason)
    of payloads that do not start with a header. ``child``: of odometry, each one's child_frame_id (the
    string after its header; -1 where the bytes given end first), ids of the same table; empty otherwise."""

    __slots__ = ("child", "failures", "frame", "message", "stamp")

    def __init__(
        self,
        message: Int64Array,
        stamp: Int64Array,
        frame: Int32Array,
        failures: list[tuple[int, str]],
        child: Int32Array | None = None,
    ) -> None:
        self.message = message
        self.stamp = stamp
        self.frame = frame
        self.failures = failures
        self.child = child if child is not None else np.zeros(0, np.int32)


#: Decodes many payloads, ``raw[starts[i] : starts[i] + lengths[i]]``, their frames interned in the table.
BulkDecoder = Callable[[UInt8Array, Int64Array, Int64Array, FrameNames], Decoded]
#: Clocks of many payloads: the messages well-formed, their times (ns), and the (message, reason) of the others.
Clocks = tuple[Int64Array, Int64Array, list[tuple[int, str]]]
ClockDecoder = Callable[[UInt8Array, Int64Array, Int64Array], Clocks]
#: Headers of many payloads (their first ``wire.HEADER_BYTES`` at most), frames interned in the table.
HeaderDecoder = Callable[[UInt8Array, Int64Array, Int64Array, FrameNames], Headers]
#: Transforms as one serialized ``tf2_msgs/TFMessage``.
TransformEncoder = Callable[[Sequence[Transform]], bytes]


def message_clock(decode: ClockDecoder, data: bytes) -> int:
    """One clock message's time (ns), decoded by the bulk decoder ``decode``; ``DecodeError`` when
    it is not well-formed."""
    _, times, failures = decode(*_one(data))
    if failures:
        raise DecodeError(failures[0][1])
    return int(times[0])


def message_header(decode: HeaderDecoder, data: bytes) -> Header | None:
    """The header one message starts with, decoded by the bulk decoder ``decode``; None where it
    cannot start with one."""
    frames = FrameNames()
    headers = decode(*_one(data), frames)
    if headers.failures:
        return None
    return int(headers.stamp[0]), frames.names[int(headers.frame[0])]


def _one(data: bytes) -> tuple[UInt8Array, Int64Array, Int64Array]:
    return np.frombuffer(data, np.uint8), np.zeros(1, np.int64), np.array([len(data)], np.int64)
