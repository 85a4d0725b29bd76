"""Remote files' local copies, by the file the readers hold open (its device and inode): the readers
of every format hold a file descriptor already, so none of their signatures need to know where a file
came from. A reader about to read some ranges of a file asks ``copy_of`` it to fill them first."""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import Protocol


class Fillable(Protocol):
    """A remote file's local copy: ``fill`` makes ``starts[i]:ends[i]`` of it hold the remote bytes."""

    def fill(self, starts: Sequence[int], ends: Sequence[int]) -> None: ...


_copies: dict[tuple[int, int], Fillable] = {}


def register(fd: int, copy: Fillable) -> None:
    """Have reads of the file open as ``fd`` (and of any other descriptor of it) fill ``copy`` first."""
    _copies[_key(fd)] = copy


def unregister(fd: int) -> None:
    _copies.pop(_key(fd), None)


def copy_of(fd: int) -> Fillable | None:
    """The remote copy the file open as ``fd`` is; None for a local file (without a lookup when no
    remote file is open: the local readers pay nothing)."""
    if not _copies:
        return None
    return _copies.get(_key(fd))


def _key(fd: int) -> tuple[int, int]:
    stat = os.fstat(fd)
    return stat.st_dev, stat.st_ino
