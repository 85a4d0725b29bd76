"""What reading bags yields: every transform in record order, and what the files held."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from tftools.core.batch import TransformBatch

#: The topics read unless told otherwise.
DEFAULT_TOPICS = ("/tf", "/tf_static")

#: Called with (bytes done, bytes in all) as bags are read, for progress bars.
ProgressCallback = Callable[[int, int], None]


def is_static_topic(topic: str) -> bool:
    """Transforms on ``/tf_static`` (or a namespaced ``.../tf_static``) hold at every time."""
    return topic.rstrip("/").endswith("tf_static")


@dataclass
class BagFileInfo:
    """One file (or ROS2 bag directory) as read."""

    path: str
    format: str  # "ros1", "rosbag2-sqlite3", "rosbag2-mcap", "mcap"
    start: int  # first message's record time (ns), every topic counted
    end: int  # last message's record time (ns)
    message_count: int  # messages of every topic
    topics: dict[str, str] = field(default_factory=dict)  # topic -> message type, all topics
    transform_count: int = 0  # transforms read from this file
    problems: list[str] = field(default_factory=list)  # what could not be read, one line each


@dataclass
class BagContents:
    """Every transform of the bags in record-time order, and the files' descriptions."""

    transforms: TransformBatch
    files: list[BagFileInfo]
    topics: tuple[str, ...]

    @property
    def start(self) -> int:
        return min((f.start for f in self.files if f.message_count), default=0)

    @property
    def end(self) -> int:
        return max((f.end for f in self.files if f.message_count), default=0)

    @property
    def problems(self) -> list[str]:
        return [p for f in self.files for p in f.problems]
