"""Checks of the input itself: no transforms at all, files read only in part, files not read."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import replace

import numpy as np

from tftools.analysis.data_frames import DataFrames, data_frames
from tftools.analysis.findings import Finding, Severity
from tftools.analysis.no_transforms import no_transforms_hint
from tftools.analysis.wtf.causes import IN_DAMAGE, in_the_damage
from tftools.analysis.wtf.registry import declare, register
from tftools.analysis.wtf.scene import Scene, listed
from tftools.analysis.wtf.silence import silent_moving_topics
from tftools.sources.codecs.select import carries_transforms
from tftools.sources.contents import SourceInfo
from tftools.sources.errors import repair_hint
from tftools.sources.recording import no_transforms


@register("no_tf", Severity.error, "no transforms at all (or none on /tf)", needs_transforms=False)
def no_tf(scene: Scene) -> Iterator[Finding]:
    contents = scene.recording.contents
    live = contents.live
    where = ("from " if live else "in ") + ", ".join(f.path for f in contents.files)
    if not len(scene.rows):
        others = {t: kind for f in contents.files for t, kind in f.topics.items() if t not in contents.topics}
        # the topics of a transform type first: the ones to name, not to hide behind "and N more"
        carriers = sorted(t for t, kind in others.items() if carries_transforms(kind))
        found = carriers + sorted(set(others) - set(carriers))
        present = f"; topics present: {listed(found, 10)}" if found else ("" if live else "; it holds no messages")
        if live:
            tool = "ros2 topic info /tf" if scene.ros2 else "rostopic info /tf"
            hint = f"is anything publishing? ({tool}); name other topics (tfx wtf --topic TOPIC)"
        else:  # every command's hint for a recording without transforms
            hint = no_transforms_hint(no_transforms([f.path for f in contents.files], contents))
        # the topics asked for in a type (or encoding) tfx does not read say which: a LaserScan given as --topic
        said = (
            f"read {where}: {'; '.join(contents.unread)}"
            if contents.unread
            else f"on {', '.join(contents.topics)} {where}{present}"
        )
        # with no transform anywhere, the frames its data names are the tree to record (not so when it
        # has transforms on topics not read: the hint says to read those)
        data = DataFrames() if carriers else data_frames(scene.streams, others)
        yield Finding(
            Severity.error,
            "no_tf",
            f"no transforms {said}{data.said}",
            hint + data.hint,
            frames=data.frames,
            figures=dict(data.figures),
        )
    elif scene.rows.static.all() and not silent_moving_topics(scene):  # else ``silent_tf`` says why
        yield Finding(
            Severity.info,
            "no_tf",
            f"only static transforms {where}: nothing moves ({len(scene.rows)} on /tf_static, none on /tf)",
            "fine for a fixed setup; otherwise check that the moving transforms' publishers ran and were recorded",
            count=len(scene.rows),
        )


@register("bag_problem", Severity.warning, "a bag read only in part", needs_transforms=False)
def bag_problem(scene: Scene) -> Iterator[Finding]:
    contents = scene.recording.contents
    if len(scene.rows):  # else ``no_tf`` tells them
        for line in contents.unread:
            yield Finding(
                Severity.warning,
                "bag_problem",
                line,
                "the findings cover the other topics: convert this one to a type and encoding tfx reads to check it",
            )
    for source in contents.files:
        # the damaged parts' span, on the clock of the findings it explains (``causes``), on its first line
        first, last = _on_stamps(scene, source.damaged) if source.damaged else (0, 0)
        listed = _listed_messages(scene, source)
        for n, problem in enumerate(source.problems):
            yield Finding(
                Severity.warning,
                "bag_problem",
                problem + (listed if not n else ""),
                f"the findings cover only what could be read: {repair_hint(source.path)}",
                first_time=first if not n else 0,
                last_time=last if not n else 0,
            )


def _listed_messages(scene: Scene, source: SourceInfo) -> str:
    """How much of a damaged ROS 2 bag was read, against the messages its metadata.yaml lists: " (metadata.yaml
    lists 2505 messages: 78 read, 3%)"; "" where it lists none, or no more than were read."""
    qos = scene.recording.qos.get(source.path)
    listed = sum(messages for messages, _ in qos.counts.values()) if qos is not None else 0
    if qos is None or listed <= source.message_count:
        return ""
    return f" ({qos.source} lists {listed} messages: {source.message_count} read, {source.message_count / listed:.0%})"


def said_where_damaged(scene: Scene, found: list[Finding]) -> list[Finding]:
    """Of the findings that ``causes`` may put under a file's damage (a pause, stop or bad value of tf), those that
    reach into the span of its lost messages and beyond (a pause of the robot's beside one the file lost, said as
    one): their message says where the file lost its transforms, so that the lost stretch is not taken for theirs."""
    damage = [f for f in found if f.code == "bag_problem" and f.last_time]
    if not damage:
        return found
    out = []
    for f in found:
        if f.code in IN_DAMAGE and f.first_time and not any(in_the_damage(d, f) for d in damage):
            where = [d for d in damage if f.first_time <= d.last_time and d.first_time <= f.last_time]
            if where:
                lost = f"from {scene.at(where[0].first_time)} to {scene.at(where[0].last_time)}"
                f = replace(f, message=f"{f.message} (the file is damaged there: its transforms {lost} were lost)")
        out.append(f)
    return out


def _on_stamps(scene: Scene, damaged: list[tuple[int, int]]) -> tuple[int, int]:
    """The record times of a file's damaged parts as moments on the stamps' clock: ROS time at their arrival
    where it is known, else the stamps of the moving transforms recorded last before them and first after them
    (stamps on simulated time recorded without /clock); (0, 0) where neither is known."""
    start, end = min(s for s, _ in damaged), max(e for _, e in damaged)
    first, last = scene.ros_times([start, end])
    if first and last:
        return first, last
    moving = np.flatnonzero(~scene.rows.static)
    if not len(moving):
        return 0, 0
    recorded, stamps = scene.rows.record_time[moving], scene.rows.stamp[moving]
    before = max(int(np.searchsorted(recorded, start)) - 1, 0)
    after = min(int(np.searchsorted(recorded, end, side="right")), len(moving) - 1)
    return int(stamps[before]), int(stamps[after])


declare("unreadable", Severity.error, "a bag that could not be read at all")
