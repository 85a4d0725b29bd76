"""The bulk decoders of transform messages against the references: rosbags for CDR and ROS1, the
protobuf library for Foxglove protobuf, ``json`` for Foxglove JSON; malformed payloads skipped."""

from __future__ import annotations

import json
import struct
from typing import Any

import numpy as np
import pytest

from tests.bags import rosbags_tf_message
from tests.sources.reference import reference_rows
from tests.sources.ros2_helpers import (
    Tf,
    batch_rows,
    foxglove_cdr,
    proto_message,
    proto_transform,
    tf_cdr,
    tf_ros1,
    varied_transform,
)
from tftools.sources.bag.messages import MessageSet
from tftools.sources.codecs import _wire, cdr, ros1
from tftools.sources.codecs.decoded import FrameNames
from tftools.sources.codecs.select import CODECS
from tftools.sources.codecs.wire import MAX_FRAME_ID, Reason, worded
from tftools.sources.live.received import Received, decode_received

TF = ("tf2_msgs/msg/TFMessage", "cdr")


def decode(payloads: list[bytes], key: tuple[str, str]) -> tuple[dict[int, list[Any]], list[str]]:
    """Rows by message number (the record time given to each payload), and the problem lines."""
    messages = MessageSet()
    channel = messages.channel("/tf", CODECS[key])
    numbers = list(range(len(payloads)))
    messages.add(channel, numbers, numbers, payloads)
    batch, _, _, problems = messages.decode()
    rows: dict[int, list[Any]] = {}
    for row in batch_rows(batch):
        rows.setdefault(row[6], []).append(row[:5])
    return rows, problems


def expected(messages: list[list[Tf]]) -> dict[int, list[Any]]:
    return {
        i: [(t.parent, t.child, t.stamp, tuple(map(float.hex, t.translation)), tuple(map(float.hex, t.rotation)))
            for t in tfs]
        for i, tfs in enumerate(messages) if tfs
    }  # fmt: skip


def varied(seed: int, count: int, most: int = 6) -> list[list[Tf]]:
    rng = np.random.default_rng(seed)
    return [[varied_transform(rng) for _ in range(int(rng.integers(0, most + 1)))] for _ in range(count)]


# --- CDR -------------------------------------------------------------------------------------


def test_tf_messages_both_byte_orders() -> None:
    """Every frame id length (so every alignment), both byte orders mixed in one topic."""
    messages = varied(1, 600)
    payloads = [tf_cdr(tfs, little_endian=i % 3 > 0) for i, tfs in enumerate(messages)]
    rows, problems = decode(payloads, TF)
    assert rows == expected(messages) == reference_rows(payloads, TF) and problems == []


def test_xcdr2_samples() -> None:
    """XCDR2 (encapsulation 0x0006/0x0007, as final types are sent): 8-byte values aligned to 4."""
    messages = [tfs for tfs in varied(11, 200) if tfs]
    payloads = [_as_xcdr2(tfs, little_endian=i % 2 == 0) for i, tfs in enumerate(messages)]
    assert any(len(p) < len(tf_cdr(tfs)) for p, tfs in zip(payloads, messages, strict=True))  # padding left out
    assert decode(payloads, TF) == (expected(messages), [])


def _as_xcdr2(transforms: list[Tf], *, little_endian: bool) -> bytes:
    order = "<" if little_endian else ">"
    out = bytearray(b"\x00\x07\x00\x00" if little_endian else b"\x00\x06\x00\x00") + struct.pack(
        f"{order}I", len(transforms)
    )
    for t in transforms:
        out += struct.pack(f"{order}iI", t.sec, t.nsec)
        for name in (t.parent, t.child):
            out += (
                b"\x00" * (-(len(out) - 4) % 4)
                + struct.pack(f"{order}I", len(name.encode()) + 1)
                + name.encode()
                + b"\x00"
            )
        out += b"\x00" * (-(len(out) - 4) % 4) + struct.pack(f"{order}7d", *t.translation, *t.rotation)
    return bytes(out)


def test_same_length_other_layout() -> None:
    """Messages of equal length whose strings split differently."""
    messages = [[Tf("ab", "c", 1)], [Tf("a", "bc", 2)], [Tf("abc", "", 3)]] * 20
    messages += [[Tf("abcde", "f", 4), Tf("g", "hijkl", 5)], [Tf("a", "b", 6), Tf("cdefg", "hijkl", 7)]] * 20
    payloads = [tf_cdr(tfs) for tfs in messages]
    assert len({len(p) for p in payloads[:3]}) == 1
    assert decode(payloads, TF)[0] == expected(messages)


def test_many_messages_of_one_layout() -> None:
    """Thousands of look-alikes: the same values as rosbags."""
    rng = np.random.default_rng(5)
    stamps = zip(rng.integers(-(2**31), 2**31, 5000), rng.integers(0, 10**9, 5000), strict=True)
    messages = [[Tf("odom", "base_link", int(s), int(n), tuple(rng.normal(size=3)), tuple(rng.normal(size=4)))]
                for s, n in stamps]  # fmt: skip
    payloads = [tf_cdr(tfs) for tfs in messages]
    assert decode(payloads, TF)[0] == reference_rows(payloads, TF) == expected(messages)


def test_truncated_and_padded_payloads() -> None:
    """No prefix of a message decodes; trailing padding does not matter; what decodes is what
    rosbags decodes."""
    messages = varied(2, 5, most=4)
    whole = [tf_cdr(tfs) for tfs in messages if tfs]
    payloads = [p[:i] for p in whole for i in range(len(p))] + [p + b"\x00" * 3 for p in whole]
    rows, problems = decode(payloads, TF)
    assert sorted(rows) == list(range(len(payloads) - len(whole), len(payloads)))
    assert rows == reference_rows(payloads, TF)
    (line,) = problems
    assert line.startswith(f"/tf: {len(payloads) - len(whole)} of {len(payloads)} messages could not be decoded")


def test_corrupt_payloads_never_raise() -> None:
    """Random bytes, huge counts and string lengths, unknown encapsulations: skipped with reasons."""
    rng = np.random.default_rng(3)
    good = [tf_cdr(tfs) for tfs in varied(4, 50)]
    bad = [bytes(rng.integers(0, 256, int(rng.integers(0, 300)), dtype=np.uint8)) for _ in range(200)]
    bad += [b"\x00\x01\x00\x00" + struct.pack("<I", 2**31), b"\x00\x03\x00\x00" + good[0][4:]]
    bad += [good[1][:8] + struct.pack("<I", 2**30) + good[1][12:]]
    for payload in good:  # each byte of each message flipped in turn, at a few places
        for at in rng.integers(0, len(payload), 3):
            broken = bytearray(payload)
            broken[at] ^= 0xFF
            bad.append(bytes(broken))
    reference = reference_rows(good + bad, TF)
    rows, problems = decode(good + bad, TF)
    assert all(rows[i] == reference.get(i) for i in rows if i < len(good))
    assert {i for i in rows if i < len(good)} == {i for i in reference if i < len(good)}
    assert len(problems) == 1 and "\n" not in problems[0]


@pytest.mark.parametrize("single", [True, False], ids=["FrameTransform", "FrameTransforms"])
def test_foxglove_cdr(single: bool) -> None:
    messages = [tfs[:1] if single else tfs for tfs in varied(6, 300) if tfs]
    key = (f"foxglove_msgs/msg/FrameTransform{'' if single else 's'}", "cdr")
    payloads = [foxglove_cdr(tfs, single=single) for tfs in messages]
    assert decode(payloads, key) == (expected(messages), [])
    assert reference_rows(payloads, key) == expected(messages)


# --- ROS1, as MCAP files recorded from ROS1 hold it --------------------------------------------


@pytest.mark.parametrize("type_name", ["tf2_msgs/TFMessage", "tf/tfMessage"])
def test_ros1_tf_messages(type_name: str) -> None:
    """Unsigned seconds, sequence numbers that differ between look-alikes; no prefix decodes."""
    messages = [[Tf(t.parent, t.child, t.sec % 2**32, t.nsec, t.translation, t.rotation) for t in tfs]
                for tfs in varied(10, 400)]  # fmt: skip
    payloads = [tf_ros1(tfs, seq=i * 7919) for i, tfs in enumerate(messages)]
    prefixes = [p[:i] for p in payloads[:5] if len(p) > 4 for i in range(len(p))]
    rows, problems = decode(payloads + prefixes, (type_name, "ros1"))
    assert rows == expected(messages) == reference_rows(payloads + prefixes, (type_name, "ros1"))
    (line,) = problems
    assert line.startswith(f"/tf: {len(prefixes)} of ")


# --- protobuf --------------------------------------------------------------------------------


def protobuf_rows(payloads: list[bytes], single: bool) -> dict[int, list[Any]]:
    """What the protobuf library reads."""
    from tests.sources.ros2_helpers import proto_classes

    cls = proto_classes()["FrameTransform" if single else "FrameTransforms"]
    out: dict[int, list[Any]] = {}
    for i, payload in enumerate(payloads):
        message = cls.FromString(payload)
        for t in [message] if single else message.transforms:
            v, q = t.translation, t.rotation
            out.setdefault(i, []).append(
                (t.parent_frame_id, t.child_frame_id, t.timestamp.seconds * 1_000_000_000 + t.timestamp.nanos,
                 tuple(map(float.hex, (v.x, v.y, v.z))), tuple(map(float.hex, (q.x, q.y, q.z, q.w))))
            )  # fmt: skip
    return out


@pytest.mark.parametrize("single", [True, False], ids=["FrameTransform", "FrameTransforms"])
def test_protobuf(single: bool) -> None:
    messages = [tfs[:1] if single else tfs for tfs in varied(7, 400) if tfs]
    rng = np.random.default_rng(8)
    for tfs in messages[::5]:  # zeros are left off the wire: messages of other layouts
        zero = rng.integers(0, 7)
        t = tfs[0]
        values = [*t.translation, *t.rotation]
        values[zero] = 0.0
        translation, rotation = (values[0], values[1], values[2]), (values[3], values[4], values[5], values[6])
        tfs[0] = Tf(t.parent, t.child, 0 if zero % 2 else t.sec, t.nsec, translation, rotation)
    payloads = [proto_message(tfs, single=single).SerializeToString() for tfs in messages]
    key = (f"foxglove.FrameTransform{'' if single else 's'}", "protobuf")
    assert decode(payloads, key) == (protobuf_rows(payloads, single), [])
    assert decode(payloads, key)[0] == expected(messages)


def test_protobuf_wire_variants() -> None:
    """Fields in any order, repeated (the last counts), unknown fields, negative and big seconds."""
    base = proto_transform(Tf("map", "odom", 5, 6, (1.0, 2.0, 3.0), (0.0, 0.0, 0.0, 1.0)))
    variants = [
        _fields(base, order=[5, 4, 3, 2, 1]),
        _fields(base, order=[1, 2, 3, 4, 5]) + _tag(9, 0) + b"\x96\x01",  # unknown varint field 9
        _fields(base, order=[1, 2, 3, 4, 5]) + _tag(12, 2) + b"\x03abc",  # unknown length-delimited field
        _fields(base, order=[2, 2, 3, 1, 4, 5]),  # a repeated string: the last one counts
        proto_transform(Tf("a", "b", -(2**33), 999_999_999)).SerializeToString(),
        proto_transform(Tf("a", "b", 2**33, -5)).SerializeToString(),
    ]
    for _ in range(3):  # look-alikes of each, so templates are used
        variants += variants[:6]
    key = ("foxglove.FrameTransform", "protobuf")
    assert decode(variants, key) == (protobuf_rows(variants, True), [])
    assert decode(variants[:6], key) == (protobuf_rows(variants[:6], True), [])  # each on its own


def test_protobuf_stamps_beyond_int64_nanoseconds() -> None:
    """Seconds are int64 in protobuf: those whose nanoseconds would overflow are not decoded."""
    fine = proto_transform(Tf("a", "b", 2**33, 1)).SerializeToString()
    far = [proto_transform(Tf("a", "b", s, 0)).SerializeToString() for s in (2**40, -(2**40), 2**62)]
    rows, problems = decode([fine] * 10 + far * 10, ("foxglove.FrameTransform", "protobuf"))
    assert sorted(rows) == list(range(10))
    assert problems == [
        "/tf: 30 of 40 messages could not be decoded as foxglove.FrameTransform (protobuf), skipped"
        " (first: a stamp beyond the int64 nanoseconds of ROS time)"
    ]


def _tag(number: int, wire: int) -> bytes:
    return bytes([number << 3 | wire])


def _fields(message: Any, order: list[int]) -> bytes:
    """``message`` serialized one field at a time in ``order``."""
    out = b""
    for number in order:
        field = message.DESCRIPTOR.fields_by_number[number]
        single = type(message)()
        if field.message_type:
            getattr(single, field.name).CopyFrom(getattr(message, field.name))
        else:
            setattr(single, field.name, getattr(message, field.name))
        out += single.SerializeToString()
    return out


def test_protobuf_malformed() -> None:
    good = proto_transform(Tf("map", "odom", 5, 6, (1.0, 2.0, 3.0))).SerializeToString()
    bad = [good[:i] for i in range(1, len(good)) if _truncation_breaks(good[:i])]
    bad += [b"\x0f", b"\x12\xff\xff\xff\xff\x0f", b"\x08" + b"\xff" * 11]
    rows, problems = decode([good, *bad], ("foxglove.FrameTransform", "protobuf"))
    assert list(rows) == [0]
    (line,) = problems
    assert line.startswith(f"/tf: {len(bad)} of {len(bad) + 1} messages could not be decoded")


def _truncation_breaks(data: bytes) -> bool:
    from google.protobuf.message import DecodeError as ProtobufError

    from tests.sources.ros2_helpers import proto_classes

    try:
        proto_classes()["FrameTransform"].FromString(data)
    except ProtobufError:
        return True
    return False


# --- JSON ------------------------------------------------------------------------------------


def test_json() -> None:
    messages = [tfs for tfs in varied(9, 200) if tfs]
    payloads = [json.dumps({"transforms": [_json(t) for t in tfs]}).encode() for tfs in messages]
    assert decode(payloads, ("foxglove.FrameTransforms", "json")) == (expected(messages), [])


def test_json_defaults_and_malformed() -> None:
    """Missing numbers are 0 (as in protobuf), ``nanosec`` is nsec; malformed ones are skipped."""
    payloads = [b"{}", b'{"timestamp": {"sec": 3, "nanosec": 4}, "rotation": {"w": 1}}', b"[1]", b"{bad",
                b'{"timestamp": {"sec": "x"}}', b'{"parent_frame_id": 5}', b'{"translation": {"x": null}}']  # fmt: skip
    rows, problems = decode(payloads, ("foxglove.FrameTransform", "json"))
    zero, one = "0x0.0p+0", "0x1.0000000000000p+0"
    assert rows == {
        0: [("", "", 0, (zero,) * 3, (zero,) * 4)],
        1: [("", "", 3_000_000_004, (zero,) * 3, (zero, zero, zero, one))],
    }
    (line,) = problems
    assert line.startswith("/tf: 5 of 7 messages could not be decoded as foxglove.FrameTransform (json)")


def _json(t: Tf) -> dict[str, Any]:
    return {"timestamp": {"sec": t.sec, "nsec": t.nsec}, "parent_frame_id": t.parent, "child_frame_id": t.child,
            "translation": dict(zip("xyz", t.translation, strict=True)),
            "rotation": dict(zip("xyzw", t.rotation, strict=True))}  # fmt: skip


def test_one_malformed_message_is_a_value_error() -> None:
    """A message decoded as live sources decode them that is not well-formed is told unreadable with the
    reason a bag's problem line gives."""
    bad = {"cdr": b"\x00\x09", "ros1": b"\x01\x00", "protobuf": b"\x0f", "json": b"{"}
    for key, codec in CODECS.items():
        (line,) = decode([bad[key[1]]], key)[1]
        ((_, reason),) = decode_received(codec.decode, [Received("/tf", bad[key[1]], "", 0)]).unreadable
        assert line.endswith(f"(first: {reason})")


@pytest.mark.parametrize("names", [("map", "odom"), ("a", "base_link_long"), ("wörld", ""), ("odom", "bc")])
def test_the_cdr_encoder_writes_rosbags_bytes(names: tuple[str, str]) -> None:
    from rosbags.typesys import Stores, get_typestore

    from tftools.core.transform import Transform
    from tftools.sources.codecs import cdr

    parent, child = names
    transforms = [
        Transform((1.5, -2.0, 0.25), (0.0, 0.0, 0.6, 0.8), 1_700_000_000_123_456_789, parent, child),
        Transform(stamp=5, frame_id=child, child_frame_id=parent + "x"),
    ]
    store = get_typestore(Stores.ROS2_HUMBLE)
    message = rosbags_tf_message(store, transforms)
    assert cdr.encode_tf_message(transforms) == bytes(store.serialize_cdr(message, "tf2_msgs/msg/TFMessage"))


@pytest.mark.parametrize("starts, lengths", [([0], [200]), ([-1], [4]), ([8], [-1]), ([0, 0], [4])])
def test_compiled_reader_refuses_payloads_outside_its_bytes(starts: list[int], lengths: list[int]) -> None:
    raw = np.frombuffer(tf_cdr([varied_transform(np.random.default_rng(1))]), np.uint8)
    wire = (1, False, 4, 8, False, True, True, False)  # plain CDR, little endian
    with pytest.raises(ValueError):
        _wire.decode_transforms(raw, np.array(starts, np.int64), np.array(lengths, np.int64), [wire], counted=True)


def test_the_compiled_reader_says_why_and_where_a_message_is_not_well_formed() -> None:
    """Each failure as (message, reason, offset, figure), worded once in Python: a field cut short, a
    count the bytes cannot hold, an unknown encapsulation; ROS1's bytes after the last transform."""
    good = tf_cdr([Tf("map", "odom", 1, 2, (1.0, 2.0, 3.0), (0.0, 0.0, 0.0, 1.0))])
    assert len(good) == 92  # encapsulation, count, stamp, "map\0" at 20, "odom\0" at 28, values at 36
    payloads = [
        good[:24] + struct.pack("<I", 1000) + good[28:],
        good[:4] + struct.pack("<I", 3) + good[8:],
        b"\x00\x09" + good[2:],
        good,
    ]
    ros1_good = tf_ros1([Tf("map", "odom", 1, 2, (1.0, 2.0, 3.0), (0.0, 0.0, 0.0, 1.0))])
    cases = [
        (
            cdr.WIRES,
            payloads,
            [[0, Reason.TRUNCATED, 28, 1000], [1, Reason.COUNT, 8, 3], [2, Reason.ENCAPSULATION, 0, 9]],
        ),
        (ros1.WIRES, [ros1_good + b"\x07\x07"], [[0, Reason.TRAILING, len(ros1_good), 2]]),
    ]
    for wires, given, failed in cases:
        lengths = np.array([len(p) for p in given], np.int64)
        raw = np.frombuffer(b"".join(given), np.uint8)
        found = _wire.decode_transforms(raw, np.cumsum(lengths) - lengths, lengths, [w.compiled for w in wires], True)
        assert found[-1].tolist() == failed
        decode = cdr.decode_tf if wires is cdr.WIRES else ros1.decode_tf
        for message, reason, offset, figure in failed:
            text = worded(Reason(reason), len(given[message]), offset, figure)
            ((_, said),) = decode_received(decode, [Received("/tf", given[message], "", 0)]).unreadable
            assert said == text
    assert [worded(*case) for case in [(Reason.TRUNCATED, 92, 28, 1000), (Reason.COUNT, 92, 8, 3)]] == [
        "message ends at byte 92, a field needs 1028",
        "3 transforms cannot fit in 92 bytes",
    ]
    assert worded(Reason.ENCAPSULATION, 92, 0, 9) == "not a CDR payload (encapsulation 0009)"
    assert worded(Reason.TRAILING, 5, 3, 2) == "2 bytes after the last transform"


def test_a_header_whose_frame_id_is_too_long_is_damage_and_a_short_clock_says_so() -> None:
    header = struct.pack("<4sIIII", b"\x00\x01\x00\x00", 1, 2, MAX_FRAME_ID + 2, 0) + b"x" * (MAX_FRAME_ID + 1)
    payload = np.frombuffer(header + b"\x00", np.uint8)
    one = np.zeros(1, np.int64), np.array([len(payload)], np.int64)
    headers = cdr.decode_headers(payload, *one, FrameNames())
    assert headers.failures == [(0, f"a frame_id of {MAX_FRAME_ID + 1} bytes")]  # its NUL left out
    assert cdr.decode_clocks(payload[:9], *[np.zeros(1, np.int64), np.array([9], np.int64)])[2] == [
        (0, "message ends at byte 9, a Clock needs 12")
    ]
