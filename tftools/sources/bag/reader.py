"""``read_bag``: recognise each path's format, read its transforms, merge in record order."""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from pathlib import Path

from tftools.core.batch import TransformBatch
from tftools.sources.bag.contents import BagContents, BagFileInfo, ProgressCallback, in_record_order, merged_clock
from tftools.sources.contents import DEFAULT_TOPICS
from tftools.sources.errors import BagNotFoundError, UnknownBagFormatError

#: A format reader: (path, topics, progress over this file's bytes) -> batches and description.
FormatReader = Callable[[Path, tuple[str, ...], ProgressCallback], tuple[list[TransformBatch], BagFileInfo]]

_ROS1_MAGIC = b"#ROSBAG V2.0\n"
_SQLITE_MAGIC = b"SQLite format 3\x00"
_MCAP_MAGIC = b"\x89MCAP0\r\n"


def read_bag(
    paths: Sequence[str | os.PathLike[str]],
    topics: Sequence[str] | None = None,
    progress: ProgressCallback | None = None,
) -> BagContents:
    """Every transform on ``topics`` (default ``/tf`` and ``/tf_static``) of the bags at ``paths``,
    and their recorded clock (a rosgraph_msgs/Clock topic, whatever ``topics`` are).

    Several paths are one recording (a split bag): their rows are merged by record time.
    Raises ``BagError`` for a path that cannot be read at all; a damaged file is read as far
    as it goes, and what was lost is listed in its ``BagFileInfo.problems``.
    """
    chosen = tuple(topics) if topics else DEFAULT_TOPICS
    files = [Path(p) for p in paths]
    readers = [(path, _format_reader(path)) for path in files]
    sizes = [_size(path) for path in files]
    total = sum(sizes)
    batches: list[TransformBatch] = []
    infos: list[BagFileInfo] = []
    done = 0
    for (path, reader), size in zip(readers, sizes, strict=True):
        offset = done

        def file_progress(read: int, _of: int, offset: int = offset) -> None:
            if progress is not None:
                progress(offset + read, total)

        file_batches, info = reader(path, chosen, file_progress)
        batches.extend(file_batches)
        infos.append(info)
        done += size
        if progress is not None:
            progress(done, total)
    return BagContents(in_record_order(batches), infos, chosen, merged_clock([f.clock for f in infos]))


def _format_reader(path: Path) -> FormatReader:
    # Each format's module is imported only when a file needs it: a ROS1 user pays for no
    # sqlite or MCAP code.
    if not path.exists():
        raise BagNotFoundError(str(path))
    if path.is_dir():
        if (path / "metadata.yaml").exists() or any(path.glob("*.db3")) or any(path.glob("*.mcap")):
            from tftools.sources.bag import rosbag2

            return rosbag2.read
        raise UnknownBagFormatError(str(path), "a directory without metadata.yaml, .db3 or .mcap files")
    try:
        with path.open("rb") as f:
            head = f.read(16)
    except OSError as e:
        raise UnknownBagFormatError(str(path), e.strerror or str(e)) from None
    if head.startswith(_ROS1_MAGIC):
        from tftools.sources.bag import ros1

        return ros1.read
    if head.startswith(_SQLITE_MAGIC):
        from tftools.sources.bag import rosbag2

        return rosbag2.read
    if head.startswith(_MCAP_MAGIC):
        from tftools.sources.bag import mcap

        return mcap.read
    raise UnknownBagFormatError(str(path), "unrecognised file header")


def _size(path: Path) -> int:
    if path.is_dir():
        return sum(p.stat().st_size for p in path.iterdir() if p.is_file())
    return path.stat().st_size
