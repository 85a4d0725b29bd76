"""Where recordings are: local paths, or URLs read through fsspec (``tftools[fleet]``, imported only
for a URL by ``remote``), and their files' bytes read by range (``source``)."""

from __future__ import annotations

import os
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING

from tftools import lazy
from tftools.sources.storage.locations import BAG_SUFFIXES, expand_local, is_url, recordings_in

if TYPE_CHECKING:
    from tftools.sources.storage.source import ByteSource, Files

__all__ = ["BAG_SUFFIXES", "ByteSource", "Files", "expand", "is_url", "local_recording", "open_files", "recordings_in"]

# The byte sources (numpy) load on first use: the CLI's option parsing and --help import this package.
__getattr__, __dir__ = lazy.exports(__name__, dict.fromkeys(["ByteSource", "Files"], f"{__name__}.source"), __all__)


def expand(arguments: Sequence[str | os.PathLike[str]]) -> list[str]:
    """Each argument's recordings, in order: a glob's matches and, for a prefix ending in ``/`` that
    is not itself a ROS 2 bag, every recording below it (sorted); any other argument as it is.

    URLs need ``tftools[fleet]`` (``MissingExtraError`` without it); a URL, glob or prefix that
    names no recording raises ``BagNotFoundError``.
    """
    found: list[str] = []
    for argument in [os.fspath(a) for a in arguments]:
        if is_url(argument):
            from tftools.sources.storage import remote  # fsspec loads only for a URL

            found += remote.expand(argument)
        else:
            found += expand_local(argument)
    return found


def open_files(location: str | os.PathLike[str]) -> Files:
    """The files of the recording at ``location`` (a path or a URL), to be read by range."""
    if not is_url(location):
        from tftools.sources.storage.source import LocalFiles

        return LocalFiles(Path(location))
    from tftools.sources.storage.remote import RemoteFiles  # fsspec loads only for a URL

    return RemoteFiles(os.fspath(location))


@contextmanager
def local_recording(location: str | os.PathLike[str]) -> Iterator[Path]:
    """``location`` as a local path: itself, or a URL's recording fetched whole for as long as the
    context lasts (``tftools[fleet]``)."""
    if not is_url(location):
        yield Path(location)
        return
    from tftools.sources.storage.remote import whole_copy  # fsspec loads only for a URL

    with whole_copy(os.fspath(location)) as local:
        yield local
