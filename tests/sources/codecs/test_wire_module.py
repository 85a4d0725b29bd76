"""The compiled reading helpers beside the TFMessage decoder (native/wire_module.cpp): ROS1 message
record headers matched against a template; and the decoder's values, written as the core takes them, and
its names (native/tf_wire.hpp's ``NameIds``)."""

from __future__ import annotations

import struct

import numpy as np
import pytest

from tests.sources.ros2_helpers import Tf, tf_cdr, tf_ros1
from tftools.sources.codecs import _wire, cdr, ros1
from tftools.sources.codecs.decoded import FrameNames


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


def test_a_record_whose_header_is_longer_than_the_template_does_not_match() -> None:
    """Its header's first bytes are the template's, a field more after them: read as the template's, its
    payload's length would be that field's (``locate`` tries every record of a chunk on the first one's)."""
    longer = _header(1, 2, 3) + _field("x", b"")
    data = _record(longer, b"abcd")
    hit, (conn, *_) = _match(data, [0], [len(data)], [False], _header(0, 0, 0))
    assert hit == [False]
    assert conn == []


def test_a_record_read_only_for_its_header_ends_at_its_limit() -> None:
    data = _record(_header(1, 2, 3), b"a long payload")
    limit = len(data) - 10
    hit, (_, _, start, end) = _match(data, [0], [limit], [True], _header(0, 0, 0))
    assert hit == [True]
    assert end == [limit] and start[0] < limit


def test_names_are_told_apart_wherever_they_come_and_after_a_message_is_refused() -> None:
    """A name is tried first as the one last seen in its place (count, first name, position): names that
    change in one place, differ only in a word or in their last byte, or take the id of a name forgotten
    with a refused message all decode as themselves."""

    def message(*pairs: tuple[str, str]) -> bytes:
        return tf_ros1([Tf(parent, child, 10 + i) for i, (parent, child) in enumerate(pairs)])

    messages = [
        message(("a", "arm_link1"), ("arm_link1", "c")),
        message(("a", "arm_link2"), ("arm_link2", "c")),  # the same place, a name differing in its last byte
        message(("a", "abcdefgh12345678"), ("abcdefgh12345678", "")),
        message(("a", "abcdefgX12345678"), ("abcdefgX12345678", "")),  # differing in the first word only
        message(("a", "new1"), ("new1", "new2"))[:-10],  # refused (truncated): new1 and new2 forgotten
        message(("a", "zz"), ("zz", "c")),  # zz takes new1's id, in new1's place
        message(("a", "arm_link1"), ("arm_link1", "c")),
        message(("a", "arm_link1")),
    ]
    expected = [pair for i, m in enumerate(messages) if i != 4 for pair in _pairs(m)]
    raw = np.frombuffer(b"".join(messages), np.uint8)
    lengths = np.array([len(m) for m in messages], np.int64)
    frames = FrameNames()
    decoded = ros1.decode_tf(raw, np.cumsum(lengths) - lengths, lengths, frames)
    names = frames.names
    assert [(names[p], names[c]) for p, c in zip(decoded.parent, decoded.child, strict=True)] == expected
    assert [m for m, _ in decoded.failures] == [4]
    assert "new1" not in names and "new2" not in names


@pytest.mark.parametrize("wire", ["ros1", "cdr", "cdr_big_endian"])
def test_values_are_copied_bit_for_bit_at_every_byte_offset(wire: str) -> None:
    """A transform's 7 doubles come out as their bytes say, whatever byte of a cache line or word each message
    starts at (ROS1 packs its fields: its doubles lie at any offset): NaNs with payloads, -0.0, subnormals and
    infinities keep their bits (the rows are refused or kept later, by the buffer). They are written as the
    core takes them: the translations (N, 3) and rotations (N, 4) apart, each contiguous."""
    bits = [0x7FF8_0000_DEAD_BEEF, 0x8000_0000_0000_0000, 0x0000_0000_0000_0001, 0x7FF0_0000_0000_0000,
            0xFFF4_0000_0000_1234, 0x3FF0_0000_0000_0001, 0xC00F_FFFF_FFFF_FFFF]  # fmt: skip
    values = struct.unpack("<7d", struct.pack("<7Q", *bits))
    tf = Tf("a", "b", 10, translation=values[:3], rotation=values[3:])
    payload = tf_ros1([tf, tf]) if wire == "ros1" else tf_cdr([tf, tf], little_endian=wire == "cdr")
    decode = ros1.decode_tf if wire == "ros1" else cdr.decode_tf
    slot = (len(payload) + 31) // 16 * 16  # message k at byte k of its slot: every offset modulo 16 once
    raw = np.frombuffer(b"".join((b"\0" * k + payload).ljust(slot, b"\0") for k in range(16)), np.uint8)
    starts = np.arange(16, dtype=np.int64) * (slot + 1)
    decoded = decode(raw, starts, np.full(16, len(payload), np.int64), FrameNames())
    assert decoded.translation.shape == (32, 3) and decoded.rotation.shape == (32, 4)
    assert decoded.translation.flags.c_contiguous and decoded.rotation.flags.c_contiguous
    assert (decoded.values.view(np.uint64) == np.array(bits, np.uint64)).all()


def _pairs(payload: bytes) -> list[tuple[str, str]]:
    """The (parent, child) names of a ROS1 TFMessage, read field by field."""
    count, at, out = struct.unpack_from("<I", payload)[0], 4, []
    for _ in range(count):
        at += 12  # seq, stamp
        names = []
        for _ in range(2):
            (size,) = struct.unpack_from("<I", payload, at)
            names.append(payload[at + 4 : at + 4 + size].decode())
            at += 4 + size
        at += 56
        out.append((names[0], names[1]))
    return out


def test_rows_take_their_messages_time_and_their_channels_static_and_authority() -> None:
    rng = np.random.default_rng(3)
    times = rng.integers(0, 10**18, 50)
    channel_of = rng.integers(0, 4, 50).astype(np.int32)
    static_of, authority_of = np.array([False, True, False, True]), np.array([0, 1, -1, 0], np.int32)
    messages, rows = rng.permutation(50)[:20], rng.integers(0, 4, 20)
    record_time, static, authority = _wire.per_row(messages, rows, times, channel_of, static_of, authority_of)
    each = np.repeat(messages, rows)
    assert np.array_equal(record_time, times[each])
    assert np.array_equal(static, static_of[channel_of[each]])
    assert np.array_equal(authority, authority_of[channel_of[each]])
    with pytest.raises(ValueError, match="outside"):
        _wire.per_row(np.array([50]), np.array([1]), times, channel_of, static_of, authority_of)
    with pytest.raises(ValueError, match="outside"):
        _wire.per_row(np.array([0]), np.array([1]), times, np.full(50, 4, np.int32), static_of, authority_of)
