"""``StreamedRecording``: a recording read one window of record time after another and never held
whole, for replays: memory stays bounded however long the recording is.

A first pass over the windows learns what a replay needs to know up front (the frames, the tf's span,
which clock the stamps are on); ``replay`` then reads the windows again as the clock reaches them.
One ``BagReader`` serves every window of both: the files are opened and their indexes read once.
"""

from __future__ import annotations

import dataclasses
import math
import os
import weakref
from collections import deque
from collections.abc import Iterator, Sequence
from typing import TypeVar

import numpy as np

from tftools.core.arrays import BoolArray, Int64Array
from tftools.core.batch import TransformBatch, take_rows
from tftools.core.buffer import DEFAULT_CACHE_TIME, Buffer
from tftools.core.errors import TransformError
from tftools.core.figures import on_one_base, record_span, time_base_of
from tftools.core.semantics import Semantics
from tftools.core.stored import stored_rows
from tftools.core.transform import Transform
from tftools.sources.bag import BagReader, ProgressCallback
from tftools.sources.bag.contents import BagFileInfo, RecordWindow
from tftools.sources.contents import ClockSamples, OfferedQos, RecordingContents, SentMessages
from tftools.sources.edge_clocks import EdgeClock, edge_clock
from tftools.sources.recording import no_transforms, semantics_of
from tftools.sources.replay import Replay
from tftools.sources.timeline import (
    KeptArrivals,
    Playback,
    Reference,
    TickedGrid,
    Timeline,
    clocked_arrivals,
    records_on_clock,
    stamp_spans,
    tf_span,
    timeline_from,
    unclocked_time,
)

First = TypeVar("First")
Second = TypeVar("Second")

#: Messages (of every topic, as the files' indexes count them) a window is planned to hold.
WINDOW_MESSAGES = 50_000
#: Windows at most: a damaged index may count any number of messages (a day of 10 kHz tf still takes
#: windows of under a million messages).
MAX_WINDOWS = 1024
#: Arrivals per frame the clocks' medians are taken from: every one in a short recording, evenly
#: spaced ones over a long recording.
SAMPLES_PER_FRAME = 8192

_NONE = np.zeros(0, np.int64)

#: Record times read at once; None: the whole recording (a file without an index).
Window = RecordWindow | None


class StreamedRecording:
    """A recording described by a first pass over its windows, whose transforms ``replay`` reads again
    through the open ``reader`` (closed by ``close``, or when the recording is let go)."""

    def __init__(
        self,
        reader: BagReader,
        windows: Sequence[Window],
        contents: RecordingContents,
        recorded: Timeline,
        frames: Sequence[str],
        semantics: Semantics,
        parents: dict[str, tuple[str, bool]] | None = None,
        arrivals: dict[str, tuple[Int64Array, Int64Array]] | None = None,
        kept: KeptArrivals | None = None,
    ) -> None:
        self.reader = reader
        weakref.finalize(self, reader.close)  # closed when the stream is let go, if not before
        self.paths = list(reader.paths)
        self.topics = reader.topics
        self.windows = tuple(windows)
        self.contents = contents  # the files described: no parts, no clock
        self.frames = list(frames)
        self.semantics = semantics  # the tf2 a replay's buffer answers as
        #: The replay's timeline: its record times are replay times, on the stamps' clock (``Timeline.played``);
        #: ``kept``: the record times of the frames measured on them (``_Summary.kept_arrivals``).
        self.timeline = recorded.played(kept)
        self._recorded = recorded  # whose clock holds the first /clock sample only: enough for ``Playback``
        #: The tree as last seen: each child's latest parent, and whether its edge is static.
        self.parents = dict(parents or {})
        self._last_tree: Buffer | None = None  # ``_tree``, built on first use
        #: Each moving frame's arrivals kept by the first pass (``_Arrivals``): stamps in order, and when
        #: each plays (``Playback``'s times, estimated alike).
        self.arrivals = dict(arrivals or {})

    @property
    def unplayable(self) -> str:
        """Why the recording cannot be replayed by when its messages arrived ("" where it can): its record
        times are no clock (``Timeline.record_clock_void``)."""
        return self._recorded.reason if self._recorded.record_clock_void else ""

    def moving_chain(self, target: str, source: str) -> list[str]:
        """The children of the dynamic edges between the frames in the tree as last seen (their latest
        parents), as ``chain_moving_edges`` finds them in a whole read: through the buffer's one walk, on a
        buffer holding that tree; none where they are not connected."""
        try:
            frames = self._tree().chain(target, source)
        except TransformError:
            return []
        on_path = set(frames)
        return [f for f in frames if (edge := self.parents.get(f)) is not None and not edge[1] and edge[0] in on_path]

    def _tree(self) -> Buffer:
        """A buffer holding the tree as last seen: one sample of each edge, static where it was."""
        if self._last_tree is None:
            tree = Buffer(cache_time=None, semantics=self.semantics)
            for child, (parent, static) in self.parents.items():
                tree.set_transform(Transform(stamp=1, frame_id=parent, child_frame_id=child), static=static)
            self._last_tree = tree
        return self._last_tree

    def replay_time(self, stamp: int, frames: Sequence[str], *, last: bool = False) -> int:
        """When the first transform of ``frames`` (children) stamped at or after ``stamp`` plays, on the
        replay's clock (``last``: the last one stamped at or before it), as a whole read windows a chain by
        arrival (``monitored_window``); between the arrivals kept of a long recording, where its
        neighbours' would. ``stamp`` itself where no arrival of them is known."""
        times = []
        for child in frames:
            stamps, played = self.arrivals.get(child, (_NONE, _NONE))
            if len(stamps):
                beyond = stamp < stamps[0] if last else stamp > stamps[-1]  # none stamped on that side
                edge = int(played[0]) - 1 if last else int(played[-1]) + 1
                times.append(edge if beyond else _between(stamp, stamps, played, last))
        if not times:
            return stamp
        return max(times) if last else min(times)

    @property
    def problems(self) -> list[str]:
        return self.contents.problems

    def parts(self) -> Iterator[TransformBatch]:
        """Every transform in record order, window after window, its record time moved onto the
        stamps' clock (``Playback``)."""
        return (part for parts, _ in self._played() for part in parts)

    def _played(self, playback: Playback | None = None) -> Iterator[tuple[list[TransformBatch], SentMessages]]:
        """Each window's transforms and the tf messages they came in, their record times moved together onto
        the stamps' clock by ``playback`` (``Playback``: a message plays when its transforms do)."""
        playback = playback or Playback(self._recorded)
        for window in self.windows:
            contents = self.reader.read(window)
            playback.heard(contents.clock)
            sent = contents.sent or SentMessages.empty()
            records = [sent.record_time, *(part.record_time for part in contents.parts)]
            moved = _moved_together(playback, records)
            parts = [dataclasses.replace(p, record_time=t) for p, t in zip(contents.parts, moved[1:], strict=True)]
            yield parts, dataclasses.replace(sent, record_time=moved[0])

    def replay(self, *, rate: float = 1.0, start: int | None = None, end: int | None = None) -> Replay:
        """A replay on the clock the tf is stamped on: what a node with use_sim_time sees while the bag
        plays with its recorded /clock, or on its record clock; its ``on_sent`` is told the tf messages."""
        playback = Playback(self._recorded)
        rows, messages = _halves(self._played(playback))
        parts = (part for parts in rows for part in parts)
        # as rosbag play, to the recording's last message (any topic's), past its tf's: moved onto the replay's
        # clock once every window was, its /clock heard to the end
        last = self._recorded.record_end

        def played_end() -> int:
            return int(playback.moved(np.array([last], np.int64))[0])

        return Replay(
            parts,
            sent=messages,
            rate=rate,
            start=start,
            end=end,
            last=played_end if last else None,
        )

    def close(self) -> None:
        self.reader.close()

    def __enter__(self) -> StreamedRecording:
        return self

    def __exit__(self, *_: object) -> None:
        self.close()


def _moved_together(playback: Playback, records: Sequence[Int64Array]) -> list[Int64Array]:
    """``Playback.moved`` of several columns of record times (each sorted) as of one, sorted: equal record
    times play at one time."""
    joined = np.concatenate(records)
    order = np.argsort(joined, kind="stable")
    moved = np.empty_like(joined)
    moved[order] = playback.moved(joined[order])
    return np.split(moved, np.cumsum([len(r) for r in records])[:-1])


def _between(stamp: int, stamps: Int64Array, played: Int64Array, last: bool) -> int:
    """When the transform stamped ``stamp`` plays (the first or ``last`` so stamped), or one stamped between
    two kept would: interpolated in integers (a float's 0.2 us at epoch times would miss it)."""
    index = int(np.searchsorted(stamps, stamp, side="right" if last else "left"))
    exact = index - 1 if last else index
    if 0 <= exact < len(stamps) and stamps[exact] == stamp:
        return int(played[exact])
    before, after = index - 1, index  # stamps[before] < stamp < stamps[after]
    low, high = int(stamps[before]), int(stamps[after])
    return int(played[before]) + (int(played[after]) - int(played[before])) * (stamp - low) // (high - low)


def stream_recording(
    paths: Sequence[str | os.PathLike[str]],
    topics: Sequence[str] | None = None,
    progress: ProgressCallback | None = None,
    *,
    semantics: Semantics | None = None,
    window_messages: int = WINDOW_MESSAGES,
) -> StreamedRecording:
    """The recording at ``paths`` (see ``read_recording``), read in windows of about ``window_messages``
    messages to describe it; its transforms are read again by ``replay``. ``NoTransformsError`` when
    no transform was found."""
    reader = BagReader(paths, topics).__enter__()
    try:
        windows, summary = _first_pass(reader, window_messages, semantics, progress)
        if reader.strays_learnt():  # messages decades from the rest: the pass again without them, said
            windows, summary = _first_pass(reader, window_messages, semantics, progress)
        contents = RecordingContents([], summary.files, reader.topics, qos=summary.qos)
        if not summary.transforms:
            raise no_transforms(paths, contents)
    except BaseException:
        reader.close()
        raise
    start = contents.start if contents.start > 0 else summary.first_known or contents.start  # of known times
    recorded = timeline_from(
        summary.edges(),
        summary.first_clock,
        start,
        contents.end,
        tf_span(summary.spans.values(), start, contents.end),
        0 if records_on_clock(summary.first_clock) else summary.grid.step(),
    )
    arrivals = summary.played_arrivals(recorded)
    kept = summary.kept_arrivals(recorded)
    return StreamedRecording(
        reader, windows, contents, recorded, summary.frames, summary.semantics, summary.parents, arrivals, kept
    )


def _first_pass(
    reader: BagReader, window_messages: int, semantics: Semantics | None, progress: ProgressCallback | None
) -> tuple[tuple[Window, ...], _Summary]:
    """The recording described, cut in windows, each read once into what the replay needs to know of it."""
    described = reader.read(RecordWindow(0, 0))
    windows = _windows(described.files, window_messages)
    summary = _Summary(semantics or semantics_of(described), described.files, described.qos)
    for index, window in enumerate(windows):
        summary.add(reader.read(window, _share(progress, index, len(windows))))
    return windows, summary


def _halves(pairs: Iterator[tuple[First, Second]]) -> tuple[Iterator[First], Iterator[Second]]:
    """Two iterators over the first and the second of each of ``pairs``, each half held until its own iterator
    takes it, no longer: ``itertools.tee`` holds its items in blocks of 57, so a replay's windows (parts and
    messages) stayed in memory until 57 had been read, a long recording whole."""
    firsts: deque[First] = deque()
    seconds: deque[Second] = deque()

    def read() -> bool:
        pair = next(pairs, None)
        if pair is not None:
            firsts.append(pair[0])
            seconds.append(pair[1])
        return pair is not None

    def first() -> Iterator[First]:
        while firsts or read():
            yield firsts.popleft()

    def second() -> Iterator[Second]:
        while seconds or read():
            yield seconds.popleft()

    return first(), second()


def _windows(files: Sequence[BagFileInfo], messages: int) -> tuple[Window, ...]:
    """Windows of about ``messages`` messages each over the files' record span (the first and
    last open-ended); the whole recording at once when a file cannot be read by window."""
    counted = [f for f in files if f.message_count]
    if not counted or not all(f.windowed for f in files):
        return (None,)
    start, end = min(f.start for f in counted), max(f.end for f in counted)
    count = min(MAX_WINDOWS, max(1, math.ceil(sum(f.message_count for f in counted) / messages)))
    step = max(1, math.ceil((end - start + 1) / count))
    lowest, highest = int(np.iinfo(np.int64).min), int(np.iinfo(np.int64).max)
    bounds = [min(start + i * step, highest) for i in range(1, count)]
    return tuple(RecordWindow(first, last) for first, last in zip([lowest, *bounds], [*bounds, highest], strict=True))


def _share(progress: ProgressCallback | None, index: int, count: int) -> ProgressCallback | None:
    """Progress of window ``index`` of ``count`` as a share of the whole read."""
    if progress is None:
        return None

    def reported(done: int, total: int) -> None:
        if total:
            progress(round(total * (index + done / total) / count), total)

    return reported


#: Arrivals per frame a streamed recording keeps for its replay's times (``StreamedRecording.replay_time``):
#: every one of a short recording, evenly spaced ones (the first and last among them) of a long one, so
#: that what it keeps while it plays does not grow with its length (16 KiB a frame).
PLAYED_ARRIVALS = 1024

#: The /clock samples of a streamed recording's first window kept to tell how often /clock ticks.
CLOCK_STEPS = 1000


class _Summary:
    """What the first pass learns of a recording, window by window, in memory that does not grow with it."""

    def __init__(self, semantics: Semantics, files: Sequence[BagFileInfo], qos: dict[str, OfferedQos]) -> None:
        self.semantics = semantics
        self.files = [dataclasses.replace(f, problems=list(f.problems), transform_count=0) for f in files]
        self.qos = qos  # the ROS 2 bags' offered QoS, as their metadata (read before any window) says
        self.transforms = 0
        self.frames: list[str] = []
        self.parents: dict[str, tuple[str, bool]] = {}  # each child's latest parent, and whether static
        self.spans: dict[bool, tuple[bool, int, int]] = {}  # static or not: the stamps' span
        self.first_clock = ClockSamples.empty()
        self.first_known = 0  # the earliest known (positive) record time, 0 before any
        self._clock = ClockSamples.empty()  # the /clock samples of the last window, after the one before
        self._arrivals: dict[str, _Arrivals] = {}
        self._carried = TransformBatch.empty()  # the last window's recent samples (``_recent``)
        self.grid = TickedGrid()  # how coarse the record times are, where they show it

    def add(self, contents: RecordingContents) -> None:
        """One window's transforms, inserted into a buffer of their own to learn them as tf2 stores them."""
        for described, read in zip(self.files, contents.files, strict=True):
            described.transform_count += read.transform_count
            described.problems += [p for p in read.problems if p not in described.problems]
        self.transforms += sum(len(p) for p in contents.parts)
        for times in (contents.clock.record_time, *(p.record_time for p in contents.parts)):
            positive = times[times > 0]
            if len(positive) and not 0 < self.first_known <= int(positive.min()):
                self.first_known = int(positive.min())
        buffer = Buffer(cache_time=None, semantics=self.semantics)
        buffer.reserve([self._carried, *contents.parts])
        buffer.insert(self._carried)
        carried = buffer.arrivals
        for part in contents.parts:
            buffer.insert(part)
        self._carried = _recent(buffer, CARRIED)
        met = set(self.frames)
        self.frames += [f for f in buffer.frames if f not in met]
        for child, hist in buffer.histories():
            if len(hist):
                self.parents[child] = (buffer.frame_name(hist.latest_parent), hist.static)
        self.grid.add(contents.clock.record_time, [h for _, h in buffer.histories()])
        for static, first, last in stamp_spans(buffer):
            seen = self.spans.get(static, (static, first, last))
            self.spans[static] = (static, min(seen[1], first), max(seen[2], last))
        if len(contents.clock) and not len(self.first_clock):
            clock = contents.clock
            # the first samples: the first /clock, and how often it ticks (``Timeline.clock_step``)
            self.first_clock = ClockSamples(clock.topic, clock.record_time[:CLOCK_STEPS], clock.clock[:CLOCK_STEPS])
        self._clock = self._clock.continued(contents.clock)
        for child, stamps, records, ros, known in clocked_arrivals(buffer, self._clock, since=carried):
            self._arrivals.setdefault(child, _Arrivals()).add(stamps, records, ros, known)

    def played_arrivals(self, timeline: Timeline) -> dict[str, tuple[Int64Array, Int64Array]]:
        """Each frame's arrivals kept (at most ``PLAYED_ARRIVALS``), by stamp, and when they play on the replay
        of ``timeline``: their record times, /clock then (``unclocked_time`` before it ticked), or record times
        less ``Timeline.replay_shift``, as ``Playback`` moves them."""
        first = unclocked_time(timeline.clock) or 0
        played: dict[str, tuple[Int64Array, Int64Array]] = {}
        for child, arrivals in self._arrivals.items():
            stamps, records, ros, known = arrivals.kept()
            if timeline.reference is Reference.CLOCK:
                times = np.where(known, ros, first)
            else:
                times = records - timeline.replay_shift
            order = np.argsort(stamps, kind="stable")
            picked = order[np.unique(np.linspace(0, len(order) - 1, min(len(order), PLAYED_ARRIVALS)).astype(np.int64))]
            played[child] = stamps[picked], times[picked]
        return played

    def kept_arrivals(self, timeline: Timeline) -> KeptArrivals:
        """The arrivals kept of the frames measured on their record clock (``Timeline.record_clocked``): by
        stamp, their record times and when they play (/clock then, as ``Playback`` moves them)."""
        first = int(timeline.clock.clock[0]) if len(timeline.clock) else 0
        frames: dict[str, tuple[Int64Array, Int64Array, Int64Array]] = {}
        for child in timeline.record_clocked:
            stamps, records, ros, known = self._arrivals[child].kept()
            order = np.argsort(stamps, kind="stable")
            frames[child] = stamps[order], records[order], np.where(known, ros, first)[order]
        return KeptArrivals(frames, timeline.record_step)

    def edges(self) -> tuple[EdgeClock, ...]:
        """Each frame's clock from the arrivals kept (its medians), counting every arrival, spanning every stamp
        (those kept, on its main time base, where they are on several: ``edge_clock``)."""
        found = []
        for child, arrivals in self._arrivals.items():
            e = edge_clock(child, *arrivals.kept())
            span = arrivals.span if e.bases == 1 else (e.first_stamp, e.last_stamp)
            last_record = arrivals.last_record if e.bases == 1 else e.last_record
            found.append(
                dataclasses.replace(
                    e, arrivals=arrivals.seen, first_stamp=span[0], last_stamp=span[1], last_record=last_record
                )
            )
        return tuple(found)


#: How far behind its newest stamp an edge's samples are carried from one window into the next: a sample
#: sent again in a later window (a re-send, a repeated stamp) is then stored once, as a whole read stores
#: it, within tf2's default cache, which is as far back as a replay's listener would have held it.
CARRIED = DEFAULT_CACHE_TIME


def _recent(buffer: Buffer, within: int) -> TransformBatch:
    """What tells the next window's buffer what this one holds, in arrival order: the samples each moving
    edge holds at most ``within`` behind its newest stamp (which samples it already has), and each static
    cache's first and latest sample to arrive (that its frame is static, and its parent now). tf2 keeps a
    frame's cache kind across every sample: ROS 1's keeps the kind its first sample made (a frame latched
    on /tf_static stays static whatever /tf sends it later), ROS 2's makes a new cache when the kind
    changes; the next buffer, fed these first, applies its own rule."""
    recent = [
        np.array([hist.sequence.min(), hist.sequence.max()])
        if hist.static
        else hist.sequence[_near_newest(hist.stamps, hist.record_times, within)]
        for _, hist in buffer.histories()
        if len(hist)
    ]
    if not recent:
        return TransformBatch.empty()
    rows, sequence = stored_rows(buffer)
    return take_rows(rows, np.flatnonzero(np.isin(sequence, np.concatenate(recent))))


def _near_newest(stamps: Int64Array, records: Int64Array, within: int) -> BoolArray:
    """The samples stamped at most ``within`` behind the newest on their own time base (``time_base_of``): of
    an edge two publishers share on clocks hours apart (a ZED beside an EKF 5.8 h ahead), each one's latest,
    not the one clock's alone, or the other's re-sends in the next window are taken anew."""
    offsets, span = records - stamps, record_span(records)
    if on_one_base(offsets, span):  # the usual case: known from the ends alone, with no sort
        one: BoolArray = stamps >= stamps.max() - within
        return one
    base = time_base_of(offsets, span)
    newest = np.full(int(base.max()) + 1, np.iinfo(np.int64).min, np.int64)
    np.maximum.at(newest, base, stamps)
    near: BoolArray = stamps >= newest[base] - within
    return near


class _Arrivals:
    """One frame's arrivals (stamp, record time, /clock at arrival and where known), every ``stride``-th
    kept: all of them up to ``SAMPLES_PER_FRAME``, then every second one, every fourth..."""

    def __init__(self) -> None:
        self._parts: list[tuple[Int64Array, Int64Array, Int64Array, BoolArray]] = []
        self._seen = 0
        self._stride = 1
        self.span = (0, 0)  # the first and last stamp of every arrival, kept or not
        self.last_record = 0  # the last record time of every arrival, kept or not

    def add(self, stamps: Int64Array, records: Int64Array, ros: Int64Array, known: BoolArray) -> None:
        picked = np.arange((-self._seen) % self._stride, len(stamps), self._stride)
        first, last = int(stamps.min()), int(stamps.max())
        self.span = (min(self.span[0], first), max(self.span[1], last)) if self._seen else (first, last)
        self.last_record = max(self.last_record, int(records.max()))
        self._seen += len(stamps)
        self._parts.append((stamps[picked], records[picked], ros[picked], known[picked]))
        while sum(len(p[0]) for p in self._parts) > SAMPLES_PER_FRAME:
            stamps, records, ros, known = self.kept()
            self._parts = [(stamps[::2], records[::2], ros[::2], known[::2])]
            self._stride *= 2

    @property
    def seen(self) -> int:
        """Every arrival added, kept or not."""
        return self._seen

    def kept(self) -> tuple[Int64Array, Int64Array, Int64Array, BoolArray]:
        stamps, records, ros, known = (np.concatenate(column) for column in zip(*self._parts, strict=True))
        return stamps, records, ros, known
