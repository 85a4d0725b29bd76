"""``tfx report``'s one call: ``report(recording, query)``, what the page shows of one recording: its facts,
``tfx wtf``'s findings, its frame graph, and its edges and sensor streams over time (``analysis.timelines``) on
one axis."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from datetime import datetime, timezone

from tftools.analysis.edges import edge_rows
from tftools.analysis.findings import Finding
from tftools.analysis.frames import FrameTree
from tftools.analysis.graph import FrameGraph, frame_graph
from tftools.analysis.report.poses import FramePoses, frame_poses
from tftools.analysis.report.query import REPORT_DEFAULTS, ReportQuery
from tftools.analysis.targets import tied_to_tf
from tftools.analysis.timelines import (
    Bins,
    EdgeTimeline,
    StreamTimeline,
    bins_over,
    edge_axis,
    edge_timelines,
    stream_axis,
    stream_timelines,
)
from tftools.analysis.wtf.fleet import checked_scene
from tftools.core.time import EPOCH_FLOOR, NS_PER_S, format_sec, from_sec
from tftools.sources.contents import StampedMessages, global_name
from tftools.sources.recording import Recording
from tftools.sources.timeline import NO_RECORD_CLOCK, Reference

#: What the tf2 semantics are called on the page.
TF2_NAMES = {
    "ros1": "ROS 1's (Noetic)",
    # Humble's answers are the same; its error classes and its empty cache's words differ (core.semantics)
    "ros2": "ROS 2's (Rolling and Jazzy; Humble answers alike)",
}


@dataclass(frozen=True)
class RecordingReport:
    """What the page shows of one recording. Times on the axis are ns; ``origin`` is shown as 0 s."""

    name: str
    facts: tuple[tuple[str, str], ...]
    findings: tuple[Finding, ...]
    graph: FrameGraph
    bins: Bins
    edges: tuple[EdgeTimeline, ...]
    streams: tuple[StreamTimeline, ...]
    delays_unavailable: str  # why delays cannot be measured ("" when they can)
    origin: int  # the time every time on the page is counted from (``Timeline.origin``: findings' +S too)
    poses: FramePoses | None = None  # every frame over time, for the 3D view
    problems: tuple[str, ...] = ()  # what its reader could not read (also among the facts)
    # findings' times on another clock than the axis (``Timeline.since_origin``: a replay's, days behind)
    other_clock: frozenset[int] = frozenset()
    delays_shown: bool = True  # some edge's delays are measured (``Timeline.delays_anywhere``): drawn where known
    # the frames stamped on another clock than their arrivals' (``Timeline.on_other_clock``): no delay, and why
    delays_other_clock: frozenset[str] = frozenset()
    delays_other_clock_why: str = ""


def report(recording: Recording, query: ReportQuery = REPORT_DEFAULTS) -> RecordingReport:
    """What ``tfx report``'s page shows of ``recording`` (read from files or URLs with ``query.reading()``, or
    captured live): its facts, its findings as ``tfx wtf`` checks it (its sensor data, the headers it was read
    with, into ``query.target``: ``analysis.targets.choose_target``; against the robot's description,
    ``robot_of``), its frame graph, its edges and sensor data over time, and every frame in 3D."""
    scene, findings = checked_scene(recording, query.checks())
    if not len(recording.buffer.frames):
        return _without_transforms(recording, findings, frame_graph(scene, findings))
    streams = scene.streams
    graph = frame_graph(scene, findings)
    buffer, timeline = recording.buffer, scene.timeline
    sensors = scene.sensors if any(tied_to_tf(s) for s in streams) else None
    order = _tree_order(graph, scene.tree)
    bins = bins_over(*_axis(recording, streams), rows=len(order) + len(streams))
    pause_floor = from_sec(scene.thresholds.max_gap)
    edges = edge_timelines(buffer, timeline, bins, pause_floor, order)
    flows = stream_timelines(timeline, bins, streams, sensors) if sensors else []
    facts = list(recording_facts(recording))
    if sensors:
        topics = ", ".join(s.topic for s in sensors.streams)
        facts.append(("Sensor data", f"{topics}: checked in {sensors.target} ({sensors.target_reason})"))
    return RecordingReport(
        name=" + ".join(recording.paths),
        facts=tuple(facts),
        findings=tuple(findings),
        graph=graph,
        bins=bins,
        edges=tuple(edges),
        streams=tuple(flows),
        delays_unavailable=timeline.delays_unavailable,
        origin=timeline.origin,
        # where tf has data
        poses=frame_poses(buffer, scene.tree, timeline.tf_start, timeline.tf_end, timeline=timeline),
        problems=tuple(recording.problems),
        other_clock=frozenset(
            t for f in findings for t in (f.first_time, f.last_time) if t and timeline.since_origin(t) is None
        ),
        delays_shown=timeline.delays_anywhere,
        delays_other_clock=frozenset(timeline.on_other_clock(e.child for e in edges)),
        delays_other_clock_why=timeline.other_clock_delays(e.child for e in edges),
    )


def _without_transforms(recording: Recording, findings: Sequence[Finding], graph: FrameGraph) -> RecordingReport:
    """The report of a recording without any transform: its facts, what it holds instead among them, and its
    findings (``no_tf``); no tree, timeline, sensor data checked in a frame or 3D view, there being no frame."""
    facts = [(name, said) for name, said in recording_facts(recording) if name not in _OF_TF]
    topics = {topic: kind for file in recording.contents.files for topic, kind in file.topics.items()}
    held = ", ".join(f"{topic} ({kind})" for topic, kind in sorted(topics.items())) or "no message"
    facts.append(("Holds", held))
    return RecordingReport(
        name=" + ".join(recording.paths),
        facts=tuple(facts),
        findings=tuple(findings),
        graph=graph,
        bins=bins_over(recording.start, recording.end),
        edges=(),
        streams=(),
        delays_unavailable="",
        origin=recording.timeline.origin,
        problems=tuple(recording.problems),
        delays_shown=False,
    )


#: The facts about tf's stamps and frames, which a recording without transforms has none of.
_OF_TF = ("tf stamps", "Clocks", "Frames")


def _tree_order(graph: FrameGraph, tree: FrameTree) -> list[tuple[str, str]]:
    """The graph's edges as the tree's lines run, top to bottom (``FrameTree.walk``); edges into frames
    under no root (a loop) last."""
    line = {frame: i for i, (_, frame, _) in enumerate(tree.walk())}
    keys = [e.key for e in graph.edges]
    return sorted(keys, key=lambda key: line.get(key[1], len(line)))


def _axis(recording: Recording, streams: Sequence[StampedMessages]) -> tuple[int, int]:
    """The stretch the timelines cover: the dynamic edges', and the sensor data's arrivals within as long
    again on either side (a stamp far off must not squash the rest into a point)."""
    timeline = recording.timeline
    start, end = edge_axis(recording.buffer, timeline)
    data = stream_axis(streams, timeline)
    if data is not None:
        slack = max(end - start, NS_PER_S)
        start, end = min(start, max(data[0], start - slack)), max(end, min(data[1], end + slack))
    return start, end


def recording_facts(recording: Recording) -> list[tuple[str, str]]:
    """What the recording is: its files and formats, clocks, span and contents, and what could not be read."""
    contents, timeline, buffer = recording.contents, recording.timeline, recording.buffer
    clocks = timeline.describe() + _off_clock(recording)
    if len(timeline.clock) and timeline.reference is not Reference.CLOCK:
        clocks += f"; {len(timeline.clock)} messages on {timeline.clock.topic} recorded"
    edges = [hist.static for _, _, hist, _ in edge_rows(buffer)]  # an edge per parent, as view-frames counts
    facts = [
        ("Files", ", ".join(recording.paths)),
        ("Format", ", ".join(dict.fromkeys(f.format for f in contents.files))),
        ("tf2 semantics", TF2_NAMES.get(buffer.semantics, buffer.semantics)),
        *_spans(recording),
        ("Clocks", clocks),
        ("Transforms", _transforms(recording)),
        (
            "Frames",
            f"{len(buffer.frames)} frames; {edges.count(False)} moving and {edges.count(True)} static transforms",
        ),
    ]
    facts += [("Could not read", problem) for problem in recording.problems]
    return facts


def _spans(recording: Recording) -> list[tuple[str, str]]:
    """The record span and tf's stamps' span; where the record times are no clock (``Timeline.stamped``), tf's
    stamps' alone, the recording's one span, as wtf's header and view-frames' legend give it."""
    timeline = recording.timeline
    if timeline.stamped is not None:
        first, last = timeline.stamped
        over = f"{(last - first) / NS_PER_S:.3f} s from {_when(first)} to {_when(last)}"
        return [("Recorded", f"tf stamped over {over} ({NO_RECORD_CLOCK})")]
    length = (recording.end - recording.start) / NS_PER_S
    tf_length = (timeline.tf_end - timeline.tf_start) / NS_PER_S
    return [
        ("Recorded", f"{_when(recording.start)} to {_when(recording.end)} ({length:.3f} s, record clock)"),
        ("tf stamps", f"{_when(timeline.tf_start)} to {_when(timeline.tf_end)} ({tf_length:.3f} s)"),
    ]


def _transforms(recording: Recording) -> str:
    """How many transforms, on which topics in how many messages (as the files name them), and which topics
    asked for held none: not 'on /tf, /tf_static' for a bag that recorded no /tf_static."""
    messages: dict[str, list[int]] = {}
    for file in recording.contents.files:
        for topic, (count, empty) in file.tf_messages.items():
            held = messages.setdefault(topic, [0, 0])
            held[0], held[1] = held[0] + count, held[1] + empty
    asked = recording.contents.topics
    if not messages:  # a live system, or a buffer: what was asked for
        return f"{recording.transform_count or 'none'} on {', '.join(asked)}"
    said = [
        f"{count:,} message{'s' * (count != 1)} on {topic}{f' ({empty:,} empty)' if empty else ''}"
        for topic, (count, empty) in messages.items()
        if count
    ]
    recorded = {global_name(topic) for topic, (count, _) in messages.items() if count}
    none = [topic for topic in asked if global_name(topic) not in recorded]
    return f"{recording.transform_count:,} in {', '.join(said) or 'no message'}" + (
        f"; none on {', '.join(none)}" if none else ""
    )


def _off_clock(recording: Recording) -> str:
    """The frames stamped on another clock than the others (``Timeline.off_reference``) and their stamps' span,
    which the tf stamps' span leaves out ("" where there are none)."""
    off = sorted(recording.timeline.off_reference)
    stamps = [h.stamps for h in map(recording.buffer.history, off) if h is not None and len(h)]
    if not stamps:
        return ""
    names = ", ".join(off[:4]) + (f" and {len(off) - 4} more" if len(off) > 4 else "")
    low, high = min(int(s.min()) for s in stamps), max(int(s.max()) for s in stamps)
    verb = "is" if len(off) == 1 else "are"
    return f"; but {names} {verb} stamped on another clock, {_when(low)} to {_when(high)} (not in the tf stamps' span)"


def _when(ns: int) -> str:
    """A time as seconds, with its UTC date where it counts from the epoch."""
    seconds = format_sec(ns, 3)
    if ns < EPOCH_FLOOR:
        return seconds
    return f"{seconds} ({datetime.fromtimestamp(ns / NS_PER_S, timezone.utc):%Y-%m-%d %H:%M:%S} UTC)"
