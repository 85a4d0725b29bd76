"""The compiled reading helpers beside the TFMessage decoder (native/wire_module.cpp): ROS1 message
record headers matched against a template, and decoded values split into the core's columns."""

from __future__ import annotations

import struct

import numpy as np
import pytest

from tftools.sources.codecs import _wire


def _field(name: str, value: bytes) -> bytes:
    body = name.encode() + b"=" + value
    return struct.pack("<I", len(body)) + body


def _header(conn: int, sec: int, nsec: int) -> bytes:
    return (
        _field("op", b"\x02") + _field("conn", struct.pack("<I", conn)) + _field("time", struct.pack("<II", sec, nsec))
    )


def _record(header: bytes, payload: bytes) -> bytes:
    return struct.pack("<I", len(header)) + header + struct.pack("<I", len(payload)) + payload


def _match(
    data: bytes, offsets: list[int], limits: list[int], cuts: list[bool], template: bytes
) -> tuple[list[bool], list[list[int]]]:
    conn_at = template.index(b"conn=") + len(b"conn=")
    time_at = template.index(b"time=") + len(b"time=")
    hit, *values = _wire.match_records(
        np.frombuffer(data, np.uint8),
        np.array(offsets, np.int64),
        np.array(limits, np.int64),
        np.array(cuts, bool),
        template,
        conn_at,
        time_at,
    )
    return hit.tolist(), [v.tolist() for v in values]


def test_records_of_the_template_layout_match_with_their_conn_time_and_payload() -> None:
    first, second = _record(_header(3, 10, 5), b"abcd"), _record(_header(7, 11, 999_999_999), b"xy")
    data = first + second
    hit, (conn, time, start, end) = _match(data, [0, len(first)], [len(data)] * 2, [False] * 2, _header(0, 0, 0))
    assert hit == [True, True]
    assert conn == [3, 7]
    assert time == [10_000_000_005, 11_999_999_999]
    assert [data[s:e] for s, e in zip(start, end, strict=True)] == [b"abcd", b"xy"]


def test_a_record_of_another_layout_or_past_its_limit_does_not_match() -> None:
    other = _field("op", b"\x03") + _field("conn", b"\0\0\0\0") + _field("time", bytes(8))  # a connection record
    data = _record(other, b"abcd") + _record(_header(1, 2, 3), b"abcd")
    second = len(data) // 2
    hit, (conn, *_) = _match(data, [0, second, second], [len(data), len(data), len(data) - 1], [False] * 3,
                             _header(0, 0, 0))  # fmt: skip
    assert hit == [False, True, False]  # the last: its payload ends a byte past its limit
    assert conn == [1]


def test_a_record_read_only_for_its_header_ends_at_its_limit() -> None:
    data = _record(_header(1, 2, 3), b"a long payload")
    limit = len(data) - 10
    hit, (_, _, start, end) = _match(data, [0], [limit], [True], _header(0, 0, 0))
    assert hit == [True]
    assert end == [limit] and start[0] < limit


def test_values_split_into_contiguous_translations_and_rotations() -> None:
    values = np.random.default_rng(1).normal(size=(5, 7))
    translation, rotation = _wire.split_values(values)
    assert np.array_equal(translation, values[:, :3]) and np.array_equal(rotation, values[:, 3:])
    assert translation.flags.c_contiguous and rotation.flags.c_contiguous
    empty_t, empty_r = _wire.split_values(np.zeros((0, 7)))
    assert empty_t.shape == (0, 3) and empty_r.shape == (0, 4)
    with pytest.raises(ValueError, match="not \\(N, 7\\)"):
        _wire.split_values(np.zeros((2, 6)))
