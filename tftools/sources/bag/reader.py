"""``read_bag``: recognise each path's format, read its transforms, merge in record order."""

from __future__ import annotations

import importlib
import os
from collections.abc import Callable, Sequence
from contextlib import ExitStack
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from tftools.core.batch import TransformBatch
from tftools.sources.bag.contents import (
    BagContents,
    BagFileInfo,
    ProgressCallback,
    RecordWindow,
    in_record_order,
    in_turn,
    merged_clock,
)
from tftools.sources.contents import DEFAULT_TOPICS, Fetched
from tftools.sources.errors import BagError, BagNotFoundError, UnknownBagFormatError
from tftools.sources.storage.locations import is_url

if TYPE_CHECKING:
    from tftools.sources.storage.remote import LocalView

#: A format reader: (path, topics, progress over this file's bytes, window) -> batches and description.
FormatReader = Callable[
    [Path, tuple[str, ...], ProgressCallback, RecordWindow | None], tuple[list[TransformBatch], BagFileInfo]
]

#: The first bytes of each format's files, and the module that reads them.
_MAGICS = ((b"#ROSBAG V2.0\n", "ros1"), (b"SQLite format 3\x00", "rosbag2"), (b"\x89MCAP0\r\n", "mcap"))


def read_bag(
    paths: Sequence[str | os.PathLike[str]],
    topics: Sequence[str] | None = None,
    progress: ProgressCallback | None = None,
    window: RecordWindow | None = None,
) -> BagContents:
    """Every transform on ``topics`` (default ``/tf`` and ``/tf_static``) of the bags at ``paths``,
    and their recorded clock (a rosgraph_msgs/Clock topic, whatever ``topics`` are).

    A path may be a URL (``s3://``, ``gs://``, ``az://``, ``http(s)://``; ``tftools[fleet]``): only
    the ranges the readers need are fetched, and its ``BagFileInfo.fetched`` says how much.
    Several paths are one recording (a split bag): their rows are merged by record time.
    Raises ``BagError`` for a path that cannot be read at all; a damaged file is read as far
    as it goes, and what was lost is listed in its ``BagFileInfo.problems``.

    With a ``window``, only the transforms, clock and headers recorded in it are read (the files'
    indexes skip the rest; a file without one is read whole, and its ``windowed`` is False); each
    ``BagFileInfo`` still describes its whole file. An empty window reads only the descriptions.
    """
    chosen = tuple(topics) if topics else DEFAULT_TOPICS
    batches, infos = read_files(paths, chosen, progress, window)
    return BagContents(in_record_order(batches), infos, chosen, merged_clock([f.clock for f in infos]))


def read_files(
    paths: Sequence[str | os.PathLike[str]],
    topics: tuple[str, ...],
    progress: ProgressCallback | None = None,
    window: RecordWindow | None = None,
) -> tuple[list[TransformBatch], list[BagFileInfo]]:
    """Each file at ``paths`` (local or a URL) read by its format's reader for ``topics`` (a
    ``HeaderTopics`` reads sensor data's headers into each ``BagFileInfo.stamped`` instead), in
    ``window`` (see ``read_bag``): the batches of all, and one ``BagFileInfo`` per file."""
    with ExitStack() as stack:
        places = [_place(os.fspath(p), stack) for p in paths]
        readers = [_format_reader(place) for place in places]
        shares = in_turn(progress or _unreported, [_size(place.path) for place in places])
        read = [
            place.said(reader, topics, share, window)
            for share, place, reader in zip(shares, places, readers, strict=True)
        ]
    return [batch for batches, _ in read for batch in batches], [info for _, info in read]


def _unreported(_done: int, _total: int) -> None:
    pass


@dataclass
class _Place:
    """Where a bag is read: its local path, or a remote one's local view (and its URL)."""

    path: Path
    url: str = ""
    view: LocalView | None = None

    def said(
        self, reader: FormatReader, topics: tuple[str, ...], progress: ProgressCallback, window: RecordWindow | None
    ) -> tuple[list[TransformBatch], BagFileInfo]:
        """The reader's result, said of the URL (with what was fetched) for a remote bag."""
        if self.view is None:
            return reader(self.path, topics, progress, window)
        try:
            batches, info = reader(self.path, topics, progress, window)
        except BagError as e:
            raise e.said_of(self.url) from None
        local = str(self.path)
        info.path = self.url
        info.problems = [line.replace(local, self.url) for line in info.problems]
        info.fetched = Fetched(self.view.fetched, self.view.size, self.view.whole)
        return batches, info


def _place(location: str, stack: ExitStack) -> _Place:
    if not is_url(location):
        return _Place(Path(location))
    from tftools.sources.storage.remote import local_view  # fsspec loads only for a URL

    view = stack.enter_context(local_view(location))
    return _Place(view.path, location, view)


def _format_reader(place: _Place) -> FormatReader:
    try:
        return _format_of(place.path)
    except BagError as e:
        raise e if place.view is None else e.said_of(place.url) from None


def _format_of(path: Path) -> FormatReader:
    if not path.exists():
        raise BagNotFoundError(str(path))
    if path.is_dir():
        if (path / "metadata.yaml").exists() or any(path.glob("*.db3")) or any(path.glob("*.mcap")):
            return _reader("rosbag2")
        raise UnknownBagFormatError(str(path), "a directory without metadata.yaml, .db3 or .mcap files")
    try:
        with path.open("rb") as f:
            head = f.read(16)
    except OSError as e:
        raise UnknownBagFormatError(str(path), e.strerror or str(e)) from None
    for magic, module in _MAGICS:
        if head.startswith(magic):
            return _reader(module)
    raise UnknownBagFormatError(str(path), "unrecognised file header")


def _reader(module: str) -> FormatReader:
    """The ``read`` of the format module ``module``, imported only when a file needs it: a ROS1 user
    pays for no sqlite or MCAP code."""
    reader: FormatReader = importlib.import_module(f"tftools.sources.bag.{module}").read
    return reader


def _size(path: Path) -> int:
    if path.is_dir():
        return sum(p.stat().st_size for p in path.iterdir() if p.is_file())
    return path.stat().st_size
