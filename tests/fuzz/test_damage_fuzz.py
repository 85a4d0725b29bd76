"""Seeded damage to copies of real recordings, many places each: what is damaged is said, and where the readers
place the lost stretch (``SourceInfo.damaged``) no transform was read and every transform missing lies."""

from __future__ import annotations

import random
import sqlite3
import struct
from contextlib import closing
from pathlib import Path
from typing import Any

import pytest
from mcap.writer import CompressionType

from tests.corpus.variants import rewrite_mcap
from tests.sources.bag.damaged import TOPICS, copied, cut, overwritten, zeroed_pages
from tests.sources.bag.reading import read_contents
from tests.sources.ros2_helpers import batch_rows
from tftools.core.errors import TfToolsError
from tftools.sources.bag.mcap.index import summary_of
from tftools.sources.storage.source import FileSource

UWB = "uwb-slam-Record_2017-11-17-12-31-28.bag"  # ROS 1, 27 lz4 chunks


def _read(path: Path) -> tuple[list[tuple[Any, ...]], list[str], list[tuple[int, int]]]:
    contents = read_contents([path], TOPICS)
    return batch_rows(contents.transforms), contents.problems, [s for f in contents.files for s in f.damaged]


@pytest.mark.slow
def test_every_flipped_byte_of_a_real_uncompressed_chunk_stating_a_crc_is_said(tmp_path: Path) -> None:
    """The CougUV AUV's .mcap written again with a CRC on its uncompressed chunk, one byte flipped at each of 40
    seeded places of the chunk's records (other topics' messages, /tf's, record heads): every read says the chunk
    is damaged (before: the flips in bytes its ranges do not read, and in /tf's values, passed silently)."""
    original = copied("ros2_mcap_coug_auv_replayed", tmp_path)
    (part,) = original.glob("*.mcap")
    crc = rewrite_mcap(part, tmp_path / "crc.mcap", compression=CompressionType.NONE)
    with closing(FileSource(crc)) as source:
        summary = summary_of(source)
    assert summary is not None
    (chunk,) = summary.chunks
    data = crc.read_bytes()
    assert struct.unpack_from("<I", data, chunk.offset + 9 + 24) != (0,)
    whole, problems, _ = _read(crc)
    assert problems == []
    rng = random.Random(44)
    flipped = tmp_path / "flipped.mcap"
    for _ in range(40):
        at = rng.randrange(chunk.records_start, chunk.records_start + chunk.records_length)
        damaged = bytearray(data)
        damaged[at] ^= 1 << rng.randrange(8)
        flipped.write_bytes(bytes(damaged))
        try:
            got, problems, _ = _read(flipped)
        except TfToolsError:
            continue  # nothing of it could be read: said in one line
        assert problems and any("damaged" in p for p in problems), at
        assert len(set(got) - set(whole)) <= 1, at


@pytest.mark.slow
@pytest.mark.parametrize("kept", [1.0, 0.97], ids=["indexed", "unindexed"])
def test_where_a_real_ros1_bag_lost_its_transforms_none_was_read(tmp_path: Path, kept: float) -> None:
    """The Robotino's lz4 bag, 16 bytes overwritten at each of 12 seeded places (from 10% to 90% of it), read
    through its index and cut before it: no transform read lies inside a damaged span, and where a part could not
    be read, a span says where (before, without the index: none)."""
    original = copied(UWB, tmp_path)
    _, _, spans = _read(original)
    assert spans == []
    rng = random.Random(44)
    damaged = tmp_path / "damaged.bag"
    for _ in range(12):
        damaged.write_bytes(original.read_bytes())
        overwritten(damaged, rng.uniform(0.1, 0.9), seed=rng.randrange(1 << 30))
        cut(damaged, int(damaged.stat().st_size * kept))
        got, problems, spans = _read(damaged)
        times = [int(row[6]) for row in got]
        assert not any(a < t < b for a, b in spans for t in times), spans
        if any("could not be read" in p for p in problems):  # transforms lost, mid-file: their stretch is said
            assert spans, problems


@pytest.mark.slow
def test_every_transform_a_real_db3_lost_with_its_pages_lies_in_a_damaged_span(tmp_path: Path) -> None:
    """The TurtleBot3 walker's .db3, 64 KiB of its pages zeroed at each of 8 seeded places (from 5% to 95%): the
    transforms read are the intact file's outside the damaged spans, less only those before the first message
    read or after the last (nothing marks those), and none inside a span."""
    bag = copied("ros2_db3_tb3_gazebo_walker", tmp_path)
    (db3,) = bag.glob("*.db3")
    intact_bytes = db3.read_bytes()
    with closing(sqlite3.connect(db3)) as db:
        (tf_ids,) = zip(*db.execute("SELECT id FROM topics WHERE name IN ('/tf', '/tf_static')"), strict=True)
        intact = [t for (t,) in db.execute(f"SELECT timestamp FROM messages WHERE topic_id IN {tuple(tf_ids)}")]
    rng = random.Random(44)
    for _ in range(8):
        db3.write_bytes(intact_bytes)
        zeroed_pages(db3, rng.uniform(0.05, 0.95))
        try:
            got, _, spans = _read(bag)
        except TfToolsError:
            continue
        times = {int(row[6]) for row in got}
        assert not any(a < t < b for a, b in spans for t in times), spans
        first, last = min(times), max(times)
        missing = {t for t in intact if t not in times and first < t < last}
        assert all(any(a < t < b for a, b in spans) for t in missing), (sorted(missing)[:5], spans)
