"""Stamped messages, from bags and live alike: each message's ``std_msgs/Header`` (stamp and frame_id).

Only the header's bytes are decoded, never the payload after it (image pixels, points), one
parser per encoding: a ROS 1 header is ``uint32 seq, uint32 sec, uint32 nsec, string frame_id``;
a ROS 2 (CDR) one, after the 4-byte encapsulation, ``int32 sec, uint32 nanosec, string frame_id``.
"""

from __future__ import annotations

import struct
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt

from tftools.core.time import NS_PER_S
from tftools.sources.bag.contents import DEFAULT_TOPICS

HEADER_TYPES = frozenset({"std_msgs/msg/Header", "std_msgs/Header"})
#: Topics never read as sensor data: the transforms and the clock themselves.
NOT_SENSOR_DATA = frozenset({*DEFAULT_TOPICS, "/clock"})
#: A frame_id longer than this is damage, not a name.
MAX_FRAME_ID = 4096

#: A message's header: its stamp (ns) and frame_id.
Header = tuple[int, str]

_ROS1 = struct.Struct("<IIII")  # seq, sec, nsec, frame_id length
_CDR_LE = struct.Struct("<iII")  # sec, nanosec, frame_id length (with its NUL)
_CDR_BE = struct.Struct(">iII")


def starts_with_header(msgtype: str, fielddefs: Mapping[str, Any]) -> bool:
    """Whether ``msgtype``'s first field is a std_msgs/Header, as a rosbags type store
    (``fielddefs``) defines it."""
    definition = fielddefs.get(msgtype)
    if not definition or not definition[1]:
        return False
    _name, (_kind, detail) = definition[1][0]
    return detail in HEADER_TYPES


def parse_ros1_header(raw: bytes | memoryview) -> Header | None:
    """The header a ROS 1 message starts with; None where ``raw`` is too short for one."""
    if len(raw) < _ROS1.size:
        return None
    _seq, sec, nsec, length = _ROS1.unpack_from(raw)
    return _stamped(sec, nsec, raw, _ROS1.size, length)


def parse_cdr_header(raw: bytes | memoryview) -> Header | None:
    """The header a ROS 2 message (CDR, encapsulation first) starts with; None where it cannot be one."""
    if len(raw) < 4 + _CDR_LE.size:
        return None
    little = raw[1] == 1  # the encapsulation: CDR_LE is 0x0001, CDR_BE 0x0000
    sec, nanosec, length = (_CDR_LE if little else _CDR_BE).unpack_from(raw, 4)
    return _stamped(sec, nanosec, raw, 4 + _CDR_LE.size, max(length - 1, 0))


def _stamped(sec: int, nsec: int, raw: bytes | memoryview, start: int, length: int) -> Header | None:
    if length > MAX_FRAME_ID or start + length > len(raw):
        return None
    frame_id = bytes(raw[start : start + length]).decode("utf-8", "replace")
    return sec * NS_PER_S + nsec, frame_id


@dataclass(frozen=True)
class StampedMessages:
    """One topic's messages with a header: when each arrived, its stamp and frame (index into ``frame_ids``)."""

    topic: str
    type: str
    record_time: npt.NDArray[np.int64]
    stamp: npt.NDArray[np.int64]
    frame: npt.NDArray[np.int32]
    frame_ids: Sequence[str]

    def __len__(self) -> int:
        return len(self.record_time)


@dataclass(frozen=True)
class StampedRead:
    """Each topic's stamped messages, and what could not be read."""

    streams: list[StampedMessages]
    problems: list[str]


@dataclass
class HeaderCollector:
    """One topic's headers as they are read, at most ``limit`` of them (None: all)."""

    type: str
    limit: int | None = None
    record_time: list[int] = field(default_factory=list)
    stamp: list[int] = field(default_factory=list)
    frame: list[int] = field(default_factory=list)
    frame_ids: dict[str, int] = field(default_factory=dict)
    damaged: int = 0
    left_out: int = 0

    def add(self, record_time: int, header: Header | None) -> None:
        """A message that arrived at ``record_time``; ``header`` None: one too damaged for a header."""
        if header is None:
            self.damaged += 1
        elif self.limit is not None and len(self.record_time) >= self.limit:
            self.left_out += 1
        else:
            stamp, frame_id = header
            self.record_time.append(record_time)
            self.stamp.append(stamp)
            self.frame.append(self.frame_ids.setdefault(frame_id, len(self.frame_ids)))

    def problems(self, topic: str) -> list[str]:
        """What was not kept of the topic, in a line each."""
        said = []
        if self.damaged:
            s = "s" if self.damaged > 1 else ""
            said.append(f"{topic}: {self.damaged} message{s} too short for a header, skipped")
        if self.left_out:
            said.append(
                f"{topic}: {self.left_out} messages after the first {self.limit} (tfx's limit per topic) not checked"
            )
        return said

    def done(self, topic: str) -> StampedMessages:
        order = np.argsort(np.array(self.record_time, np.int64), kind="stable")
        return StampedMessages(
            topic,
            self.type,
            np.array(self.record_time, np.int64)[order],
            np.array(self.stamp, np.int64)[order],
            np.array(self.frame, np.int32)[order],
            list(self.frame_ids),
        )
