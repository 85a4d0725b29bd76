"""ROS2 bags: a directory (metadata.yaml, one or several sqlite3 or mcap files) or a bare .db3."""

from __future__ import annotations

import re
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath
from typing import Any

from tftools.core.batch import TransformBatch
from tftools.sources import yaml_input
from tftools.sources.bag.contents import BagFileInfo, ProgressCallback, RecordWindow, in_turn
from tftools.sources.bag.messages import MessageSet
from tftools.sources.bag.scan import FileScan, file_result
from tftools.sources.bag.unpack import Budget, CompressionUnavailableError, zstd_file, zstd_messages
from tftools.sources.errors import CorruptBagError


def read(
    path: Path, topics: tuple[str, ...], progress: ProgressCallback, window: RecordWindow | None = None
) -> tuple[list[TransformBatch], BagFileInfo]:
    """The transforms of a ROS2 bag directory or a bare .db3 file (see ``reader.read_bag``)."""
    if not path.is_dir():
        bag = _Bag("mcap" if path.suffix == ".mcap" else "sqlite3", [path])
        return file_result(path, f"rosbag2-{bag.storage}", [_scan_file(path, bag, topics, progress, window)])
    bag = _layout(path)
    scans, labels = _scan_files(path, bag, topics, progress, window)
    batches, info = file_result(path, f"rosbag2-{bag.storage}", scans, labels)
    info.problems[:0] = bag.problems
    return batches, info


@dataclass
class _Bag:
    """What a bag directory is made of, from its metadata.yaml or, failing that, its files."""

    storage: str  # "sqlite3" or "mcap"
    files: list[Path]
    compression_mode: str = ""  # "", "file" or "message"
    problems: list[str] = field(default_factory=list)


def _layout(path: Path) -> _Bag:
    problems: list[str] = []
    info = _metadata(path / "metadata.yaml", problems)
    if info is not None:
        storage = str(info.get("storage_identifier") or "sqlite3")
        files = _bag_files(path, info.get("relative_file_paths"), problems)
        mode = str(info.get("compression_mode") or "").lower()
        if files:
            return _Bag(storage, files, mode, problems)
        problems.append("metadata.yaml lists no files, read the bag files found instead")
    files = sorted(
        (*path.glob("*.db3"), *path.glob("*.mcap"), *path.glob("*.db3.zstd"), *path.glob("*.mcap.zstd")), key=_natural
    )
    storage = "mcap" if files and ".mcap" in files[0].suffixes else "sqlite3"
    return _Bag(storage, files, "", problems)


def _metadata(path: Path, problems: list[str]) -> dict[str, Any] | None:
    if not _exists(path):
        return None
    try:
        document = yaml_input.load(path)
    except yaml_input.YamlInputError as e:
        problems.append(f"metadata.yaml is unreadable ({e}), read the bag files found instead")
        return None
    info = document.get("rosbag2_bagfile_information") if isinstance(document, dict) else None
    if not isinstance(info, dict):
        problems.append("metadata.yaml has no rosbag2_bagfile_information, read the bag files found instead")
        return None
    return info


def _bag_files(directory: Path, names: object, problems: list[str]) -> list[Path]:
    """The files metadata.yaml lists, inside ``directory``: a name that leads out of it (absolute,
    or through ``..``) is refused. Old bags list paths with the bag directory in front; keep the
    names that exist."""
    files: list[Path] = []
    for name in names if isinstance(names, list) else []:
        relative = PurePosixPath(str(name))
        if not str(name) or "\0" in str(name) or relative.is_absolute() or ".." in relative.parts:
            problems.append(f"metadata.yaml lists {_shown(str(name))}, outside the bag directory: not read")
            continue
        candidate = directory / relative
        files.append(candidate if _exists(candidate) else directory / relative.name)
    return files


_SHOWN = 80  # characters of a file name printed


def _shown(name: str) -> str:
    """A file name from metadata.yaml to be printed: cut short, and quoted with escapes if it
    holds characters that are not printable (escape codes, newlines)."""
    short = name if len(name) <= _SHOWN else name[: _SHOWN - 3] + "..."
    return short if short.isprintable() else repr(short)


def _exists(path: Path) -> bool:
    """Whether ``path`` exists; False for a name the system refuses (too long, say)."""
    try:
        return path.exists()
    except (OSError, ValueError):
        return False


def _natural(path: Path) -> list[Any]:
    """Sort key of split files: bag_2 before bag_10."""
    return [int(part) if part.isdigit() else part for part in re.split(r"(\d+)", path.name)]


def _scan_files(
    path: Path, bag: _Bag, topics: tuple[str, ...], progress: ProgressCallback, window: RecordWindow | None
) -> tuple[list[FileScan], list[str]]:
    """Each file's scan, and a label per scan for its problems (the file name when there are several)."""
    scans: list[FileScan] = []
    labels: list[str] = []
    lost: list[str] = []
    shares = in_turn(progress, [file.stat().st_size if _exists(file) else 0 for file in bag.files])
    for share, file in zip(shares, bag.files, strict=True):
        if not _exists(file):
            lost.append(f"{_shown(file.name)} is listed in metadata.yaml but missing; its messages are lost")
            continue
        try:
            scans.append(_scan_file(file, bag, topics, share, window))
            labels.append(file.name if len(bag.files) > 1 else "")
        except CorruptBagError as e:
            lost.append(f"{file.name}: {str(e).removeprefix(e.path + ': ')}; nothing read from it")
    if not scans:
        raise CorruptBagError(str(path), "; ".join(lost) or "no bag files in it")
    bag.problems += lost
    return scans, labels


def _scan_file(
    file: Path, bag: _Bag, topics: tuple[str, ...], progress: ProgressCallback, window: RecordWindow | None
) -> FileScan:
    # Each storage's module is imported only when a file needs it.
    unpack = zstd_messages(file.stat().st_size) if bag.compression_mode == "message" else None
    messages = MessageSet(unpack, window)
    with _uncompressed(file, bag.problems) as plain:
        if plain.suffix == ".mcap":
            from tftools.sources.bag import mcap

            scan = mcap.scan(plain, topics, progress, messages)
        else:
            from tftools.sources.bag.rosbag2 import db3

            scan = db3.scan(plain, topics, progress, messages)
    scan.windowed &= plain == file  # a file compressed whole is decompressed whole first
    return scan


@contextmanager
def _uncompressed(file: Path, problems: list[str]) -> Iterator[Path]:
    """A file compressed whole (``.zstd``) is decompressed into a temporary file first (within
    ``unpack.zstd_file``'s limits; what is lost noted in ``problems``)."""
    if file.suffix != ".zstd":
        yield file
        return
    with tempfile.TemporaryDirectory(prefix="tftools-") as tmp:
        plain = Path(tmp) / file.stem
        try:
            with file.open("rb") as src:
                loss = zstd_file(src, plain, Budget(file.stat().st_size))
        except (CompressionUnavailableError, OSError) as e:
            raise CorruptBagError(str(file), f"cannot be decompressed ({getattr(e, 'strerror', None) or e})") from None
        if loss:
            problems.append(f"{file.name}: {loss}")
        yield plain
