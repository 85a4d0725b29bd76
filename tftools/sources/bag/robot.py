"""What a recording says of the robot itself (``Recording.robot``): its description (the latest
``/robot_description``, a std_msgs/String: latched in ROS 1, transient local in ROS 2) and its joints'
positions over time (``/joint_states``, sensor_msgs/JointState), read whole by the bag readers in the
pass that reads the transforms (``read_recording(..., whole=ROBOT_TOPICS)``)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import field
from typing import TYPE_CHECKING

import numpy as np

from tftools.core.arrays import Int64Array
from tftools.sources.contents import RecordingContents
from tftools.values import value

if TYPE_CHECKING:
    from tftools.sources.codecs.robot import JointState

DESCRIPTION_TOPIC = "/robot_description"
JOINT_STATES_TOPIC = "/joint_states"
#: What a read that checks the robot takes whole beside the transforms.
ROBOT_TOPICS = (DESCRIPTION_TOPIC, JOINT_STATES_TOPIC)


@value
class RobotMessages:
    """The recorded description (its URDF text, "" when none was recorded) and joint states (in record
    order, ``record_time`` beside each), and one line per topic whose messages could not all be read."""

    description: str = ""
    record_time: Int64Array = field(default_factory=lambda: np.zeros(0, np.int64))
    joint_states: Sequence[JointState] = ()
    joint_topic: str = JOINT_STATES_TOPIC
    recorded_topics: frozenset[str] = frozenset()  # every topic of the recording
    problems: Sequence[str] = ()


def robot_messages(contents: RecordingContents) -> RobotMessages:
    """The robot's messages among those a read took whole (``BagReader(..., whole=ROBOT_TOPICS)``)."""
    texts: list[tuple[int, str]] = []
    states: list[tuple[int, JointState]] = []
    for whole in contents.whole:
        times = whole.record_time.tolist()
        if whole.topic == DESCRIPTION_TOPIC:
            texts += [(t, str(v)) for t, v in zip(times, whole.values, strict=True)]
        elif whole.topic == JOINT_STATES_TOPIC:
            from tftools.sources.codecs.robot import JointState  # loaded already: its decoder made these

            states += [(t, v) for t, v in zip(times, whole.values, strict=True) if isinstance(v, JointState)]
    states.sort(key=lambda pair: pair[0])
    texts.sort(key=lambda pair: pair[0])
    topics = frozenset(t for info in contents.files for t in info.topics)
    problems = [line for info in contents.files for line in info.problems if line.startswith(ROBOT_TOPICS)]
    return RobotMessages(
        texts[-1][1] if texts else "",
        np.array([t for t, _ in states], np.int64),
        [s for _, s in states],
        JOINT_STATES_TOPIC,
        topics,
        problems,
    )
