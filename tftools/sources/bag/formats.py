"""The one table of recording formats: each file format's first bytes, its name and the module that reads it."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from tftools.sources.errors import BagNotFoundError, UnknownBagFormatError
from tftools.sources.storage.locations import is_bag_directory


@dataclass(frozen=True)
class Format:
    """A file format: how its files begin, and the module of ``tftools.sources.bag`` that reads them."""

    name: str
    magic: bytes
    module: str


ROS1 = Format("ros1", b"#ROSBAG V2.0\n", "ros1")
SQLITE3 = Format("sqlite3", b"SQLite format 3\x00", "rosbag2")
MCAP = Format("mcap", b"\x89MCAP0\r\n", "mcap")
FORMATS = (ROS1, SQLITE3, MCAP)
#: A ROS 2 bag directory: read by the rosbag2 module, whatever its storage.
ROSBAG2_DIRECTORY = Format("rosbag2", b"", "rosbag2")
#: The first bytes of a zstd frame: a message (or file) rosbag2 compressed.
ZSTD_MAGIC = b"\x28\xb5\x2f\xfd"
#: Bytes read to recognise a file.
HEAD_BYTES = max(len(f.magic) for f in FORMATS)


def format_of_head(head: bytes) -> Format | None:
    """The format of a file beginning with ``head``; None when no format's does."""
    return next((f for f in FORMATS if head.startswith(f.magic)), None)


def is_format(path: Path, fmt: Format) -> bool:
    """Whether the file at ``path`` begins as ``fmt``'s files do (False when it cannot be read)."""
    try:
        with path.open("rb") as f:
            return f.read(len(fmt.magic)) == fmt.magic
    except OSError:
        return False


def format_of(path: Path) -> Format:
    """The format of the recording at ``path``: a ROS 2 bag directory, or a file by its first bytes."""
    if not path.exists():
        raise BagNotFoundError(str(path))
    if path.is_dir():
        if is_bag_directory(path):
            return ROSBAG2_DIRECTORY
        raise UnknownBagFormatError(str(path), "a directory without metadata.yaml, .db3 or .mcap files")
    if not path.is_file():  # a FIFO or a device: opening it may wait forever
        raise UnknownBagFormatError(str(path), "not a regular file (a FIFO, socket or device)")
    try:
        with path.open("rb") as f:
            head = f.read(HEAD_BYTES)
    except OSError as e:
        raise UnknownBagFormatError(str(path), e.strerror or str(e)) from None
    found = format_of_head(head)
    if found is None:
        raise UnknownBagFormatError(str(path), "unrecognised file header")
    return found
