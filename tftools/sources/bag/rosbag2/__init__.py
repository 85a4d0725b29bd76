"""ROS2 bags: a directory (metadata.yaml, one or several sqlite3 or mcap files) or a bare .db3."""

from __future__ import annotations

import re
from contextlib import ExitStack
from pathlib import Path, PurePosixPath
from typing import TYPE_CHECKING, Any

from tftools.sources import user_files
from tftools.sources.bag.contents import ProgressCallback, RecordWindow, in_turn
from tftools.sources.bag.formats import EMPTY_HINT
from tftools.sources.bag.messages import MessageSet
from tftools.sources.bag.scan import FileRead, FileScan, file_result, qos_in_files
from tftools.sources.bag.unpack import Budget, CompressionUnavailableError, zstd_file, zstd_messages
from tftools.sources.codecs.select import Wanted
from tftools.sources.contents import IN_DB3, IN_MCAP, OfferedQos, is_static_topic
from tftools.sources.errors import CorruptBagError, UnreadableFileError
from tftools.sources.storage.source import ByteSource, Files, FileSource

if TYPE_CHECKING:
    from tftools.sources.bag.mcap import McapFile
    from tftools.sources.bag.rosbag2.db3 import Db3File


class Rosbag2Bag:
    """A ROS2 bag directory (or a bare .db3 or .mcap file of one) open for reading: its metadata.yaml
    read once, each of its files opened once (one compressed whole decompressed once), each file's
    index or schema read once; read whole, or window after window."""

    def __init__(self, path: Path, files: Files, source: ByteSource | None = None) -> None:
        """The bag at ``path`` among ``files``; ``source``: the bare file's, opened already."""
        self.path = path
        self.files = files
        self._source = source
        if files.is_dir(path):
            self.bag = _layout(path, files)
        else:
            self.bag = _Bag("mcap" if ".mcap" in path.suffixes else "sqlite3", [path], qos=_beside(path, files))
        self._stack = ExitStack()
        self._files: dict[Path, Db3File | McapFile | CorruptBagError] = {}
        self._decompressed: dict[Path, list[str]] = {}  # files compressed whole: what decompressing them lost

    def read(self, wanted: Wanted, progress: ProgressCallback, window: RecordWindow | None = None) -> FileRead:
        """The bag's transforms (see ``reader.BagReader.read``)."""
        fmt = f"rosbag2-{self.bag.storage}"
        if not self.files.is_dir(self.path):
            scans = [self._scan_file(self.path, wanted, progress, window, [])]
            read = file_result(self.path, fmt, scans)
        else:
            problems = list(self.bag.problems)
            scans, labels = self._scan_files(wanted, progress, window, problems)
            read = file_result(self.path, fmt, scans, labels)
            read.info.problems[:0] = problems
        in_files = IN_MCAP if self.bag.storage == "mcap" else IN_DB3
        read.qos = self.bag.qos if self.bag.qos.metadata else qos_in_files(scans, in_files) or self.bag.qos
        return read

    def _scan_files(
        self, wanted: Wanted, progress: ProgressCallback, window: RecordWindow | None, problems: list[str]
    ) -> tuple[list[FileScan], list[str]]:
        """Each file's scan, and a label per scan for its problems (the file name when there are several)."""
        scans: list[FileScan] = []
        labels: list[str] = []
        lost: list[str] = []
        errors: list[CorruptBagError] = []
        missing: list[str] = []
        files = self.bag.files
        shares = in_turn(progress, [self.files.size(file) for file in files])
        for share, file in zip(shares, files, strict=True):
            if not self.files.exists(file):
                missing.append(_shown(file.name))
                continue
            try:
                scans.append(self._scan_file(file, wanted, share, window, problems))
                labels.append(file.name if len(files) > 1 else "")
            except CorruptBagError as e:
                errors.append(e)
                lost.append(f"{file.name}: {e.detail}; nothing read from it")
        if missing:
            lost.insert(0, _missing(missing))
        if not scans:
            detail = "; ".join(lost) or "no bag files in it"
            if errors and not missing and all(isinstance(e, UnreadableFileError) for e in errors):
                raise UnreadableFileError(str(self.path), detail)
            every_missing = "copy the files metadata.yaml lists into the directory beside it (it holds no message)"
            hint = self._unlisted_hint() or (every_missing if missing and not errors else "")
            raise CorruptBagError(str(self.path), detail, hint)
        problems += lost
        return scans, labels

    def _unlisted_hint(self) -> str:
        """Where metadata.yaml's files are missing but the directory holds others (renamed after recording,
        as a CompRobo student's person_follower_0.db3 was to person_follower_demo_0.db3): what to give tfx."""
        unlisted = [file for file in _storage_files(self.path, self.files) if file not in self.bag.files]
        if not unlisted:
            return ""
        named = ", ".join(_shown(file.name) for file in unlisted[:NAMED_MISSING])
        more = f" and {len(unlisted) - NAMED_MISSING} more" if len(unlisted) > NAMED_MISSING else ""
        return (
            f"the directory holds {named}{more}, which metadata.yaml does not list (renamed after recording?): "
            f"give tfx that file ({unlisted[0]}), or correct relative_file_paths in metadata.yaml"
        )

    def _scan_file(
        self, file: Path, wanted: Wanted, progress: ProgressCallback, window: RecordWindow | None, problems: list[str]
    ) -> FileScan:
        opened = self._opened(file)
        problems += self._decompressed.get(file, [])
        unpack = zstd_messages(opened.source.size) if self.bag.compression_mode == "message" else None
        try:
            scan = opened.scan(wanted, progress, MessageSet(unpack, window))
        finally:
            opened.source.close()  # its descriptor let go until the next read: files opened one at a time
        scan.windowed &= file not in self._decompressed  # a file compressed whole is decompressed whole first
        return scan

    def _opened(self, file: Path) -> Db3File | McapFile:
        """The file opened, once (what could not be opened is raised each time)."""
        if file not in self._files:
            try:
                plain = self._uncompressed(file)
                source = self._open(plain)
                if source.size == 0:
                    raise CorruptBagError(str(file), "an empty file: 0 bytes", EMPTY_HINT)
                if plain.suffix == ".mcap":
                    from tftools.sources.bag.mcap import McapFile  # each storage's module only when needed

                    self._files[file] = McapFile(plain, source)
                else:
                    from tftools.sources.bag.rosbag2.db3 import Db3File

                    local = plain if plain in self._decompressed else self.files.local(plain)
                    self._files[file] = Db3File(local, source)
            except CorruptBagError as e:
                self._files[file] = e
        opened = self._files[file]
        if isinstance(opened, CorruptBagError):
            raise opened
        return opened

    def _open(self, file: Path) -> ByteSource:
        """The file's bytes (a file decompressed here is local, whatever the bag's files are)."""
        if self._source is not None and file == self.path:
            source, self._source = self._source, None
        elif file in self._decompressed:
            source = FileSource(file)
        else:
            source = self.files.open(file)
        return self._stack.enter_context(source)

    def _uncompressed(self, file: Path) -> Path:
        """A file compressed whole (``.zstd``) decompressed into a temporary file, kept while the bag is
        open (within ``unpack.zstd_file``'s limits; what is lost noted)."""
        if file.suffix != ".zstd":
            return file
        import tempfile  # here: with shutil, random, bz2 and lzma ~5 ms of every ROS 2 bag's first load

        folder = Path(self._stack.enter_context(tempfile.TemporaryDirectory(prefix="tftools-")))
        plain = folder / file.stem
        try:
            with self.files.open(file) as compressed, compressed.stream() as src:
                loss = zstd_file(src, plain, Budget(compressed.size))
        except (CompressionUnavailableError, OSError) as e:
            raise CorruptBagError(str(file), f"cannot be decompressed ({getattr(e, 'strerror', None) or e})") from None
        self._decompressed[file] = [f"{file.name}: {loss}"] if loss else []
        self._decompressed[plain] = []
        return plain

    def close(self) -> None:
        self._stack.close()


_NO_METADATA = OfferedQos({}, metadata=False)


class _Bag:
    """What a bag directory is made of, from its metadata.yaml or, failing that, its files."""

    __slots__ = ("compression_mode", "files", "problems", "qos", "storage")

    def __init__(
        self,
        storage: str,
        files: list[Path],
        compression_mode: str = "",
        problems: list[str] | None = None,
        qos: OfferedQos = _NO_METADATA,
    ) -> None:
        self.storage = storage  # "sqlite3" or "mcap"
        self.files = files
        self.compression_mode = compression_mode  # "", "file" or "message"
        self.problems = [] if problems is None else problems
        self.qos = qos


def _layout(path: Path, stored: Files) -> _Bag:
    problems: list[str] = []
    info = _metadata(path / "metadata.yaml", stored, problems)
    qos = _qos(path / "metadata.yaml", stored, info, problems)
    if info is not None:
        storage = str(info.get("storage_identifier") or "sqlite3")
        files = _bag_files(path, stored, info.get("relative_file_paths"), problems)
        mode = str(info.get("compression_mode") or "").lower()
        if files:
            return _Bag(storage, files, mode, problems, qos)
        problems.append("metadata.yaml lists no files, read the bag files found instead")
    files = _storage_files(path, stored)
    storage = "mcap" if files and ".mcap" in files[0].suffixes else "sqlite3"
    return _Bag(storage, files, "", problems, qos)


def _storage_files(path: Path, stored: Files) -> list[Path]:
    """The bag files in directory ``path``, whatever metadata.yaml lists, in their split order."""
    names = stored.listing(path)
    return sorted((p for p in names if p.name.endswith((".db3", ".mcap", ".db3.zstd", ".mcap.zstd"))), key=_natural)


def _beside(path: Path, stored: Files) -> OfferedQos:
    """The offered QoS of a bare file's bag directory, where the metadata.yaml beside it lists it (a .db3
    given inside its folder)."""
    bag = _listing_bag(path, stored)
    return bag.qos if bag is not None else _NO_METADATA


def _listing_bag(path: Path, stored: Files) -> _Bag | None:
    """The bag directory file ``path`` is in, where the metadata.yaml beside it lists it; None for a file
    it does not list (renamed after recording: then the file is a recording of its own)."""
    if not stored.exists(path.parent / "metadata.yaml"):
        return None
    bag = _layout(path.parent, stored)
    return bag if path in bag.files else None


def listed_in_bag(path: Path) -> bool:
    """Whether the bag file ``path`` (on this machine) is one the metadata.yaml beside it lists: a file of a ROS 2
    bag directory, not one renamed since, which metadata.yaml no longer names."""
    from tftools.sources.storage.source import LocalFiles

    return _listing_bag(path, LocalFiles(path)) is not None


def _qos(path: Path, stored: Files, info: dict[str, Any] | None, problems: list[str]) -> OfferedQos:
    """The QoS profiles each static topic's publishers offered, as metadata.yaml says (what ``ros2 bag
    play`` publishes them with)."""
    if not stored.exists(path):
        return _NO_METADATA
    if info is None:
        return OfferedQos({}, problems[-1] if problems else "it is unreadable")
    try:
        found: dict[str, list[object]] = {}
        counts: dict[str, tuple[int, int]] = {}
        for entry in info.get("topics_with_message_count") or []:
            topic = entry["topic_metadata"]
            profiles = topic.get("offered_qos_profiles") or []
            offered = user_files.load_text(profiles) or [] if isinstance(profiles, str) else profiles
            count = int(entry.get("message_count") or 0)
            if not isinstance(offered, list) or not all(isinstance(p, dict) for p in offered):
                raise ValueError(f"offered_qos_profiles of {topic['name']} is no list of profiles: {profiles!r:.60}")
            if count < 0:
                raise ValueError(f"message_count of {topic['name']} is {count}")
            counts[str(topic["name"])] = (count, len(offered))
            if is_static_topic(str(topic["name"])):
                found[str(topic["name"])] = offered
        return OfferedQos(found, counts=counts)
    except (user_files.UserFileError, KeyError, TypeError, ValueError, AttributeError) as error:
        return OfferedQos({}, str(error) or type(error).__name__)


def _metadata(path: Path, stored: Files, problems: list[str]) -> dict[str, Any] | None:
    if not stored.exists(path):
        return None
    try:
        document = stored.load_yaml(path)
    except user_files.UserFileError as e:
        problems.append(f"metadata.yaml is unreadable ({e}), read the bag files found instead")
        return None
    info = document.get("rosbag2_bagfile_information") if isinstance(document, dict) else None
    if not isinstance(info, dict):
        problems.append("metadata.yaml has no rosbag2_bagfile_information, read the bag files found instead")
        return None
    return info


def _bag_files(directory: Path, stored: Files, names: object, problems: list[str]) -> list[Path]:
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
        files.append(candidate if stored.exists(candidate) else directory / relative.name)
    return files


_SHOWN = 80  # characters of a file name printed


def _shown(name: str) -> str:
    """A file name from metadata.yaml to be printed: cut short, and quoted with escapes if it
    holds characters that are not printable (escape codes, newlines)."""
    short = name if len(name) <= _SHOWN else name[: _SHOWN - 3] + "..."
    return short if short.isprintable() else repr(short)


def _natural(path: Path) -> list[Any]:
    """Sort key of split files: bag_2 before bag_10."""
    return [int(part) if part.isdigit() else part for part in re.split(r"(\d+)", path.name)]


#: Missing files named in one line; the rest are counted.
NAMED_MISSING = 3


def _missing(names: list[str]) -> str:
    """One line for the files metadata.yaml lists that are not there, however many (a damaged metadata.yaml
    may list thousands)."""
    if len(names) == 1:
        return f"{names[0]} is listed in metadata.yaml but missing; its messages are lost"
    shown = ", ".join(names[:NAMED_MISSING]) + (
        f" and {len(names) - NAMED_MISSING} more" if len(names) > NAMED_MISSING else ""
    )
    return f"{len(names)} files listed in metadata.yaml are missing ({shown}); their messages are lost"
