"""The one table of recording formats: each file format's first bytes, its name and the module that reads it."""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

from tftools.sources.errors import CorruptBagError, OldRos1BagError, UnknownBagFormatError, UnreadableFileError
from tftools.sources.storage import open_files
from tftools.sources.storage.locations import METADATA
from tftools.values import value

if TYPE_CHECKING:
    from tftools.sources.storage.source import ByteSource, Files


@value
class Format:
    """A file format: how its files begin, and the module of ``tftools.sources.bag`` that reads them."""

    name: str
    magic: bytes
    module: str


ROS1 = Format("ros1", b"#ROSBAG V2.0\n", "ros1")
SQLITE3 = Format("sqlite3", b"SQLite format 3\x00", "rosbag2")
MCAP = Format("mcap", b"\x89MCAP0\r\n", "mcap")
FORMATS = (ROS1, SQLITE3, MCAP)
#: How a ROS 1 bag of a format before 2.0 begins ("#ROSRECORD V1.2\n"): recognised to be said so, not read.
OLD_ROS1_MAGIC = b"#ROSRECORD V"
#: A ROS 2 bag directory: read by the rosbag2 module, whatever its storage.
ROSBAG2_DIRECTORY = Format("rosbag2", b"", "rosbag2")
#: The first bytes of a zstd frame: a message (or file) rosbag2 compressed.
ZSTD_MAGIC = b"\x28\xb5\x2f\xfd"
#: A rosbag2 file compressed whole (``--compression-mode file``), given without its folder: read as its folder's.
ZSTD_FILE_SUFFIXES = (".db3.zstd", ".mcap.zstd")
#: What to do about a recording of 0 bytes: nothing in it can be read, whatever its format.
EMPTY_HINT = "its recorder wrote nothing (killed at once?) or its copy failed: re-copy it"
#: Bytes read to recognise a file.
HEAD_BYTES = max(len(f.magic) for f in FORMATS)


def format_of_head(head: bytes) -> Format | None:
    """The format of a file beginning with ``head``; None when no format's does."""
    return next((f for f in FORMATS if head.startswith(f.magic)), None)


def sniff(files: Files) -> tuple[Format, ByteSource | None]:
    """The format of the recording at ``files``' root (local or remote): a ROS 2 bag directory, or a
    file by its first bytes, then returned open (its ``ByteSource``, the caller's to close); a rosbag2 file
    compressed whole is read as its directory is (no source: it is decompressed first)."""
    root = files.root
    if files.is_dir(root):
        if not any(p.name == METADATA or p.suffix in (".db3", ".mcap") for p in files.listing(root)):
            raise UnknownBagFormatError(str(root), "a directory without metadata.yaml, .db3 or .mcap files")
        return ROSBAG2_DIRECTORY, None
    try:
        source = files.open(root)
    except UnreadableFileError:  # a recording, maybe, that tfx may not read: said so, not that it is none
        raise
    except CorruptBagError as e:  # not a file that can be read (a FIFO, say): not a recording
        raise UnknownBagFormatError(e.path, e.detail) from None
    try:
        head = source.read(0, HEAD_BYTES)
        if not head:
            raise CorruptBagError(str(root), "an empty file: 0 bytes", EMPTY_HINT)
        found = format_of_head(head)
        if found is None and head.startswith(ZSTD_MAGIC) and root.name.endswith(ZSTD_FILE_SUFFIXES):
            source.close()
            return ROSBAG2_DIRECTORY, None
        if found is None and head.startswith(OLD_ROS1_MAGIC):
            version = head[len(OLD_ROS1_MAGIC) :].split(b"\n")[0].decode("ascii", "replace")
            raise OldRos1BagError(str(root), version)
        if found is None:
            raise UnknownBagFormatError(str(root), "unrecognised file header")
    except BaseException:
        source.close()
        raise
    return found, source


def format_of(path: str | os.PathLike[str]) -> Format:
    """The format of the recording at ``path`` (``sniff``): ``BagNotFoundError`` when there is none,
    ``UnknownBagFormatError`` when it is not a recording."""
    with open_files(path) as files:
        found, source = sniff(files)
        if source is not None:
            source.close()
        return found
