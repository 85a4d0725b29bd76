"""``read_stamped``: the header (stamp and frame_id) of every message that has one, per topic.

Any message type whose first field is a ``std_msgs/Header`` qualifies (sensor_msgs, nav_msgs,
geometry_msgs ``*Stamped``, custom types alike), as the type definitions the recording carries say
(else rosbags' type stores). The bag readers read them as they read transforms, through one message
set, and the codecs decode only each message's header bytes.
"""

from __future__ import annotations

import os
from collections.abc import Sequence

from tftools.sources.bag.reader import read_files
from tftools.sources.codecs.select import HeaderTopics
from tftools.sources.contents import StampedMessages
from tftools.sources.headers import StampedRead, merged

__all__ = ["StampedMessages", "StampedRead", "read_stamped"]


def read_stamped(paths: Sequence[str | os.PathLike[str]], topics: Sequence[str] | None = None) -> StampedRead:
    """The headers of every message on ``topics`` (default: every topic whose type starts with a
    header, but /tf, /tf_static and /clock) of the recording at ``paths`` (several: a split one)."""
    asked = HeaderTopics(topics or ())
    _, infos = read_files(paths, asked)
    streams = merged([stream for info in infos for stream in info.stamped])
    problems = [line for info in infos for line in info.problems]
    missing = sorted(set(asked) - {stream.topic for stream in streams})
    problems += [f"{topic}: not in the recording, or its messages have no header" for topic in missing]
    return StampedRead(streams, problems)
