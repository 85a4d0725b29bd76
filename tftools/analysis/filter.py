"""What a ``tf2_ros::MessageFilter`` would have done to each stamped message of a recording.

A MessageFilter holds each message until its ``header.frame_id`` can be transformed into the
target frame at ``header.stamp``, with only the tf that had arrived so far, in a listener whose
cache holds ``cache_time`` behind the newest stamp of each edge. Replaying that per message with a
Python loop over tf messages is slow; here each edge of the chain is reduced to step functions of
arrival time (the newest stamp held, the oldest stamp still held), and each message to a few
binary searches on them: transformable at arrival time ``t`` exactly when, for every moving edge,
the oldest stamp held at ``t`` <= stamp <= the newest stamp held at ``t`` (static edges: once one
arrived). A message is ready at the first such ``t`` from its arrival on, or never.
"""

from __future__ import annotations

import enum
import heapq
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from tftools.analysis.edges import Edge, chain_edges, rate_hz, silence_limit
from tftools.analysis.frames import FrameTree, frame_tree
from tftools.core.arrays import BoolArray, Int8Array, Int64Array, IntpArray
from tftools.core.buffer import DEFAULT_CACHE_TIME, Buffer
from tftools.core.errors import TransformError, UnknownFrameError
from tftools.core.time import NS_PER_S
from tftools.sources.contents import StampedMessages

#: A time that never comes.
NEVER = np.iinfo(np.int64).max


class Fate(enum.IntEnum):
    """What became of one message."""

    ON_ARRIVAL = 0  # transformable when it arrived
    LATER = 1  # after a wait for tf
    UNKNOWN_FRAME = 2  # never: its frame is in no transform (a misspelt frame_id?)
    NOT_CONNECTED = 3  # never: its frame and the target are in separate trees
    NEEDS_NEWER_TF = 4  # never: tf never reached its stamp (extrapolation into the future)
    OLDER_THAN_CACHE = 5  # never: by the time tf reached its stamp, the cache no longer held it
    BEFORE_RECORDED_TF = 6  # undecided: stamped before the recording's tf of an edge began
    AFTER_RECORDED_TF = 7  # undecided: still waiting when the recording's tf of an edge ended

    @property
    def reason(self) -> str:
        return self.name.lower()


#: Messages a filter loses for good; the recording cannot tell what became of the undecided ones.
LOST = (Fate.UNKNOWN_FRAME, Fate.NOT_CONNECTED, Fate.NEEDS_NEWER_TF, Fate.OLDER_THAN_CACHE)
UNDECIDED = (Fate.BEFORE_RECORDED_TF, Fate.AFTER_RECORDED_TF)


@dataclass(frozen=True)
class Fates:
    """Each message's fate: ``ready`` is when it became transformable (``NEVER`` if it did not);
    ``edge`` the (parent, child) that decided it (made it wait, never caught up, or had dropped its
    stamp), ``lag`` how far that edge's newest stamp was behind the message's stamp at arrival (ns)."""

    fate: Int8Array
    ready: Int64Array
    edge: Sequence[tuple[str, str] | None]
    lag: Int64Array

    @property
    def decided(self) -> int:
        """How many messages' fate the recording tells (not ``UNDECIDED``)."""
        return len(self.fate) - int(np.isin(self.fate, UNDECIDED).sum())

    def waits(self, messages: StampedMessages) -> Int64Array:
        """How long each message waited (ns), for those transformed after a wait."""
        later = self.fate == Fate.LATER
        waits: Int64Array = self.ready[later] - messages.record_time[later]
        return waits


@dataclass(frozen=True)
class _Edge(Edge):
    """One edge of a chain as a listener saw it fill: after each arrival (record times, sorted), the
    newest and the oldest stamp it held."""

    static: bool
    rate_hz: float
    records: Int64Array
    newest: Int64Array
    oldest: Int64Array

    def first_ready(self, stamps: Int64Array) -> Int64Array:
        """When the edge first held a stamp at or after each of ``stamps`` (any sample, for stamp 0)."""
        if not len(self.records):
            return np.full(len(stamps), NEVER, np.int64)
        if self.static:
            return np.full(len(stamps), self.records[0], np.int64)
        index = np.searchsorted(self.newest, stamps, side="left")
        index[stamps == 0] = 0
        return _at(self.records, index)

    def last_ready(self, stamps: Int64Array) -> Int64Array:
        """When the cache first dropped each of ``stamps`` (every sample it held is newer), else NEVER."""
        if self.static or not len(self.records):
            return np.full(len(stamps), NEVER, np.int64)
        index = np.searchsorted(self.oldest, stamps, side="right")
        index[stamps == 0] = len(self.records)
        return _at(self.records, index)

    def would_reach(self, stamps: Int64Array, end: int) -> BoolArray:
        """Whether the edge's next transforms, had the recording not ended at ``end``, would soon have
        reached each of ``stamps``: it was still being published (``silence_limit``, as ``stale`` has it),
        and the stamp is no further than that limit ahead of its newest."""
        if self.static or self.rate_hz <= 0:
            return np.zeros(len(stamps), np.bool_)
        limit = silence_limit(self.rate_hz)
        publishing = end - int(self.records[-1]) <= limit
        return np.asarray(publishing & (stamps - int(self.newest[-1]) <= limit), np.bool_)

    def newest_at(self, times: Int64Array) -> Int64Array:
        """The newest stamp held at each of ``times`` (-1 before the first arrival)."""
        index = np.searchsorted(self.records, times, side="right") - 1
        return np.where(index >= 0, self.newest[np.maximum(index, 0)], -1)


def message_fates(
    buffer: Buffer,
    messages: StampedMessages,
    target: str,
    cache_time: int = DEFAULT_CACHE_TIME,
    end: int | None = None,
) -> Fates:
    """Replay a MessageFilter on ``messages`` against a listener filled with ``buffer``'s transforms in
    the order they arrived (record times), its cache ``cache_time`` long, until the recording's
    ``end`` (record time; default: its last transform or message)."""
    end = recording_end(buffer, [messages]) if end is None else end
    n = len(messages)
    fate = np.zeros(n, np.int8)
    ready = np.full(n, NEVER, np.int64)
    lag = np.zeros(n, np.int64)
    decided: list[tuple[str, str] | None] = [None] * n
    for frame_index, frame_id in enumerate(messages.frame_ids):
        rows = np.flatnonzero(messages.frame == frame_index)
        if not len(rows):
            continue
        chain = _chain(buffer, target, frame_id.removeprefix("/"), cache_time)
        if isinstance(chain, Fate):
            fate[rows] = chain
            continue
        arrived, stamps = messages.record_time[rows], messages.stamp[rows]
        fate[rows], ready[rows], lag[rows], limiting = _judge(chain, arrived, stamps, end)
        for row, edge in zip(rows.tolist(), limiting, strict=True):
            decided[row] = edge
    return Fates(fate, ready, decided, lag)


def _chain(buffer: Buffer, target: str, frame: str, cache_time: int) -> list[_Edge] | Fate:
    """The edges between ``frame`` and ``target`` in the tree as it ended, as a listener filled them."""
    try:
        frames = buffer.chain(target, frame)
    except UnknownFrameError:
        return Fate.UNKNOWN_FRAME if not buffer.has_frame(frame) else Fate.NOT_CONNECTED
    except TransformError:
        return Fate.NOT_CONNECTED
    return [_edge_of(parent, child, buffer, cache_time) for parent, child in chain_edges(buffer, frames)]


def _edge_of(parent: str, child: str, buffer: Buffer, cache_time: int) -> _Edge:
    hist = buffer.history(child)
    assert hist is not None
    order = np.argsort(hist.sequence, kind="stable")  # arrival order
    records = np.maximum.accumulate(hist.record_times[order])
    stamps = hist.stamps[order]
    newest = np.maximum.accumulate(stamps) if len(stamps) else stamps
    rate = 0.0 if hist.static else rate_hz(len(hist), hist.latest_stamp - hist.oldest_stamp)
    return _Edge(parent, child, hist.static, rate, records, newest, _oldest_held(stamps, newest, cache_time))


def _oldest_held(stamps: Int64Array, newest: Int64Array, cache_time: int) -> Int64Array:
    """After each arrival, the oldest stamp a cache of ``cache_time`` held: tf2 drops samples more than
    ``cache_time`` behind the newest."""
    if not len(stamps) or bool((np.diff(stamps) >= 0).all()):  # arrivals in stamp order: binary searches
        return stamps[np.searchsorted(stamps, newest - cache_time, side="left")] if len(stamps) else stamps
    oldest = np.empty(len(stamps), np.int64)
    held: list[int] = []
    for i, (stamp, limit) in enumerate(zip(stamps.tolist(), (newest - cache_time).tolist(), strict=True)):
        heapq.heappush(held, stamp)
        while held[0] < limit:  # the limit never goes down, so a dropped stamp never comes back
            heapq.heappop(held)
        oldest[i] = held[0]
    return oldest


def recording_end(buffer: Buffer, streams: Sequence[StampedMessages]) -> int:
    """The record time of the last transform or message: where a replay of the recording stops."""
    last = [int(hist.record_times.max()) for _, hist in buffer.histories() if len(hist.record_times)]
    last += [int(s.record_time[-1]) for s in streams if len(s)]
    return max(last, default=0)


def _judge(
    chain: list[_Edge], arrived: Int64Array, stamps: Int64Array, end: int
) -> tuple[Int8Array, Int64Array, Int64Array, list[tuple[str, str] | None]]:
    """Fate, ready time, lag and deciding edge of messages of one frame, in a recording ending at ``end``."""
    n = len(stamps)
    if not chain:  # the frame is the target itself
        return np.zeros(n, np.int8), arrived.copy(), np.zeros(n, np.int64), [None] * n
    first = np.stack([e.first_ready(stamps) for e in chain])
    last = np.stack([e.last_ready(stamps) for e in chain])
    waited_for, dropped_by = np.argmax(first, axis=0), np.argmin(last, axis=0)
    ready_from, ready_until = first.max(axis=0), last.min(axis=0)
    ready = np.maximum(arrived, ready_from)
    fate = np.where(ready_from <= arrived, Fate.ON_ARRIVAL, Fate.LATER).astype(np.int8)
    fate[ready_from == NEVER] = Fate.NEEDS_NEWER_TF
    fate[(ready_from != NEVER) & (ready >= ready_until)] = Fate.OLDER_THAN_CACHE
    ready[fate >= Fate.NEEDS_NEWER_TF] = NEVER
    deciding = np.where(fate == Fate.OLDER_THAN_CACHE, dropped_by, waited_for)
    # What the recording cut off: tf that began after the stamp, ended before the message came, or
    # was still coming when the recording stopped (its next transform would have come after the end).
    began = np.array([e.oldest.min() if len(e.oldest) else NEVER for e in chain])[deciding]
    ended = np.array([e.records[-1] if len(e.records) else 0 for e in chain])[deciding]
    reach = np.stack([e.would_reach(stamps, end) for e in chain])[deciding, np.arange(n)]
    fate[(fate == Fate.OLDER_THAN_CACHE) & (stamps < began)] = Fate.BEFORE_RECORDED_TF
    fate[(fate == Fate.NEEDS_NEWER_TF) & ((ended <= arrived) | reach)] = Fate.AFTER_RECORDED_TF
    newest = np.stack([e.newest_at(arrived) for e in chain])
    lag = np.maximum(stamps - newest[deciding, np.arange(n)], 0)
    lag[(fate == Fate.OLDER_THAN_CACHE) | (fate == Fate.BEFORE_RECORDED_TF)] = 0
    keys = [e.key for e in chain]
    edges = [keys[i] if f != Fate.ON_ARRIVAL else None for i, f in zip(deciding.tolist(), fate.tolist(), strict=True)]
    return fate, ready, lag, edges


def _at(values: Int64Array, index: IntpArray) -> Int64Array:
    """``values[index]``, NEVER where the index is past the end."""
    inside = index < len(values)
    return np.where(inside, values[np.minimum(index, len(values) - 1)], NEVER)


#: The share of messages a filter's settings should let through, for the settings it suggests.
KEEP = 0.999
#: Cache lengths tried, in seconds, for the smallest that keeps ``KEEP`` of a stream.
CACHES_S = (1, 2, 5, 10, 15, 20, 30, 60, 120, 300, 600, 1800, 3600)


@dataclass(frozen=True)
class StreamReport:
    """One topic through a MessageFilter: how many messages went through on arrival, after a wait
    (and how long), or never (and why); what a filter with a timeout or queue would have dropped;
    the smallest timeout, queue and cache that keep ``KEEP`` of them; the edge that made them wait."""

    topic: str
    type: str
    frame_ids: tuple[str, ...]
    messages: int
    on_arrival: int
    later: int
    never: int  # lost for good (``LOST``); the undecided ones are only in ``reasons``
    wait_s: dict[str, float]  # p50, p95, p99, max of the waits of the messages transformed later
    reasons: dict[str, int]  # why messages were never transformable
    late_edge: tuple[str, str] | None  # the edge most of the waits were for
    late_by_s: float  # that edge's median lag behind the stamps, when they arrived
    wait_needed_s: float | None  # the smallest timeout keeping KEEP (None: no timeout can)
    queue_needed: int  # the queue size that drops nothing that would become transformable
    cache_needed_s: float | None  # the smallest cache keeping KEEP, where the cache loses messages
    dropped_by_wait: int | None = None  # with a timeout: messages lost (waited longer, or never)
    dropped_by_queue: int | None = None  # with a queue size: messages lost (pushed out, or never)


@dataclass(frozen=True)
class FilterReport:
    """Every stream's report against one target frame, and how the target was chosen."""

    target: str
    target_reason: str
    cache_s: float
    streams: list[StreamReport]
    skipped: list[str]  # topics with a header but never a frame_id: not tied to tf
    fates: dict[str, Fates]  # each reported topic's messages' fates, by topic


def default_target(tree: FrameTree) -> tuple[str, str]:
    """The frame sensor data is usually transformed into: ``odom`` or ``map`` where REP 105's frames
    exist (odom, where both do: what a costmap or a scan matcher asks for), else the tree's root."""
    for frame in ("odom", "map"):
        if frame in tree.frames:
            return frame, f"REP 105's {frame} frame"
    trees = tree.trees()
    return max(sorted(trees), key=lambda root: len(trees[root]), default=""), "the root of the largest tree"


def tied_to_tf(stream: StampedMessages) -> bool:
    """Whether some message of ``stream`` names a frame (a header with an empty frame_id only is not tf's)."""
    return any(stream.frame_ids)


def choose_target(tree: FrameTree, asked: str | None = None) -> tuple[str, str]:
    """The target frame and why it was chosen: ``asked`` where it is a frame of ``tree``, else
    ``default_target`` (saying that ``asked`` is not there: a fleet's robots may differ)."""
    if asked is None:
        return default_target(tree)
    if asked.removeprefix("/") in tree.frames:  # a leading '/' dropped, as tf's tools do
        return asked.removeprefix("/"), "asked for"
    target, reason = default_target(tree)
    return target, f"{reason}: '{asked}', asked for, is not a frame of this recording"


def filter_report(
    buffer: Buffer,
    streams: Sequence[StampedMessages],
    target: str | None = None,
    cache_time: int = DEFAULT_CACHE_TIME,
    wait: int | None = None,
    queue: int | None = None,
    tree: FrameTree | None = None,
) -> FilterReport:
    """What a MessageFilter into ``target`` (see ``choose_target``; ``tree``: the buffer's ``frame_tree``,
    if already made) with a ``cache_time`` cache, and optionally a timeout ``wait`` (ns) or a queue of
    ``queue`` messages, did to each stream."""
    target, reason = choose_target(tree if tree is not None else frame_tree(buffer), target)
    end = recording_end(buffer, streams)
    reports, skipped, fates = [], [], {}
    for stream in streams:
        if not tied_to_tf(stream):
            skipped.append(stream.topic)
            continue
        fates[stream.topic] = message_fates(buffer, stream, target, cache_time, end)
        reports.append(_stream_report(buffer, stream, target, fates[stream.topic], wait, queue, end))
    return FilterReport(target, reason, cache_time / 1e9, reports, skipped, fates)


def _stream_report(
    buffer: Buffer,
    stream: StampedMessages,
    target: str,
    fates: Fates,
    wait: int | None,
    queue: int | None,
    end: int,
) -> StreamReport:
    counts = np.bincount(fates.fate, minlength=len(Fate))
    waits = fates.waits(stream)
    later = np.flatnonzero(fates.fate == Fate.LATER).tolist()
    late = [fates.edge[i] for i in later]
    late_edge = max(set(late), key=late.count) if late else None
    lags = fates.lag[[i for i in later if fates.edge[i] == late_edge]]
    never = int(sum(counts[f] for f in LOST))
    return StreamReport(
        topic=stream.topic,
        type=stream.type,
        frame_ids=tuple(stream.frame_ids),
        messages=len(stream),
        on_arrival=int(counts[Fate.ON_ARRIVAL]),
        later=int(counts[Fate.LATER]),
        never=never,
        wait_s=_percentiles(waits),
        reasons={Fate(code).reason: int(n) for code, n in enumerate(counts) if code >= Fate.UNKNOWN_FRAME and n},
        late_edge=late_edge,
        late_by_s=float(np.median(lags)) / 1e9 if len(lags) else 0.0,
        wait_needed_s=_wait_needed(fates, stream),
        queue_needed=_queue_needed(fates, stream),
        cache_needed_s=_cache_needed(buffer, stream, target, fates, end),
        dropped_by_wait=None if wait is None else int(never + (waits > wait).sum()),
        dropped_by_queue=None if queue is None else _dropped_by_queue(fates, stream, queue),
    )


def _percentiles(waits: Int64Array) -> dict[str, float]:
    if not len(waits):
        return {"p50": 0.0, "p95": 0.0, "p99": 0.0, "max": 0.0}
    p50, p95, p99 = np.percentile(waits, [50, 95, 99]) / 1e9
    return {"p50": float(p50), "p95": float(p95), "p99": float(p99), "max": float(waits.max()) / 1e9}


def _wait_needed(fates: Fates, stream: StampedMessages) -> float | None:
    """The smallest timeout that lets ``KEEP`` of the stream through (0 if on arrival already)."""
    must = int(np.ceil(KEEP * fates.decided)) - int((fates.fate == Fate.ON_ARRIVAL).sum())
    waits = np.sort(fates.waits(stream))
    if must <= 0:
        return 0.0
    return float(waits[must - 1]) / 1e9 if must <= len(waits) else None


def _queue_needed(fates: Fates, stream: StampedMessages) -> int:
    """The most messages waiting at once (those that would become transformable): a queue that long drops none."""
    waiting = fates.fate == Fate.LATER
    if not waiting.any():
        return 0
    arrivals, readies = stream.record_time[waiting], np.sort(fates.ready[waiting])
    pending = np.arange(1, len(arrivals) + 1) - np.searchsorted(readies, arrivals, side="right")
    return int(pending.max())


def _dropped_by_queue(fates: Fates, stream: StampedMessages, queue: int) -> int:
    """Messages lost by a filter holding at most ``queue`` waiting messages (the oldest pushed out), or never ready."""
    dropped = 0
    waiting: list[tuple[int, int]] = []  # (ready, arrival order) of the messages held
    held: dict[int, None] = {}  # arrival order -> held, oldest first
    for i in np.argsort(stream.record_time, kind="stable").tolist():
        arrived = int(stream.record_time[i])
        while waiting and waiting[0][0] <= arrived:
            held.pop(heapq.heappop(waiting)[1], None)
        if fates.fate[i] == Fate.ON_ARRIVAL:
            continue
        held[i] = None
        if fates.fate[i] == Fate.LATER:
            heapq.heappush(waiting, (int(fates.ready[i]), i))
        elif fates.fate[i] in LOST:
            dropped += 1  # never ready: lost whatever the queue
        if len(held) > queue:
            oldest = next(iter(held))
            del held[oldest]
            dropped += int(fates.fate[oldest] == Fate.LATER)
    return dropped


def _cache_needed(buffer: Buffer, stream: StampedMessages, target: str, fates: Fates, end: int) -> float | None:
    """The smallest cache (from ``CACHES_S``) with which no more than 1 - ``KEEP`` are lost to its length."""
    if not (fates.fate == Fate.OLDER_THAN_CACHE).any():
        return None
    allowed = (1 - KEEP) * fates.decided
    for seconds in CACHES_S:
        tried = message_fates(buffer, stream, target, seconds * NS_PER_S, end)
        if (tried.fate == Fate.OLDER_THAN_CACHE).sum() <= allowed:
            return float(seconds)
    return None
