"""ROS1 bags (format 2.0): the transforms of the wanted topics, read through the bag's index
(``index``) or, without one, chunk after chunk (``salvage``)."""

from __future__ import annotations

import mmap
from collections.abc import Iterator
from contextlib import contextmanager, suppress
from pathlib import Path

from tftools.core.batch import TransformBatch
from tftools.sources.bag.contents import BagFileInfo, ProgressCallback, RecordWindow
from tftools.sources.bag.ros1.file import BagFile
from tftools.sources.bag.ros1.index import read_index, read_indexed
from tftools.sources.bag.ros1.records import FormatError, read_bag_header
from tftools.sources.bag.ros1.salvage import read_unindexed
from tftools.sources.bag.scan import file_result
from tftools.sources.errors import CorruptBagError


def read(
    path: Path, topics: tuple[str, ...], progress: ProgressCallback, window: RecordWindow | None = None
) -> tuple[list[TransformBatch], BagFileInfo]:
    """The ROS1 bag at ``path`` (see ``reader.read_bag``); its chunks scanned when its index is missing or damaged."""
    with _mapped(path) as buf, path.open("rb") as file:
        try:
            header = read_bag_header(buf)
        except FormatError as e:
            raise CorruptBagError(str(path), f"no readable ROS1 bag header: {e}") from None
        if header.encryptor:
            raise CorruptBagError(
                str(path), f"encrypted with {header.encryptor}; decrypt it with `rosbag decrypt` first"
            )
        bag = BagFile(path.name, buf, file.fileno(), topics, progress, window)
        if 0 < header.index_pos <= bag.size:
            try:
                infos = read_index(bag, header)
            except FormatError as e:
                read_unindexed(bag, header, str(e))
            else:
                read_indexed(bag, infos, header.index_pos)
        else:
            read_unindexed(bag, header)
        bag.note_damage()
    return file_result(path, "ros1", [bag.scan])


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
