"""What every transform decoder gives: rows of transforms, message by message, their frame names
interned once per source."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from tftools.core.batch import FloatArray, Int32Array, Int64Array, TransformBatch

ByteArray = npt.NDArray[np.uint8]
#: A payload: bytes as received, a view into a file, or a numpy array of them.
BytesLike = bytes | memoryview | ByteArray


class DecodeError(ValueError):
    """A payload that is not a well-formed message of its type."""


class FrameTable:
    """Frame names interned once for a whole source: name -> index into ``names``."""

    def __init__(self) -> None:
        self.names: list[str] = []
        self.ids: dict[str, int] = {}

    def id(self, name: str) -> int:
        index = self.ids.get(name)
        if index is None:
            index = self.ids[name] = len(self.names)
            self.names.append(name)
        return index


@dataclass
class Decoded:
    """Transforms of decoded messages, message by message in order: ``message`` is each row's
    message (an index into the payloads given), ``parent`` and ``child`` ids of a ``FrameTable``;
    ``failures`` the (message, reason) of payloads that are not well-formed messages."""

    message: Int64Array
    parent: Int32Array
    child: Int32Array
    stamp: Int64Array
    values: FloatArray  # (N, 7): x y z qx qy qz qw
    failures: list[tuple[int, str]] = field(default_factory=list)

    @classmethod
    def empty(cls, failures: Sequence[tuple[int, str]] = ()) -> Decoded:
        none, ids = np.zeros(0, np.int64), np.zeros(0, np.int32)
        return cls(none, ids, ids, none, np.zeros((0, 7)), list(failures))

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
        message, parent, child, stamp, values = columns
        return cls(message, parent, child, stamp, values, sorted(f for p in parts for f in p.failures))

    def batch(self, frames: FrameTable, *, static: bool, authority: str, record_time: int) -> TransformBatch:
        """The rows as one source's batch, every row from ``authority`` at ``record_time``."""
        n = len(self.message)
        return TransformBatch(
            frame_names=frames.names,
            authorities=[authority],
            parent=self.parent,
            child=self.child,
            stamp=self.stamp,
            translation=np.ascontiguousarray(self.values[:, :3]),
            rotation=np.ascontiguousarray(self.values[:, 3:]),
            static=np.full(n, static),
            record_time=np.full(n, record_time, np.int64),
        )


_COLUMNS = ("message", "parent", "child", "stamp", "values")
_MIN_STAMP, _MAX_STAMP = -(2**63), 2**63 - 1


@dataclass
class Parsed:
    """One message parsed in Python: its transforms (stamps in ns, values x y z qx qy qz qw)."""

    parents: list[str] = field(default_factory=list)
    children: list[str] = field(default_factory=list)
    stamps: list[int] = field(default_factory=list)
    values: list[tuple[float, ...]] = field(default_factory=list)


def parsed_one_by_one(
    raw: ByteArray, starts: Int64Array, lengths: Int64Array, frames: FrameTable, parse: Callable[[bytes], Parsed]
) -> Decoded:
    """The payloads parsed one by one in Python, by ``parse`` (which raises ``DecodeError``)."""
    rows: list[tuple[int, int, int, int, tuple[float, ...]]] = []
    failures: list[tuple[int, str]] = []
    for number, (start, length) in enumerate(zip(starts.tolist(), lengths.tolist(), strict=True)):
        try:
            parsed = parse(raw[start : start + length].tobytes())
            if any(not _MIN_STAMP <= stamp <= _MAX_STAMP for stamp in parsed.stamps):
                raise DecodeError("a stamp beyond the int64 nanoseconds of ROS time")
        except DecodeError as e:
            failures.append((number, str(e)))
            continue
        ids = [(frames.id(p), frames.id(c)) for p, c in zip(parsed.parents, parsed.children, strict=True)]
        rows += [(number, *pair, s, v) for pair, s, v in zip(ids, parsed.stamps, parsed.values, strict=True)]
    if not rows:
        return Decoded.empty(failures)
    message, parent, child, stamp, values = zip(*rows, strict=True)
    return Decoded(
        np.array(message, np.int64),
        np.array(parent, np.int32),
        np.array(child, np.int32),
        np.array(stamp, np.int64),
        np.array(values, np.float64).reshape(-1, 7),
        failures,
    )


def gathered(raw: ByteArray, starts: Int64Array, length: int) -> ByteArray:
    """The ``length`` bytes from each of ``starts`` in ``raw`` (a flat byte array, each run within
    it), as the rows of a matrix: one gather of whole items rather than a slice per row."""
    if not length or len(raw) < length:
        return np.zeros((len(starts) if not length else 0, length), np.uint8)
    items = np.ndarray((len(raw) - length + 1,), f"V{length}", raw, strides=(1,))
    rows: ByteArray = items[starts].view(np.uint8).reshape(len(starts), length)
    return rows


#: Decodes many payloads, ``raw[starts[i] : starts[i] + lengths[i]]``, their frames interned in the table.
BulkDecoder = Callable[[ByteArray, Int64Array, Int64Array, FrameTable], Decoded]


#: Clocks of many payloads: the messages well-formed, their times (ns), and the (message, reason) of the others.
Clocks = tuple[Int64Array, Int64Array, list[tuple[int, str]]]
ClockDecoder = Callable[[ByteArray, Int64Array, Int64Array], Clocks]


def message_batch(
    decode: BulkDecoder, data: bytes, *, static: bool, authority: str, record_time: int
) -> TransformBatch:
    """One message decoded by the bulk decoder ``decode`` (as live sources receive them), as a batch;
    ``DecodeError`` when it is not well-formed."""
    frames = FrameTable()
    decoded = decode(np.frombuffer(data, np.uint8), np.zeros(1, np.int64), np.array([len(data)], np.int64), frames)
    if decoded.failures:
        raise DecodeError(decoded.failures[0][1])
    return decoded.batch(frames, static=static, authority=authority, record_time=record_time)


def message_clock(decode: ClockDecoder, data: bytes) -> int:
    """One clock message's time (ns), decoded by the bulk decoder ``decode``; ``DecodeError`` when
    it is not well-formed."""
    _, times, failures = decode(np.frombuffer(data, np.uint8), np.zeros(1, np.int64), np.array([len(data)], np.int64))
    if failures:
        raise DecodeError(failures[0][1])
    return int(times[0])
