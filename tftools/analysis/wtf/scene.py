"""``Scene``: one recording prepared for the checks: its rows under tf2's frame names, and how to name things."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import cached_property
from typing import TypeVar, cast

import numpy as np

from tftools.analysis.description import Robot
from tftools.analysis.detections import Sibling, by_siblings, detected
from tftools.analysis.edges import Edge, EdgeStats, TimeWindow, edge_rows, edge_stats, publishers
from tftools.analysis.expected import TreeShape, publishers_named
from tftools.analysis.filter import FilterQuery, FilterReport, filter_streams
from tftools.analysis.findings import Finding, Severity, counted
from tftools.analysis.frames import FrameTree, tree_of
from tftools.analysis.wtf.rows import Rows, rows_of
from tftools.analysis.wtf.thresholds import Thresholds
from tftools.core.arrays import FloatArray, Int64Array, IntpArray, UInt8Array
from tftools.core.buffer import Buffer
from tftools.core.figures import Sightings, record_span
from tftools.core.frames import base_name as base_name  # said by many checks
from tftools.core.time import NS_PER_S, from_sec, signed_seconds
from tftools.core.time import duration as duration  # said by every check
from tftools.sources import clocks_apart
from tftools.sources.contents import StampedMessages
from tftools.sources.recording import Recording, recording_of_buffer
from tftools.sources.timeline import Reference

T = TypeVar("T")

#: A sample's second in a replay and its stamp's further apart than this (s) are both said (``Scene.at``): a
#: replay's start offset picked by the stamp's would miss it.
HEARD_APART = 0.5


@dataclass(frozen=True)
class EdgeSamples(Edge):
    """The samples tf2 stored for one parent -> child edge (dynamic), sorted by stamp."""

    stamps: Int64Array
    record_times: Int64Array
    values: FloatArray
    flags: UInt8Array  # ``EdgeHistory.flags``
    authorities: tuple[str, ...]

    def finding(self, severity: Severity, code: str, message: str, hint: str, times: Int64Array) -> Finding:
        """A finding about this edge's samples at ``times``: their stamps, or when they arrived (on the stamps'
        clock) where the message says so."""
        first, last = int(times.min()), int(times.max())
        return Finding(severity, code, message, hint, self.key, self.authorities, first, last, len(times))

    def recorded_at(self, stamp: int) -> int:
        """The record time of its sample stamped ``stamp`` (0: none, or unknown): where that one sample arrived."""
        at = int(np.searchsorted(self.stamps, stamp))
        return int(self.record_times[at]) if at < len(self.stamps) and self.stamps[at] == stamp else 0


class Scene:
    """A recording as the checks see it: the buffer tf2 would hold, the raw rows, the thresholds,
    and the wording shared by findings (edges, publishers, times). A bare buffer is seen as the
    recording of what it holds (``recording_of_buffer``)."""

    def __init__(
        self,
        recording: Recording | Buffer,
        thresholds: Thresholds | None = None,
        streams: Sequence[StampedMessages] = (),
        target: str | None = None,
        expected: TreeShape | None = None,
        robot: Robot | None = None,
    ) -> None:
        if isinstance(recording, Buffer):
            recording = recording_of_buffer(recording)
        self.recording = recording
        self.streams = streams  # the recording's sensor data (messages with a header), for the sensor checks
        self.target = target  # the frame that data is transformed into (None: the usual one)
        self.expected = expected  # the tree it should have (--expect), if any
        self.robot = robot  # its description and joint states (--urdf, or recorded), if any
        self.buffer = recording.buffer
        self.thresholds = thresholds if thresholds is not None else Thresholds()
        self.timeline = recording.timeline.within(from_sec(self.thresholds.clock))
        self.start = recording.start  # the record clock's span
        self.end = recording.end
        self._shared: dict[str, object] = {}

    def shared(self, key: str, compute: Callable[[], T]) -> T:
        """What several checks need, computed once per scene."""
        if key not in self._shared:
            self._shared[key] = compute()
        return cast(T, self._shared[key])

    @cached_property
    def rows(self) -> Rows:
        return rows_of(self.recording)

    @cached_property
    def sensors(self) -> FilterReport:
        """What a MessageFilter into the target frame made of each sensor stream."""
        query = FilterQuery(target=self.target)
        return filter_streams(self.buffer, self.streams, query, self.tree, self.timeline.record_step)

    @cached_property
    def tree(self) -> FrameTree:
        return tree_of(self.buffer)

    @cached_property
    def stats(self) -> list[EdgeStats]:
        """Each edge's figures over the whole recording, its silence to the recording's end as monitor's."""
        return edge_stats(self.buffer, TimeWindow(timeline=self.timeline, until=self.timeline.record_end))

    @property
    def ros2(self) -> bool:
        """Whether the recording is ROS 2's (its tf2's rules, and ROS 2's commands in hints)."""
        return self.buffer.semantics == "ros2"

    def list_publishers(self, topic: str) -> str:
        """The command that lists ``topic``'s publishers on a live system of the recording's ROS."""
        return f"ros2 topic info {topic} --verbose" if self.ros2 else f"rostopic info {topic}"

    @cached_property
    def publishers_known(self) -> bool:
        return publishers_named(self.recording)

    @cached_property
    def dynamic_edges(self) -> list[EdgeSamples]:
        """Each moving edge's stored samples, per parent the child ever had."""
        result = []
        for parent, child, hist, rows in edge_rows(self.buffer):
            if hist.static:
                continue
            mine = slice(None) if rows.all() else rows  # one parent (the usual case): the history's arrays, not copies
            result.append(
                EdgeSamples(
                    parent=parent,
                    child=child,
                    stamps=hist.stamps[mine],
                    record_times=hist.record_times[mine],
                    values=hist.values[mine],
                    flags=hist.flags[mine],
                    authorities=publishers(self.buffer, hist.authorities[mine]),
                )
            )
        return result

    @cached_property
    def detections(self) -> dict[tuple[str, str], tuple[str, Sightings | None]]:
        """The moving edges that are a detector's (``detections.detection``, or ``detections.by_siblings``): why,
        and how they were seen (``figures.sightings``; None where never unseen or seen fewer than 3 times)."""
        found = {}
        for e in self.dynamic_edges:
            if (seen := detected(e.parent, e.child, e.stamps, record_span(e.record_times))) is not None:
                found[e.key] = seen
        for key, sibling in self.siblings.items():  # never unseen (else ``detected`` saw it come and go): no sightings
            found.setdefault(key, (sibling.why, None))
        return found

    @cached_property
    def siblings(self) -> dict[tuple[str, str], Sibling]:
        """The moving edges that are a detector's by a sibling under a camera frame (``detections.by_siblings``)."""
        return by_siblings([(e.parent, e.child, e.stamps) for e in self.dynamic_edges])

    # --- rows ------------------------------------------------------------------------------

    def authorities_of(self, rows: IntpArray) -> tuple[str, ...]:
        """The publishers of ``rows``, in order of first appearance."""
        return tuple(self.rows.authorities[a] for a in dict.fromkeys(self.rows.authority[rows].tolist()))

    def arrival(self, rows: IntpArray) -> Int64Array:
        """When ``rows`` arrived, on the stamps' clock: ROS time at arrival, or stamps where unknown."""
        return self.timeline.arrival_on_stamps(self.rows.stamp[rows], self.rows.record_time[rows])

    def received(self, rows: IntpArray) -> Int64Array:
        """When the recorder received ``rows``, on the record clock (stamps where unknown): their rhythm."""
        records = self.rows.record_time[rows]
        return np.where(records > 0, records, self.rows.stamp[rows])

    def first_at(self, rows: IntpArray) -> str:
        """When the first of ``rows`` arrived (``at_row``)."""
        return self.at_row(int(rows[int(np.argmin(self.arrival(rows)))]))

    def at_row(self, row: int) -> str:
        """When transform ``row`` arrived (``arrival``), said by ``at`` with its record time."""
        rows = np.array([row], np.intp)
        return self.at(int(self.arrival(rows)[0]), int(self.rows.record_time[rows][0]))

    def finding(
        self,
        severity: Severity,
        code: str,
        message: str,
        hint: str,
        frames: tuple[str, ...],
        rows: IntpArray,
        times: Int64Array | None = None,
    ) -> Finding:
        """A finding about the transforms ``rows``: their publishers, count, and first and last ``times``
        (default: their stamps)."""
        times = self.rows.stamp[rows] if times is None else times
        first, last = int(times.min()), int(times.max())
        return Finding(severity, code, message, hint, frames, self.authorities_of(rows), first, last, len(rows))

    # --- wording ----------------------------------------------------------------------------

    def by(self, authorities: Sequence[str]) -> str:
        """' by /a and /b' (ROS1 names publishers), ' on /tf' (a ROS2 bag, or a ROS1 bag without callerids:
        the topics), or '' if unknown."""
        named = [a for a in authorities if a]
        if not named:
            return ""
        topics = self.recording.contents.topics
        if not self.publishers_known or all(a in topics for a in named):  # no node named: the topics
            return " on " + and_joined(named)
        return " by " + and_joined([self.publisher(a) for a in named])

    def publisher(self, authority: str) -> str:
        """A publisher as a person knows it: its node; where the recording names none, the topic it sent on."""
        if authority in self.recording.contents.topics:
            return f"a publisher on {authority} (unnamed)"
        return authority

    def at(self, stamp: int, recorded: int = 0) -> str:
        """A moment on the stamps' clock: absolute seconds, and seconds into the tf data where plausible
        (a stamp on another time base than the tf data's has none); ``recorded``: the record time of the one
        sample stamped so, where the finding is about one (``clocks_apart.placed``), and where a replay plays it
        at another second than its stamp's (``_heard``), that one too: "15.840 (+1.3 s; heard 19.6 s into the
        replay)". Every "first at" of a finding is said so."""
        since = self.timeline.since_origin(stamp)
        if since is None:
            return f"{stamp / NS_PER_S:.3f}{self._elsewhere(stamp, recorded)}"
        heard = self._heard(since, recorded)
        if signed_seconds(since).startswith("-"):  # what was observed, not a negative offset that reads as an error
            return f"{stamp / NS_PER_S:.3f} ({signed_seconds(-since)[1:]} s before the first tf stamp{heard})"
        return f"{stamp / NS_PER_S:.3f} ({signed_seconds(since)} s{heard})"

    def _heard(self, since: float, recorded: int) -> str:
        """Where the recording has no clock of its stamps (``Timeline.replay_shift``) and a replay plays the sample
        recorded at ``recorded`` more than ``HEARD_APART`` s from ``since`` (its stamp's second): "; heard 19.6 s into
        the replay", the second ``monitor --play --start`` counts (a simulation slower than real time, a robot's
        stamps on a clock drifting from the recorder's); "" where they agree, or a replay's second is unknown."""
        timeline = self.timeline
        if timeline.reference is not Reference.NONE or timeline.replayed or recorded <= 0:
            return ""
        heard = timeline.since_origin(recorded - timeline.replay_shift)
        if heard is None or abs(heard - since) <= HEARD_APART:
            return ""
        return f"; heard {heard:.1f} s into the replay"

    def rel(self, stamp: int) -> str:
        """Seconds into the tf data (``Timeline.origin``), or the absolute time on another time base."""
        since = self.timeline.since_origin(stamp)
        return (
            f"{signed_seconds(since)} s" if since is not None else f"at {stamp / NS_PER_S:.3f}{self._elsewhere(stamp)}"
        )

    def _elsewhere(self, stamp: int, recorded: int = 0) -> str:
        """Where a stamp on another clock than the tf span's falls in the recording (``clocks_apart.placed``; by
        its sample's own arrival where ``recorded`` gives it): " (on a clock 5.8 h ahead of the recorder's:
        +0.1 s)"; "" where the recording does not tell."""
        placed = clocks_apart.placed(self.timeline, stamp, recorded)
        if placed is None:
            return ""
        since, ahead = placed
        side = "ahead of" if ahead > 0 else "behind"
        return f" (on a clock {duration(abs(ahead) / NS_PER_S)} {side} the recorder's: {signed_seconds(since)} s)"

    def ros_times(self, record_times: Sequence[int]) -> list[int]:
        """ROS time at the arrival of messages recorded at ``record_times``, 0 where unknown: the clock of a
        finding's ``first_time`` and ``last_time`` where it is about arrivals (as a stamp is, on the stamps'
        clock), never the record clock (record times months from the stamps read "(another clock)")."""
        ros, known = self.timeline.ros_time(np.array(record_times, np.int64))
        return [int(t) for t in np.where(known, ros, 0)]

    def at_arrival(self, record_time: int) -> str:
        """When a message arrived: in ROS time where the timeline knows it, else on the record clock."""
        ros, known = self.timeline.ros_time(np.array([record_time], np.int64))
        if known[0]:
            return self.at(int(ros[0]))
        since = signed_seconds((record_time - self.start) / NS_PER_S)
        return f"{record_time / NS_PER_S:.3f} on the record clock ({since} s)"


def edge(parent: str, child: str) -> str:
    return f"{parent} -> {child}"


def and_joined(items: Sequence[str], most: int | None = None) -> str:
    """ "a", "a and b", "a, b and c"; past ``most`` items, ``listed``'s "a, b, c and N more"."""
    if most is not None and len(items) > most:
        return listed(items, most)
    return items[0] if len(items) == 1 else f"{', '.join(items[:-1])} and {items[-1]}"


def transforms(n: int) -> str:
    return counted(n, "transform")


def listed(items: Sequence[str], most: int = 6) -> str:
    """ "a, b, c" with at most ``most`` items, then "and N more"."""
    if len(items) <= most:
        return ", ".join(items)
    return f"{', '.join(items[:most])} and {len(items) - most} more"
