"""What a command's query needs read of a recording (``CheckQuery.reading()``, ``ReportQuery.reading()``), and a
fleet's worker reading each recording so."""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from contextlib import AbstractContextManager, nullcontext
from dataclasses import dataclass

from tftools.core.semantics import Semantics
from tftools.sources.bag import ProgressCallback
from tftools.sources.recording import Recording, read_recording

#: Per recording read in this process, a context whose value is told the bytes read (or None): a progress bar.
Progress = Callable[[Sequence[str]], AbstractContextManager[ProgressCallback | None]]


@dataclass(frozen=True, slots=True, kw_only=True)
class Reading:
    """How to read a recording for a query: its tf ``topics`` (None: /tf and /tf_static), answering as
    ``semantics`` (None: the recording's own), the ``headers`` of the sensor data (None: none; empty: every
    topic whose messages start with a header), the ``whole`` messages of some topics (the robot's); without
    transforms, an empty recording (``allow_empty``) or ``NoTransformsError``."""

    topics: tuple[str, ...] | None = None
    semantics: Semantics | None = None
    headers: tuple[str, ...] | None = None
    whole: tuple[str, ...] = ()
    allow_empty: bool = False
    header_limit: int | None = None  # the headers read of each topic at most (None: every one)

    def read(self, paths: Sequence[str | os.PathLike[str]], progress: ProgressCallback | None = None) -> Recording:
        """The recording at ``paths`` (several: a split one), read so."""
        return read_recording(
            paths,
            self.topics,
            progress,
            allow_empty=self.allow_empty,
            semantics=self.semantics,
            headers=self.headers,
            whole=self.whole,
            header_limit=self.header_limit,
        )


def unwatched(paths: Sequence[str]) -> AbstractContextManager[None]:
    """No progress told."""
    return nullcontext()
