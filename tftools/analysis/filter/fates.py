"""What a ``tf2_ros::MessageFilter`` would have done to each stamped message of a recording.

The listener's tf arrives in record order, a transform recorded at the same instant as a message in the
order the recording replays them where its reader said (``StampedMessages.tf_before``), else first; its
cache is ``cache_time`` long behind each frame's newest stamp. tf2's rule, per message
(``MessageFilter::add`` and ``BufferCore::addTransformableRequest`` / ``testTransformableRequests``):

- an empty frame_id is dropped at once; a frame that is the target passes at once;
- transformable at its stamp when it arrives: passed then. A stamp of 0 asks for the chain's latest
  common time, transformable only where that time is inside every edge's cache;
- else, where stamp + cache is before the chain's latest common time (the newest stamp every moving
  edge has reached), dropped at once ("out the back": older than the cache on arrival);
- else it waits in the queue; after each tf arrival, tf2 first drops it if stamp + cache is now
  before the latest common time, else passes it if it is transformable. So a stamp-0 message never
  passes after a wait, and one whose stamp the cache dropped waits until the latest common time
  passes it;
- still waiting when the recording ended: lost, unless the edge it waited for was still publishing
  (then undecided), or its frame is unknown or apart from the target (lost: it waits for good).

Each edge is reduced to step functions of arrival time (the newest and oldest stamp held), and each
chain to its latest common time after each arrival, so each message is a few binary searches. The
chain is walked as tf2 walks it: through each frame's parent at the message's stamp. Where tf2 0.7
(ROS 1) departs from its own rule by a defect (``testTransformableRequests`` hands each callback a
reference to a loop variable, so a request going out the back can drop another that became
transformable in the same tf arrival, or pass a stamp-0 one), this follows the rule.
"""

from __future__ import annotations

import enum
import heapq
import itertools
import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from tftools.analysis.edges import Edge, chain_edges, history_rate, parents_in_order, sorted_unique
from tftools.analysis.frames import tree_of
from tftools.analysis.targets import (
    WORLD_FRAMES,
    fused_edge,
    is_odometry,
    odometry_fused,
    stated_children,
    world_frame_unpublished,
    world_pose_unpublished,
)
from tftools.core.arrays import BoolArray, Int8Array, Int64Array, IntpArray
from tftools.core.buffer import DEFAULT_CACHE_TIME, Buffer
from tftools.core.errors import TransformError, UnknownFrameError
from tftools.core.figures import (
    KEEP,
    base_near,
    median_ns,
    record_span,
    same_base,
    seconds_in_words,
    silence_limit,
    wait_keeping,
)
from tftools.core.frames import base_name, frame_name
from tftools.core.history import EdgeHistory
from tftools.core.time import NS_PER_S
from tftools.sources.contents import StampedMessages
from tftools.sources.timeline import SAME_CLOCK

if TYPE_CHECKING:
    pass

#: A time that never comes.
NEVER = np.iinfo(np.int64).max


class Fate(enum.IntEnum):
    """What became of one message in a ``tf2_ros::MessageFilter`` (tf2's rule, see the module)."""

    ON_ARRIVAL = 0  # transformable when it arrived: passed inside add()
    LATER = 1  # passed later, from the tf arrival that made it transformable
    UNKNOWN_FRAME = 2  # never: its frame is in no transform (a misspelt frame_id?); it waits in the queue for good
    NOT_CONNECTED = 3  # never: its frame and the target are in separate trees; it waits for good
    NEEDS_NEWER_TF = 4  # never: it waits for tf of an edge that stopped publishing before reaching its stamp
    OLDER_THAN_CACHE = 5  # never: it waited until the chain's latest common time passed stamp + cache
    BEFORE_RECORDED_TF = 6  # undecided: as OLDER_THAN_CACHE, but stamped before the recording's tf of an edge began
    AFTER_RECORDED_TF = 7  # undecided: still waiting at the end for an edge that was still publishing
    TOO_OLD_ON_ARRIVAL = 8  # never: older than the cache already when it arrived, dropped inside add()
    EMPTY_FRAME = 9  # never: an empty frame_id, dropped inside add()
    # never: as BEFORE_RECORDED_TF, but stamped before the first transform anyone sent on /tf and arrived before it
    # did: the recorder was listening and no tf existed yet, so no listener had tf that old (the sensor started first)
    BEFORE_ANY_TF = 10

    @property
    def reason(self) -> str:
        return self.name.lower()


#: Messages a filter loses for good; the recording cannot tell what became of the undecided ones.
LOST = (
    Fate.UNKNOWN_FRAME,
    Fate.NOT_CONNECTED,
    Fate.NEEDS_NEWER_TF,
    Fate.OLDER_THAN_CACHE,
    Fate.TOO_OLD_ON_ARRIVAL,
    Fate.EMPTY_FRAME,
    Fate.BEFORE_ANY_TF,
)
UNDECIDED = (Fate.BEFORE_RECORDED_TF, Fate.AFTER_RECORDED_TF)
#: ``Fates.lag`` of a message that arrived before the edge it waited for had sent anything.
UNHELD = -1
#: Messages lost to tf's timing (not to their frame): tf too late, or they too old.
TF_LOST = (Fate.NEEDS_NEWER_TF, Fate.OLDER_THAN_CACHE, Fate.TOO_OLD_ON_ARRIVAL)


@dataclass(frozen=True)
class Fates:
    """Each message's fate: ``ready`` is when it became transformable (``NEVER`` if it did not), ``left``
    when it left the filter's queue (passed or dropped; its arrival where it never entered the queue,
    ``NEVER`` where it was still waiting when the recording ended); ``edge`` the (parent, child) that
    decided it (made it wait, never caught up, or had dropped its stamp), ``lag`` how far that edge's
    newest stamp was behind the message's stamp at arrival (ns; ``UNHELD`` where the edge had sent nothing
    yet: no stamp to be behind); ``after`` how far after the message's
    stamp that edge's sample that let it through was stamped (ns, 0 where it did not wait; none where empty):
    the edge's step between samples, where it is what a message waits for; ``before_tf`` which were stamped before
    the recording's tf of their chain began (none where empty): no cache keeps those if they age out;
    ``zero_early`` which were stamped 0 (an unset header.stamp) and arrived before their chain's tf existed
    (none where empty): tf2 reads 0 as the latest transform only where there is one, and drops the waiting
    request as older than its cache once tf comes; ``left_place`` where each left among the tf arrivals and the
    messages' arrivals (``_places``; none where empty: by ``left``, a tf arrival at a message's instant first)."""

    fate: Int8Array
    ready: Int64Array
    edge: Sequence[tuple[str, str] | None]
    lag: Int64Array
    left: Int64Array
    before_tf: BoolArray = field(default_factory=lambda: np.zeros(0, np.bool_))
    left_place: Int64Array = field(default_factory=lambda: np.zeros(0, np.int64))
    after: Int64Array = field(default_factory=lambda: np.zeros(0, np.int64))
    zero_early: BoolArray = field(default_factory=lambda: np.zeros(0, np.bool_))

    def early(self) -> BoolArray:
        """``before_tf``, one flag per message."""
        return self.before_tf if len(self.before_tf) == len(self.fate) else np.zeros(len(self.fate), np.bool_)

    def zero_before_chain(self) -> BoolArray:
        """``zero_early``, one flag per message."""
        return self.zero_early if len(self.zero_early) == len(self.fate) else np.zeros(len(self.fate), np.bool_)

    @property
    def decided(self) -> int:
        """How many messages' fate the recording tells (not ``UNDECIDED``)."""
        return len(self.fate) - int(np.isin(self.fate, UNDECIDED).sum())

    def waits(self, messages: StampedMessages) -> Int64Array:
        """How long each message waited (ns), for those transformed after a wait."""
        later = self.fate == Fate.LATER
        waits: Int64Array = self.ready[later] - messages.record_time[later]
        return waits

    def queued(self) -> BoolArray:
        """The messages that entered the filter's queue (not passed or dropped inside their own add())."""
        return np.asarray(~np.isin(self.fate, (Fate.ON_ARRIVAL, Fate.TOO_OLD_ON_ARRIVAL, Fate.EMPTY_FRAME)), np.bool_)


@dataclass(frozen=True)
class _Edge(Edge):
    """One edge of a chain as a listener saw it fill: after each arrival (record times, sorted; their
    ``places`` in the listener's order, ``_places``), the newest and the oldest stamp it held."""

    static: bool
    rate_hz: float
    records: Int64Array
    newest: Int64Array
    oldest: Int64Array
    places: Int64Array

    def first_ready(self, stamps: Int64Array) -> Int64Array:
        """The place of the arrival from which the edge first held a stamp at or after each of ``stamps``
        (any sample, for stamp 0)."""
        if not len(self.records):
            return np.full(len(stamps), NEVER, np.int64)
        if self.static:
            return np.full(len(stamps), self.places[0], np.int64)
        index = np.searchsorted(self.newest, stamps, side="left")
        index[stamps == 0] = 0
        return _at(self.places, index)

    def last_ready(self, stamps: Int64Array) -> Int64Array:
        """The place of the arrival at which the cache first dropped each of ``stamps`` (every sample it held
        is newer), else NEVER."""
        if self.static or not len(self.records):
            return np.full(len(stamps), NEVER, np.int64)
        index = np.searchsorted(self.oldest, stamps, side="right")
        index[stamps == 0] = len(self.records)
        return _at(self.places, index)

    def would_reach(self, stamps: Int64Array, end: int) -> BoolArray:
        """Whether the edge's next transforms, had the recording not ended at ``end``, would soon have
        reached each of ``stamps``: it was still being published (``silence_limit``, as ``stale`` has it),
        and the stamp is no further than that limit ahead of its newest."""
        if self.static or self.rate_hz <= 0 or not len(self.records):
            return np.zeros(len(stamps), np.bool_)
        limit = silence_limit(self.rate_hz)
        publishing = end - int(self.records[-1]) <= limit
        return np.asarray(publishing & (stamps - int(self.newest[-1]) <= limit), np.bool_)

    def newest_at(self, places: Int64Array) -> Int64Array:
        """The newest stamp held at each of ``places`` (-1 before the first arrival)."""
        return self._held(self.newest, places)

    def oldest_at(self, places: Int64Array) -> Int64Array:
        """The oldest stamp held at each of ``places`` (-1 before the first arrival)."""
        return self._held(self.oldest, places)

    def _held(self, values: Int64Array, places: Int64Array) -> Int64Array:
        index = np.searchsorted(self.places, places, side="right") - 1  # a state includes the arrival at its place
        return np.where(index >= 0, values[np.maximum(index, 0)], -1)


def _places(buffer_order: bool, sequence: Int64Array, records: Int64Array) -> Int64Array:
    """Where tf arrivals (their ``sequence`` numbers in the buffer, recorded at ``records``) stand in the
    listener's order, against ``_message_places``: even numbers, never equal to a message's."""
    return 2 * (sequence if buffer_order else records)


def _message_places(messages: StampedMessages, rows: IntpArray) -> Int64Array:
    """Where messages (``rows`` of ``messages``) stand among the tf arrivals (``_places``): right after the
    transforms read before each (``StampedMessages.tf_before``: ties of record time in the order the
    recording replays them) where the reader said; else after every transform recorded at the same
    instant or earlier."""
    if messages.ordered:
        return 2 * messages.tf_before[rows] - 1
    return 2 * messages.record_time[rows] + 1


@dataclass(frozen=True)
class _Chain:
    """The edges between a frame and the target, and what tf2 knows of the chain as they fill: after
    each of ``times`` (from when every edge had arrived), the latest common time (0 where every edge
    is static) and whether a lookup at time 0 succeeds (the latest common time inside every edge)."""

    edges: list[_Edge]
    places: Int64Array  # of the tf arrivals after which the chain's state is given (``_places``)
    common: Int64Array
    latest_ok: BoolArray

    @staticmethod
    def of(edges: list[_Edge]) -> _Chain:
        if not edges or any(not len(e.records) for e in edges):
            empty = np.zeros(0, np.int64)
            return _Chain(edges, empty, empty, np.zeros(0, np.bool_))
        connected = max(int(e.places[0]) for e in edges)
        moving = [e for e in edges if not e.static]
        places = sorted_unique(np.concatenate([[connected], *(e.places[e.places > connected] for e in moving)]))
        if not moving:
            return _Chain(edges, places, np.zeros(len(places), np.int64), np.ones(len(places), np.bool_))
        common = np.min(np.stack([e.newest_at(places) for e in moving]), axis=0)
        oldest = np.max(np.stack([e.oldest_at(places) for e in moving]), axis=0)
        return _Chain(edges, places, common, np.asarray(oldest <= common, np.bool_))

    def time_of(self, places: Int64Array) -> Int64Array:
        """The record time of the tf arrivals at ``places`` (NEVER for NEVER)."""
        every = np.concatenate([e.places for e in self.edges])
        order = np.argsort(every, kind="stable")
        every, times = every[order], np.concatenate([e.records for e in self.edges])[order]
        index = np.minimum(np.searchsorted(every, places), max(len(every) - 1, 0))
        return np.where(places == NEVER, NEVER, times[index] if len(times) else NEVER)

    @property
    def began(self) -> int:
        """The first stamp at which the recording's tf holds every moving edge (0: none moves)."""
        return max((int(e.oldest.min()) for e in self.edges if not e.static and len(e.oldest)), default=0)

    def out_the_back(self, stamps: Int64Array, cache_time: int) -> Int64Array:
        """The place of the tf arrival at which tf2 first finds each of ``stamps`` plus the cache before the
        latest common time (``BufferCore::testTransformableRequests``' TransformFailure), else NEVER."""
        index = np.searchsorted(self.common, stamps + cache_time, side="right")
        return _at(self.places, index)

    def latest(self, arrived: Int64Array) -> tuple[BoolArray, Int64Array]:
        """For stamp-0 messages arriving at places ``arrived``: transformable then, and the place of the
        first tf arrival after it that makes them transformable (NEVER if none)."""
        index = np.searchsorted(self.places, arrived, side="right") - 1
        now = (index >= 0) & self.latest_ok[np.maximum(index, 0)] if len(self.places) else np.zeros(len(arrived), bool)
        ok = np.flatnonzero(self.latest_ok)
        after = np.searchsorted(ok, index + 1, side="left")
        return np.asarray(now, np.bool_), _at(self.places, _at(ok, after).clip(max=len(self.places)))


def message_fates(
    buffer: Buffer,
    messages: StampedMessages,
    target: str,
    cache_time: int = DEFAULT_CACHE_TIME,
    end: int | None = None,
    began: TfBegan | None = None,
) -> Fates:
    """Replay a MessageFilter on ``messages`` against a listener filled with ``buffer``'s transforms in
    the order they arrived (record times), its cache ``cache_time`` long, until the recording's
    ``end`` (record time; default: its last transform or message); ``began``: ``TfBegan.of(buffer)``,
    if already found."""
    end = recording_end(buffer, [messages]) if end is None else end
    first_tf = (TfBegan.of(buffer) if began is None else began).first_tf(messages)
    n = len(messages)
    fate = np.zeros(n, np.int8)
    ready = np.full(n, NEVER, np.int64)
    left = np.full(n, NEVER, np.int64)
    left_place = _message_places(messages, np.arange(n))
    lag = np.zeros(n, np.int64)
    after = np.zeros(n, np.int64)
    before_tf = np.zeros(n, np.bool_)
    zero_early = np.zeros(n, np.bool_)
    decided: list[tuple[str, str] | None] = [None] * n
    for frame_index, frame_id in enumerate(messages.frame_ids):
        rows = np.flatnonzero(messages.frame == frame_index)
        if not len(rows):
            continue
        chains = _chains(buffer, target, frame_name(frame_id), messages.stamp[rows], cache_time, messages.ordered)
        for group, chain in chains:
            mine = rows[group]
            if isinstance(chain, Fate):
                fate[mine] = chain
                if chain == Fate.EMPTY_FRAME:
                    left[mine] = messages.record_time[mine]
                else:
                    left_place[mine] = NEVER
                continue
            arrived, stamps, places = messages.record_time[mine], messages.stamp[mine], _message_places(messages, mine)
            judged = _judge(chain, arrived, places, stamps, end, cache_time)
            fate[mine], ready[mine], left[mine], left_place[mine], lag[mine], after[mine], limiting = judged
            for parent, child in _switching(buffer, chain):
                answers = _Answers.of(buffer, parent, child, messages.ordered)
                _under_parent(answers, chain, mine, stamps, places, cache_time, fate, ready, left, left_place)
            before_tf[mine] = (stamps < chain.began) & (stamps != 0)
            predate = (fate[mine] == Fate.BEFORE_RECORDED_TF) & _before(first_tf, stamps, arrived)
            fate[mine[predate]] = Fate.BEFORE_ANY_TF
            zero_early[mine] = (stamps == 0) & (places < (chain.places[0] if len(chain.places) else NEVER))
            for row, edge in zip(mine.tolist(), limiting, strict=True):
                decided[row] = edge
    return Fates(fate, ready, decided, lag, left, before_tf, left_place, after, zero_early)


@dataclass(frozen=True)
class TfBegan:
    """When a recording's moving tf began, from its buffer alone (``message_fates`` needs it for every topic):
    ``stamp`` the first stamp of any transform on /tf, ``arrived`` the first record time one arrived at (both
    None where no moving transform's arrival is recorded), ``heard`` the first record time of any transform
    (None if none), ``silence`` how long (ns) the first edge to arrive may be silent and still be publishing
    (``silence_limit``)."""

    stamp: int | None
    arrived: int | None
    heard: int | None
    silence: float

    @staticmethod
    def of(buffer: Buffer) -> TfBegan:
        moving = [h for _, h in buffer.histories() if not h.static and len(h.stamps) and (h.record_times > 0).any()]
        recorded = [h.record_times[h.record_times > 0] for _, h in buffer.histories()]
        heard = min((int(r.min()) for r in recorded if len(r)), default=None)
        if not moving:
            return TfBegan(None, None, heard, 0.0)
        arrivals = [int(h.record_times[h.record_times > 0].min()) for h in moving]
        silence = silence_limit(history_rate(moving[int(np.argmin(arrivals))]))
        return TfBegan(min(int(h.stamps.min()) for h in moving), min(arrivals), heard, silence)

    def first_tf(self, messages: StampedMessages) -> tuple[int, int] | None:
        """The first stamp of any transform on /tf and the first record time one arrived at, where the recorder
        was listening long before it came: since its first record (a /tf_static message, the stream's first) for
        longer than ``silence``, so that tf started during the recording. None where that is not observed (or
        no moving transform's arrival is recorded)."""
        if self.stamp is None or self.arrived is None:
            return None
        heard = [self.heard] if self.heard is not None else []
        heard += [int(messages.record_time[messages.record_time > 0].min())] if (messages.record_time > 0).any() else []
        if self.arrived - min(heard) <= self.silence:
            return None
        return self.stamp, self.arrived


def _before(first_tf: tuple[int, int] | None, stamps: Int64Array, arrived: Int64Array) -> BoolArray:
    """Which messages are stamped before the first tf anyone sent and arrived before any did (``first_tf``)."""
    if first_tf is None:
        return np.zeros(len(stamps), np.bool_)
    before: BoolArray = (stamps < first_tf[0]) & (arrived > 0) & (arrived < first_tf[1])
    return before


def _chains(
    buffer: Buffer, target: str, frame: str, stamps: Int64Array, cache_time: int, buffer_order: bool
) -> Iterator[tuple[IntpArray | slice, _Chain | Fate]]:
    """The messages of one frame (those of ``stamps``) grouped by the chain tf2 walks for them: each
    edge's parent at the message's stamp, as ``Buffer.chain`` walks it, where a frame on the way changed
    parent; else the tree as it ended. A frame tf2 cannot reach from the target gets its ``Fate``.
    ``buffer_order``: the tf arrivals are placed by their order in the buffer (``_places``)."""
    if not frame:
        yield slice(None), Fate.EMPTY_FRAME
        return
    try:
        frames = buffer.chain(target, frame)
    except UnknownFrameError:
        known = buffer.has_frame(frame) and buffer.has_frame(target)
        yield slice(None), Fate.NOT_CONNECTED if known else Fate.UNKNOWN_FRAME
        return
    except TransformError:  # apart as the tree ended; through a frame's other parent, joined at some stamps
        joined = _through_any_parent(buffer, target, frame)
        if joined is None:
            yield slice(None), Fate.NOT_CONNECTED
            return
        frames = joined
    if not any(_reparented(buffer, f) for f in frames):
        edges = [_edge_of(p, c, buffer, cache_time, buffer_order) for p, c in chain_edges(buffer, frames)]
        yield slice(None), _Chain.of(edges)
        return
    walked: dict[tuple[str, ...], list[int]] = {}
    at_stamp: dict[int, tuple[str, ...]] = {}
    for i, stamp in enumerate(stamps.tolist()):
        if stamp not in at_stamp:
            try:
                at_stamp[stamp] = tuple(buffer.chain(target, frame, stamp))
            except TransformError:  # no data at the stamp: the tree as it ended says what it waits for
                at_stamp[stamp] = tuple(frames)
        walked.setdefault(at_stamp[stamp], []).append(i)
    for path, group in walked.items():
        edges = [_edge_of(p, c, buffer, cache_time, buffer_order) for p, c in _path_edges(buffer, path)]
        yield np.array(group, np.intp), _Chain.of(edges)


def _through_any_parent(buffer: Buffer, target: str, frame: str) -> list[str] | None:
    """The frames from ``frame`` up to an ancestor it shares with ``target`` and down to ``target``, through
    parents any frame ever had, where one was re-parented (its other parent joins what the tree as it ended keeps
    apart); None where there is no such ancestor. tf2 walks up from both ends, never down through a child."""
    parents: dict[str, list[str]] = {}
    switched = False
    for child, hist in buffer.histories():
        parents[child] = [buffer.frame_name(p) for p in parents_in_order(hist)]
        switched |= len(parents[child]) > 1
    if not switched:
        return None
    up_from_frame, up_from_target = _ancestry(parents, frame), _ancestry(parents, target)
    shared = [f for f in up_from_frame if f in up_from_target]
    if not shared:
        return None
    meet = min(shared, key=lambda f: len(up_from_frame[f]) + len(up_from_target[f]))
    return up_from_frame[meet] + up_from_target[meet][::-1][1:]


def parent_that_joins(buffer: Buffer, target: str, frame: str) -> tuple[str, str] | None:
    """Where ``frame`` reaches ``target`` only at some stamps: the re-parented frame on its way and the parent
    under which it joins ``target`` (cf0/base_link and cf0/odom in aerostack2's Crazyflie); None where the way
    passes no re-parented frame, or there is none."""
    try:
        path = buffer.chain(target, frame)
    except TransformError:
        path = _through_any_parent(buffer, target, frame) or []
    for parent, child in _path_edges(buffer, path):
        if _reparented(buffer, child):
            return child, parent
    return None


def _ancestry(parents: dict[str, list[str]], frame: str) -> dict[str, list[str]]:
    """Each frame reachable from ``frame`` by going up to a parent it ever had, with the shortest such path."""
    paths = {frame: [frame]}
    queue = [frame]
    for here in queue:
        for parent in parents.get(here, ()):
            if parent not in paths:
                paths[parent] = [*paths[here], parent]
                queue.append(parent)
    return paths


def _switching(buffer: Buffer, chain: _Chain) -> list[tuple[str, str]]:
    """The chain's moving edges whose child has other parents too (the path is one of them)."""
    found = []
    for e in chain.edges:
        hist = buffer.history(e.child)
        if hist is not None and not hist.static and _reparented(buffer, e.child):
            found.append((e.parent, e.child))
    return found


#: How many of a frame's samples around a message's stamp ``_Answers.good_from`` reads at most (a frame's
#: samples arrive about in stamp order: a handful are ever looked at).
ANSWER_SAMPLES = 256


@dataclass(frozen=True)
class _Answers:
    """A re-parented frame's samples as a listener received them, to tell under which parent tf2 answers a
    stamp at each moment: of the samples held with the newest stamp at or before it, ROS 2's tf2 answers from
    the one received last (``insertData`` puts a sample before the others of its stamp), ROS 1's from the
    first (it refuses the others, TF_REPEATED_DATA); between two samples of different parents, from the older
    (``getData``: no interpolation across parents)."""

    stamps: Int64Array  # sorted, ties in arrival order
    places: Int64Array  # each sample's arrival place (``_places``)
    parent_is_path: BoolArray  # each sample's parent is the path's
    last_wins: bool

    @staticmethod
    def of(buffer: Buffer, parent: str, child: str, buffer_order: bool) -> _Answers:
        hist = buffer.history(child)
        assert hist is not None
        arrival = np.argsort(hist.sequence, kind="stable")
        records = np.maximum.accumulate(hist.record_times[arrival])
        places = np.empty(len(arrival), np.int64)
        places[arrival] = _places(buffer_order, hist.sequence[arrival], records)
        order = np.lexsort((places, hist.stamps))
        return _Answers(
            hist.stamps[order], places[order], _under(buffer, hist, parent)[order], buffer.semantics == "ros2"
        )

    def good_from(self, stamp: int, place: int) -> tuple[bool, int]:
        """Whether tf2 answers ``stamp`` under the path's parent at ``place`` (a message's), and the first later
        place at which it does (NEVER where it never does, as far as ``ANSWER_SAMPLES`` tells)."""
        end = int(np.searchsorted(self.stamps, stamp, side="right"))
        start = max(end - ANSWER_SAMPLES, 0)
        stamps, places, path = self.stamps[start:end], self.places[start:end], self.parent_is_path[start:end]
        before = places < place
        best_stamp, best_path = -1, True  # no sample at or before the stamp yet: the chain's rule decides
        if before.any():
            held = np.flatnonzero(before)
            top = held[stamps[held] == stamps[held].max()]
            pick = top[np.argmax(places[top])] if self.last_wins else top[np.argmin(places[top])]
            best_stamp, best_path = int(stamps[pick]), bool(path[pick])
        now = best_path
        for k in np.argsort(places, kind="stable").tolist():
            if places[k] < place or stamps[k] < best_stamp or (stamps[k] == best_stamp and not self.last_wins):
                continue
            best_stamp, best_path = int(stamps[k]), bool(path[k])
            if best_path:
                return now, int(places[k])
        return now, NEVER


def _under_parent(
    answers: _Answers,
    chain: _Chain,
    mine: IntpArray,
    stamps: Int64Array,
    places: Int64Array,
    cache_time: int,
    fate: Int8Array,
    ready: Int64Array,
    left: Int64Array,
    left_place: Int64Array,
) -> None:
    """Hold back the messages (``mine``, their ``stamps`` and arrival ``places``) that ``_judge`` passed while tf2
    answered their stamp under another parent than the chain's (aerostack2's Crazyflie: cf0/base_link under cf0
    and under cf0/odom at each stamp; a twist that came after both, the cf0 one last, never passes into
    cf0/odom): they pass where it answers under the chain's parent, before their stamp leaves the cache, else
    never (their frame, at their stamp, in a tree apart from the target)."""
    dropped = chain.out_the_back(stamps, cache_time)
    for i, row in enumerate(mine.tolist()):
        if fate[row] not in (Fate.ON_ARRIVAL, Fate.LATER):
            continue
        passed_at = int(places[i]) if fate[row] == Fate.ON_ARRIVAL else int(left_place[row])
        good_now, good_from = answers.good_from(int(stamps[i]), passed_at)
        if good_now:
            continue
        if good_from < dropped[i]:
            fate[row], left_place[row] = Fate.LATER, good_from
            ready[row] = left[row] = int(chain.time_of(np.array([good_from], np.int64))[0])
        elif dropped[i] != NEVER:
            fate[row], ready[row], left_place[row] = Fate.OLDER_THAN_CACHE, NEVER, int(dropped[i])
            left[row] = int(chain.time_of(np.array([dropped[i]], np.int64))[0])
        else:
            fate[row], ready[row], left[row], left_place[row] = Fate.NOT_CONNECTED, NEVER, NEVER, NEVER


def _reparented(buffer: Buffer, frame: str) -> bool:
    hist = buffer.history(frame)
    return hist is not None and len(hist) > 0 and bool(hist.parents.min() != hist.parents.max())


def _path_edges(buffer: Buffer, frames: Sequence[str]) -> list[tuple[str, str]]:
    """The (parent, child) edges of a walked path: a neighbour that ever was a frame's parent is it."""
    edges = []
    for a, b in itertools.pairwise(frames):
        hist = buffer.history(a)
        parents = {buffer.frame_name(p) for p in parents_in_order(hist)} if hist is not None else set()
        edges.append((b, a) if b in parents else (a, b))
    return edges


def _edge_of(parent: str, child: str, buffer: Buffer, cache_time: int, buffer_order: bool) -> _Edge:
    """The child's cache as a listener filled it: every sample of the frame, whatever its parent (tf2
    keeps one cache per frame)."""
    hist = buffer.history(child)
    assert hist is not None
    order = np.argsort(hist.sequence, kind="stable")  # arrival order
    if hist.static and hist.parents.min() != hist.parents.max():
        # A static frame (ROS 1: its first transform came on /tf_static) whose parent a later transform replaced
        # for every time: the edge from ``parent`` holds from the first sample naming it, not the frame's first.
        named = np.array([buffer.frame_name(int(p)) == parent for p in hist.parents[order]], np.bool_)
        order = order[int(np.argmax(named)) :] if named.any() else order
    records = np.maximum.accumulate(hist.record_times[order])
    stamps = hist.stamps[order]
    newest = np.maximum.accumulate(stamps) if len(stamps) else stamps
    # on its time bases: a replay's beside a live publisher's are not 7 days apart; a re-parented frame's edge
    # from ``parent`` alone (aerostack2's Crazyflie: cf0/odom -> cf0/base_link at 83.3 Hz, not the frame's 167.1)
    rate = history_rate(hist, rows=_under(buffer, hist, parent) if _reparented(buffer, child) else None)
    oldest = _oldest_held(stamps, newest, cache_time)
    places = _places(buffer_order, hist.sequence[order], records)
    return _Edge(parent, child, hist.static, rate, records, newest, oldest, places)


def _under(buffer: Buffer, hist: EdgeHistory, parent: str) -> BoolArray:
    """Which of a frame's samples are under ``parent``."""
    ids = [p for p in parents_in_order(hist) if buffer.frame_name(p) == parent]
    return np.asarray(hist.parents == ids[0], np.bool_) if ids else np.zeros(len(hist.parents), np.bool_)


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
    return np.maximum.accumulate(oldest)  # a late sample below the oldest held refills little: ignored


def recording_end(buffer: Buffer, streams: Sequence[StampedMessages]) -> int:
    """The record time of the last transform or message: where a replay of the recording stops."""
    last = [int(hist.record_times.max()) for _, hist in buffer.histories() if len(hist.record_times)]
    last += [int(s.record_time[-1]) for s in streams if len(s)]
    return max(last, default=0)


def _judge(
    chain: _Chain, arrived: Int64Array, places: Int64Array, stamps: Int64Array, end: int, cache_time: int
) -> tuple[Int8Array, Int64Array, Int64Array, Int64Array, Int64Array, Int64Array, list[tuple[str, str] | None]]:
    """Fate, ready time, leaving time and place, lag, how far after the stamp the sample that let it
    through was stamped, and deciding edge of messages of one chain, arrived at
    ``arrived`` (record times) and ``places`` (among the tf arrivals, ``_message_places``), in a recording
    ending at ``end``: tf2's rule, as the module says."""
    n = len(stamps)
    edges = chain.edges
    if not edges:  # the frame is the target itself
        none = np.zeros(n, np.int64)
        return np.zeros(n, np.int8), arrived.copy(), arrived.copy(), places.copy(), none, none.copy(), [None] * n
    first = np.stack([e.first_ready(stamps) for e in edges])
    last = np.stack([e.last_ready(stamps) for e in edges])
    waited_for, dropped_by = np.argmax(first, axis=0), np.argmin(last, axis=0)
    ready_from, ready_until = first.max(axis=0), last.min(axis=0)  # places, never equal to a message's
    now = (ready_from < places) & (places < ready_until)
    passes = np.where((ready_from > places) & (ready_from < ready_until), ready_from, NEVER)
    zero = stamps == 0
    if zero.any():
        now[zero], passes[zero] = chain.latest(places[zero])
    dropped = chain.out_the_back(stamps, cache_time)
    fate = np.full(n, Fate.OLDER_THAN_CACHE, np.int8)
    fate[passes < dropped] = Fate.LATER
    fate[dropped < places] = Fate.TOO_OLD_ON_ARRIVAL
    fate[now] = Fate.ON_ARRIVAL
    ready = np.where(fate == Fate.LATER, chain.time_of(passes), NEVER)
    ready[now] = arrived[now]
    on_arrival = np.isin(fate, (Fate.ON_ARRIVAL, Fate.TOO_OLD_ON_ARRIVAL))
    left_place = np.where(on_arrival, places, np.minimum(passes, dropped))
    left = np.where(on_arrival, arrived, chain.time_of(left_place))
    # Still waiting when the recording ended: for newer tf (lost if its edge had stopped, undecided if it
    # was still publishing), or for nothing (the cache had dropped its stamp, lost).
    waiting = (left == NEVER) & (ready_from == NEVER)
    reach = np.stack([e.would_reach(stamps, end) for e in edges])[waited_for, np.arange(n)]
    fate[waiting] = np.where(reach[waiting], Fate.AFTER_RECORDED_TF, Fate.NEEDS_NEWER_TF)
    # Dropped for its age after a wait, stamped before the recording's tf of an edge began: a listener
    # started before the recording might have had that tf.
    fate[(fate == Fate.OLDER_THAN_CACHE) & (stamps < chain.began) & ~zero] = Fate.BEFORE_RECORDED_TF
    deciding = np.where(np.isin(fate, (Fate.OLDER_THAN_CACHE, Fate.TOO_OLD_ON_ARRIVAL)), dropped_by, waited_for)
    held = np.stack([e.newest_at(places) for e in edges])[deciding, np.arange(n)]
    lag = np.where(held >= 0, np.maximum(stamps - held, 0), UNHELD)  # newest_at: -1 before its first arrival
    lag[np.isin(fate, (Fate.OLDER_THAN_CACHE, Fate.TOO_OLD_ON_ARRIVAL, Fate.BEFORE_RECORDED_TF)) | zero] = 0
    released = np.stack([e.newest_at(passes) for e in edges])[waited_for, np.arange(n)]
    # Waiting for an edge's first transform, not for its next sample: no step to say.
    after = np.where((fate == Fate.LATER) & ~zero & (lag != UNHELD), np.maximum(released - stamps, 0), 0)
    keys = [e.key for e in edges]
    deciding_list, fate_list = deciding.tolist(), fate.tolist()
    limiting = [keys[i] if f != Fate.ON_ARRIVAL else None for i, f in zip(deciding_list, fate_list, strict=True)]
    return fate, ready, left, left_place, lag, after, limiting


def _at(values: Int64Array, index: IntpArray) -> Int64Array:
    """``values[index]``, NEVER where the index is past the end."""
    if not len(values):
        return np.full(len(index), NEVER, np.int64)
    inside = index < len(values)
    return np.where(inside, values[np.minimum(index, len(values) - 1)], NEVER)


#: Cache lengths tried, in seconds, for the smallest that keeps ``KEEP`` of a stream.
CACHES_S = (1, 2, 5, 10, 15, 20, 30, 60, 120, 300, 600, 1800, 3600)


@dataclass(frozen=True)
class StreamReport:
    """One topic through a MessageFilter: how many messages went through on arrival, after a wait
    (and how long), or never (and why); what a filter with a timeout or queue would have dropped;
    the smallest timeout, queue and cache that keep ``KEEP`` of them; the edge that made them wait. Durations in ns."""

    topic: str
    type: str
    frame_ids: tuple[str, ...]
    messages: int
    on_arrival: int
    later: int
    never: int  # lost for good (``LOST``)
    wait: dict[str, float]  # p50, p95, p99, max of the waits of the messages transformed later
    reasons: dict[str, int]  # why the ``never`` ones were lost (their counts add up to ``never``)
    late_edge: tuple[str, str] | None  # the edge most of the waits were for
    late_by: float  # that edge's median lag behind the stamps, when they arrived
    wait_needed: int | None  # the smallest timeout keeping KEEP (None: no timeout can)
    queue_needed: int  # the smallest queue that pushes out nothing that would pass (``smallest_queue``)
    cache_needed: int | None  # the smallest cache keeping KEEP, where the cache loses messages
    dropped_by_wait: int | None = None  # with a timeout: messages lost (waited longer, or never)
    dropped_by_queue: int | None = None  # with a queue size: messages lost (pushed out, or never)
    undecided: dict[str, int] = field(default_factory=dict)  # what the recording cannot tell, and why
    lost_edge: tuple[str, str] | None = None  # the edge most of the messages lost to tf were lost for
    # Lost to their age (or undecided for it), stamped before the recording's tf of their chain began: no
    # cache keeps them (tf2 never held tf that old), starting tf before the sensor or dropping them does.
    before_tf: int = 0
    # Whether every one of ``before_tf`` is stamped before the first transform anyone sent on /tf and arrived
    # before it did: the recorder was listening and no tf existed yet (a simulation's first 0.2 s), so nothing
    # earlier can be recorded: the sensor started before tf.
    before_any_tf: bool = False
    # Of ``before_tf`` left undecided, where each arrived before the first transform of the edge they waited for
    # while other tf was recorded already: that edge (parent, child), and how long (ns) after the first of them
    # its first transform arrived: its publisher started after the sensor (or its first transforms went unheard),
    # so recording earlier keeps none of them. None where that is not observed.
    began_late: tuple[str, str, int] | None = None
    # Lost to their age, stamped 0 (an unset header.stamp), arrived before their chain's tf existed: no cache
    # keeps them either (tf2 drops the waiting request once tf comes), setting the stamp does.
    stamped_zero: int = 0
    late_after: float = 0.0  # how long after the stamps that edge's next sample was stamped (median): its step
    late_rate_hz: float = 0.0  # that edge's rate, of its samples on the messages' clock (``history_rate``)
    # where that edge's samples are on several clocks, the rate of them all (monitor's): the figure said beside the
    # other, not in its place; 0 where they are on one clock
    late_rate_all_hz: float = 0.0
    late_unheld: int = 0  # of the waits for that edge, those for its first transform (it had sent nothing yet)
    # The edge the longest wait was for, where it is not ``late_edge`` (a static sent after the sensor's first
    # messages): it sets ``wait_needed``; how many waited for it, and how many of those for its first transform.
    longest_edge: tuple[str, str] | None = None
    longest_waited: int = 0
    longest_unheld: int = 0
    tick: int = 0  # the step of the clock the waits were read off (record times on /clock's ticks; 0: fine)
    # How far (ns) the messages lost to tf are stamped ahead of the edge they were lost for, both against their
    # arrival, where more than ``SAME_CLOCK`` (negative: behind): the sensor on another machine's clock, which no
    # wait or cache bridges; 0 on one clock.
    clock_apart: int = 0
    # What keeps the messages lost to an unknown frame where that frame is REP 105's map or odom (``tfx wtf``'s
    # words, ``world_frame_unpublished``), or odometry's own beside another odometry on tf (``odometry_fused``);
    # "" for other frames.
    unplaced: str = ""
    # The child frames its messages state a transform to (nav_msgs/Odometry's child_frame_id), as they first come.
    children: tuple[str, ...] = ()
    # Odometry whose own frame no transform names while another odometry places the robot on tf (``fused_edge``):
    # that estimate's input, its frame needed by nothing.
    fused: bool = False
    # Of its frames no transform names, those with a namesake in the tree that no data is in (``namesakes``): the
    # data's frame, the tree's, and the tree's frame's parent (None: a root).
    namesakes: tuple[tuple[str, str, str | None], ...] = ()

    def longest_made_of(self) -> str:
        """Who waited for the edge of the longest wait (``longest_edge``), in words: "7 arrived before its first
        transform and waited for it"; "" where that edge is ``late_edge``."""
        if self.longest_edge is None:
            return ""
        if self.longest_unheld >= self.longest_waited:
            return f"{self.longest_waited} arrived before its first transform and waited for it"
        return f"{self.longest_waited} waited for it"

    def wait_made_of(self) -> str:
        """What the wait for ``late_edge`` was made of, in words: how far its newest stamp was behind the
        message's on arrival, and how long after the message's stamp its next sample was stamped (its step,
        at its rate): the wait is that step, give or take the delays of delivery."""
        first = f"{self.late_unheld} arrived before its first transform and waited for it"
        if self.late_unheld and self.late_unheld >= self.later:
            return first
        rate = f" at {self.late_rate_hz:.1f} Hz" if self.late_rate_hz > 0 else ""
        if rate and self.late_rate_all_hz > 0:
            every = f"{self.late_rate_all_hz:.1f} Hz over all its clocks, as monitor counts it"
            rate += f" on the messages' clock ({every})"
        after = f"{seconds_in_words(self.late_after)} after it" if self.late_after else "with the message's stamp"
        newest = f"its newest stamp {seconds_in_words(self.late_by)} behind the message's on arrival"
        said = f"{newest}, its next sample stamped {after}{rate}"
        return f"{first}; then {said}" if self.late_unheld else said


@dataclass(frozen=True)
class Unchecked:
    """Why ``tfx filter`` found no sensor data to check, where none was asked for by name: ``reasons`` (empty:
    no topic has a header at all) and ``topics``, what the recording holds (topic -> type)."""

    reasons: list[str]
    topics: dict[str, str]
    hint: str = ""  # what to do where the topics read hold no message (``NoStampedDataError.hint``); "": none said
    live: bool = False  # heard from a live system, not read from a recording


@dataclass(frozen=True)
class FilterReport:
    """Every stream's report against one target frame, and how the target was chosen."""

    target: str
    target_reason: str
    cache_time: int  # the listener's cache (ns)
    streams: list[StreamReport]
    skipped: list[str]  # topics with a header but never a frame_id: not tied to tf
    fates: dict[str, Fates]  # each reported topic's messages' fates, by topic
    #: Where no topic was named and none holds sensor data tied to tf (a recording of tf alone, or of
    #: /rosout's frameless headers): why, in ``NoStampedDataError.problems``' words, and every topic the
    #: recording holds (topic -> type); None where topics were checked.
    unchecked: Unchecked | None = None

    @property
    def lost(self) -> bool:
        """Some message never went through, or the timeout or queue given drops some (``tfx filter`` exits 1)."""
        return any(s.never or s.dropped_by_wait or s.dropped_by_queue for s in self.streams)


def stream_report(
    buffer: Buffer,
    stream: StampedMessages,
    target: str,
    fates: Fates,
    wait: int | None,
    queue: int | None,
    end: int,
    tick: int = 0,
    began: TfBegan | None = None,
) -> StreamReport:
    """What the filter did to ``stream`` (its ``fates``), and what would change it (``began``: as
    ``message_fates`` has it)."""
    counts = np.bincount(fates.fate, minlength=len(Fate))
    waits = fates.waits(stream)
    later = np.flatnonzero(fates.fate == Fate.LATER).tolist()
    late_edge = _most([fates.edge[i] for i in later])
    waited = [i for i in later if fates.edge[i] == late_edge]
    longest = _longest_edge(fates, waits, later, late_edge)
    longest_waited = [i for i in later if longest is not None and fates.edge[i] == longest]
    lags = fates.lag[waited]
    held = lags != UNHELD
    afters = (fates.after[waited] if len(fates.after) else np.zeros(len(waited), np.int64))[held]
    lags = lags[held]
    never = int(sum(counts[f] for f in LOST))
    later_mask = fates.fate == Fate.LATER
    lost_rows = np.flatnonzero(np.isin(fates.fate, TF_LOST))
    lost = [fates.edge[i] for i in lost_rows.tolist()]
    early = fates.early() & np.isin(fates.fate, (*AGED, Fate.BEFORE_RECORDED_TF, Fate.BEFORE_ANY_TF))
    return StreamReport(
        topic=stream.topic,
        type=stream.type,
        frame_ids=tuple(stream.frame_ids),
        messages=len(stream),
        on_arrival=int(counts[Fate.ON_ARRIVAL]),
        later=int(counts[Fate.LATER]),
        never=never,
        wait=_percentiles(waits),
        reasons={Fate(code).reason: int(counts[code]) for code in LOST if counts[code]},
        late_edge=late_edge,
        late_by=float(np.median(lags)) if len(lags) else 0.0,
        late_after=float(np.median(afters)) if len(afters) else 0.0,
        late_rate_hz=(late_rate := _rate(buffer, late_edge, stream.stamp[waited])),
        late_rate_all_hz=_rate_all(buffer, late_edge, late_rate),
        late_unheld=int((~held).sum()),
        longest_edge=longest,
        longest_waited=len(longest_waited),
        longest_unheld=int((fates.lag[longest_waited] == UNHELD).sum()),
        tick=tick,
        wait_needed=_wait_needed(fates, stream),
        queue_needed=smallest_queue(fates, stream),
        cache_needed=_cache_needed(buffer, stream, target, fates, end, began),
        dropped_by_wait=None if wait is None else int(never + (waits > wait).sum()),
        dropped_by_queue=None if queue is None else int(never + (pushed_out(fates, stream, queue) & later_mask).sum()),
        undecided={Fate(code).reason: int(counts[code]) for code in UNDECIDED if counts[code]},
        lost_edge=_most(lost),
        clock_apart=_clock_apart(buffer, _most(lost), stream, lost_rows),
        before_tf=int(early.sum()),
        before_any_tf=bool(early.any()) and bool((fates.fate[early] == Fate.BEFORE_ANY_TF).all()),
        began_late=_began_late(buffer, stream, fates, early & (fates.fate == Fate.BEFORE_RECORDED_TF), began),
        stamped_zero=int((fates.zero_before_chain() & np.isin(fates.fate, AGED)).sum()),
        unplaced=_unplaced(buffer, stream, target) if counts[Fate.UNKNOWN_FRAME] else "",
        children=stated_children(stream),
        fused=bool(counts[Fate.UNKNOWN_FRAME]) and _fused(buffer, stream),
    )


def began_late_in_words(began_late: tuple[str, str, int]) -> str:
    """What keeps messages stamped before an edge's first transform, which came after them while tf was recorded
    (``StreamReport.began_late``): not a cache, nor recording earlier."""
    parent, child, after = began_late
    return (
        f"{parent} -> {child}'s first transform arrived {seconds_in_words(after)} after the first of them, while "
        "other tf was recorded already: its publisher started after the sensor (or its first transforms went "
        "unheard); no cache keeps them and there is nothing earlier to record: start it before the sensor, or drop "
        "messages stamped before it starts"
    )


def _began_late(
    buffer: Buffer, stream: StampedMessages, fates: Fates, early: BoolArray, began: TfBegan | None
) -> tuple[str, str, int] | None:
    """``StreamReport.began_late`` of the ``early`` messages (stamped before their chain's recorded tf, undecided):
    the edge most of them waited for, where every one of them arrived before its first transform did and the
    recording held tf from before the first of them (the recorder was listening); None otherwise."""
    rows = np.flatnonzero(early)
    began = TfBegan.of(buffer) if began is None else began
    edge_ = _most([fates.edge[i] for i in rows.tolist()])
    arrived = stream.record_time[rows]
    if edge_ is None or began.heard is None or not len(arrived) or (arrived <= 0).any():
        return None
    hist = buffer.history(edge_[1])
    records = hist.record_times[hist.record_times > 0] if hist is not None else np.zeros(0, np.int64)
    first = int(records.min()) if len(records) else None
    if first is None or int(arrived.max()) >= first or began.heard > int(arrived.min()):
        return None
    return edge_[0], edge_[1], first - int(arrived.min())


def _missing(buffer: Buffer, stream: StampedMessages) -> set[str]:
    """The frames of ``stream`` no transform names (their base names)."""
    return {base_name(f) for f in stream.frame_ids if f and not buffer.has_frame(frame_name(f))}


def _fused(buffer: Buffer, stream: StampedMessages) -> bool:
    """Whether ``stream`` is odometry in a frame no transform names, the robot placed on tf by another odometry
    (``fused_edge``)."""
    missing = _missing(buffer, stream)
    if not is_odometry(stream.type) or not missing or missing <= WORLD_FRAMES:
        return False
    return fused_edge(tree_of(buffer), missing, stated_children(stream)) is not None


def _unplaced(buffer: Buffer, stream: StampedMessages, target: str) -> str:
    """``world_frame_unpublished`` of the frames of ``stream`` no transform names (ROS 2's words where its type
    is spelt as ROS 2 spells it); of odometry, ``world_pose_unpublished`` where they are world frames, else ""
    (its own tf's words, ``odometry_tf_unpublished``)."""
    missing = _missing(buffer, stream)
    if is_odometry(stream.type):
        named = ", ".join(repr(f) for f in sorted(missing))
        if missing <= WORLD_FRAMES:
            return world_pose_unpublished(named, buffer.has_frame("odom"))
        edge = fused_edge(tree_of(buffer), missing, stated_children(stream))
        return odometry_fused(named, edge) if edge is not None else ""
    return world_frame_unpublished(missing, buffer.has_frame("odom"), target, "/msg/" in stream.type) or ""


def _rate(buffer: Buffer, edge: tuple[str, str] | None, stamps: Int64Array | None = None) -> float:
    """The rate of ``edge`` where the messages stamped ``stamps`` wait for it (0 for none, or a static one): of its
    samples on their time base (``history_rate``), not a blend of two publishers' clocks; of a re-parented frame,
    its samples under the edge's parent alone."""
    hist = None if edge is None else buffer.history(edge[1])
    if hist is None or edge is None:
        return 0.0
    return history_rate(hist, stamps, _under(buffer, hist, edge[0]) if _reparented(buffer, edge[1]) else None)


def _rate_all(buffer: Buffer, edge: tuple[str, str] | None, on_their_clock: float) -> float:
    """The rate of all of ``edge``'s samples, where it differs from the rate ``on_their_clock`` (``_rate``'s, of
    those on the messages' clock): its samples are on several clocks (two publishers 5.8 h apart); else 0."""
    every = _rate(buffer, edge)
    return 0.0 if math.isclose(every, on_their_clock, rel_tol=1e-9) else every


def _clock_apart(buffer: Buffer, edge: tuple[str, str] | None, stream: StampedMessages, rows: IntpArray) -> int:
    """How far (ns) messages ``rows`` are stamped ahead of ``edge``'s samples on their clock (``base_near``), each
    against its arrival (the medians of stamp minus record time), where more than ``SAME_CLOCK`` and the time
    those samples took to arrive, on one time base (both from the epoch, or neither): two machines' clocks, not
    a delay; else 0. Messages stamped 0 (unset) are no clock."""
    hist = None if edge is None else buffer.history(edge[1])
    rows = rows[stream.stamp[rows] > 0]
    if hist is None or hist.static or not len(rows):
        return 0
    arrived, known = stream.record_time[rows], hist.record_times > 0
    if not known.any() or (arrived <= 0).any():
        return 0
    stamps, samples, records = stream.stamp[rows], hist.stamps[known], hist.record_times[known]
    mine = base_near(samples, record_span(records), stamps)
    samples, records = samples[mine], records[mine]
    if not same_base(median_ns(stamps), median_ns(samples)):
        return 0
    apart = median_ns(stamps - arrived) - median_ns(samples - records)
    # further than the edge's samples took to arrive: no sample of the recording's tf is near their stamps
    return apart if abs(apart) > max(SAME_CLOCK, record_span(records)) else 0


def _longest_edge(
    fates: Fates, waits: Int64Array, later: list[int], late_edge: tuple[str, str] | None
) -> tuple[str, str] | None:
    """The edge the longest of ``waits`` (one per message of ``later``) was for, where it is not ``late_edge``."""
    if not later:
        return None
    edge = fates.edge[later[int(np.argmax(waits))]]
    return edge if edge != late_edge else None


def _most(edges: list[tuple[str, str] | None]) -> tuple[str, str] | None:
    named = [e for e in edges if e is not None]
    return max(sorted(set(named)), key=named.count) if named else None


def _percentiles(waits: Int64Array) -> dict[str, float]:
    if not len(waits):
        return {"p50": 0.0, "p95": 0.0, "p99": 0.0, "max": 0.0}
    p50, p95, p99 = np.percentile(waits, [50, 95, 99])
    return {"p50": float(p50), "p95": float(p95), "p99": float(p99), "max": float(waits.max())}


def _wait_needed(fates: Fates, stream: StampedMessages) -> int | None:
    """The smallest timeout (ns) that lets ``KEEP`` of the stream through (``figures.wait_keeping``), of the messages
    a timeout decides: not those stamped before any tf existed (``Fate.BEFORE_ANY_TF``, said apart)."""
    decided = fates.decided - int((fates.fate == Fate.BEFORE_ANY_TF).sum())
    return wait_keeping(fates.waits(stream), int((fates.fate == Fate.ON_ARRIVAL).sum()), decided)


def smallest_queue(fates: Fates, stream: StampedMessages) -> int:
    """The smallest queue under which every message that passes with an unlimited one still passes.

    The filter pushes out its oldest message when one more would not fit, so a message is lost to a
    queue of ``q`` exactly when, at some arrival while it waits, it and the held messages that arrived
    after it are more than ``q``. So: at each arrival, the held messages from the oldest held one that
    will pass on, every held message counted (those that never pass hold a slot too, until tf2 drops
    them or for good); the most of these."""
    queued = np.flatnonzero(fates.queued())
    order = queued[np.argsort(stream.record_time[queued], kind="stable")]
    arrived, left = stream.record_time[order], fates.left[order]
    passes = fates.fate[order] == Fate.LATER
    if not passes.any():
        return 0
    index = np.arange(len(order))
    held = index + 1 - np.searchsorted(np.sort(left), arrived, side="right")  # a tf first at a tie
    # The oldest held message that will pass, at each arrival (its position never goes back).
    good = np.flatnonzero(passes)
    oldest = good[np.minimum(np.searchsorted(np.maximum.accumulate(left[good]), arrived, side="right"), len(good) - 1)]
    valid = (oldest <= index) & (left[oldest] > arrived) & (arrived[oldest] <= arrived)
    # Held messages older than it: those that never pass, for good (stuck) or until tf2 drops them.
    stuck = np.flatnonzero(~passes & (left == NEVER))
    doomed = np.flatnonzero(~passes & (left != NEVER))
    older = np.searchsorted(stuck, oldest) + np.searchsorted(doomed, oldest)
    if len(doomed):  # minus the dropped ones older than it: counted from the arrival where both hold
        enters = np.searchsorted(oldest, doomed, side="right")
        expires = np.searchsorted(arrived, left[doomed], side="left")
        gone = np.cumsum(np.bincount(np.maximum(enters, expires), minlength=len(order) + 1))[: len(order)]
        older -= gone
    return int((held - older)[valid].max(initial=0))


def pushed_out(fates: Fates, stream: StampedMessages, queue: int) -> BoolArray:
    """The messages a filter holding at most ``queue`` messages pushes out (the oldest first), as
    ``tf2_ros::MessageFilter::add`` does when one more would not fit."""
    out = np.zeros(len(stream), np.bool_)
    leaving: list[tuple[int, int]] = []  # (left, message) of the messages held
    held: dict[int, None] = {}  # message -> held, oldest first
    placed = len(fates.left_place) == len(stream)  # else by time, a tf arrival at a message's instant first
    arrivals = _message_places(stream, np.arange(len(stream))) if placed else stream.record_time
    lefts = fates.left_place if placed else fates.left
    for i in np.argsort(stream.record_time, kind="stable").tolist():
        if not _entered(fates, i):
            continue
        arrived = int(arrivals[i])
        while leaving and leaving[0][0] <= arrived:
            held.pop(heapq.heappop(leaving)[1], None)
        if len(held) + 1 > queue:
            oldest = next(iter(held))
            del held[oldest]
            out[oldest] = True
        held[i] = None
        heapq.heappush(leaving, (int(lefts[i]), i))
    return out


def _entered(fates: Fates, i: int) -> bool:
    return int(fates.fate[i]) not in (Fate.ON_ARRIVAL, Fate.TOO_OLD_ON_ARRIVAL, Fate.EMPTY_FRAME)


def _cache_needed(
    buffer: Buffer, stream: StampedMessages, target: str, fates: Fates, end: int, began: TfBegan | None
) -> int | None:
    """The smallest cache (ns, from ``CACHES_S``) with which no more than 1 - ``KEEP`` are lost to its length,
    of the messages stamped after their chain's tf began: those stamped before it no cache keeps (tf2 never
    held tf that old; the real filter drops them with any cache), ``StreamReport.before_tf`` counts them; nor those
    stamped 0 before their chain's tf existed (``StreamReport.stamped_zero``)."""
    after = ~fates.early() & ~fates.zero_before_chain()
    if not (np.isin(fates.fate, AGED) & after).any():
        return None
    allowed = (1 - KEEP) * int((after & ~np.isin(fates.fate, UNDECIDED)).sum())
    for seconds in CACHES_S:
        tried = message_fates(buffer, stream, target, seconds * NS_PER_S, end, began)
        if (np.isin(tried.fate, AGED) & after).sum() <= allowed:
            return seconds * NS_PER_S
    return None


#: The messages lost to the cache's length: too old on arrival, or by the time tf reached them.
AGED = (Fate.OLDER_THAN_CACHE, Fate.TOO_OLD_ON_ARRIVAL)
