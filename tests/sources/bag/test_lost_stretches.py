"""Where a damaged copy of a real recording lost its messages (``SourceInfo.damaged``), in the readers that have no
index to say it: a ROS 1 bag read without its index, an MCAP file without its summary, a .db3 read from its pages.
Each stretch runs from the last message read before the damage to the first read after it."""

from __future__ import annotations

import sqlite3
import tracemalloc
from contextlib import closing
from pathlib import Path

from mcap.writer import CompressionType

from tests.corpus.variants import rewrite_mcap
from tests.sources.bag.damaged import TOPICS, copied, cut, zeroed_pages
from tests.sources.bag.damaged import overwritten as _overwritten
from tests.sources.bag.reading import read_contents
from tests.sources.ros2_helpers import batch_rows
from tftools.sources.bag.rosbag2.db3_salvage import salvage
from tftools.sources.storage.source import FileSource

UWB = "uwb-slam-Record_2017-11-17-12-31-28.bag"  # ROS 1, 27 lz4 chunks


def _damaged(path: Path) -> tuple[list[tuple[int, int]], list[int]]:
    """The damaged spans the reader gives, and the record times of the transforms it read."""
    contents = read_contents([path], TOPICS)
    (source,) = contents.files
    return source.damaged, [int(row[6]) for row in batch_rows(contents.transforms)]


def _holds_none_of(span: tuple[int, int], times: list[int]) -> bool:
    return not any(span[0] < t < span[1] for t in times)


def test_a_real_ros1_bag_read_without_its_index_says_where_its_damaged_chunk_lost_messages(tmp_path: Path) -> None:
    """The Robotino's bag, 16 bytes overwritten inside an lz4 chunk, then cut before its index: read chunk after
    chunk, its damaged span (before: none) is the 2.0 s between the last transform read before the damage and the
    first after it, the stretch the indexed read of the same damage puts the lost messages in."""
    indexed = copied(UWB, tmp_path)
    _overwritten(indexed, 0.45)
    (by_index,), _ = _damaged(indexed)
    unindexed = tmp_path / "unindexed.bag"
    unindexed.write_bytes(indexed.read_bytes())
    cut(unindexed, int(unindexed.stat().st_size * 0.97))
    (span,), times = _damaged(unindexed)
    assert 1.9e9 < span[1] - span[0] < 2.2e9 and _holds_none_of(span, times)
    assert span[0] <= by_index[0] + 10**8 and by_index[1] <= span[1] + 10**8  # the same stretch, to 0.1 s


def test_a_real_mcap_read_without_its_summary_says_where_its_damaged_chunk_lost_messages(tmp_path: Path) -> None:
    """The Nav2 TurtleBot 4 in lz4 chunks, 16 bytes overwritten at 45% and cut before its summary: read record by
    record, its damaged span (before: none) is the 20.8 s its damaged chunk lost, as read through the summary."""
    lz4 = rewrite_mcap(
        copied("ros2_mcap_nav2_turtlebot4.mcap", tmp_path), tmp_path / "lz4.mcap", compression=CompressionType.LZ4
    )
    _overwritten(lz4, 0.45)
    (by_summary,), _ = _damaged(lz4)
    streamed = tmp_path / "streamed.mcap"
    streamed.write_bytes(lz4.read_bytes())
    cut(streamed, int(streamed.stat().st_size * 0.97))
    (span,), times = _damaged(streamed)
    assert 20e9 < span[1] - span[0] < 21e9 and _holds_none_of(span, times)
    assert (
        span[0] <= by_summary[0]
        and by_summary[1] <= span[1]
        and span[1] - span[0] < by_summary[1] - by_summary[0] + 1e8
    )


def test_a_real_db3_read_from_its_pages_says_where_its_lost_pages_held_messages(tmp_path: Path) -> None:
    """The TurtleBot3 walker's .db3 with 64 KiB of its pages zeroed at 45%: sqlite gives up, its pages are read,
    and the stretch of the messages whose pages were lost is its damaged span (before: none): every /tf message of
    the intact file recorded inside it is lost, none outside it."""
    bag = copied("ros2_db3_tb3_gazebo_walker", tmp_path)
    (db3,) = bag.glob("*.db3")
    with closing(sqlite3.connect(db3)) as db:
        intact = [t for (t,) in db.execute("SELECT timestamp FROM messages WHERE topic_id IN (2, 8)")]
    zeroed_pages(db3, 0.45)
    (span,), times = _damaged(bag)
    inside = [t for t in intact if span[0] < t < span[1]]
    assert inside and _holds_none_of(span, times)
    assert set(times) == {t for t in intact if not span[0] < t < span[1]}


def test_a_real_db3_cut_short_holds_its_salvaged_rows_in_arrays_not_an_object_each(tmp_path: Path) -> None:
    """The TurtleBot3 walker's .db3 cut at 60% and read from its pages (739 transforms of its 5118 messages): a
    Python tuple, payload and dict entry per message took 750 kB at the salvage's peak, the payloads' 111 kB and 125
    bytes a message; flat arrays and one buffer take 434 kB (63 bytes a message beside the payloads)."""
    bag = copied("ros2_db3_tb3_gazebo_walker", tmp_path)
    (db3,) = bag.glob("*.db3")
    cut(db3, db3.stat().st_size * 6 // 10)
    with closing(FileSource(db3)) as source:
        data = source.mapped()
        tracemalloc.start()
        try:
            found = salvage(data, {2, 8})
            _, peak = tracemalloc.get_traced_memory()
        finally:
            tracemalloc.stop()
        payloads = sum(len(payload) for _, _, payload in found.rows)
    assert found.count > 1000 and payloads > 0
    assert peak < payloads + 80 * found.count, (peak, payloads, found.count)
