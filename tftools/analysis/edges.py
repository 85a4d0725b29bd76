"""Per-edge and per-publisher statistics of a buffer: rates, intervals, delays (tf_monitor's numbers), each
figure as ``core.figures`` defines it, in ns."""

from __future__ import annotations

import dataclasses
import itertools
import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import numpy as np

from tftools.analysis.detections import detection_sightings
from tftools.core.arrays import BoolArray, Int32Array, Int64Array, IntpArray, UInt8Array
from tftools.core.batch import TransformBatch
from tftools.core.buffer import Buffer
from tftools.core.errors import TransformError
from tftools.core.figures import (
    Sightings,
    base_near,
    jitter,
    longest_interval,
    mean_max,
    message_rate,
    rate_of,
    record_span,
    silence,
    time_bases,
)
from tftools.core.history import FROM_STATIC_TOPIC, EdgeHistory
from tftools.core.stored import with_replaced
from tftools.sources import clocks_apart
from tftools.sources.contents import SentMessages
from tftools.sources.timeline import ON_RECORD_CLOCK, Timeline
from tftools.values import value


@value
class TimeWindow:
    """Which samples a statistic counts: those stamped in ``[start, end]`` (ns; None: open), or with
    ``by_record_time`` those that arrived then (``Timeline.arrival``; the stamp where that is unknown): what a
    live monitor saw in its last seconds; static ones always. ``timeline`` turns record times into ROS time (a
    recording's); without it, record times are ROS time (a live buffer's). ``until``: the record time an open
    window's silences end at (a recording's end: ``edge_stats``)."""

    start: int | None = None
    end: int | None = None
    by_record_time: bool = False
    timeline: Timeline | None = None
    until: int | None = None

    @property
    def clock(self) -> Timeline:
        """The timeline that times arrivals (``ON_RECORD_CLOCK`` where none was given)."""
        return self.timeline or ON_RECORD_CLOCK

    def times(self, stamps: Int64Array, record_times: Int64Array) -> Int64Array:
        """The times the window selects by: stamps, or with ``by_record_time`` the arrivals
        (``Timeline.arrival``)."""
        return self.clock.arrival(stamps, record_times) if self.by_record_time else stamps

    def holds(self, stamps: Int64Array, record_times: Int64Array, static: BoolArray | bool = False) -> BoolArray:
        """Which samples (stamped ``stamps``, recorded at ``record_times``) are in it: ``static`` ones always."""
        if static is True:
            return np.ones(len(stamps), np.bool_)
        return self.inside(self.times(stamps, record_times), static)

    def inside(self, times: Int64Array, static: BoolArray | bool = False) -> BoolArray:
        """Which of the ``times`` (``TimeWindow.times``) are in the window: ``static`` ones always."""
        inside = np.ones(len(times), np.bool_)
        if self.start is not None:
            inside &= times >= self.start
        if self.end is not None:
            inside &= times <= self.end
        held: BoolArray = inside | static
        return held


#: Every sample, stamps on the record clock: a whole live buffer's window.
WHOLE = TimeWindow()


@dataclass(frozen=True)
class Edge:
    """A parent -> child edge, by its frames' names."""

    parent: str
    child: str

    @property
    def key(self) -> tuple[str, str]:
        return (self.parent, self.child)


@dataclass(frozen=True)
class EdgeStats(Edge):
    """One parent -> child edge over a time window.

    Rates and intervals come from the stamps (sorted, as tf2 stores them); delays are ROS time at
    arrival minus stamp (``Timeline.delays``), NaN where that is unknown and for static edges. Durations in ns.
    """

    static: bool
    count: int
    authorities: tuple[str, ...]
    first_stamp: int
    last_stamp: int
    rate_hz: float  # (count - 1) / stamp span; 0 for static or single samples
    jitter: float  # standard deviation of the intervals between stamps
    longest_interval: int  # the longest interval between two consecutive stamps (``figures.longest_interval``)
    longest_interval_start: int  # stamp where that interval begins
    delay_mean: float  # NaN where no delay is known
    delay_max: float
    last_record: int  # latest record time (0 where unknown)
    clocks: int = 1  # the time bases its stamps are on (``figures.time_bases``): 2 for a replay's beside a live one's
    apart: int = 0  # how far (ns) its stamps run ahead of their arrival where that leaves no delay (``apart``)
    # since its last arrival to the window's or recording's end (``figures.silence``); 0 if static, None: unknown
    silent_for: int | None = 0
    # a detection's bursts of sightings in the window (``detections.detection_sightings``); None for any other
    sightings: Sightings | None = None

    @property
    def once(self) -> bool:
        """One moving sample in the window: it has no rate nor jitter (their 0 is none: "-" in tables, null in
        JSON), and no gap but one from a sample before the window."""
        return not self.static and self.count < 2


@dataclass(frozen=True)
class AuthorityStats:
    """One publisher: its messages (``messages_in_window``) and their rate, its edges, and
    the mean and largest delay (ns) of its transforms on /tf (tf_monitor's "Node:" line, ``_sent_delays``)."""

    authority: str
    messages: int
    rate_hz: float
    edges: tuple[tuple[str, str], ...]
    delay_mean: float = math.nan
    delay_max: float = math.nan
    static: bool = False  # all its messages came on /tf_static (those of an edge later sent on /tf too)
    apart: int = 0  # how far (ns) its stamps run ahead of their arrival where that leaves no delay (``apart``)
    # where its delay is over some of its moving edges only (the others on another clock, or under /clock's
    # ticks: a simulated robot beside a device on the wall clock): those measured and those not; () where all are
    delay_of: tuple[str, ...] = ()
    no_delay_of: tuple[str, ...] = ()
    #: How many transforms its delay is over (``_sent_delays``), and how many of them no edge's delay holds
    #: (``edge_delays``): those tf2 refused or did not store again (re-sent stamps), and those of a frame tf2
    #: holds static though sent on /tf. Where some are, its delay and its edges' may differ, each right.
    delays_counted: int = 0
    delays_beyond_edges: int = 0
    #: Each frame it sent on /tf came once in the window (one-shot transforms): its messages have no rhythm, and
    #: a rate over two of them 1 ms apart would say 1000 a second.
    once: bool = False


def edge_stats(buffer: Buffer, window: TimeWindow = WHOLE) -> list[EdgeStats]:
    """Statistics of every edge with samples in the ``window`` (static edges always).

    The longest interval counts every interval that overlaps the window, the one from the last sample before it
    too; by arrival (``TimeWindow.by_record_time``), the silence since the last arrival is counted apart
    (``figures.silence``), to the window's end or, where it is open, to ``TimeWindow.until``: the record time the
    recording ends at, counted on the
    record clock as ``stale`` counts it (ROS time at its end is a guess where no clock gives arrivals: the newest
    stamp, a map -> odom post-dated 1 s by AMCL). An edge that stopped says so at once, the same in a whole
    recording, its replay and a live window; never where staleness cannot be measured (``Timeline.available``: a
    simulation at 0.07x real time recorded without /clock, its rates on simulated time, its silences on wall time).
    """
    timeline = window.clock
    result = []
    for parent, child, hist, mine in edge_rows(buffer):
        rows = _window(hist, window) & mine
        if rows.any():
            before = _previous_stamp(hist, mine, rows) if window.start is not None else None
            silence_end = window.end if window.by_record_time and timeline.available else None
            counted_to = window.until if timeline.available else None
            since = _window_start_stamp(hist, rows, window) if before is not None else None
            result.append(_edge(buffer, child, parent, hist, rows, timeline, before, silence_end, counted_to, since))
    return result


def authority_stats(
    buffer: Buffer,
    window: TimeWindow = WHOLE,
    *,
    unstored: TransformBatch | None = None,
    sent: SentMessages | None = None,
) -> list[AuthorityStats]:
    """Each publisher's messages over the ``window`` (as ``edge_stats`` selects it) and its edges; ``unstored``:
    the rows tf2 refused or took again without storing them (``Recording.refused``; default: the refused
    ones the buffer's log keeps): their edges are the publisher's too.

    A message is counted as tf_monitor counts it, on arrival, whatever tf2 then kept of it: ``sent``, the
    messages as the source told them apart, counted by ``messages_in_window``. Its rate counts its /tf
    messages only: a latched static message sent once is not part of a rhythm (tf_monitor lists static
    publishers apart). Without ``sent`` (a buffer filled by hand, which knows no message boundaries), the
    messages are guessed from the rows that arrived in the window (``_guessed``).
    """
    delays: dict[int, list[Int64Array]] = {}
    aparts: dict[int, int] = {}
    edges: dict[int, list[tuple[str, str]]] = {}
    beyond: dict[int, int] = {}  # how many of each publisher's delays no edge's delay holds
    repeated: set[int] = set()  # the publishers that sent some frame on /tf more than once in the window
    timed: dict[int, list[str]] = {}  # the moving children whose delays each publisher's figure holds
    untimed: dict[int, list[str]] = {}  # and those it does not
    arrived: list[_Arrived] = []  # the rows, for a guess of the messages where ``sent`` does not tell them
    timeline = window.clock
    if unstored is None:
        unstored = buffer.rejections.rows()[0] if len(buffer.rejections) else TransformBatch.empty()
    refused = _unstored(unstored, window)
    # with the histories ROS 2's tf2 replaced when a child switched between /tf_static and /tf
    for child, hist in ((child, h) for child, current in buffer.histories() for h in with_replaced(current)):
        held = _window(hist, window)
        for authority in _ids(hist.authorities[held]):
            a = int(authority)
            mine = held & (hist.authorities == authority)
            extra = refused.pop((buffer.authorities[a], child, hist.static), None)
            if sent is None:
                arrived.append((a, hist.static, hist.record_times[mine], hist.stamps[mine]))
                arrived += [(a, hist.static, extra[1], extra[2])] if extra is not None else []
            if not hist.static and np.count_nonzero(mine) + (len(extra[1]) if extra is not None else 0) > 1:
                repeated.add(a)
            measured, unstored_measured = _sent_delays(child, hist, mine, timeline, extra)
            delays.setdefault(a, []).append(measured)
            beyond[a] = beyond.get(a, 0) + (len(measured) if hist.static else unstored_measured)
            if not hist.static:
                (timed if len(measured) else untimed).setdefault(a, []).append(child)
            aparts[a] = max(aparts.get(a, 0), _apart(child, hist, mine, timeline))
            edges.setdefault(a, []).extend((buffer.frame_name(int(p)), child) for p in _ids(hist.parents[mine]))
    known = {name: a for a, name in enumerate(buffer.authorities)}
    for (name, child, was_static), (parent, times, stamps) in refused.items():
        # the edge's only rows of this publisher were not stored (a live buffer keeps no cache ROS 2's tf2 replaced)
        if (index := known.get(name)) is not None:
            arrived.append((index, was_static, times, stamps))
            if not was_static and len(times) > 1:
                repeated.add(index)
            # a transform without frames names no edge (foxglove-wizard's drone.mcap: 17 default-made ones)
            edges.setdefault(index, []).extend([(parent, child)] if parent and child else [])
            unheld = timeline.delays(child, stamps, times, _topic_flags(was_static, len(stamps)))
            delays.setdefault(index, []).append(unheld)
            beyond[index] = beyond.get(index, 0) + len(unheld)
    if sent is None:  # the rows guessed into messages were those of the window: all of them count
        sent, window = _guessed(buffer.authorities, arrived), dataclasses.replace(window, start=None, end=None)
    counted = messages_in_window(sent, window)
    return [
        dataclasses.replace(
            _partly_timed(
                _counted(
                    buffer.authorities[a], counted.get(buffer.authorities[a]), edges[a], delays[a], aparts.get(a, 0)
                ),
                timed.get(a, []),
                untimed.get(a, []),
            ),
            delays_counted=sum(len(d) for d in delays[a]),
            delays_beyond_edges=beyond.get(a, 0),
            once=a not in repeated,
        )
        for a in sorted(edges, key=lambda a: buffer.authorities[a])
    ]


def _partly_timed(stats: AuthorityStats, timed: list[str], untimed: list[str]) -> AuthorityStats:
    """``stats`` saying which of its moving edges its delay is over, where it is over some of them only."""
    untimed = [child for child in untimed if child not in timed]
    if not (timed and untimed):
        return stats
    return dataclasses.replace(stats, delay_of=tuple(dict.fromkeys(timed)), no_delay_of=tuple(dict.fromkeys(untimed)))


#: Rows of one publisher that arrived: its id, whether on /tf_static, their record times and stamps.
_Arrived = tuple[int, bool, Int64Array, Int64Array]


def _guessed(authorities: Sequence[str], arrived: list[_Arrived]) -> SentMessages:
    """The messages of rows whose source did not tell them apart (a buffer filled by hand): the rows of one
    publisher on one topic kind at one record time are one message, or where that is unknown (0), at one stamp
    (a broadcaster sends its transforms of one instant together)."""
    if not arrived:
        return SentMessages.empty()
    authority = np.concatenate([np.full(len(r), a, np.int32) for a, _, r, _ in arrived])
    static = np.concatenate([np.full(len(r), s, bool) for _, s, r, _ in arrived])
    records = np.concatenate([r for _, _, r, _ in arrived])
    stamps = np.concatenate([t for _, _, _, t in arrived])
    timed = records != 0
    instant = np.where(timed, records, stamps)
    order = np.lexsort((stamps, instant, timed, static, authority))
    keys = np.stack([authority[order], static[order], timed[order], instant[order]]).astype(np.int64)
    first = order[np.flatnonzero(np.any(np.diff(keys, axis=1, prepend=-1), axis=0))]  # each one's earliest stamp
    first = first[np.argsort(records[first], kind="stable")]
    return SentMessages(authorities, authority[first], static[first], records[first], stamps[first])


@dataclass(frozen=True)
class Counted:
    """One publisher's messages in a window: how many came on /tf, how many on /tf_static, and the rate of
    its /tf ones that are timed (``messages_in_window``)."""

    moving: int
    static: int
    rate_hz: float


def messages_in_window(sent: SentMessages, window: TimeWindow = WHOLE) -> dict[str, Counted]:
    """The one definition of a publisher's messages in a window: those of ``sent`` in the ``window`` as
    ``edge_stats`` selects transforms (``TimeWindow.times``: by their first transform's stamp, or on the axis of
    arrivals, ``Timeline.arrival``), its /tf_static messages always; by publisher.

    They are windowed and rated (``figures.message_rate``) on the clock they arrived on (``Timeline.counted_at``),
    the same in a whole read and in its replay: a message whose arrival is unknown (a record time of 0) is
    windowed by its stamp and counted, not timed; where the record times are no clock, by stamp on each time
    base apart (the logistic cobot's /tf, an arm on simulated time beside detections on wall time, is not one
    span of 55 years)."""
    timeline = window.clock
    counted_at, timed = timeline.counted_at(sent.record_time, sent.stamp)
    inside = window.inside(window.times(sent.stamp, sent.record_time), sent.static)
    counted = {}
    for a in _ids(sent.authority[inside]):
        mine = inside & (sent.authority == a)
        moving = mine & ~sent.static
        statics = int(np.count_nonzero(mine & sent.static))
        rate = message_rate(counted_at[moving & timed])
        counted[sent.authorities[int(a)]] = Counted(int(np.count_nonzero(moving)), statics, rate)
    return counted


def _counted(
    name: str, counted: Counted | None, edges: list[tuple[str, str]], delays: list[Int64Array], apart: int = 0
) -> AuthorityStats:
    """The publisher's numbers from its messages ``counted`` (none: it sent none in the window): its rate over
    its /tf messages' times (``messages_in_window``)."""
    moving = counted.moving if counted is not None else 0
    statics = counted.static if counted is not None else 0
    rate = counted.rate_hz if counted is not None else 0.0
    mean, largest = mean_max(np.concatenate(delays) if delays else np.zeros(0, np.int64))
    only_static = not moving and statics > 0
    apart = apart if math.isnan(mean) else 0
    return AuthorityStats(name, moving + statics, rate, tuple(dict.fromkeys(edges)), mean, largest, only_static, apart)


def _unstored(
    rows: TransformBatch, window: TimeWindow
) -> dict[tuple[str, str, bool], tuple[str, Int64Array, Int64Array]]:
    """The record times and stamps of ``rows`` within the window (static ones always, as ``_window`` selects),
    per (publisher, child, static), with the edge's parent: they arrived, though the buffer holds none of them."""
    if not len(rows):
        return {}
    inside = window.holds(rows.stamp, rows.record_time, rows.static)
    found: dict[tuple[str, str, bool], tuple[str, list[Int64Array], list[Int64Array]]] = {}
    for was_static in (False, True):
        chosen = inside & (rows.static == was_static)
        if not chosen.any():  # np.split would give one empty group for no key
            continue
        authority, child, record = rows.authority[chosen], rows.child[chosen], rows.record_time[chosen]
        parent, stamp = rows.parent[chosen], rows.stamp[chosen]
        pairs = authority.astype(np.int64) * len(rows.frame_names) + child
        order = np.argsort(pairs, kind="stable")
        keys, starts = np.unique(pairs[order], return_index=True)
        groups = zip(keys, starts, np.split(record[order], starts[1:]), np.split(stamp[order], starts[1:]), strict=True)
        for key, first, times, stamps in groups:
            a, c = divmod(int(key), len(rows.frame_names))
            name = (rows.authorities[a], rows.frame_names[c].lstrip("/"), was_static)
            edge = found.setdefault(name, (rows.frame_names[int(parent[order][first])].lstrip("/"), [], []))
            edge[1].append(times)
            edge[2].append(stamps)
    return {
        key: (parent, np.concatenate(times), np.concatenate(stamps)) for key, (parent, times, stamps) in found.items()
    }


def sorted_unique(values: Int64Array) -> Int64Array:
    """``np.unique`` for arrays made of a few sorted runs: timsort merges runs in linear time."""
    ordered = np.sort(values, kind="stable")
    if len(ordered) < 2:
        return ordered
    keep = np.empty(len(ordered), bool)
    keep[0] = True
    np.not_equal(ordered[1:], ordered[:-1], out=keep[1:])
    return ordered[keep]


def _ids(values: Int32Array) -> IntpArray:
    """The distinct small non-negative ids in ``values``, ascending (faster than ``np.unique``)."""
    return np.flatnonzero(np.bincount(values)) if len(values) else np.zeros(0, np.intp)


def publishers(buffer: Buffer, authorities: Int32Array) -> tuple[str, ...]:
    """The names of the distinct ``authorities`` (ids of ``buffer``'s), by id."""
    if len(authorities) == 1:  # a static edge sent once: numpy's calls cost more than the answer
        return (buffer.authorities[int(authorities[0])],)
    return tuple(buffer.authorities[int(a)] for a in _ids(authorities))


def parents_in_order(hist: EdgeHistory) -> list[int]:
    """The ids of every parent ``hist`` had, first seen first: the one order a frame's history splits into edges."""
    parents = hist.parents
    if len(parents) == 1:
        return [int(parents[0])]
    if len(parents) and parents.min() == parents.max():  # the usual case: one parent ever
        return [int(parents[0])]
    arrival = hist.parents[np.argsort(hist.sequence, kind="stable")]
    ids, first = np.unique(arrival, return_index=True)
    return [int(i) for i in ids[np.argsort(first)]]


def edge_rows(buffer: Buffer) -> Iterator[tuple[str, str, EdgeHistory, BoolArray]]:
    """Each parent -> child edge of ``buffer``: its frames, its child's history, and which of the history's
    rows are the edge's (a frame that changed parent has an edge per parent, ``parents_in_order``)."""
    for child, hist in buffer.histories():
        for parent_id in parents_in_order(hist):
            yield buffer.frame_name(parent_id), child, hist, hist.parents == parent_id


def chain_edges(buffer: Buffer, frames: Sequence[str]) -> list[tuple[str, str]]:
    """The (parent, child) edges joining the neighbours of ``frames`` (a ``Buffer.chain``), in its order."""
    return [(b, a) if buffer.parent(a) == b else (a, b) for a, b in itertools.pairwise(frames)]


def _window(hist: EdgeHistory, window: TimeWindow) -> BoolArray:
    """The samples of ``hist`` in the ``window``: all of a static one."""
    return window.holds(hist.stamps, hist.record_times, hist.static)


def _window_start_stamp(hist: EdgeHistory, rows: BoolArray, window: TimeWindow) -> int | None:
    """The ``window``'s start on the edge's stamp axis: itself for a window of stamps; for one of arrivals, the
    stamp of its first sample in the window less how long after the start that sample arrived (a gap from a
    sample before the window is counted from here, ``figures.longest_interval``)."""
    if window.start is None or not window.by_record_time:
        return window.start
    first = int(np.argmax(rows))
    arrived = window.times(hist.stamps[first : first + 1], hist.record_times[first : first + 1])
    return int(hist.stamps[first]) - max(int(arrived[0]) - window.start, 0)


def _previous_stamp(hist: EdgeHistory, mine: BoolArray, rows: BoolArray) -> int | None:
    """The stamp of the edge's sample just before the first one in the window, if any."""
    if hist.static:
        return None
    earlier = np.flatnonzero(mine[: int(np.argmax(rows))])
    return int(hist.stamps[earlier[-1]]) if len(earlier) else None


def edge_delays(child: str, hist: EdgeHistory, rows: BoolArray, timeline: Timeline) -> tuple[Int64Array, BoolArray]:
    """The one definition of an edge's delays: those of its samples ``rows`` that have one (``Timeline.delays_of``),
    and which those are; none of a history tf2 holds static. ROS 1's tf2 makes a frame static for every time once
    it came on /tf_static, and each /tf sample of it then replaces its value for every time (the agv's lasers, the
    Neato's laser beside its URDF): no lookup waits for one, so how late it came is no edge's delay, in ``monitor``
    (whole and ``--play``), ``report`` and ``view-frames`` alike (a publisher's is the link's, ``_sent_delays``)."""
    if hist.static:
        return np.zeros(0, np.int64), np.zeros(int(np.count_nonzero(rows)), np.bool_)
    return timeline.delays_of(child, hist.stamps[rows], hist.record_times[rows], hist.flags[rows])


def _sent_delays(
    child: str,
    hist: EdgeHistory,
    rows: BoolArray,
    timeline: Timeline,
    unstored: tuple[str, Int64Array, Int64Array] | None = None,
) -> tuple[Int64Array, int]:
    """How late a publisher's transforms ``rows`` of ``child`` arrived, as tf_monitor's "Node:" line times every one
    it hears on /tf: those of a frame tf2 holds static too (no edge's delay, ``edge_delays``; the link's all the
    same: the Neato's driver's 413 odometries 0.7 ms late on average, its base_link static beside its URDF), and
    its ``unstored`` ones (``_unstored``: parent, record times, stamps) that tf2 refused or did not store again,
    counted among its messages all the same (Gazebo's drone pose re-sent at 1 kHz on 1 ms sim ticks: 2810
    messages, of which tf2 stored 574, were 1.46 ms late on average, not the stored ones' 1.1 ms). With how many
    of them are of the ``unstored`` ones."""
    stamps, times, flags = hist.stamps[rows], hist.record_times[rows], hist.flags[rows]
    held = len(stamps)
    if unstored is not None:
        _, more_times, more_stamps = unstored
        stamps, times = np.concatenate((stamps, more_stamps)), np.concatenate((times, more_times))
        flags = np.concatenate((flags, _topic_flags(hist.static, len(more_stamps))))
    found, measured = timeline.delays_of(child, stamps, times, flags)
    return found, int(np.count_nonzero(measured[held:]))


def _topic_flags(static: bool, count: int) -> UInt8Array:
    """``EdgeHistory.flags`` of ``count`` transforms that came on /tf_static (``static``) or /tf."""
    return np.full(count, FROM_STATIC_TOPIC if static else 0, np.uint8)


def _apart(child: str, hist: EdgeHistory, rows: BoolArray, timeline: Timeline) -> int:
    if hist.static or not rows.any():
        return 0
    return clocks_apart.apart(timeline, child, hist.stamps[rows], hist.record_times[rows], hist.flags[rows])


def _edge(
    buffer: Buffer,
    child: str,
    parent: str,
    hist: EdgeHistory,
    rows: BoolArray,
    timeline: Timeline,
    before: int | None,
    silence_end: int | None,
    until: int | None = None,
    since: int | None = None,
) -> EdgeStats:
    stamps = hist.stamps[rows]  # a dynamic history is sorted by stamp already
    records = hist.record_times[rows]
    dynamic = not hist.static
    arrived = int(timeline.arrival(stamps, records).max())
    span = record_span(records)  # no figure across two time bases (``figures.across_clocks``)
    longest, longest_start = longest_interval(stamps if dynamic else stamps[:1], before, span, since)
    delay_mean, delay_max = mean_max(edge_delays(child, hist, rows, timeline)[0])
    return EdgeStats(
        parent=parent,
        child=child,
        static=hist.static,
        count=len(stamps),
        authorities=publishers(buffer, hist.authorities[rows]),
        first_stamp=int(stamps.min()),
        last_stamp=int(stamps.max()),
        rate_hz=rate_of(stamps, span, records) if dynamic else 0.0,
        jitter=jitter(stamps, span) if dynamic else 0.0,
        longest_interval=longest if dynamic else 0,
        longest_interval_start=longest_start,
        delay_mean=delay_mean,
        delay_max=delay_max,
        last_record=int(records.max()),
        clocks=time_bases(stamps, span) if dynamic else 1,
        apart=_apart(child, hist, rows, timeline),
        silent_for=0 if not dynamic else _silent(arrived, silence_end, int(records.max()), until),
        sightings=detection_sightings(parent, child, stamps, span) if dynamic else None,
    )


def history_rate(hist: EdgeHistory, near: Int64Array | None = None, rows: BoolArray | None = None) -> float:
    """The rate of a frame's whole history as ``edge_stats`` counts an edge's (``figures.rate_of``: on its time
    bases, placed on the record clock); 0 for a static one. Given the stamps of messages that wait for it
    (``near``), the rate of its samples on their clock alone (``figures.base_near``): of an edge two
    publishers send on clocks 5.8 h apart, the one whose samples those messages can meet. Given ``rows`` (the
    samples under one of a re-parented frame's parents, ``edge_rows``), that edge's, as ``edge_stats`` has it."""
    if hist.static:
        return 0.0
    stamps, records = hist.stamps, hist.record_times
    if rows is not None and rows.any():
        stamps, records = stamps[rows], records[rows]
    if near is not None:
        mine = base_near(stamps, record_span(records), near)
        stamps, records = (stamps, records) if mine.all() else (stamps[mine], records[mine])
    return rate_of(stamps, record_span(records), records)


def _silent(arrived: int, end: int | None, last_record: int, until: int | None) -> int | None:
    """An edge's silence (``figures.silence``): since its last arrival in ROS time to a window's ``end``, else
    since its last record time to the record time ``until`` (a whole recording's end)."""
    return silence(arrived, end) if end is not None else silence(last_record, until)


def chain_moving_edges(buffer: Buffer, target: str, source: str) -> dict[str, EdgeHistory]:
    """The dynamic edges a lookup between the frames composes now (latest common time), by child frame
    (none where they are not connected)."""
    try:
        frames = buffer.chain(target, source)
    except TransformError:
        return {}
    edges = {}
    for name in frames:
        hist = buffer.history(name)
        if hist is not None and not hist.static and buffer.frame_name(hist.latest_parent) in frames:
            edges[name] = hist
    return edges
