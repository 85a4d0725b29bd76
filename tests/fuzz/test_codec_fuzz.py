"""Property-based fuzzing of the ROS1 and CDR transform decoders: mutants of well-formed messages
decoded in bulk (compiled, native/tf_wire.hpp) read as each is read on its own, field by field in
Python (``read_alone`` here, with ``wire.Cursor``, the reader of headers and robot messages) and
through the bulk decoder as live sources decode them: the same rows, the same messages refused, for
the same reasons at the same offsets.

``TFTOOLS_FUZZ_EXAMPLES`` raises the number of examples (default: a quick run for CI).
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from functools import cache

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tests.fuzz.test_live_fuzz import mutants
from tests.sources.ros2_helpers import Tf, foxglove_cdr, tf_cdr, tf_ros1, varied_transform
from tftools.sources.codecs import cdr, ros1
from tftools.sources.codecs.decoded import Decoded, DecodeError, FrameNames
from tftools.sources.codecs.select import CLOCK_CODECS, CODECS
from tftools.sources.codecs.wire import VALUES_SIZE, Cursor, Reason, Wire, wire_of, worded

EXAMPLES = int(os.environ.get("TFTOOLS_FUZZ_EXAMPLES", "40"))
FUZZ = settings(max_examples=EXAMPLES, deadline=None, suppress_health_check=[HealthCheck.too_slow])
KEYS = [key for key in CODECS if key[1] in ("ros1", "cdr")]


@cache
def seeds(key: tuple[str, str]) -> list[bytes]:
    """Well-formed messages of the codec ``key``: 0 to 5 transforms, both byte orders in CDR."""
    rng = np.random.default_rng(len(key[0]))
    out = []
    for i in range(12):
        tfs = [varied_transform(rng) for _ in range(1 if key[0].endswith("FrameTransform") else i % 6)]
        if key[1] == "ros1":
            out.append(tf_ros1([Tf(t.parent, t.child, t.sec % 2**32, t.nsec, t.translation, t.rotation) for t in tfs]))
        elif key[0].startswith("foxglove"):
            out.append(foxglove_cdr(tfs, single=key[0].endswith("FrameTransform")))
        else:
            out.append(tf_cdr(tfs, little_endian=i % 3 > 0))
    return out


def recounted(seed: bytes, key: tuple[str, str]) -> st.SearchStrategy[bytes]:
    """``seed`` with its count of transforms changed, or bytes added after it."""
    at = 0 if key[1] == "ros1" else 4
    order = ">" if key[1] == "cdr" and seed[1] == 0 else "<"
    counts = st.integers(0, 8).map(
        lambda n: seed[:at] + n.to_bytes(4, "big" if order == ">" else "little") + seed[at + 4 :]
    )
    return counts | st.binary(min_size=1, max_size=9).map(lambda tail: seed + tail)


Row = tuple[str, str, int, bytes]


def read_alone(payload: bytes, wires: Sequence[Wire], counted: bool) -> tuple[list[Row], list[str]]:
    """One message read field by field in Python: its rows, or why it is not well-formed."""
    try:
        cursor = Cursor(payload, wire_of(payload, 0, len(payload), wires))
        count = cursor.uint() if counted else 1
        if count * cursor.wire.smallest > cursor.rest:
            raise DecodeError(worded(Reason.COUNT, len(payload), cursor.pos, count))
        fields = []
        for _ in range(count):
            stamp, frame_at, frame_size = cursor.header()
            child_at, child_size = cursor.string()
            at = cursor.take(VALUES_SIZE, 8)
            values = np.frombuffer(payload[at : at + VALUES_SIZE], f"{cursor.wire.order}f8").astype(np.float64)
            fields.append(
                (payload[frame_at : frame_at + frame_size], payload[child_at : child_at + child_size], stamp, values)
            )
        if cursor.wire.exact and cursor.rest:
            raise DecodeError(worded(Reason.TRAILING, len(payload), cursor.pos, cursor.rest))
        return [(frame.decode(), child.decode(), stamp, values.tobytes()) for frame, child, stamp, values in fields], []
    except DecodeError as e:
        return [], [str(e)]
    except UnicodeDecodeError:
        return [], [worded(Reason.NOT_UTF8, len(payload))]


def rows(decoded: Decoded, frames: FrameNames, message: int) -> list[Row]:
    names = frames.names
    return [
        (names[decoded.parent[i]], names[decoded.child[i]], int(decoded.stamp[i]), decoded.values[i].tobytes())
        for i in np.flatnonzero(decoded.message == message)
    ]


@pytest.mark.parametrize("key", KEYS, ids=lambda key: f"{key[0]}-{key[1]}")
def test_in_bulk_as_one_by_one(key: tuple[str, str]) -> None:
    decode = CODECS[key].decode
    changed = [recounted(seed, key) for seed in seeds(key)[:6]] + [mutants(seed) for seed in seeds(key)[:4]]

    @FUZZ
    @given(st.lists(st.one_of(st.sampled_from(seeds(key)), *changed), min_size=9, max_size=40))
    def check(payloads: list[bytes]) -> None:
        lengths = np.array([len(p) for p in payloads], np.int64)
        raw = np.frombuffer(b"".join(payloads), np.uint8)
        frames = FrameNames()
        bulk = decode(raw, np.cumsum(lengths) - lengths, lengths, frames)
        assert np.all(np.diff(bulk.message) >= 0)
        wires = ros1.WIRES if key[1] == "ros1" else cdr.WIRES
        counted = not key[0].endswith("FrameTransform")
        for i, payload in enumerate(payloads):
            one_frames = FrameNames()
            one = decode(np.frombuffer(payload, np.uint8), np.zeros(1, np.int64), lengths[i : i + 1], one_frames)
            reasons = [reason for m, reason in bulk.failures if m == i]
            assert (rows(bulk, frames, i), reasons) == read_alone(payload, wires, counted)
            assert (rows(one, one_frames, 0), [reason for _, reason in one.failures]) == (
                rows(bulk, frames, i),
                reasons,
            )

    check()


@pytest.mark.parametrize("encoding", ["ros1", "cdr", "json"])
def test_clocks_in_bulk_as_one_by_one(encoding: str) -> None:
    decode = CLOCK_CODECS[("rosgraph_msgs/msg/Clock", encoding)].decode
    clock = {"ros1": b"\x01\x00\x00\x00\x02\x00\x00\x00", "cdr": b"\x00\x01\x00\x00" + b"\x01\x00\x00\x00" * 2}
    seed = clock.get(encoding, b'{"clock": {"sec": 1, "nanosec": 2}}')

    @FUZZ
    @given(st.lists(st.sampled_from([seed]) | mutants(seed), max_size=20))
    def check(payloads: list[bytes]) -> None:
        lengths = np.array([len(p) for p in payloads], np.int64)
        messages, times, failures = decode(
            np.frombuffer(b"".join(payloads), np.uint8), np.cumsum(lengths) - lengths, lengths
        )
        for i, payload in enumerate(payloads):
            alone = decode(np.frombuffer(payload, np.uint8), np.zeros(1, np.int64), lengths[i : i + 1])
            assert times[messages == i].tolist() == alone[1].tolist()
            assert [reason for m, reason in failures if m == i] == [reason for _, reason in alone[2]]

    check()
