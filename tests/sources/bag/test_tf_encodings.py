"""TFMessage in every encoding an MCAP file carries: JSON read as CDR is, an encoding tfx does not
read named in one line (a healthy file: nothing to repair)."""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pytest
from mcap.writer import Writer as McapWriter

from tests.sources.bag.reading import read_contents
from tests.sources.ros2_helpers import NS, T0, TF_TYPE, Tf, batch_rows, tf_cdr, typestore, varied_transform
from tftools.analysis.wtf.fleet import check
from tftools.sources.errors import NoTransformsError
from tftools.sources.recording import read_recording

#: (topic, record time, transforms) of each message.
Message = tuple[str, int, Sequence[Tf]]


def messages(seed: int, count: int = 120) -> list[Message]:
    rng = np.random.default_rng(seed)
    out: list[Message] = []
    for i in range(count):
        transforms = [varied_transform(rng) for _ in range(int(rng.integers(0, 5)))]
        finite = [t for t in transforms if all(map(math.isfinite, (*t.translation, *t.rotation)))]  # as JSON has
        out.append(("/tf_static" if i % 9 == 0 else "/tf", T0 + i * NS // 10, finite))
    return out


def json_tf(transforms: Sequence[Tf], nanoseconds: str) -> bytes:
    """A TFMessage as Foxglove writes it in JSON (``nanoseconds``: "nanosec" of ROS 2, "nsec" of ROS 1)."""
    items = [
        {
            "header": {"stamp": {"sec": t.sec, nanoseconds: t.nsec}, "frame_id": t.parent},
            "child_frame_id": t.child,
            "transform": {
                "translation": dict(zip("xyz", t.translation, strict=True)),
                "rotation": dict(zip("xyzw", t.rotation, strict=True)),
            },
        }
        for t in transforms
    ]
    return json.dumps({"transforms": items}).encode()


def write_mcap(path: Path, written: list[Message], encoding: str, type_name: str = TF_TYPE) -> Path:
    """An MCAP of TFMessage channels in ``encoding``: "cdr", "json" (half "nanosec", half "nsec"),
    or any other name (then the payloads are CDR, never to be read)."""
    schema_encoding, definition = {
        "cdr": ("ros2msg", typestore().generate_msgdef(TF_TYPE, ros_version=2)[0].encode()),
        "json": ("jsonschema", b""),
    }.get(encoding, ("", b""))
    with path.open("wb") as f:
        writer = McapWriter(f, chunk_size=4000)
        writer.start(profile="ros2", library="tftools-tests")
        schema = writer.register_schema(type_name, schema_encoding, definition)
        channels: dict[str, int] = {}
        for i, (topic, record, transforms) in enumerate(written):
            if topic not in channels:
                channels[topic] = writer.register_channel(topic, encoding, schema)
            writer.add_message(channels[topic], record, _payload(encoding, transforms, i), record)
        writer.finish()
    return path


def _payload(encoding: str, transforms: Sequence[Tf], number: int) -> bytes:
    if encoding == "json":
        return json_tf(transforms, "nanosec" if number % 2 else "nsec")
    return tf_cdr(transforms)


@pytest.mark.parametrize("type_name", [TF_TYPE, "tf2_msgs/TFMessage"])
def test_json_tf_messages_read_as_cdr_ones(tmp_path: Path, type_name: str) -> None:
    written = messages(1)
    cdr = read_contents([write_mcap(tmp_path / "cdr.mcap", written, "cdr")])
    as_json = read_contents([write_mcap(tmp_path / "json.mcap", written, "json", type_name)])
    assert len(cdr.transforms) > 150 and cdr.problems == []
    assert batch_rows(as_json.parts) == batch_rows(cdr.parts) and as_json.problems == []


def test_json_tf_messages_malformed_skipped(tmp_path: Path) -> None:
    path = tmp_path / "bad.mcap"
    with path.open("wb") as f:
        writer = McapWriter(f)
        writer.start(profile="", library="tftools-tests")
        channel = writer.register_channel("/tf", "json", writer.register_schema(TF_TYPE, "jsonschema", b""))
        good = json_tf([Tf("map", "odom", 3, 4)], "nanosec")
        for i, payload in enumerate([good, b"{", b'{"transforms": 1}', b'{"transforms": [{"header": 2}]}', good]):
            writer.add_message(channel, T0 + i, payload, T0 + i)
        writer.finish()
    contents = read_contents([path])
    assert len(contents.transforms) == 2 and contents.unread == []
    (line,) = contents.problems
    assert line.startswith(f"/tf: 3 of 5 messages could not be decoded as {TF_TYPE} (json), skipped")


def unsupported(tmp_path: Path, encoding: str = "cbor") -> Path:
    return write_mcap(tmp_path / "tf.mcap", messages(2, 30), encoding)


def test_unsupported_encoding_named_not_damage(tmp_path: Path) -> None:
    """Topic, type, encoding and what tfx reads, in one line; not among the file's damage."""
    contents = read_contents([unsupported(tmp_path)])
    assert len(contents.transforms) == 0 and contents.files[0].problems == []
    (line,) = contents.unread
    assert line.startswith(f"/tf_static, /tf: {TF_TYPE} in cbor encoding, which tfx does not read (it reads ")
    assert f"it reads {TF_TYPE} as cdr or json;" in line and "foxglove.FrameTransform(s) as protobuf or json" in line
    assert contents.problems == [line]  # warned about, as before


def test_unsupported_encoding_among_read_topics(tmp_path: Path) -> None:
    """A JSON /tf read, a protobuf /tf_static named; the asked-for topics only."""
    path = tmp_path / "mixed.mcap"
    with path.open("wb") as f:
        writer = McapWriter(f)
        writer.start(profile="", library="tftools-tests")
        read = writer.register_channel("/tf", "json", writer.register_schema(TF_TYPE, "jsonschema", b""))
        not_read = writer.register_channel("/tf_static", "protobuf", writer.register_schema(TF_TYPE, "protobuf", b""))
        elsewhere = writer.register_channel("/other/tf", "protobuf", writer.register_schema(TF_TYPE, "protobuf", b""))
        for channel in (read, not_read, elsewhere):
            writer.add_message(channel, T0, json_tf([Tf("map", "odom", 1)], "nanosec"), T0)
        writer.finish()
    contents = read_contents([path])
    assert len(contents.transforms) == 1
    (line,) = contents.unread
    assert line.startswith(f"/tf_static: {TF_TYPE} in protobuf encoding, which tfx does not read (it reads ")
    findings = [(f.code, f.message, f.hint) for f in check(read_recording([path])).findings]
    assert ("bag_problem", line) in [(code, message) for code, message, _ in findings]
    assert not any("repair" in hint for _, _, hint in findings)


def test_wtf_names_the_encoding(tmp_path: Path) -> None:
    path = unsupported(tmp_path, "protobuf")
    findings = check(read_recording([path], allow_empty=True)).findings
    (no_tf,) = [f for f in findings if f.code == "no_tf"]
    assert f"no transforms read in {path}: /tf_static, /tf: {TF_TYPE} in protobuf encoding" in no_tf.message
    assert "topics present" not in no_tf.message
    assert not any("repair" in f.hint for f in findings) and not any(f.code == "bag_problem" for f in findings)


def test_no_transforms_error_names_the_encoding(tmp_path: Path) -> None:
    path = unsupported(tmp_path)
    contents = read_contents([path])
    error = NoTransformsError([str(path)], ("/tf", "/tf_static"), ["/tf", "/tf_static", "/odom"], contents.unread)
    message = str(error)
    assert message.startswith(f"{path}: no transforms read: /tf_static, /tf: {TF_TYPE} in cbor encoding")
    assert "repair" not in error.hint


@pytest.mark.parametrize(
    ("found", "expected"),
    [
        (["/tf", "/odom"], "no transforms on /tf, /tf_static (/tf present, in a type or encoding tfx does not read); "
         "topics present: /odom"),
        (["/odom"], "no transforms on /tf, /tf_static; topics present: /odom"),
        ([], "no transforms on /tf, /tf_static"),
    ],
)  # fmt: skip
def test_no_transforms_error_never_lists_asked_topics_as_present(found: list[str], expected: str) -> None:
    assert str(NoTransformsError(["x.mcap"], ("/tf", "/tf_static"), found)) == f"x.mcap: {expected}"


def test_read_recording_error_without_repair_hint(tmp_path: Path) -> None:
    path = unsupported(tmp_path)
    with pytest.raises(NoTransformsError) as raised:
        read_recording([path])
    message = str(raised.value)
    assert "topics present: /tf" not in message and "repair" not in raised.value.hint
