"""Remote files' local copies, by the file the readers hold open: a reader about to read some byte
ranges of a file asks ``need`` (or, ahead of time, ``ahead``) whatever the file, and only a copy of
a remote file fetches them; a local file's ranges are read ahead by the system.

A table keyed by the open file (its device and inode), not an argument: the readers of every format
hold a file descriptor already, and none of their signatures need to know where a file came from.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import Protocol


class Fillable(Protocol):
    """A remote file's local copy, whose bytes are fetched on request."""

    def fill(self, starts: Sequence[int], ends: Sequence[int]) -> None:
        """Make ``starts[i]:ends[i]`` of the copy hold the remote file's bytes."""


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
