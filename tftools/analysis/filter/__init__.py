"""``tfx filter``'s work: what a ``tf2_ros::MessageFilter`` would have done to each stamped message of a
recording (``filter_messages(recording, query)``; each message's fate: ``fates``)."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

from tftools.analysis.filter.fates import (
    FilterReport,
    StreamReport,
    TfBegan,
    Unchecked,
    message_fates,
    recording_end,
    stream_report,
)
from tftools.analysis.filter.namesakes import namesakes
from tftools.analysis.frames import FrameTree, tree_of
from tftools.analysis.reading import Reading
from tftools.analysis.targets import choose_target, tied_to_tf
from tftools.core.buffer import DEFAULT_CACHE_TIME, Buffer
from tftools.core.frames import frame_name
from tftools.sources.codecs.select import placed_nowhere
from tftools.sources.contents import StampedMessages
from tftools.sources.errors import UNRECORDED, NoStampedDataError

if TYPE_CHECKING:
    from tftools.sources.recording import Recording

__all__ = ["FilterQuery", "FilterReport", "filter_messages", "filter_streams"]


@dataclass(frozen=True, slots=True, kw_only=True)
class FilterQuery:
    """What ``tfx filter`` asks: what a MessageFilter into ``target`` (``choose_target``: asked for where it is
    a frame of the recording, else REP 105's odom or map, else the largest tree's root) with a listener's
    cache of ``cache_time`` (ns), and optionally a timeout ``wait`` (ns) or a queue of ``queue`` messages,
    does to the messages of ``sensor_topics`` (None: every topic whose messages start with a header)."""

    target: str | None = None
    sensor_topics: tuple[str, ...] | None = None
    cache_time: int = DEFAULT_CACHE_TIME
    wait: int | None = None
    queue: int | None = None

    def reading(self) -> Reading:
        """What to read of a recording for it: tf and the headers of the topics asked for (all whose messages
        start with a header when none are named; live, ``capture_live`` takes ``reading().headers``)."""
        return Reading(headers=tuple(self.sensor_topics or ()))


def filter_messages(
    recording: Recording, query: FilterQuery, *, on_problem: Callable[[str], object] | None = None
) -> FilterReport:
    """``tfx filter``: a MessageFilter replayed on the sensor data ``recording`` was read or heard with
    (``query.reading()``) against its tf; what could not be read of the topics asked for goes to
    ``on_problem``. Where no topic has a header with a frame_id (a recording of /rosout alone: an empty table
    said nothing), a report of none that says why (``FilterReport.unchecked``: a recording of tf alone is no
    fault), or, where topics were named, ``NoStampedDataError``."""
    stamped = recording.stamped
    if not stamped.streams:
        nothing = NoStampedDataError([*stamped.problems, *_placed_nowhere(recording, query)])
        return _unchecked(recording, query, FilterReport("", "", query.cache_time, [], [], {}), nothing)
    for problem in stamped.problems:
        if on_problem is not None:
            on_problem(problem)
    report = filter_streams(recording.buffer, stamped.streams, query, tick=recording.timeline.record_step)
    unrecorded = [s.topic for s in stamped.streams if not len(s)]
    if not report.streams:
        whose = "whose header has" if len(report.skipped) == 1 else "whose headers have"
        unframed = [f"only {', '.join(report.skipped)}, {whose} no frame_id (not tied to tf)"] if report.skipped else []
        nothing = NoStampedDataError([*stamped.problems, *unframed, *_placed_nowhere(recording, query)], unrecorded)
        return _unchecked(recording, query, report, nothing)
    if query.sensor_topics and on_problem is not None:  # asked for by name: not left out of the table unsaid
        for topic in unrecorded:
            on_problem(f"{topic}: {UNRECORDED}")
    return report


def _unchecked(
    recording: Recording, query: FilterQuery, report: FilterReport, nothing: NoStampedDataError
) -> FilterReport:
    """``report`` (of no topic) saying why none was checked, and what the recording holds; ``nothing`` raised
    where topics were named: what was asked for is not there."""
    if query.sensor_topics:
        raise nothing
    target, reason = choose_target(tree_of(recording.buffer), query.target)
    topics = dict(sorted({t: kind for f in recording.contents.files for t, kind in f.topics.items()}.items()))
    hint = nothing.hint if nothing.unrecorded else ""
    unchecked = Unchecked(nothing.problems, topics, hint, recording.contents.live)
    return replace(report, target=target, target_reason=reason, unchecked=unchecked)


def _placed_nowhere(recording: Recording, query: FilterQuery) -> list[str]:
    """The topics not checked because their header places nothing in space (``placed_nowhere``: a gamepad's
    Joy, whose frame_id is joy_node's 'joy' or empty, no coordinate frame), said as what they are: the KTH
    arm's recording (ros2_mcap_kth_robp_arm_joy_no_tf_2025) holds /joy alone of such types."""
    if query.sensor_topics:  # asked for by name: read all the same
        return []
    topics = {t: kind for f in recording.contents.files for t, kind in f.topics.items() if placed_nowhere(kind)}
    return [
        f"{topic} is {kind}, {placed_nowhere(kind)}: its frame_id places nothing in space, so nothing ties "
        "it to tf (asked for by name, it is checked all the same)"
        for topic, kind in topics.items()
    ]


def filter_streams(
    buffer: Buffer,
    streams: Sequence[StampedMessages],
    query: FilterQuery,
    tree: FrameTree | None = None,
    tick: int = 0,
) -> FilterReport:
    """``filter_messages`` of ``streams`` against the tf in ``buffer`` (``tree``: its ``tree_of``, if
    already made; ``query.sensor_topics`` not looked at: the streams are those asked about; ``tick``: the
    step of the clock the record times were read off, ``Timeline.record_step``)."""
    tree = tree if tree is not None else tree_of(buffer)
    target, reason = choose_target(tree, query.target)
    end, began = recording_end(buffer, streams), TfBegan.of(buffer)
    reports, skipped, fates = [], [], {}
    for stream in streams:
        if not len(stream):  # recorded without a message: nothing says whether it names a frame
            continue
        if not tied_to_tf(stream):
            skipped.append(stream.topic)
            continue
        fates[stream.topic] = message_fates(buffer, stream, target, query.cache_time, end, began)
        reports.append(
            stream_report(buffer, stream, target, fates[stream.topic], query.wait, query.queue, end, tick, began)
        )
    return FilterReport(target, reason, query.cache_time, _with_namesakes(tree, reports), skipped, fates)


def _with_namesakes(tree: FrameTree, reports: list[StreamReport]) -> list[StreamReport]:
    """Each report of data lost to an unknown frame with that frame's namesakes in the tree (``namesakes``), among
    the frames no checked data is in."""
    data_frames = {frame_name(f) for r in reports for f in r.frame_ids if f}
    out = []
    for r in reports:
        missing = [f for f in r.frame_ids if f and frame_name(f) not in tree.frames]
        found = namesakes(missing, tree.frames, data_frames) if r.reasons.get("unknown_frame") else {}
        pairs = tuple((data, mount, tree.frames[mount].parent) for data, mount in found.items())
        out.append(replace(r, namesakes=pairs) if pairs else r)
    return out
