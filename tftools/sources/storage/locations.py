"""Recording locations: a local path or a URL (``s3://``, ``gs://``, ``az://``, ``http(s)://``, any
fsspec protocol), and the recordings a glob or a prefix ending in ``/`` stands for."""

from __future__ import annotations

import glob
import os
import re
from collections.abc import Iterable
from pathlib import Path, PurePosixPath

from tftools.sources.errors import BagError, BagNotFoundError

#: Files that are recordings (a ROS 2 bag directory, with its metadata.yaml, is one too).
BAG_SUFFIXES = (".bag", ".mcap", ".db3")
METADATA = "metadata.yaml"
#: What a rosbag2 directory holds: its metadata and storage files (compressed or not, sqlite's journals).
BAG_DIRECTORY_SUFFIXES = frozenset({".yaml", ".db3", ".mcap", ".zstd", ".db3-shm", ".db3-wal", ".db3-journal"})
GLOB_CHARACTERS = frozenset("*?[")
#: Files a folder may hold below it to be searched for recordings (``tfx wtf /`` would walk the disk).
MAX_FILES_BELOW = 200_000

_URL = re.compile(r"^[A-Za-z][A-Za-z0-9+.-]*://")


def is_url(location: str | os.PathLike[str]) -> bool:
    """Whether ``location`` names a remote recording (``scheme://...``), not a local path."""
    return bool(_URL.match(os.fspath(location)))


def is_glob(location: str) -> bool:
    return any(c in GLOB_CHARACTERS for c in location)


def expand_local(argument: str) -> list[str]:
    """A local argument's recordings (see ``storage.expand``)."""
    if is_glob(argument) and not os.path.lexists(argument):  # quoted, so the shell left it
        matches = sorted(glob.glob(argument, recursive=True))
        if not matches:
            raise BagNotFoundError(argument)
        return [recording for match in matches for recording in _below_local(match, listed_only=False)]
    if argument.endswith(("/", os.sep)) and os.path.isdir(argument):
        return _below_local(argument, listed_only=True)
    return [argument]


def recordings_in(files: Iterable[str]) -> list[str]:
    """The recordings among ``files`` ('/'-separated paths below a prefix): each ROS 2 bag directory
    (a folder with a metadata.yaml) once, and each bag file outside one; sorted."""
    names = [PurePosixPath(f) for f in files]
    bag_directories = {name.parent for name in names if name.name == METADATA}
    found = {str(d) if str(d) != "." else "" for d in bag_directories}
    for name in names:
        if name.suffix in BAG_SUFFIXES and not bag_directories.intersection(name.parents):
            found.add(str(name))
    return sorted(found)


def _below_local(path: str, *, listed_only: bool) -> list[str]:
    """The recordings at or below ``path``: itself when it is a file or a ROS 2 bag directory."""
    directory = Path(path)
    if not directory.is_dir() or is_bag_directory(directory):
        return [path]
    files: list[str] = []
    for root, _, names in os.walk(directory):
        files += (str(PurePosixPath(os.path.relpath(os.path.join(root, name), directory))) for name in names)
        if len(files) > MAX_FILES_BELOW:
            raise BagError(
                path,
                f"holds more than {MAX_FILES_BELOW:,} files below it: not searched for recordings",
                "name the recordings, or a folder closer to them",
            )
    found = [str(directory / name) for name in recordings_in(files)]
    if not found and listed_only:
        raise BagNotFoundError(path)
    return found


def names_a_recording(word: str) -> bool:
    """Whether a command-line word is a recording: a bag file by its suffix, or a folder with a metadata.yaml."""
    return not word.startswith("-") and (word.endswith(BAG_SUFFIXES) or os.path.isfile(os.path.join(word, METADATA)))


def is_bag_directory(directory: Path) -> bool:
    """A ROS 2 bag as the readers take one: a metadata.yaml, or .db3/.mcap files, directly inside."""
    return (directory / METADATA).exists() or any(directory.glob("*.db3")) or any(directory.glob("*.mcap"))


def only_bag_files(directory: Path) -> bool:
    """A rosbag2 directory and nothing else: its ``metadata.yaml`` and storage files (an output that
    ``--force`` may replace)."""
    try:
        entries = list(directory.iterdir())
    except OSError:
        return False
    names = {entry.name for entry in entries}
    return METADATA in names and all(
        entry.is_file() and not entry.is_symlink() and entry.suffix in BAG_DIRECTORY_SUFFIXES for entry in entries
    )
