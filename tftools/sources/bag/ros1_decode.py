"""ROS1-serialized tf2_msgs/TFMessage payloads decoded in bulk with numpy, or by rosbags as reference.

A TFMessage is a uint32 count, then per transform: header (uint32 seq, uint32 sec, uint32 nsec,
string frame_id), string child_frame_id, 7 float64; a string is a uint32 length and its bytes.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from tftools.core.time import NS_PER_S
from tftools.sources.bag.gather import bytes_at, distinct, u32_at

IntArray = npt.NDArray[np.int64]
Int32Array = npt.NDArray[np.int32]
FloatArray = npt.NDArray[np.float64]
ByteArray = npt.NDArray[np.uint8]

_SMALLEST = 12 + 4 + 4 + 56  # one transform with empty frame ids
#: When this few messages are left with more than ``_TAIL_STEPS`` transforms still to read, each is
#: read on its own: in step, one message of a million transforms would take a million numpy rounds.
_TAIL_MESSAGES = 8
_TAIL_STEPS = 64
_HASH_PRIME = np.uint64(0x100000001B3)


class FrameTable:
    """Frame names interned once for a whole file: name -> index into ``names``."""

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
    """Transforms of the decoded messages, message by message in order: ``message`` is each row's
    message (an index into the payloads given); ``failed`` the messages that are not TFMessages."""

    message: IntArray
    parent: Int32Array
    child: Int32Array
    stamp: IntArray
    values: FloatArray  # (N, 7): x y z qx qy qz qw
    failed: IntArray

    @classmethod
    def empty(cls, failed: IntArray | None = None) -> Decoded:
        none = np.zeros(0, np.int64)
        ids = np.zeros(0, np.int32)
        return cls(none, ids, ids, none, np.zeros((0, 7)), none if failed is None else failed)


def decode_tf_messages(raw: ByteArray, starts: IntArray, lengths: IntArray, frames: FrameTable) -> Decoded:
    """The TFMessages at ``raw[starts[i] : starts[i] + lengths[i]]``, all at once.

    Messages are walked transform by transform in step: every message's j-th transform is read
    by the same few numpy operations. A message that does not parse exactly (as rosbags would
    parse it) is reported in ``failed``; the reference decoder may say why.
    """
    n = len(starts)
    ends = starts + lengths
    readable = lengths >= 4
    counts = np.zeros(n, np.int64)
    counts[readable] = u32_at(raw, starts[readable])
    bad = ~readable | (counts * _SMALLEST > lengths - 4) | ((counts == 0) & (lengths != 4))
    counts[bad] = 0
    steps = _walk(raw, starts + 4, ends, counts, bad)
    counts[bad] = 0
    keep = [~bad[step.message] for step in steps]
    return _assemble(raw, steps, keep, counts, np.flatnonzero(bad), frames)


@dataclass
class _Step:
    """The j-th transforms of the messages that have one (or, read on its own, the j-th onwards of one)."""

    j: int | IntArray
    message: IntArray
    stamp: IntArray
    frame: tuple[IntArray, IntArray]  # starts, lengths
    child: tuple[IntArray, IntArray]
    values: FloatArray


def _walk(
    raw: ByteArray, cursor: IntArray, ends: IntArray, counts: IntArray, bad: npt.NDArray[np.bool_]
) -> list[_Step]:
    # Messages sorted by count, most first: those with a j-th transform are a prefix.
    order = np.argsort(-counts, kind="stable")
    cursor, ends, sorted_counts = cursor[order], ends[order], counts[order]
    size = len(raw)
    steps: list[_Step] = []
    active = int(np.count_nonzero(sorted_counts))
    j = 0
    while active:
        if active <= _TAIL_MESSAGES and sorted_counts[0] - j > _TAIL_STEPS:
            for k in range(active):
                steps.append(_rest(raw, int(order[k]), int(cursor[k]), int(ends[k]), j, int(sorted_counts[k]), bad))
            cursor[:active] = ends[:active]  # read to their ends (or marked bad)
            break
        at, end = cursor[:active], ends[:active]
        ok = at + 16 <= end
        head = bytes_at(raw, np.where(ok, at, 0) + 4, 12).view("<u4").astype(np.int64)  # sec, nsec, frame_id length
        frame_start = at + 16
        child_len_at = frame_start + head[:, 2]
        ok &= child_len_at + 4 <= end
        child_start = child_len_at + 4
        child_len = u32_at(raw, np.where(ok, child_len_at, 0))
        values_at = child_start + child_len
        ok &= values_at + 56 <= end
        values_at = np.where(ok, values_at, 0)
        values = bytes_at(raw, np.minimum(values_at, size - 56), 56).view("<f8")
        messages = order[:active]
        bad[messages[~ok]] = True
        steps.append(
            _Step(
                j,
                messages,
                head[:, 0] * NS_PER_S + head[:, 1],
                (frame_start, head[:, 2]),
                (child_start, child_len),
                values,
            )
        )
        cursor[:active] = values_at + 56
        j += 1
        while active and sorted_counts[active - 1] <= j:
            active -= 1
    if len(order):
        consumed = sorted_counts > 0
        bad[order[consumed & (cursor != ends)]] = True
    return steps


def _rest(raw: ByteArray, message: int, at: int, end: int, first: int, count: int, bad: npt.NDArray[np.bool_]) -> _Step:
    """Transforms ``first`` to ``count`` of one message, from ``at``: their places found one by one
    (plain integers), their bytes gathered at once."""
    data = raw[at:end].tobytes()
    rows = count - first
    frame_at, child_at, values_at = np.empty(rows, np.int64), np.empty(rows, np.int64), np.empty(rows, np.int64)
    frame_len, child_len = np.empty(rows, np.int64), np.empty(rows, np.int64)
    offset, done = 0, 0
    for row in range(rows):
        if offset + 16 > len(data):
            break
        length = int.from_bytes(data[offset + 12 : offset + 16], "little")
        child_length_at = offset + 16 + length
        if child_length_at + 4 > len(data):
            break
        child_length = int.from_bytes(data[child_length_at : child_length_at + 4], "little")
        values = child_length_at + 4 + child_length
        if values + 56 > len(data):
            break
        frame_at[row], frame_len[row], child_at[row], child_len[row] = (
            offset + 16,
            length,
            child_length_at + 4,
            child_length,
        )
        values_at[row] = values
        offset, done = values + 56, row + 1
    if done < rows or offset != len(data):
        bad[message] = True
    head = bytes_at(raw, at + frame_at[:done] - 12, 8).view("<u4").astype(np.int64)  # sec, nsec: before frame_id
    return _Step(
        np.arange(first, first + done),
        np.full(done, message),
        head[:, 0] * NS_PER_S + head[:, 1],
        (at + frame_at[:done], frame_len[:done]),
        (at + child_at[:done], child_len[:done]),
        bytes_at(raw, at + values_at[:done], 56).view("<f8"),
    )


def _assemble(
    raw: ByteArray,
    steps: list[_Step],
    keep: list[npt.NDArray[np.bool_]],
    counts: IntArray,
    failed: IntArray,
    frames: FrameTable,
) -> Decoded:
    first = np.cumsum(counts) - counts  # each message's first row
    total = int(counts.sum())
    if not total:
        return Decoded.empty(failed)
    place = np.concatenate([first[s.message[k]] + s.j for s, k in zip(steps, keep, strict=True)])
    message = np.empty(total, np.int64)
    stamp = np.empty(total, np.int64)
    values = np.empty((total, 7), np.float64)
    name_starts, name_lengths = [], []
    for step, k in zip(steps, keep, strict=True):
        name_starts += [step.frame[0][k], step.child[0][k]]
        name_lengths += [step.frame[1][k], step.child[1][k]]
    message[place] = np.concatenate([s.message[k] for s, k in zip(steps, keep, strict=True)])
    stamp[place] = np.concatenate([s.stamp[k] for s, k in zip(steps, keep, strict=True)])
    values[place] = np.concatenate([s.values[k] for s, k in zip(steps, keep, strict=True)])
    ids, undecodable = intern(raw, np.concatenate(name_starts), np.concatenate(name_lengths), frames)
    # The names came step by step, each step's frame ids then its child ids: (from, middle, to).
    sizes = [int(k.sum()) for k in keep]
    bounds = np.cumsum([0] + [2 * s for s in sizes]).tolist()
    spans = [(bounds[i], bounds[i] + sizes[i], bounds[i + 1]) for i in range(len(sizes))]
    parent = np.empty(total, np.int32)
    child = np.empty(total, np.int32)
    parent[place] = np.concatenate([ids[a:b] for a, b, _ in spans])
    child[place] = np.concatenate([ids[b:c] for _, b, c in spans])
    decoded = Decoded(message, parent, child, stamp, values, failed)
    if undecodable.any():
        bad_row = np.zeros(total, bool)
        bad_row[place] = np.concatenate([undecodable[a:b] | undecodable[b:c] for a, b, c in spans])
        decoded = _without(decoded, bad_row)
    return decoded


def _without(decoded: Decoded, bad_row: npt.NDArray[np.bool_]) -> Decoded:
    lost = np.unique(decoded.message[bad_row])
    keep = ~np.isin(decoded.message, lost)
    return Decoded(
        decoded.message[keep],
        decoded.parent[keep],
        decoded.child[keep],
        decoded.stamp[keep],
        decoded.values[keep],
        np.union1d(decoded.failed, lost),
    )


def intern(
    raw: ByteArray, starts: IntArray, lengths: IntArray, frames: FrameTable
) -> tuple[Int32Array, npt.NDArray[np.bool_]]:
    """The frame ids of the strings ``raw[starts:starts+lengths]``, and which are not UTF-8.

    Strings of one length are told apart by a 64-bit hash of their bytes, checked byte for byte
    afterwards (a collision falls back to sorting the bytes themselves).
    """
    ids = np.zeros(len(starts), np.int32)
    undecodable = np.zeros(len(starts), bool)
    for length in distinct(lengths).tolist():
        rows = np.flatnonzero(lengths == length)
        if length == 0:
            ids[rows] = frames.id("")
            continue
        matrix = bytes_at(raw, starts[rows], length)
        firsts, inverse = _distinct(matrix)
        table = np.zeros(len(firsts), np.int32)
        broken = np.zeros(len(firsts), bool)
        for i, row in enumerate(firsts.tolist()):
            try:
                table[i] = frames.id(matrix[row].tobytes().decode("utf-8"))
            except UnicodeDecodeError:
                broken[i] = True
        ids[rows] = table[inverse]
        undecodable[rows] = broken[inverse]
    return ids, undecodable


def _distinct(matrix: ByteArray) -> tuple[IntArray, IntArray]:
    """A first row of each distinct row of ``matrix``, and each row's index among them."""
    n, width = matrix.shape
    padded = np.zeros((n, -(-width // 8) * 8), np.uint8)
    padded[:, :width] = matrix
    words = padded.view("<u8")
    key = np.full(n, width, np.uint64)
    for column in words.T:
        key = key * _HASH_PRIME ^ column
    firsts, inverse = _peel(key)
    if np.array_equal(matrix[firsts][inverse], matrix):
        return firsts, inverse
    rows = np.ascontiguousarray(matrix).view(f"V{width}").reshape(-1)
    _, firsts, inverse = np.unique(rows, return_index=True, return_inverse=True)
    return firsts, inverse.reshape(-1)


def _peel(key: npt.NDArray[np.uint64]) -> tuple[IntArray, IntArray]:
    """A first row of each distinct value of ``key``, and each row's index among them.

    Frame names are few and repeat, so the rows of each value are picked out in turn (a pass
    each, no sort); past ``_PEELED`` values, the rest are sorted out by ``np.unique``."""
    n = len(key)
    inverse = np.empty(n, np.int64)
    firsts: list[int] = []
    rows = np.arange(n)
    rest = key
    while len(rows) and len(firsts) < _PEELED:
        same = rest == rest[0]
        inverse[rows[same]] = len(firsts)
        firsts.append(int(rows[0]))
        rows, rest = rows[~same], rest[~same]
    if len(rows):
        _, more, index = np.unique(rest, return_index=True, return_inverse=True)
        inverse[rows] = len(firsts) + index.reshape(-1)
        return np.concatenate([np.array(firsts, np.int64), rows[more]]), inverse
    return np.array(firsts, np.int64), inverse


_PEELED = 16


# The reference: rosbags' own deserializer, message by message.


@functools.cache
def _typestore() -> Any:
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore

    store = get_typestore(Stores.ROS1_NOETIC)
    for name in ("tf2_msgs/msg/TFMessage", "tf/msg/tfMessage"):
        if name not in store.fielddefs:
            store.register(get_types_from_msg("geometry_msgs/TransformStamped[] transforms", name))
    return store


def reference_transforms(payload: bytes | memoryview, type_name: str) -> list[tuple[str, str, int, tuple[float, ...]]]:
    """(frame_id, child_frame_id, stamp ns, 7 values) of each transform, as rosbags decodes them;
    ``ValueError`` when ``payload`` is not such a message."""
    from rosbags.serde import SerdeError

    package, _, name = type_name.partition("/")
    try:
        message = _typestore().deserialize_ros1(bytes(payload), f"{package}/msg/{name}")
    except SerdeError as e:
        raise ValueError(str(e)) from None
    rows: list[tuple[str, str, int, tuple[float, ...]]] = []
    for t in message.transforms:
        # ROS1 times are unsigned; rosbags reads their seconds into a signed int32.
        stamp = (t.header.stamp.sec & 0xFFFFFFFF) * NS_PER_S + t.header.stamp.nanosec
        a, r = t.transform.translation, t.transform.rotation
        rows.append((t.header.frame_id, t.child_frame_id, stamp, (a.x, a.y, a.z, r.x, r.y, r.z, r.w)))
    return rows
