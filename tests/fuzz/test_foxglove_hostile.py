"""Foxglove FrameTransform(s) in an MCAP, in JSON and protobuf (one and several a message), carrying what a broken
publisher or a hand-written file puts there: NaN, infinities, 1e308, a frame name of a megabyte, empty names,
stamps past what int64 nanoseconds hold. A healthy stream beside them is read whole; each hostile transform is
either read as what it is (NaN and infinities: tf2 refuses them, and wtf says so) or its message is said in one
line; no command prints a megabyte or raises. And JSON payloads of any such value: a row or one line, never
another exception."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.fuzz.test_bag_fuzz import FUZZ
from tests.sources.bag.reading import read_contents
from tests.sources.ros2_helpers import FoxgloveChannel, Msg, Tf, batch_rows, write_foxglove_mcap
from tftools.sources.bag.messages import MessageSet
from tftools.sources.codecs.select import CODECS
from tftools.sources.codecs.wire import MAX_FRAME_ID

T0 = 1_700_000_000
MEGA = "x" * (1 << 20)
HOSTILE = [
    Tf("odom", "nan_t", T0 + 1, translation=(math.nan, 0.0, 0.0)),
    Tf("odom", "inf_r", T0 + 1, rotation=(math.inf, 0.0, 0.0, 1.0)),
    Tf("odom", "huge", T0 + 1, translation=(1e308, -1e308, 0.0)),
    Tf("odom", MEGA, T0 + 1),
    Tf("", "", T0 + 1),
    Tf("odom", "late", 2**62),  # seconds: past int64 nanoseconds
    Tf("odom", "early", -(2**40)),
]
FAILED = 3  # of the hostile messages: the megabyte's and the two stamps'
CHANNELS = [
    FoxgloveChannel("/json_one", "json", single=True),
    FoxgloveChannel("/json_many", "json"),
    FoxgloveChannel("/pb_one", "protobuf", single=True),
    FoxgloveChannel("/pb_many", "protobuf"),
]
HEALTHY = 100


def _hostile_mcap(path: Path) -> Path:
    """Per channel, odom -> base<k> at 10 Hz for 10 s, and at 5 s a message of each hostile transform (one of
    several: with a base<k> one beside it)."""
    messages = []
    for k, channel in enumerate(CHANNELS):
        base = f"base{k}"
        for i in range(HEALTHY):
            at = (T0 + i // 10) * 10**9 + (i % 10) * 10**8 + k
            messages.append(Msg(channel.topic, at, (Tf("odom", base, T0 + i // 10, (i % 10) * 10**8),)))
        for j, tf in enumerate(HOSTILE):
            carried = (tf,) if channel.single else (tf, Tf("odom", base, T0 + 5, 5 * 10**7))
            messages.append(Msg(channel.topic, (T0 + 5) * 10**9 + 10**7 + j * 1000 + k, carried))
    return write_foxglove_mcap(path, CHANNELS, messages)


def test_hostile_frame_transforms_are_read_as_they_are_or_said(tmp_path: Path) -> None:
    contents = read_contents([_hostile_mcap(tmp_path / "hostile.mcap")], [c.topic for c in CHANNELS])
    rows = batch_rows(contents.transforms)
    children = {row[1] for row in rows}
    assert MEGA not in children and not any(len(c) > MAX_FRAME_ID for c in children)
    assert {"nan_t", "inf_r", "huge", ""} <= children and not {"late", "early"} & children
    for k, channel in enumerate(CHANNELS):
        kept = len(HOSTILE) - FAILED
        base = sum(1 for row in rows if row[1] == f"base{k}")
        assert base == HEALTHY + (0 if channel.single else kept), channel  # the healthy stream read whole
    batch = contents.transforms
    named = {batch.frame_names[c]: i for i, c in enumerate(batch.child.tolist())}
    assert math.isnan(batch.translation[named["nan_t"], 0]) and math.isinf(batch.rotation[named["inf_r"], 0])
    assert batch.translation[named["huge"], 0] == 1e308  # as published: tf2 takes it, refuses the others
    # one line a channel: how many of its messages, and why the first
    assert len(contents.problems) == len(CHANNELS), contents.problems
    for topic, line in zip(sorted(c.topic for c in CHANNELS), sorted(contents.problems), strict=True):
        assert line.startswith(f"{topic}: {FAILED} of {HEALTHY + len(HOSTILE)} messages could not be decoded")
        assert "a frame_id of 1048576 bytes" in line or "beyond the int64 nanoseconds" in line, line


def test_no_command_prints_a_megabyte_nor_raises(tfx: Tfx, tmp_path: Path) -> None:  # noqa: F811
    """Before, wtf printed the megabyte name in four findings (3.1 MB of output) and frames in one (1.0 MB)."""
    bag = _hostile_mcap(tmp_path / "hostile.mcap")
    for args in (("wtf",), ("frames",), ("monitor",), ("echo", "odom", "base0", "--at", "+5")):
        result = tfx(*args, "-b", bag)
        assert result.code in (0, 1, 2) and "Traceback" not in result.stderr, (args, result.stderr[-2000:])
        longest = max(map(len, (result.stdout + result.stderr).splitlines()), default=0)
        assert longest < 2_000 and len(result.stdout) < 100_000, (args, longest)
    checked = tfx("wtf", "-b", bag)
    assert (
        "odom -> nan_t" in checked.stdout and "odom -> inf_r" in checked.stdout and "invalid_values" in checked.stdout
    )


def _any_number() -> st.SearchStrategy[Any]:
    return st.one_of(
        st.floats(allow_nan=True, allow_infinity=True),
        st.integers(min_value=-(2**80), max_value=2**80),
        st.sampled_from([None, True, "1", [], {}, 1e308, -0.0]),
    )


def _any_name() -> st.SearchStrategy[Any]:
    return st.one_of(
        st.text(max_size=20),
        st.integers(min_value=MAX_FRAME_ID - 2, max_value=MAX_FRAME_ID + 2).map(lambda n: "n" * n),
        st.sampled_from([None, 7, ["a"], "\x00", "é" * 2049]),
    )


_TRANSFORM = st.fixed_dictionaries(
    {},
    optional={
        "timestamp": st.fixed_dictionaries({}, optional={"sec": _any_number(), "nsec": _any_number()}),
        "parent_frame_id": _any_name(),
        "child_frame_id": _any_name(),
        "translation": st.dictionaries(st.sampled_from("xyz"), _any_number(), max_size=3),
        "rotation": st.dictionaries(st.sampled_from("xyzw"), _any_number(), max_size=4),
    },
)


@pytest.mark.parametrize("single", [True, False], ids=["FrameTransform", "FrameTransforms"])
def test_json_frame_transforms_of_any_value(single: bool) -> None:
    codec = CODECS[("foxglove.FrameTransform" if single else "foxglove.FrameTransforms", "json")]

    @FUZZ
    @given(st.lists(_TRANSFORM, min_size=1, max_size=4))
    def check(transforms: list[dict[str, Any]]) -> None:
        payloads = (
            [json.dumps(t).encode() for t in transforms]
            if single
            else [json.dumps({"transforms": transforms}).encode()]
        )
        messages = MessageSet()
        channel = messages.channel("/fox", codec)
        messages.add(channel, np.arange(len(payloads)), np.arange(len(payloads)), payloads)
        batches, _, _, problems = messages.decode()
        assert all("\n" not in p and len(p) < 1_000 for p in problems)
        for batch in batches:
            names = [batch.frame_names[i] for i in (*batch.parent.tolist(), *batch.child.tolist())]
            assert all(len(name) <= MAX_FRAME_ID for name in names)
        read = {int(m) for m in messages.sent.record_time}
        assert len(read) <= len(payloads)

    check()
