"""``tfx echo``'s work: the transform between two frames over time, as tf_echo shows it: ``echo(recording,
query)`` on a recording, ``echo_stream(feed, query, on_series)`` on a replay or a live system."""

from __future__ import annotations

import contextlib
import dataclasses
import math
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from tftools.analysis.edges import chain_moving_edges
from tftools.analysis.findings import counted
from tftools.analysis.frames import tree_of
from tftools.analysis.times import Offset, Stamp, TimeSpec, played_range, resolve_range, resolve_time
from tftools.analysis.wtf.thresholds import Thresholds
from tftools.core.arrays import BoolArray, FloatArray, Int64Array
from tftools.core.buffer import DEFAULT_CACHE_TIME, Buffer
from tftools.core.errors import ExtrapolationError, TooManyLinesError, TransformError
from tftools.core.figures import pause_rows, record_span, time_base_of
from tftools.core.frames import frame_name
from tftools.core.rotation import rpy_from_quat_many
from tftools.core.time import NS_PER_S, from_sec
from tftools.sources.timeline import Timeline

if TYPE_CHECKING:
    from tftools.core.semantics import Semantics
    from tftools.sources.live.base import LiveSource
    from tftools.sources.live.capture import Waiting
    from tftools.sources.recording import Recording
    from tftools.sources.stream import StreamedRecording

#: ``tfx echo`` prints at most this many lines over a range (``every`` sample prints one per sample instead).
MAX_ECHO_LINES = 1_000_000


@dataclass(frozen=True)
class EchoSeries:
    """``T_target^source`` at each requested time; failed rows carry tf2's reason."""

    target: str
    source: str
    times: Int64Array  # requested (ns)
    stamps: Int64Array  # the stamp of each answer (ns)
    translations: FloatArray
    rotations: FloatArray
    rpy: FloatArray
    valid: BoolArray
    errors: dict[int, TransformError]  # row -> why it failed

    def __len__(self) -> int:
        return len(self.times)


@dataclass(frozen=True, slots=True, kw_only=True)
class EchoQuery:
    """What ``tfx echo`` asks: ``T_target^source`` at one time ``at`` (``Stamp(0)``: the latest), or from
    ``start`` to ``end`` (default: where every moving edge between the frames has data, ``chain_span``,
    else the tf data's span) at ``every`` stamp of the moving edges between the frames, or ``rate`` times a
    second (at most ``MAX_ECHO_LINES``). Times count on the clock of the frames asked about. Streamed (a
    replay, a live system): the latest transform ``rate`` times a second, from ``start`` to ``end`` of a
    replay; live, in a listener's buffer of ``cache_time`` (ns)."""

    target: str
    source: str
    at: TimeSpec | None = None
    start: TimeSpec | None = None
    end: TimeSpec | None = None
    rate: float = 1.0
    every: bool = False
    cache_time: int = DEFAULT_CACHE_TIME


def echo(recording: Recording, query: EchoQuery) -> EchoSeries:
    """``tfx echo TARGET SOURCE -b BAG``: the lookups at the times ``query`` asks for (``echo_times``).
    Raises ``InvalidTimeError``, ``TimeRangeError`` or ``TooManyLinesError`` for times that cannot be."""
    times = echo_times(recording.buffer, recording.timeline, query)
    return lookups(recording.buffer, query.target, query.source, times)


def echo_stream(
    feed: StreamedRecording | LiveSource,
    query: EchoQuery,
    on_series: Callable[[EchoSeries, Buffer], object],
    *,
    count: int | None = None,
    wait: float | None = None,
    semantics: Semantics | None = None,
    on_reminder: Callable[[Waiting], object] | None = None,
    on_waiting: Callable[[EchoSeries, Buffer], object] | None = None,
) -> None:
    """``tfx echo`` on a stream, as tf_echo sees a live system: ``on_series`` given the latest transform
    (``latest``) and the buffer it is looked up in ``query.rate`` times a second of the feed's clock.

    A recording streamed (``--play``): replayed in real time from ``query.start`` to ``query.end`` into a
    buffer as tf_echo's (the stamps' clock, the recording's semantics), until it ends. A live source (not
    yet started; ``semantics``: its tf2's, default the source's): listened to into a buffer of
    ``query.cache_time``, the transform awaited first (``wait`` seconds at most: ``TransformNotHeardError``;
    meanwhile ``on_reminder``, as ``wait_for_transform``, and ``on_waiting`` given the latest lookup that failed,
    with each reminder and on giving up), then ``count`` times, or until it ends or Ctrl-C."""
    from tftools.sources.stream import StreamedRecording

    if not isinstance(feed, StreamedRecording):
        _echo_live(feed, query, on_series, count, wait, semantics, on_reminder, on_waiting)
        return
    from tftools.sources.replay import follow_into

    first, last = played_range(feed, query.start, query.end, query.target, query.source)
    replay = feed.replay(start=first, end=last)
    buffer = Buffer(clock=replay.clock, semantics=feed.semantics)
    target, source = query.target, query.source
    follow_into(replay, buffer, lambda: on_series(latest(buffer, target, source), buffer), period=1.0 / query.rate)


def _echo_live(
    source: LiveSource,
    query: EchoQuery,
    on_series: Callable[[EchoSeries, Buffer], object],
    count: int | None,
    wait: float | None,
    semantics: Semantics | None,
    on_reminder: Callable[[Waiting], object] | None,
    on_waiting: Callable[[EchoSeries, Buffer], object] | None,
) -> None:
    from tftools.sources.live.capture import listen, wait_for_transform
    from tftools.sources.live.errors import TransformNotHeardError
    from tftools.sources.ticker import tick_every

    target, source_frame = frame_name(query.target), frame_name(query.source)

    def failing() -> None:
        if on_waiting is not None:
            on_waiting(latest(buffer, target, source_frame), buffer)

    def reminded(waiting: Waiting) -> None:
        if on_reminder is not None:
            on_reminder(waiting)
        failing()

    with source:
        buffer = listen(source, query.cache_time, semantics)
        try:
            wait_for_transform(buffer, target, source_frame, wait, reminded)
        except TransformNotHeardError:
            failing()
            raise

        def tick() -> None:
            on_series(latest(buffer, target, source_frame), buffer)

        with contextlib.suppress(KeyboardInterrupt):
            tick_every(1.0 / query.rate, tick, count=count, stop=lambda: source.finished, clock=source.clock)


def lookups(buffer: Buffer, target: str, source: str, times: npt.ArrayLike) -> EchoSeries:
    """Look ``T_target^source`` up at every time (vectorized), with tf2's reason for each failure."""
    requested = np.asarray(times, np.int64).reshape(-1)
    batch = buffer.lookup_many(target, source, requested)
    errors: dict[int, TransformError] = {}
    for row in np.flatnonzero(~batch.valid):
        try:
            buffer.lookup(target, source, int(requested[row]))
        except TransformError as error:
            errors[int(row)] = error
    return EchoSeries(
        target,
        source,
        requested,
        batch.stamps,
        batch.translations,
        batch.rotations,
        rpy_from_quat_many(batch.rotations),
        batch.valid,
        errors,
    )


def latest(buffer: Buffer, target: str, source: str) -> EchoSeries:
    """The lookup of the latest transform, said at the buffer's time now, as a live tf_echo prints it (its
    "At time" of a success is the transform's stamp, its "Failure at" that time). A frame not heard yet (a
    replay started where its first transform is still to come) is a failure with tf2's reason, as tf_echo
    prints it and goes on."""
    with buffer.lock:
        now = np.array([buffer.now()], np.int64)
        try:
            return dataclasses.replace(lookups(buffer, target, source, [0]), times=now)
        except TransformError as error:
            nothing = np.zeros((1, 3))
            return EchoSeries(
                target, source, now, np.zeros(1, np.int64), nothing, np.array([[0.0, 0.0, 0.0, 1.0]]), nothing,
                np.zeros(1, bool), {0: error},
            )  # fmt: skip


@dataclass(frozen=True)
class SeparateTrees:
    """Two frames in trees that no transform joins (by each frame's latest parent): the root of each one's
    tree, how many frames that tree has, and how to join them (``wtf``'s ``disconnected`` hint)."""

    target_root: str
    target_frames: int
    source_root: str
    source_frames: int
    hint: str


def separate_trees(buffer: Buffer, target: str, source: str) -> SeparateTrees | None:
    """Where ``target`` and ``source`` are in two separate trees, which (None: one tree, a frame unknown, or
    a loop). tf2 reports the first edge it cannot use at the time asked (an extrapolation) before it finds
    that the trees do not meet: this says why no time would do. Cheap where they are in one tree (a walk up
    from each, as a live echo asks with each reminder while it waits); the trees are summed up only where not."""
    roots = [_root(buffer, frame) for frame in (target, source)]
    if None in roots or roots[0] == roots[1]:
        return None
    tree = tree_of(buffer)
    from tftools.analysis.wtf.structure import join_hint

    members = tree.trees()
    named = [root for root in roots if root is not None]
    if any(root not in members for root in named):
        return None
    alike = (_robots_alike(buffer, root, members[root]) for root in named)
    hint = next((h for h in alike if h is not None), None) or join_hint(named, members, tree)
    return SeparateTrees(named[0], len(members[named[0]]), named[1], len(members[named[1]]), hint)


def _robots_alike(buffer: Buffer, root: str, frames: list[str]) -> str | None:
    """``wtf``'s hint for a tree that the same node of several robots sends under frames without a robot's prefix
    (two drones' MAVROS each sending fcu -> lidarlite_laser), from the publishers the buffer heard; else None."""
    from tftools.analysis.wtf.structure import robots_alike_hint

    children = [(f, h) for f in frames if f != root and (h := buffer.history(f)) is not None]
    if not children:
        return None
    heard = np.unique(np.concatenate([h.authorities for _, h in children]))
    publishers = [buffer.authorities[int(a)] for a in heard if a >= 0]
    return robots_alike_hint(root, children[0][0], publishers, buffer.semantics == "ros2")


def _root(buffer: Buffer, frame: str) -> str | None:
    """The root above ``frame`` by latest parents (``frame`` itself where it has none); None where the frame is
    unknown or its parents loop."""
    if not buffer.has_frame(frame):
        return None
    seen = {frame}
    while (parent := buffer.parent(frame)) is not None:
        if parent in seen:
            return None
        seen.add(parent)
        frame = parent
    return frame


def apart_hint(
    buffer: Buffer, target: str, source: str, errors: Iterable[TransformError], *, heard_so_far: bool = False
) -> str | None:
    """What to say under the failed lookups between ``target`` and ``source`` (tf2's ``errors``) where they are in
    separate trees (``separate_trees``): which trees, and how to join them; where tf2 named an edge instead (an
    extrapolation on the first edge it walked, as a lookup at a time fails), that no time would do. None where
    they are in one tree. ``heard_so_far``: the tree is a live system's, as heard until now."""
    apart = separate_trees(buffer, target, source)
    if apart is None:
        return None
    named_an_edge = any(isinstance(e, ExtrapolationError) for e in errors)
    why = " (tf2 names the first edge it cannot use at the time asked, not the missing join)" if named_an_edge else ""
    joins = "no transform heard so far joins them" if heard_so_far else "no transform joins them"
    return (
        f"{source} and {target} are in separate trees, {source} in {apart.source_root}'s "
        f"({counted(apart.source_frames, 'frame')}) and {target} in {apart.target_root}'s "
        f"({counted(apart.target_frames, 'frame')}): {joins}, so no lookup between them succeeds "
        f"{'yet' if heard_so_far else 'at any time'}{why}; {apart.hint}"
    )


def span_hint(recording: Recording, query: EchoQuery, series: EchoSeries) -> str | None:
    """What to say under a lookup at ``query.at`` that failed because it is outside the recording's tf of the
    chain (tf2's extrapolation text says the edge's data, not the recording's length): the chain's span on its
    clock, and the ``+S`` (``-S`` where the time was given from the end) that reach it. None where the lookup
    succeeded, was of the latest, or failed for another reason (inside the span, or no moving chain)."""
    at = query.at
    if at is None or at == Stamp(0) or series.valid.all() or not len(series):
        return None
    buffer, target, source = recording.buffer, query.target, query.source
    span = chain_span(buffer, target, source)
    asked = int(series.times[0])
    if span is None or span[0] <= asked <= span[1]:
        return None
    first, last = span
    start, end = recording.timeline.span_of(list(chain_moving_edges(buffer, target, source)))
    if isinstance(at, Offset) and at.from_end:  # the -S that reach the chain's span, rounded inwards to the ms
        reach = f"-{math.ceil((end - last) / 1e6) / 1e3:.3f} to -{math.floor((end - first) / 1e6) / 1e3:.3f}"
    else:
        reach = f"+{math.ceil((first - start) / 1e6) / 1e3:.3f} to +{math.floor((last - start) / 1e6) / 1e3:.3f}"
    return (
        f"{asked / NS_PER_S:.3f} is {'before' if asked < first else 'after'} the recording's tf of {target} <- "
        f"{source} ({first / NS_PER_S:.3f} to {last / NS_PER_S:.3f}, {(last - first) / NS_PER_S:.3f} s on its "
        f"clock): --at {reach} look it up there"
    )


def gap_hint(buffer: Buffer, series: EchoSeries, floor: float = Thresholds().max_gap) -> str | None:
    """What to say under lookups that answered inside a pause of a moving edge of their chain (``figures.pauses``,
    longer than ``floor`` s and its rhythm allows: wtf's gap): tf2 interpolates across it, as tf_echo prints, a
    guess of where the frame was (e-Yantra's fruit detection unseen for 13.99 s, echoed in between without a
    word). The edge with the most such lookups, and its longest pause among them; None where none falls in one."""
    answered = series.times[series.valid]
    found = []
    for child, hist in chain_moving_edges(buffer, series.target, series.source).items() if len(answered) else ():
        stamps = hist.stamps
        _, _, rows = pause_rows(stamps, from_sec(floor), record_span(hist.record_times))
        if not len(rows):
            continue
        starts, ends = stamps[rows], stamps[rows + 1]
        index = np.searchsorted(starts, answered, side="right") - 1
        at = np.maximum(index, 0)
        inside = (index >= 0) & (answered > starts[at]) & (answered < ends[at])
        if inside.any():
            hit = np.unique(at[inside])
            longest = int(hit[np.argmax(ends[hit] - starts[hit])])
            parent = buffer.frame_name(hist.latest_parent)
            found.append((int(inside.sum()), parent, child, int(starts[longest]), int(ends[longest])))
    if not found:
        return None
    count, parent, child, start, end = max(found)
    which = "the lookup falls" if len(answered) == 1 else f"{count} of the {len(answered)} lookups fall"
    return (
        f"{which} where {parent} -> {child} had no sample for {(end - start) / NS_PER_S:.3f} s ({start / NS_PER_S:.3f} "
        f"to {end / NS_PER_S:.3f}): tf2 interpolates across that stretch, a guess of where {child} was, not a sample"
    )


def echo_times(buffer: Buffer, timeline: Timeline, query: EchoQuery) -> Int64Array:
    """The times ``echo`` looks the transform up at on a recording (its ``buffer`` and ``timeline``)."""
    target, source = query.target, query.source
    frames = list(chain_moving_edges(buffer, target, source))  # times are on their clock (``Timeline.span_of``)
    if query.at is not None:
        at = query.at
        return np.array([0 if at == Stamp(0) else resolve_time(at, timeline, frames, "at")], np.int64)
    span = chain_span(buffer, target, source) or timeline.span_of(frames)
    first, last = resolve_range(timeline, query.start, query.end, span, frames)
    if query.every:
        return sample_times(buffer, target, source, first, last)
    stretches = one_clock_stretches(buffer, target, source, first, last) or [(first, last)]
    echo_line_count(0, sum(end - start for start, end in stretches), query.rate)
    return np.concatenate([ticks(start, end, query.rate) for start, end in stretches])


def echo_line_count(first: int, last: int, rate: float) -> int:
    """How many lines ``tfx echo`` prints from ``first`` to ``last`` at ``rate``; a ``TooManyLinesError``
    past ``MAX_ECHO_LINES``."""
    length = (last - first) / NS_PER_S
    lines = math.floor(length * rate) + 1
    if lines > MAX_ECHO_LINES:
        raise TooManyLinesError(lines, rate, length, MAX_ECHO_LINES)
    return lines


def chain_span(buffer: Buffer, target: str, source: str) -> tuple[int, int] | None:
    """The stretch of time over which every moving edge between the frames has data (None: they are not
    connected now, or only by static edges)."""
    edges = list(chain_moving_edges(buffer, target, source).values())
    if not edges:
        return None
    start = max(hist.oldest_stamp for hist in edges)
    end = min(hist.latest_stamp for hist in edges)
    return (start, end) if start <= end else None


def one_clock_stretches(buffer: Buffer, target: str, source: str, first: int, last: int) -> list[tuple[int, int]]:
    """The stretches of ``[first, last]`` where every moving edge between the frames has data on one of its time
    bases (``figures.time_base_of``), in order: the whole where each is on one clock; none where no stretch is.
    A replay's map -> odom a week behind a live gmapping's (ros1_raspimouse_replay_beside_live_gmapping_2018)
    has no sample in the week between its two clocks: echo printed 603,917 lines interpolated across it."""
    stretches = [(first, last)]
    for hist in chain_moving_edges(buffer, target, source).values():
        base = time_base_of(hist.stamps, record_span(hist.record_times))
        if not base.any():
            continue
        spans = [(int(hist.stamps[base == b].min()), int(hist.stamps[base == b].max())) for b in range(base.max() + 1)]
        stretches = [(max(a, c), min(b, d)) for a, b in stretches for c, d in spans if max(a, c) <= min(b, d)]
    return sorted(stretches)


def sample_times(buffer: Buffer, target: str, source: str, start: int, end: int) -> Int64Array:
    """Every stamp of the moving edges between the frames within ``[start, end]``, sorted; ``start`` alone
    where only static edges join them (one transform, holding at every time: one line, not none)."""
    edges = list(chain_moving_edges(buffer, target, source).values())
    if not edges:
        return np.array([start], np.int64)
    every = np.unique(np.concatenate([hist.stamps for hist in edges]))
    return every[(every >= start) & (every <= end)]


def ticks(start: int, end: int, rate_hz: float) -> Int64Array:
    """Times from ``start`` to ``end`` inclusive, ``rate_hz`` per second."""
    if rate_hz <= 0:
        raise ValueError("the rate must be above 0 Hz")
    step = NS_PER_S / rate_hz
    count = int((end - start) // step) + 1 if end >= start else 0
    return start + np.round(np.arange(count) * step).astype(np.int64)


def joined(parts: Sequence[EchoSeries]) -> EchoSeries:
    """Series of the same two frames as one, in order (a live echo's lines); at least one part."""
    offsets = np.cumsum([0, *(len(p) for p in parts)]).tolist()
    errors = {offset + row: error for p, offset in zip(parts, offsets, strict=False) for row, error in p.errors.items()}
    arrays: dict[str, Any] = {
        column: np.concatenate([getattr(p, column) for p in parts])
        for column in ("times", "stamps", "translations", "rotations", "rpy", "valid")
    }
    return dataclasses.replace(parts[0], errors=errors, **arrays)
