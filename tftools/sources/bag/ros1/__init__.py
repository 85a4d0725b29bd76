"""ROS1 bags (format 2.0): the transforms of the wanted topics, read through the bag's index
(``index``) or, without one, chunk after chunk (``salvage``)."""

from __future__ import annotations

from pathlib import Path
from typing import Literal

from tftools.core.arrays import Int64Array
from tftools.sources.bag.contents import ProgressCallback, RecordWindow
from tftools.sources.bag.damage import DamageError
from tftools.sources.bag.ros1.file import BagFile
from tftools.sources.bag.ros1.index import BagIndex, read_index, read_indexed, replay_order
from tftools.sources.bag.ros1.records import read_bag_header
from tftools.sources.bag.ros1.salvage import read_unindexed
from tftools.sources.bag.scan import FileRead, file_result
from tftools.sources.codecs.select import Wanted
from tftools.sources.errors import CorruptBagError
from tftools.sources.storage.source import ByteSource


class Ros1File:
    """A ROS1 bag open for reading, its header and index read once: read whole, or window after
    window; its chunks scanned when its index is missing or damaged."""

    def __init__(self, path: Path, source: ByteSource) -> None:
        self.path = path
        self.source = source
        # Headers and index records are read from the source's buffer (a local file's map), chunks'
        # data from the source.
        self.buf = source.buffer()
        try:
            self.header = read_bag_header(self.buf)
        except DamageError as e:
            self.close()
            raise CorruptBagError(str(path), f"no readable ROS1 bag header: {e}") from None
        if self.header.encryptor:
            self.close()
            raise CorruptBagError(
                str(path), f"encrypted with {self.header.encryptor}; decrypt it with `rosbag decrypt` first"
            )
        self._index: BagIndex | str | None = None  # once read: the index, or what is wrong with it
        #: Once the index is read: the order rosbag play replays ties of record time in (``replay_order``),
        #: False where that is record time order.
        self._replayed: tuple[Int64Array, Int64Array] | Literal[False] | None = None

    def read(self, wanted: Wanted, progress: ProgressCallback, window: RecordWindow | None = None) -> FileRead:
        """The bag's transforms (see ``reader.BagReader.read``)."""
        header = self.header
        bag = BagFile(self.path.name, self.buf, self.source, wanted, progress, window)
        if 0 < header.index_pos <= bag.size:
            if self._index is None:
                try:
                    self._index = read_index(bag, header)
                except DamageError as e:
                    self._index = str(e)
            if isinstance(self._index, str):
                read_unindexed(bag, header, self._index)
            else:
                if wanted.headers is not None:  # sensor data read with the tf: a MessageFilter's replay
                    if self._replayed is None:
                        for connection in self._index.connections:
                            bag.connect(connection)
                        self._replayed = replay_order(bag, self._index.infos, header.index_pos) or False
                    bag.scan.messages.replayed = self._replayed or None
                read_indexed(bag, self._index, header.index_pos)
        else:
            read_unindexed(bag, header)
        bag.note_damage()
        return file_result(self.path, "ros1", [bag.scan])

    def close(self) -> None:
        self.source.close()
