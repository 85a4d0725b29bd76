"""``read_contents(..., window=...)``: the transforms and clock recorded in a window of record time, each
file's index skipping what lies outside it; files without one read whole, and saying so."""

from __future__ import annotations

import sqlite3
from functools import cache
from pathlib import Path

import numpy as np
import pytest

from tests.bags import BagFormat, ClockMessage, TfMessage, write_bag
from tests.sources.bag.reading import read_contents
from tests.sources.ros1_helpers import rows_of
from tests.sources.ros2_helpers import varied_messages, write_rosbag2
from tftools.core.transform import Transform
from tftools.sources.bag.contents import BagContents, RecordWindow
from tftools.sources.bag.mcap.index import summary_of
from tftools.sources.bag.ros1.file import BagFile
from tftools.sources.bag.ros1.index import read_index
from tftools.sources.bag.ros1.records import read_bag_header
from tftools.sources.codecs.select import Wanted
from tftools.sources.storage.source import FileSource

SAMPLES = Path(__file__).resolve().parents[3] / "sample_bags"
NS = 1_000_000_000
T0 = 1_700_000_000 * NS
STEP = 10_000_000  # between transform messages: 1500 of them over 15 s, in about 3 chunks of a MiB


def _messages() -> list[TfMessage]:
    frames = ["map", *(f"link_{i}" for i in range(20))]
    moving = [
        TfMessage(
            "/tf",
            T0 + k * STEP,
            [Transform((k, i, 0.5), (0, 0, 0, 1), T0 + k * STEP - i, frames[i], frames[i + 1]) for i in range(20)],
            "/robot",
        )
        for k in range(1500)
    ]
    static = TfMessage("/tf_static", T0 + 5 * STEP, [Transform((1, 2, 3), (0, 0, 0, 1), 0, "map", "world")], "/s")
    return sorted([*moving, static], key=lambda m: m.record_time)


CLOCK = [ClockMessage(T0 + k * 10 * STEP + 1, k * 10 * STEP) for k in range(150)]


@cache
def _bag(fmt: BagFormat, root: Path) -> Path:
    return write_bag(root / fmt.value, _messages(), fmt, CLOCK)


@pytest.fixture(params=list(BagFormat), ids=lambda f: f.value)
def bag(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory) -> Path:
    return _bag(request.param, tmp_path_factory.getbasetemp())


def _assert_windows_make_the_whole(path: Path, width: int) -> BagContents:
    """Windows of ``width`` ns one after the other over the recording (and past its ends) give its
    rows and clock, each described as the whole file; returns the whole read."""
    whole = read_contents([path])
    rows: list[object] = []
    clock_times, clock_values = [], []
    for first in range(whole.start - width, whole.end + width, width):
        part = read_contents([path], window=RecordWindow(first, first + width))
        assert all(first <= t < first + width for b in part.parts for t in b.record_time.tolist())
        rows += rows_of(part.parts)
        clock_times.append(part.clock.record_time)
        clock_values.append(part.clock.clock)
        (info,) = part.files
        assert (info.start, info.end, info.message_count, info.topics) == (
            whole.files[0].start,
            whole.files[0].end,
            whole.files[0].message_count,
            whole.files[0].topics,
        )
        assert info.transform_count == sum(len(b) for b in part.parts)
    assert rows == rows_of(whole.parts)
    np.testing.assert_array_equal(np.concatenate(clock_times), whole.clock.record_time)
    np.testing.assert_array_equal(np.concatenate(clock_values), whole.clock.clock)
    return whole


def test_windows_make_the_whole_recording(bag: Path) -> None:
    whole = _assert_windows_make_the_whole(bag, 700_000_000)
    assert len(whole.clock) == len(CLOCK) and whole.files[0].windowed


@pytest.mark.parametrize("name", ["robot.bag", "robot_db3", "robot_mcap"])
def test_sample_bags_windowed(name: str) -> None:
    _assert_windows_make_the_whole(SAMPLES / name, 2 * NS)


@pytest.mark.parametrize("where", ["before", "after", "empty"])
def test_window_without_messages(bag: Path, where: str) -> None:
    whole = read_contents([bag])
    window = {
        "before": RecordWindow(0, whole.start),
        "after": RecordWindow(whole.end + 1, whole.end + NS),
        "empty": RecordWindow(whole.start + NS, whole.start + NS),
    }[where]
    part = read_contents([bag], window=window)
    assert part.parts == [] and len(part.clock) == 0
    assert part.files[0].message_count == whole.files[0].message_count and part.files[0].transform_count == 0


# The index skips what lies outside the window: a damaged first chunk is not met by a later window.


def _damage_first_chunk(path: Path, fmt: BagFormat, into: Path) -> tuple[Path, int]:
    """A copy (in ``into``) of the bag with its first chunk's record header overwritten (of a .db3:
    the page of its first message), and the record time of that chunk's last message."""
    if fmt is BagFormat.ros1:
        data = bytearray(path.read_bytes())
        with FileSource(path) as source:
            bag = BagFile(path.name, bytes(data), source, Wanted(("/tf",)), lambda *_: None)
            chunks = read_index(bag, read_bag_header(memoryview(data))).infos
        assert len(chunks) >= 3
        at, end = chunks[0].pos, chunks[0].end
    elif fmt is BagFormat.rosbag2_mcap:
        path = next(path.glob("*.mcap"))
        data = bytearray(path.read_bytes())
        with FileSource(path) as source:
            summary = summary_of(source)
        assert summary is not None and len(summary.chunks) >= 3
        at, end = summary.chunks[0].offset, summary.chunks[0].message_end
    else:
        path = next(path.glob("*.db3"))
        data = bytearray(path.read_bytes())
        at, end = _first_leaf_page(path), T0 + 100 * STEP
    data[at : at + 16] = b"\xff" * 16
    damaged = into / path.name
    damaged.write_bytes(data)
    return damaged, end


def _first_leaf_page(path: Path) -> int:
    """Where the page holding the first message's payload begins in a .db3."""
    with sqlite3.connect(path) as db:
        (page_size,) = db.execute("PRAGMA page_size").fetchone()
        (first,) = db.execute("SELECT data FROM messages ORDER BY timestamp LIMIT 1").fetchone()
    at = path.read_bytes().find(bytes(first))
    assert at > 0
    return int(at - at % page_size)


def test_index_skips_what_lies_outside_the_window(bag: Path, tmp_path: Path) -> None:
    damaged, first_chunk_end = _damage_first_chunk(bag, BagFormat(bag.name), tmp_path)
    assert read_contents([damaged]).problems  # read whole, the damage is met
    assert read_contents([damaged]).files[0].windowed == (
        bag.name != "rosbag2-sqlite3"
    )  # a damaged .db3: from its pages
    later = RecordWindow(first_chunk_end + 1, T0 + 15 * NS)
    part = read_contents([damaged], window=later)
    assert part.problems == [] and part.files[0].windowed
    assert rows_of(part.parts) == rows_of(read_contents([bag], window=later).parts)
    assert read_contents([damaged], window=RecordWindow(T0, T0)).problems == []


# Files without an index are read whole, and filtered to the window.


@pytest.mark.parametrize("fmt", [BagFormat.ros1, BagFormat.rosbag2_mcap], ids=lambda f: f.value)
def test_unindexed_files_read_whole(fmt: BagFormat, tmp_path_factory: pytest.TempPathFactory, tmp_path: Path) -> None:
    bag = _bag(fmt, tmp_path_factory.getbasetemp())
    source = bag if fmt is BagFormat.ros1 else next(bag.glob("*.mcap"))
    cut = tmp_path / f"cut{source.suffix}"
    data = source.read_bytes()
    cut.write_bytes(data[: len(data) * 2 // 3])  # no index: the bag's end, the MCAP summary lost
    whole = _assert_windows_make_the_whole(cut, 900_000_000)
    assert whole.problems and not whole.files[0].windowed
    assert not read_contents([cut], window=RecordWindow(T0, T0)).files[0].windowed


@pytest.mark.parametrize("storage", ["sqlite3", "mcap"])
@pytest.mark.parametrize("mode", ["file", "message"])
def test_zstd_compressed_rosbag2(tmp_path: Path, storage: str, mode: str) -> None:
    """Messages out of record order and sharing record times; a file compressed whole is read whole."""
    bag = write_rosbag2(tmp_path / "bag", varied_messages(3), storage=storage, compression=mode)
    whole = _assert_windows_make_the_whole(bag, 3 * NS // 2)
    assert whole.files[0].windowed == (mode == "message")
