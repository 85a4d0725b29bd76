"""MCAP files: the transforms of their tf and foxglove channels, through the summary's index
(``index``) or record by record (``stream``)."""

from __future__ import annotations

from pathlib import Path

from tftools.core.batch import TransformBatch
from tftools.sources.bag.contents import BagFileInfo, ProgressCallback, RecordWindow
from tftools.sources.bag.mcap.index import read_indexed
from tftools.sources.bag.mcap.records import MAGIC, Channels
from tftools.sources.bag.mcap.stream import UnreadableError, stream
from tftools.sources.bag.messages import MessageSet
from tftools.sources.bag.scan import FileScan, file_result
from tftools.sources.errors import CorruptBagError


def read(
    path: Path, topics: tuple[str, ...], progress: ProgressCallback, window: RecordWindow | None = None
) -> tuple[list[TransformBatch], BagFileInfo]:
    """The transforms of a bare ``.mcap`` file (see ``reader.read_bag``)."""
    return file_result(path, "mcap", [scan(path, topics, progress, MessageSet(window=window))])


def scan(path: Path, topics: tuple[str, ...], progress: ProgressCallback, messages: MessageSet) -> FileScan:
    """One MCAP file's messages (into ``messages``) and description; ``CorruptBagError`` when nothing could be read."""
    result = FileScan(messages)
    try:
        with path.open("rb") as f:
            size = path.stat().st_size
            if f.read(len(MAGIC)) != MAGIC:
                raise CorruptBagError(str(path), "no MCAP magic at the start")
            channels = Channels(topics, result, size)
            if not read_indexed(f, size, channels, progress):
                stream(f, size, channels, progress)
    except OSError as e:
        raise CorruptBagError(str(path), e.strerror or str(e)) from None
    except UnreadableError as e:
        raise CorruptBagError(str(path), str(e)) from None
    return result
