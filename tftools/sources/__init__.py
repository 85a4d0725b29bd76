"""Sources: bags and live systems turned into transforms for a buffer."""

from tftools.sources.bag import BagContents, BagFileInfo, BagReader, read_bag
from tftools.sources.contents import DEFAULT_TOPICS, RecordingContents, SourceInfo
from tftools.sources.errors import (
    BagError,
    BagNotFoundError,
    CorruptBagError,
    NoTransformsError,
    SourceError,
    UnknownBagFormatError,
)
from tftools.sources.recording import Recording, load, read_recording

__all__ = [
    "DEFAULT_TOPICS",
    "BagContents",
    "BagError",
    "BagFileInfo",
    "BagNotFoundError",
    "BagReader",
    "CorruptBagError",
    "NoTransformsError",
    "Recording",
    "RecordingContents",
    "SourceError",
    "SourceInfo",
    "UnknownBagFormatError",
    "load",
    "read_bag",
    "read_recording",
]
