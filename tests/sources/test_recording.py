"""A recording holds its transforms once, in the buffer's histories, and gives them back as read."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from tests.analysis.robot_scenes import URDF, Setup, robot_bag
from tests.bags import BagFormat, ClockMessage, TfMessage, write_bag
from tests.sources.bag.reading import read_contents
from tests.sources.ros2_helpers import batch_rows
from tftools.core.batch import BatchBuilder, TransformBatch
from tftools.core.buffer import Buffer
from tftools.core.rejection import RejectionCode
from tftools.core.transform import Transform
from tftools.sources.bag.contents import BagContents, BagFileInfo, RecordWindow, in_record_order
from tftools.sources.bag.robot import ROBOT_TOPICS
from tftools.sources.contents import SentMessages
from tftools.sources.recording import read_recording, recording_of, recording_of_buffer

SAMPLE_BAGS = Path(__file__).resolve().parents[2] / "sample_bags"
IDENTITY = (0.0, 0.0, 0.0, 1.0)


def _part(builder: BatchBuilder, first_record: int, rows: list[tuple[str, str, int, float]]) -> TransformBatch:
    for k, (parent, child, stamp, x) in enumerate(rows):
        static = child.endswith("laser")
        builder.add(
            parent, child, stamp, (x, 0.0, 0.0), IDENTITY,
            static=static, record_time=first_record + k, authority="/static" if static else "/ekf",
        )  # fmt: skip
    return builder.take()


def _contents(parts: list[TransformBatch]) -> BagContents:
    end = max(int(p.record_time[-1]) for p in parts)
    info = BagFileInfo("memory.bag", "ros1", 1, end, sum(map(len, parts)), transform_count=sum(map(len, parts)))
    return BagContents(parts, [info], ("/tf", "/tf_static"))


def _two_parts() -> tuple[TransformBatch, TransformBatch]:
    builder = BatchBuilder()
    first = _part(
        builder,
        1,
        [
            ("/map", "odom", 10, 1.0),  # a slash tf2 strips
            ("odom", "base", 10, 2.0),
            ("base", "laser", 5, 3.0),  # static
            ("odom", "base", 10, 9.0),  # TF_REPEATED_DATA
            ("odom", "odom", 11, 0.0),  # TF_SELF_TRANSFORM
            ("odom", "base", 8, 4.0),  # older than the newest: stored, sorted in
        ],
    )
    second = _part(
        builder,
        100,
        [
            ("map", "/odom", 20, math.nan),  # TF_NAN_INPUT
            ("", "base", 21, 5.0),  # TF_NO_FRAME_ID
            ("map", "base", 30, 6.0),  # re-parented
            ("map", "odom", 20, 7.0),
        ],
    )
    return first, second


def test_rows_come_back_in_record_order_with_the_refused_ones() -> None:
    first, second = _two_parts()
    expected = batch_rows([first, second])
    recording = recording_of(_contents([first, second]))
    assert not recording.contents.parts  # taken by the buffer: held once
    refused = sorted((r.sequence, r.code) for r in recording.buffer.rejections)
    assert refused == [
        (3, RejectionCode.REPEATED_DATA),
        (4, RejectionCode.SELF_TRANSFORM),
        (6, RejectionCode.NAN_INPUT),
        (7, RejectionCode.NO_FRAME_ID),
    ]
    assert batch_rows(recording.transforms) == expected
    assert recording.transform_count == len(expected) == 10
    assert recording.buffer.lookup("map", "base", 30).translation == (6.0, 0.0, 0.0)


def _table_reordered(batch: TransformBatch, names: list[str]) -> TransformBatch:
    """``batch`` over the table ``names`` (its own names, in another order, and others): as a reader that
    interned its names in another order, a header's frame among them, would have made it."""
    number = np.array([names.index(n) for n in batch.frame_names], np.int32)
    return replace(batch, frame_names=names, parent=number[batch.parent], child=number[batch.child])


def test_the_refused_rows_name_their_frames_as_they_first_come_whatever_the_readers_table() -> None:
    """The refused rows (``Recording.refused``) share the reader's table, interned in the order its parts were
    decoded, which depends on how the read grouped them (every header's frame among them): their names are the
    ones they use, as they first come, so that every grouping gives one batch."""
    first, second = _two_parts()
    tables = (
        [*first.frame_names, "camera"],
        ["camera", *reversed(first.frame_names)],
    )
    found = []
    for table in tables:
        recording = recording_of(_contents([_table_reordered(first, table), _table_reordered(second, table)]))
        refused = recording.refused
        found.append((list(refused.frame_names), refused.parent.tolist(), refused.child.tolist()))
    assert found[0] == found[1]
    assert found[0] == (["odom", "base", "map", "/odom", ""], [0, 0, 2, 4], [1, 0, 3, 1]), found[0]
    assert batch_rows(recording_of(_contents(list(_two_parts()))).transforms) == batch_rows([first, second])


def test_a_buffer_as_a_recording_gives_back_its_rows_and_the_refused_ones_its_log_keeps() -> None:
    first, second = _two_parts()
    buffer = Buffer(None)
    buffer.insert(first)
    buffer.insert(second)
    recording = recording_of_buffer(buffer)
    assert batch_rows(recording.transforms) == batch_rows([first, second])  # a slash, static, NaN and all
    assert (recording.start, recording.end, recording.transform_count) == (1, 103, 10)
    assert [(f.format, f.live) for f in recording.contents.files] == [("buffer", False)]


def test_a_bag_read_into_a_recording_gives_back_every_row_as_read() -> None:
    bag = SAMPLE_BAGS / "robot.bag"
    read = read_contents([bag])
    assert len(read.parts) >= 1
    recording = read_recording([bag])
    assert batch_rows(recording.transforms) == batch_rows(read.transforms)
    history = recording.buffer.history("base_link")
    assert history is not None and len(history) == np.count_nonzero(
        np.array(read.transforms.frame_names)[read.transforms.child] == "base_link"
    )


@pytest.mark.parametrize("name", ["robot.bag", "robot_db3", "robot_mcap"])
def test_a_whole_read_brings_in_the_buffers_block_as_it_reads(monkeypatch: pytest.MonkeyPatch, name: str) -> None:
    """A file read whole brings in the histories' block as its rows are read (``RecordingContents.room``), which
    ``recording_of`` hands to the buffer: the histories are those of a read without it (the sample's block is
    too small to take it: ``test_insert`` has one that does). A windowed read (a replay's) does not, nor a read
    where no other core is free."""
    from tftools.sources.bag import messages

    bag = SAMPLE_BAGS / name
    monkeypatch.setattr(messages, "_a_core_free", lambda: True)
    loaded = []
    for rows in (1 << 60, 0):  # never; from the first part decoded
        monkeypatch.setattr(messages, "_ROOM_FROM_ROWS", rows)
        read = read_contents([bag])
        room = read.room
        assert (room is None) == bool(rows)
        recording = recording_of(read)
        assert read.room is None  # handed to the buffer (which takes a block on large pages: 2 MiB and up)
        columns = ("stamps", "values", "parents", "authorities", "record_times", "sequence", "flags")
        loaded.append(
            [(child, [getattr(h, c).tobytes() for c in columns]) for child, h in recording.buffer.histories()]
        )
    assert loaded[0] == loaded[1]
    assert read_contents([bag], window=RecordWindow(0, 1 << 62)).room is None
    monkeypatch.setattr(messages, "_a_core_free", lambda: False)  # every core busy: its thread would slow the read
    assert read_contents([bag]).room is None


@pytest.mark.parametrize("name", ["robot.bag", "robot_db3", "robot_mcap"])
def test_payloads_decoded_on_another_thread_make_the_same_recording(monkeypatch: pytest.MonkeyPatch, name: str) -> None:
    """A whole read on two cores or more decodes a codec's payloads on another thread while it reads the next
    (``SteppedDecoder.start``): every history, refusal, message count, sent message and problem is the one read
    on one core. Every part is made one to start (``_ALONE_BYTES``: the sample's parts are too small), and the
    ``.db3`` is fetched in many parts, each finished while the next is read. A windowed read (a replay's) and
    one with every core busy decode on the reading thread."""
    from tftools.sources.bag import messages
    from tftools.sources.bag.rosbag2 import db3
    from tftools.sources.codecs.stepped import Started, SteppedDecoder

    bag = SAMPLE_BAGS / name
    started: list[int] = []
    start = SteppedDecoder.start

    def counted(decoder: SteppedDecoder, *payloads: Any) -> Started:
        started.append(1)
        return start(decoder, *payloads)

    monkeypatch.setattr(SteppedDecoder, "start", counted)
    monkeypatch.setattr(messages, "_ALONE_BYTES", 1)
    monkeypatch.setattr(db3, "_FETCH", 256)
    monkeypatch.setattr(messages, "_a_core_free", lambda: True)
    found = []
    for cores in (1, 2):
        monkeypatch.setattr(messages, "_cores", lambda cores=cores: cores)
        started.clear()
        recording = read_recording([bag])
        assert len(started) >= (0 if cores == 1 else 5 if name == "robot_db3" else 1)
        assert cores > 1 or not started
        columns = ("stamps", "values", "parents", "authorities", "record_times", "sequence", "flags")
        found.append(
            (
                [(child, [getattr(h, c).tobytes() for c in columns]) for child, h in recording.buffer.histories()],
                batch_rows(recording.refused),
                recording.refused_sequence.tolist(),
                [(f.tf_messages, f.transform_count, f.problems) for f in recording.contents.files],
                _sent(recording.contents.sent),
            )
        )
    assert found[0] == found[1]
    started.clear()
    monkeypatch.setattr(messages, "_cores", lambda: 2)
    read_contents([bag], window=RecordWindow(0, 1 << 62))
    assert not started
    monkeypatch.setattr(messages, "_a_core_free", lambda: False)
    read_contents([bag])
    assert not started


@pytest.mark.parametrize("name", ["robot.bag", "robot_db3", "robot_mcap"])
def test_pages_given_back_on_another_core_make_the_same_recording(monkeypatch: pytest.MonkeyPatch, name: str) -> None:
    """Where another core is free, ``recording_of`` gives the freed parts' pages back (``malloc_trim``) on a thread
    of its own while it inserts the next part, one at a time, and the last at once on its own thread; else each at
    once. The histories, refusals and sent messages are the same either way (here a trim after every part)."""
    import threading

    from tftools.sources import recording as module

    trims: list[str] = []
    monkeypatch.setattr(module, "_malloc_trim", lambda: lambda pad: trims.append(threading.current_thread().name))
    monkeypatch.setattr(module, "FREED_BYTES_TO_GIVE_BACK", 1)
    found, where = [], []
    for aside in (False, True):
        monkeypatch.setattr(module, "a_core_aside", lambda aside=aside: aside)
        trims.clear()
        recording = recording_of(read_contents([SAMPLE_BAGS / name]))
        columns = ("stamps", "values", "parents", "authorities", "record_times", "sequence", "flags")
        found.append(
            (
                [(child, [getattr(h, c).tobytes() for c in columns]) for child, h in recording.buffer.histories()],
                batch_rows(recording.refused),
                recording.refused_sequence.tolist(),
                _sent(recording.contents.sent),
            )
        )
        where.append(list(trims))
    assert found[0] == found[1]
    caller = threading.current_thread().name
    assert len(where[0]) == len(where[1]) >= 2  # a trim after each part, and the last
    assert set(where[0]) == {caller}
    assert set(where[1][:-1]) == {"tfx-give-back"} and where[1][-1] == caller


def _sent(sent: SentMessages | None) -> object:
    if sent is None:
        return None
    columns = (sent.authority, sent.static, sent.record_time, sent.stamp)
    return list(sent.authorities), [c.tobytes() for c in columns]


def test_parts_that_overlap_in_record_time_are_merged_in_order() -> None:
    builder = BatchBuilder()
    early = _part(builder, 1, [("a", "b", 1, 0.0), ("a", "b", 2, 0.0), ("a", "b", 3, 0.0)])
    late = _part(builder, 3, [("a", "b", 4, 0.0), ("a", "b", 5, 0.0)])
    assert in_record_order([early, late]) == [early, late]  # they follow each other: kept as they are
    (merged,) = in_record_order([late, early])
    assert merged.record_time.tolist() == [1, 2, 3, 3, 4]
    assert merged.stamp.tolist() == [1, 2, 4, 3, 5]  # a tie keeps the order given


@pytest.mark.parametrize("fmt", list(BagFormat))
def test_what_a_read_took_beside_the_transforms_is_the_recordings_own(tmp_path: Path, fmt: BagFormat) -> None:
    """One read gives, as the recording's attributes: the robot's latest description and its joint states, the
    QoS a ROS 2 bag's publishers offered (by the bag's path), and the sensor headers asked for, one asked for
    and not recorded said in their problems."""
    bag = robot_bag(tmp_path, "rover", Setup(description=True), fmt)
    recording = read_recording([bag], headers=("/nothing",), whole=ROBOT_TOPICS)
    assert recording.robot.description == URDF and len(recording.robot.joint_states) == 100
    assert recording.stamped.streams == []
    assert recording.stamped.problems == ["/nothing: not in the recording"]
    ros2 = fmt is not BagFormat.ros1
    assert list(recording.qos) == ([str(bag)] if ros2 else [])
    assert all(qos.metadata and not qos.problem and "/tf_static" in qos.profiles for qos in recording.qos.values())
    plain = read_recording([bag])  # read without them: none of them
    assert (plain.robot.description, plain.robot.joint_states, plain.stamped.streams) == ("", [], [])


@pytest.mark.parametrize("fmt", list(BagFormat))
def test_the_recorded_clock_is_the_recordings(tmp_path: Path, fmt: BagFormat) -> None:
    """The /clock samples recorded (a split recording's merged) are ``Recording.clock``, in record order."""
    first, second = (
        write_bag(tmp_path / name, [_tf(record)], fmt, [ClockMessage(record + k, 5_000 + record + k) for k in range(3)])
        for name, record in (("a", 1_000), ("b", 2_000))
    )
    clock = read_recording([second, first]).clock
    assert clock.topic == "/clock" and clock.record_time.tolist() == [1_000, 1_001, 1_002, 2_000, 2_001, 2_002]
    assert (clock.clock - clock.record_time).tolist() == [5_000] * 6


def _tf(record: int) -> TfMessage:
    return TfMessage("/tf", record, [Transform((1.0, 0.0, 0.0), IDENTITY, record, "map", "odom")])
