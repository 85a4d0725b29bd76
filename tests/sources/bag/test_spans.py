"""Message records' rows (``Spans``) selected without copies where every row is kept in order, and the
ROS 1 chunk reader's one-layout path giving what its record-by-record path gives."""

from __future__ import annotations

import struct

import numpy as np
import pytest

from tests.sources.bag.hostile import ros1_record
from tftools.sources.bag.ros1.chunks import locate, walk
from tftools.sources.bag.ros1.records import OP_CONNECTION, OP_MESSAGE
from tftools.sources.bag.spans import Spans, bounded, selects_all


def _spans(n: int) -> Spans:
    column = np.arange(n, dtype=np.int64)
    return Spans(column % 3, column * 10, column % 2, column * 100, column * 10, column * 10 + 5)


@pytest.mark.parametrize(
    ("which", "n", "expected"),
    [
        (np.ones(4, bool), 4, True),
        (np.array([True, True, False, True]), 4, False),
        (np.arange(4), 4, True),
        (np.array([0, 2, 1, 3]), 4, False),
        (np.array([0, 1, 3]), 4, False),
        (np.array([0, 1, 1, 3]), 4, False),
        (np.array([0, 1, 2, 3]), 5, False),
        (np.zeros(0, np.int64), 0, True),
        (np.zeros(0, bool), 0, True),
    ],
)
def test_selects_all(which: np.ndarray, n: int, expected: bool) -> None:
    assert selects_all(which, n) is expected


def test_rows_of_every_row_share_columns_others_copy() -> None:
    spans = _spans(5)
    names = ("chunk", "offset", "channel", "time", "start", "end")
    every = spans.rows(np.ones(5, bool))
    assert every is not spans
    assert all(getattr(every, name) is getattr(spans, name) for name in names)
    assert all(getattr(spans.rows(np.arange(5)), name) is getattr(spans, name) for name in names)
    some = spans.rows(np.array([4, 0, 2]))
    for name in names:
        assert getattr(some, name).tolist() == getattr(spans, name)[[4, 0, 2]].tolist()
        assert not np.shares_memory(getattr(some, name), getattr(spans, name))


@pytest.mark.parametrize("shuffled", [False, True])
def test_bounded_same_in_order_or_not(shuffled: bool) -> None:
    """Records listed in file order (no sort) and the same listed out of order (sorted) bound alike."""
    offsets = np.array([0, 40, 90, 0, 30], np.int64)
    chunks = np.array([0, 0, 0, 1, 1], np.int64)
    order = np.array([3, 1, 4, 0, 2]) if shuffled else np.arange(5)
    listed = Spans(chunks[order], offsets[order], order, order * 7, offsets[order], offsets[order])
    spans, damaged = bounded(listed, np.array([1000, 2000], np.int64), np.array([1200, 2100], np.int64))
    assert spans.start.tolist() == [1000, 1040, 1090, 2000, 2030]
    assert spans.end.tolist() == [1040, 1090, 1200, 2030, 2100]
    assert spans.channel.tolist() == [0, 1, 2, 3, 4]
    assert not damaged.any()


def test_bounded_two_at_one_offset() -> None:
    """Two entries at one offset: their chunk is damaged, and both reach to the next record further on."""
    offsets = np.array([0, 40, 40, 90], np.int64)
    listed = Spans(np.zeros(4, np.int64), offsets, np.arange(4), np.arange(4), offsets, offsets)
    spans, damaged = bounded(listed, np.array([1000], np.int64), np.array([1200], np.int64))
    assert spans.start.tolist() == [1000, 1040, 1040, 1090]
    assert spans.end.tolist() == [1040, 1090, 1090, 1200]
    assert damaged.tolist() == [True]


def _message(conn: int, secs: int, nsecs: int, payload: bytes) -> bytes:
    fields = [
        ("op", bytes([OP_MESSAGE])),
        ("conn", struct.pack("<I", conn)),
        ("time", struct.pack("<II", secs, nsecs)),
    ]
    return ros1_record(fields, payload)


def _columns(spans: Spans) -> list[list[int]]:
    return [getattr(spans, name).tolist() for name in ("chunk", "offset", "channel", "time", "start", "end")]


def test_locate_one_layout_as_record_by_record() -> None:
    """A chunk of message records of one layout is read without its rows gathered; the same messages
    behind a connection record (read one by one, then gathered) come out alike, but for their offsets."""
    messages = b"".join(_message(c, 100 + c, 5 * c, bytes(range(c + 3))) for c in range(6))
    described = ros1_record([("type", b"tf2_msgs/TFMessage")], b"")[4:-4]  # header fields only
    fields = [("op", bytes([OP_CONNECTION])), ("conn", struct.pack("<I", 9)), ("topic", b"/tf")]
    connection = ros1_record(fields, described)
    one, connections, error = locate(messages, walk(messages, 2), follow=False)
    assert (connections, error) == ([], "")
    assert one.channel.tolist() == list(range(6))
    assert one.time.tolist() == [(100 + c) * 1_000_000_000 + 5 * c for c in range(6)]
    assert [messages[s:e] for s, e in zip(one.start.tolist(), one.end.tolist(), strict=True)] == [
        bytes(range(c + 3)) for c in range(6)
    ]
    mixed = connection + messages
    other, connections, error = locate(mixed, walk(mixed, 2), follow=False)
    assert len(connections) == 1 and error == ""
    shift = len(connection)
    expected = _columns(one)
    expected[1] = [o + shift for o in expected[1]]
    expected[4] = [s + shift for s in expected[4]]
    expected[5] = [e + shift for e in expected[5]]
    assert _columns(other) == expected


def test_locate_records_of_two_layouts_each_by_its_own() -> None:
    """A message whose header holds one field more than the others', its first fields theirs: located by
    its own layout whether it comes first or after one of theirs (read as theirs, its payload's length
    would be that field's)."""
    plain = [_message(c, 100 + c, 0, bytes(range(c + 3))) for c in range(3)]
    fields = [("op", bytes([OP_MESSAGE])), ("conn", struct.pack("<I", 7)), ("time", struct.pack("<II", 5, 0))]
    longer = ros1_record([*fields, ("x", b"")], b"abcd")
    ours = [bytes(range(c + 3)) for c in range(3)]
    for records, channels, payloads in (
        ([plain[0], longer, *plain[1:]], [0, 7, 1, 2], [ours[0], b"abcd", *ours[1:]]),
        ([longer, *plain], [7, 0, 1, 2], [b"abcd", *ours]),
    ):
        data = b"".join(records)
        found, connections, error = locate(data, walk(data, 0), follow=False)
        assert (connections, error) == ([], "")
        assert found.channel.tolist() == channels
        assert [data[s:e] for s, e in zip(found.start.tolist(), found.end.tolist(), strict=True)] == payloads
