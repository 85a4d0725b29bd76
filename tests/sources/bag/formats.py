"""One file read by one format's reader directly (not recognised by its magic first), as tests need."""

from __future__ import annotations

from contextlib import closing
from pathlib import Path

from tftools.core.batch import TransformBatch
from tftools.sources.bag.contents import BagFileInfo, RecordWindow
from tftools.sources.bag.mcap import McapFile
from tftools.sources.bag.ros1 import Ros1File
from tftools.sources.bag.rosbag2 import Rosbag2Bag
from tftools.sources.codecs.select import Wanted
from tftools.sources.storage.source import FileSource, LocalFiles


def read_as(
    kind: str, path: Path, topics: tuple[str, ...], window: RecordWindow | None = None
) -> tuple[list[TransformBatch], BagFileInfo]:
    """The file or ROS 2 bag at ``path`` read by the ``kind`` ("ros1", "mcap", "rosbag2") reader: its
    transforms and its description."""
    wanted = Wanted(topics)
    if kind == "rosbag2":
        with closing(Rosbag2Bag(path, LocalFiles(path))) as bag:
            read = bag.read(wanted, lambda *_: None, window)
            return read.batches, read.info
    source = FileSource(path)
    try:
        opened = McapFile(path, source) if kind == "mcap" else Ros1File(path, source)
    except BaseException:
        source.close()
        raise
    with closing(opened):
        read = opened.read(wanted, lambda *_: None, window)
        return read.batches, read.info
