"""Which of a recorded robot's joints follow another (``<mimic>`` in its recorded /robot_description), by frame."""

from __future__ import annotations

from tftools.analysis.description import robot_of
from tftools.sources.recording import Recording


def recorded_mimics(recording: Recording) -> dict[str, str]:
    """Each mimic joint's child frame and the child frame of the joint it follows, by the description the recording
    holds (its /robot_description, read by ``robot_of`` and named as tf names its links); empty where it holds
    none, or none tfx reads (no guess from names or motion)."""
    robot, _ = robot_of(recording.paths, recording, None)
    if robot is None:
        return {}
    description = robot.description
    by_name = {j.name: j for j in description.joints}
    return {
        j.child: by_name[j.mimic[0]].child
        for j in description.joints
        if j.mimic is not None and j.mimic[0] in by_name and j.mimic[0] != j.name
    }
