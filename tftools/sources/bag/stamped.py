"""``read_stamped``: the header (stamp and frame_id) of every message that has one, per topic.

Any message type whose first field is a ``std_msgs/Header`` qualifies (sensor_msgs, nav_msgs,
geometry_msgs ``*Stamped``, custom types alike), found from the type definitions the recording
carries. Only the header's bytes are decoded (by the codecs, as for live systems).
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from tftools.sources.codecs import cdr, ros1
from tftools.sources.codecs.types import starts_with_header
from tftools.sources.errors import BagError, BagNotFoundError
from tftools.sources.headers import NOT_SENSOR_DATA, HeaderCollector, StampedMessages, StampedRead

__all__ = ["StampedMessages", "StampedRead", "read_stamped"]


def read_stamped(paths: Sequence[str | os.PathLike[str]], topics: Sequence[str] | None = None) -> StampedRead:
    """The headers of every message on ``topics`` (default: every topic whose type starts with a
    header, but /tf, /tf_static and /clock) of the recording at ``paths`` (several: a split one)."""
    from rosbags.highlevel import AnyReader, AnyReaderError

    files = [Path(p) for p in paths]
    for path in files:
        if not path.exists():
            raise BagNotFoundError(str(path))
    try:
        with AnyReader(files) as reader:
            return _read(reader, topics)
    except AnyReaderError as error:
        where = ", ".join(str(p) for p in files)
        raise BagError(where, f"cannot be read ({error})", "check that it is a bag") from None


def _read(reader: Any, topics: Sequence[str] | None) -> StampedRead:
    fielddefs = reader.typestore.fielddefs
    chosen = [c for c in reader.connections if _wanted(c, topics, fielddefs)]
    collected: dict[str, HeaderCollector] = {}
    parse = cdr.header if reader.is2 else ros1.header
    for connection, record_time, raw in reader.messages(connections=chosen) if chosen else ():  # none: all
        stream = collected.setdefault(connection.topic, HeaderCollector(connection.msgtype))
        stream.add(record_time, parse(raw))
    problems = [line for topic, s in collected.items() for line in s.problems(topic)]
    asked = set(topics or ())
    missing = sorted(asked - {c.topic for c in chosen})
    problems += [f"{topic}: not in the recording, or its messages have no header" for topic in missing]
    return StampedRead([s.done(topic) for topic, s in sorted(collected.items())], problems)


def _wanted(connection: Any, topics: Sequence[str] | None, fielddefs: dict[str, Any]) -> bool:
    if topics is not None:
        return connection.topic in topics and starts_with_header(connection.msgtype, fielddefs)
    return connection.topic not in NOT_SENSOR_DATA and starts_with_header(connection.msgtype, fielddefs)
