"""A recording read at once through the public reader (``BagReader``), for the readers' tests."""

from __future__ import annotations

import os
from collections.abc import Sequence

from tftools.sources.bag import BagContents, BagReader, ProgressCallback, RecordWindow


def read_contents(
    paths: Sequence[str | os.PathLike[str]],
    topics: Sequence[str] | None = None,
    progress: ProgressCallback | None = None,
    window: RecordWindow | None = None,
) -> BagContents:
    """What ``BagReader(paths, topics).read(window, progress)`` gives, the files closed again."""
    with BagReader(paths, topics) as reader:
        return reader.read(window, progress)
