"""The header (stamp and frame_id) of every message that has one, per topic: ``stamped_of`` a read
recording, or ``read_stamped`` at once.

Any message type whose first field is a ``std_msgs/Header`` qualifies (sensor_msgs, nav_msgs,
geometry_msgs ``*Stamped``, custom types alike), as the type definitions the recording carries say
(else rosbags' type stores). The bag readers read them as they read transforms, in the same pass
(``BagReader(..., headers=...)``), through one message set, and the codecs decode only each
message's header bytes.
"""

from __future__ import annotations

import os
from collections.abc import Sequence

from tftools.sources.bag.reader import BagReader
from tftools.sources.contents import SourceInfo, StampedMessages
from tftools.sources.headers import StampedRead, merged

__all__ = ["StampedMessages", "StampedRead", "read_stamped", "stamped_of"]


def stamped_of(files: Sequence[SourceInfo], topics: Sequence[str] | None = None) -> StampedRead:
    """The headers the files were read with (``BagReader``'s ``headers``: ``topics``, default every topic
    whose type starts with a header), and what could not be read of them."""
    streams = merged([stream for info in files for stream in info.stamped])
    problems = [line for info in files for line in info.stamped_problems]
    missing = sorted(set(topics or ()) - {stream.topic for stream in streams})
    problems += [f"{topic}: not in the recording, or its messages have no header" for topic in missing]
    return StampedRead(streams, problems)


def read_stamped(paths: Sequence[str | os.PathLike[str]], topics: Sequence[str] | None = None) -> StampedRead:
    """The headers of every message on ``topics`` (default: every topic whose type starts with a
    header, but /tf, /tf_static and /clock) of the recording at ``paths`` (several: a split one)."""
    with BagReader(paths, headers=tuple(topics or ())) as reader:
        files = reader.read().files
    return stamped_of(files, topics)
