"""tf topics that say nothing: publishers that sent no message while recorded, and messages that carry
no transform. Only rosbag2 recordings say so: metadata.yaml lists each topic's messages and the QoS of
each publisher the recorder found (``offered_qos_profiles``)."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from tftools.analysis.findings import Finding, Severity, counted
from tftools.analysis.wtf.registry import register
from tftools.analysis.wtf.scene import Scene
from tftools.sources.contents import SourceInfo, is_static_topic


@dataclass(frozen=True)
class TopicTally:
    """One tf topic of one rosbag2 file: its messages, those that carried a transform, its publishers."""

    file: str
    topic: str
    messages: int
    transforms: int
    instants: int  # record times of those transforms: messages at one instant cannot be told apart
    publishers: int
    observed: int | None = None  # the messages read that held no transform, where the reader counted them

    @property
    def empty(self) -> int:
        """Messages that carry no transform: as read, else at least those that metadata.yaml counts beyond
        the transforms (each other one carries one or more)."""
        return self.observed if self.observed is not None else max(0, self.messages - self.transforms)

    @property
    def empty_at_most(self) -> int:
        return self.observed if self.observed is not None else max(0, self.messages - self.instants)

    @property
    def static(self) -> bool:
        return is_static_topic(self.topic)


def tallies(scene: Scene) -> list[TopicTally]:
    """Each tf topic of each rosbag2 file on disk whose metadata.yaml counts it; computed once per scene."""
    return scene.shared("tf_topic_tallies", lambda: list(_tallies(scene)))


def silent_moving_topics(scene: Scene) -> list[TopicTally]:
    """/tf topics whose publishers (one or more) sent not one message, in a recording without moving transforms."""
    if (~scene.rows.static).any():
        return []
    return [t for t in tallies(scene) if not t.static and t.publishers and not t.messages]


def _tallies(scene: Scene) -> Iterator[TopicTally]:
    """Per file and tf topic: metadata.yaml's counts (a rosbag2 directory), and the empty messages as read
    where the reader counted them (every file read: a bare .db3, an MCAP, a ROS 1 bag)."""
    rows = scene.rows
    records, static = rows.record_time.whole(), rows.static
    for file in scene.recording.contents.files:
        listed = _counts(file, scene.recording.contents.topics) if Path(file.path).is_dir() else {}
        read = file.tf_messages
        inside = (records >= file.start) & (records <= file.end)
        for topic in dict.fromkeys([*listed, *read]):
            messages, publishers = listed.get(topic, (read.get(topic, (0, 0))[0], 0))
            seen, empty = read.get(topic, (0, 0))
            observed = empty if topic in read and seen == messages else None  # a window read: not all of it
            if topic not in listed and not empty:
                continue  # no metadata to judge by, and nothing empty observed
            mine = inside & (static == is_static_topic(topic))
            transforms, instants = int(mine.sum()), len(np.unique(records[mine]))
            yield TopicTally(file.path, topic, messages, transforms, instants, publishers, observed)


def _counts(file: SourceInfo, topics: tuple[str, ...]) -> dict[str, tuple[int, int]]:
    """Per tf topic: its messages and its publishers, as metadata.yaml has them (read with the bag; nothing
    if unreadable: ``static_volatile`` says so)."""
    counts = file.qos.counts if file.qos is not None else {}
    return {topic: counted for topic, counted in counts.items() if topic in topics}


@register("silent_tf", Severity.warning, "tf publishers that sent nothing, tf messages without transforms")
def silent_tf(scene: Scene) -> Iterator[Finding]:
    silent = silent_moving_topics(scene)
    for tally in tallies(scene):
        said = []
        if tally in silent:
            said.append(
                f"{tally.topic} had {counted(tally.publishers, 'publisher')} when recording began (metadata.yaml's "
                "offered QoS) and not one message was recorded: nothing in this recording moves"
            )
        if tally.empty:
            exactly = "" if tally.empty == tally.empty_at_most else "at least "
            said.append(
                f"{exactly}{tally.empty:,} of {tally.messages:,} messages on {tally.topic} carry no transform "
                f"({counted(tally.transforms, 'transform')} in the others)"
            )
        if not said:
            continue
        warning = tally in silent or tally.empty * 2 > tally.messages  # mostly empty: a publisher gone wrong
        hints = []
        if tally in silent:
            hints.append(
                "the moving transforms' publishers ran but sent nothing while recorded (their input never came: "
                "joint states, odometry, a clock), or the recorder missed them: lookups through them all fail"
            )
        if tally.empty:
            named = "ros2 topic info -v" if scene.ros2 else "rostopic info"
            hints.append(f"a node sending tf messages without transforms is misconfigured: {named} names them")
        yield Finding(
            Severity.warning if warning else Severity.info,
            "silent_tf",
            f"{tally.file}: {'; '.join(said)}",
            "; ".join(hints),
            (),
            (tally.topic,),
            count=tally.empty or tally.publishers,
        )
