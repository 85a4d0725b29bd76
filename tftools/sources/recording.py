"""``Recording``: bags read into a buffer, with what the files held."""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass

from tftools.core.buffer import Buffer
from tftools.core.time import SimClock
from tftools.sources.bag import BagContents, ProgressCallback, read_bag
from tftools.sources.errors import NoTransformsError


@dataclass
class Recording:
    """One recording (one bag or a split bag): its buffer on bag time, and its description."""

    buffer: Buffer
    contents: BagContents

    @property
    def start(self) -> int:
        """Record time of the first message, every topic counted (ns)."""
        return self.contents.start

    @property
    def end(self) -> int:
        return self.contents.end

    @property
    def paths(self) -> list[str]:
        return [f.path for f in self.contents.files]

    @property
    def problems(self) -> list[str]:
        """What could not be read, one line each; the rest was read."""
        return self.contents.problems


def read_recording(
    paths: Sequence[str | os.PathLike[str]],
    topics: Sequence[str] | None = None,
    progress: ProgressCallback | None = None,
    *,
    allow_empty: bool = False,
) -> Recording:
    """Read bags into a whole-recording buffer (no cache limit; clock at the recording's end).

    Raises ``NoTransformsError`` when no transform was found, unless ``allow_empty``.
    """
    contents = read_bag(paths, topics, progress)
    if not len(contents.transforms) and not allow_empty:
        found = sorted({t for f in contents.files for t in f.topics})
        raise NoTransformsError(", ".join(str(p) for p in paths), ", ".join(contents.topics), ", ".join(found))
    buffer = Buffer(cache_time=None, clock=SimClock(contents.end))
    buffer.insert(contents.transforms)
    return Recording(buffer, contents)


def load(
    *paths: str | os.PathLike[str],
    topics: Sequence[str] | None = None,
    progress: ProgressCallback | None = None,
) -> Buffer:
    """Every transform of the bags at ``paths`` (one recording) in a buffer with tf2's semantics."""
    return read_recording(paths, topics, progress).buffer
