"""Sources: bags and live systems turned into transforms for a buffer.

The names load on first use (PEP 562): a light module of the package (``errors``,
``storage.locations``) costs no numpy, so that ``tfx --help`` and its subcommands' help need none."""

from __future__ import annotations

from typing import TYPE_CHECKING

from tftools import lazy

if TYPE_CHECKING:
    from tftools.sources.bag import BagContents, BagFileInfo, BagReader
    from tftools.sources.contents import DEFAULT_TOPICS, RecordingContents, SourceInfo
    from tftools.sources.errors import (
        BagError,
        BagNotFoundError,
        CorruptBagError,
        NoTransformsError,
        SourceError,
        UnknownBagFormatError,
    )
    from tftools.sources.recording import Recording, read_recording
    from tftools.sources.stream import StreamedRecording, stream_recording

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
    "StreamedRecording",
    "UnknownBagFormatError",
    "read_recording",
    "stream_recording",
]

#: Where each name is defined.
_HOME = {
    "BagContents": "tftools.sources.bag",
    "BagError": "tftools.sources.errors",
    "BagFileInfo": "tftools.sources.bag",
    "BagNotFoundError": "tftools.sources.errors",
    "BagReader": "tftools.sources.bag",
    "CorruptBagError": "tftools.sources.errors",
    "DEFAULT_TOPICS": "tftools.sources.contents",
    "NoTransformsError": "tftools.sources.errors",
    "Recording": "tftools.sources.recording",
    "RecordingContents": "tftools.sources.contents",
    "SourceError": "tftools.sources.errors",
    "SourceInfo": "tftools.sources.contents",
    "StreamedRecording": "tftools.sources.stream",
    "UnknownBagFormatError": "tftools.sources.errors",
    "read_recording": "tftools.sources.recording",
    "stream_recording": "tftools.sources.stream",
}


__getattr__, __dir__ = lazy.exports(__name__, _HOME, __all__)
