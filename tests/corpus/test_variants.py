"""Issue 39: "the same holds on recordings of the same kinds that are not in the corpus". A user's recording differs
from the corpus's mostly in how it was written: every corpus recording is written again as other recorders and
tools write the same messages (``variants``: bz2 / lz4 / small chunks, ties of record time interleaved otherwise,
a ROS 1 bag as MCAP with the ros1 profile; a rosbag2 folder in the other storage, compressed by message, split in
several files; MCAP unchunked, lz4, without summary or index) and ``tfx wtf`` must find the same in it: the same
(code, severity, frames) said in the same words and figures, the same transforms and frames counted.

Where a variant holds other bytes the answer may differ, and is left out here with the reason (``JUSTIFIED``)."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.corpus import variants
from tests.corpus.fetch import Recording
from tests.corpus.recordings import RECORDINGS, Corpus
from tftools import CheckQuery, check

Found = tuple[int, int, set[tuple[str, str, tuple[str, ...], str]]]

#: Recordings rosbags' readers cannot read whole (their damage is what they are in the corpus for): no variant of
#: them can be written from what a reader gives.
UNREADABLE = {
    "ros2-neato-gazebo-person-follower-renamed-db3-2023",  # a bare .db3 whose metadata.yaml names another file
    "ros2-turtlebot3-gazebo-no-metadata-wal-2023-db3",  # no metadata.yaml: rosbags needs one
}
#: (recording id, variant) whose findings differ for a reason in the bytes.
JUSTIFIED: dict[tuple[str, str], str] = {}


def _found(path: Path) -> Found:
    query = CheckQuery()
    report = check(query.reading().read([str(path)]), query)
    said = {(f.code, f.severity.value, f.frames, f.message.replace(str(path), "<recording>")) for f in report.findings}
    return report.transforms, report.frames, said


def _variants(path: Path) -> dict[str, variants.Variant]:
    if path.is_dir():
        return variants.ROS2_VARIANTS
    return variants.MCAP_VARIANTS if path.suffix == ".mcap" else variants.ROS1_VARIANTS


def _readable(recording: Recording) -> bool:
    return recording.id not in UNREADABLE and recording.meta.get("format") in ("ros1", "db3", "mcap")


@pytest.mark.slow
@pytest.mark.parametrize("recording", [r for r in RECORDINGS if _readable(r)], ids=lambda r: r.id)
def test_written_otherwise_found_alike(corpus: Corpus, recording: Recording, tmp_path: Path) -> None:
    path = corpus(recording)
    original = _found(path)
    try:
        for name, variant in _variants(path).items():
            if (recording.id, name) in JUSTIFIED:
                continue
            folder = tmp_path / name.replace(" ", "_")
            folder.mkdir()
            assert _found(variant(path, folder)) == original, f"{recording.id} as {name}"
    finally:
        variants.read.cache_clear()  # one recording's messages held at a time
