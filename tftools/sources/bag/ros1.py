"""ROS1 bags (format 2.0): the transforms of the wanted topics, read through the bag's index."""

from __future__ import annotations

import mmap
from collections.abc import Iterator
from contextlib import contextmanager, suppress
from pathlib import Path

from tftools.core.batch import TransformBatch
from tftools.sources.bag.contents import BagFileInfo, ProgressCallback
from tftools.sources.bag.ros1_format import FormatError, read_bag_header
from tftools.sources.bag.ros1_scan import BagScan
from tftools.sources.errors import CorruptBagError


def read(path: Path, topics: tuple[str, ...], progress: ProgressCallback) -> tuple[list[TransformBatch], BagFileInfo]:
    """The transforms on ``topics`` and the clock of the ROS1 bag at ``path`` (see ``reader.read_bag``).

    A bag without (or with a damaged) index is read by scanning its chunks; what could not be
    read is one line each in the description's ``problems``.
    """
    with _mapped(path) as buf, path.open("rb") as file:
        try:
            header = read_bag_header(buf)
        except FormatError as e:
            raise CorruptBagError(str(path), f"no readable ROS1 bag header: {e}") from None
        if header.encryptor:
            raise CorruptBagError(
                str(path), f"encrypted with {header.encryptor}; decrypt it with `rosbag decrypt` first"
            )
        scan = BagScan(path.name, buf, topics, progress, file.fileno())
        scan.read(header)
        batches, clock, undecodable = scan.messages.decode()
    info = BagFileInfo(
        path=str(path),
        format="ros1",
        start=scan.start,
        end=scan.end,
        message_count=scan.message_count,
        topics=scan.topics,
        transform_count=sum(len(b) for b in batches),
        problems=scan.problems + undecodable,
        unread=scan.skipped,
        clock=clock,
    )
    return batches, info


@contextmanager
def _mapped(path: Path) -> Iterator[mmap.mmap]:
    """The file mapped read-only: headers and index records are read from it (chunks' data is
    read from the file)."""
    try:
        with path.open("rb") as f:
            buf = mmap.mmap(f.fileno(), 0, access=mmap.ACCESS_READ)
    except (OSError, ValueError) as e:  # ValueError: an empty file cannot be mapped
        raise CorruptBagError(str(path), getattr(e, "strerror", None) or str(e)) from None
    try:
        yield buf
    finally:
        with suppress(BufferError):  # a numpy view still alive: the map closes when it is freed
            buf.close()
