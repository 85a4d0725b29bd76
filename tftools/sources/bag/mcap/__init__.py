"""MCAP files: the transforms of their tf and foxglove channels, through the summary's index
(``index``) or record by record (``stream``)."""

from __future__ import annotations

from pathlib import Path

from tftools.sources.bag.contents import ProgressCallback, RecordWindow
from tftools.sources.bag.damage import DamageError
from tftools.sources.bag.formats import MCAP
from tftools.sources.bag.mcap.index import Summary, read_indexed, summary_of
from tftools.sources.bag.mcap.records import Channels, profile_of
from tftools.sources.bag.mcap.stream import stream
from tftools.sources.bag.messages import MessageSet
from tftools.sources.bag.scan import FileRead, FileScan, file_result, qos_in_files
from tftools.sources.codecs.select import Wanted
from tftools.sources.contents import IN_MCAP
from tftools.sources.errors import CorruptBagError
from tftools.sources.storage.source import ByteSource

#: ``SourceInfo.format`` of an MCAP file of the ros1 profile (``mcap convert`` of a ROS 1 bag, a ROS 1
#: recorder writing MCAP): ROS 1 data, read with ROS 1's tf2 and its channels' callerids as publishers.
ROS1_MCAP = "ros1-mcap"


class McapFile:
    """An MCAP file open for reading, its summary read once: read whole, or window after window."""

    def __init__(self, path: Path, source: ByteSource) -> None:
        self.path = path
        self.source = source
        try:
            if source.read(0, len(MCAP.magic)) != MCAP.magic:
                raise CorruptBagError(str(path), "no MCAP magic at the start")
            self.summary: Summary | None = summary_of(source)
            self.profile = profile_of(source)
        except OSError as e:
            raise CorruptBagError(str(path), e.strerror or str(e)) from None

    def read(self, wanted: Wanted, progress: ProgressCallback, window: RecordWindow | None = None) -> FileRead:
        """The transforms of a bare ``.mcap`` file (see ``reader.BagReader.read``)."""
        fmt = ROS1_MCAP if self.profile == "ros1" else "mcap"
        scan = self.scan(wanted, progress, MessageSet(window=window))
        read = file_result(self.path, fmt, [scan])
        if self.profile == "ros2":  # a rosbag2 file given alone: ros2 bag play plays it with its channels' QoS
            read.qos = qos_in_files([scan], IN_MCAP)
        return read

    def scan(self, wanted: Wanted, progress: ProgressCallback, messages: MessageSet) -> FileScan:
        """The file's messages (into ``messages``) and description; ``CorruptBagError`` when nothing could be read."""
        result = FileScan(messages)
        try:
            channels = Channels(wanted, result, self.source.size)
            if not read_indexed(self.source, self.summary, channels, progress):
                stream(self.source, channels, progress)
        except OSError as e:
            raise CorruptBagError(str(self.path), e.strerror or str(e)) from None
        except DamageError as e:
            raise CorruptBagError(str(self.path), str(e)) from None
        return result

    def close(self) -> None:
        self.source.close()
