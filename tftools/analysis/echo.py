"""``tfx echo``'s work: the transform between two frames over time, as tf_echo shows it."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from tftools.analysis.times import parse_time, time_range
from tftools.core.arrays import BoolArray, FloatArray, Int64Array
from tftools.core.buffer import Buffer
from tftools.core.errors import TransformError, UsageError
from tftools.core.history import EdgeHistory
from tftools.core.rotation import rpy_from_quat_many
from tftools.core.time import NS_PER_S
from tftools.sources.timeline import Timeline

if TYPE_CHECKING:
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


def echo(buffer: Buffer, target: str, source: str, times: npt.ArrayLike) -> EchoSeries:
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


def echo_recording(
    recording: Recording,
    target: str,
    source: str,
    rate: float = 1.0,
    at: str | None = None,
    every: bool = False,
    start: str | None = None,
    end: str | None = None,
) -> EchoSeries:
    """``tfx echo TARGET SOURCE -b BAG``: the lookups at the times ``echo_times`` chooses on the recording."""
    times = echo_times(recording.buffer, recording.timeline, target, source, rate, at, every, start, end)
    return echo(recording.buffer, target, source, times)


def echo_latest(buffer: Buffer, target: str, source: str) -> EchoSeries:
    """The lookup of the latest transform, said at the buffer's time now, as a live tf_echo prints it (its
    "At time" of a success is the transform's stamp, its "Failure at" that time)."""
    with buffer.lock:
        return dataclasses.replace(echo(buffer, target, source, [0]), times=np.array([buffer.now()], np.int64))


def echo_played(
    streamed: StreamedRecording,
    target: str,
    source: str,
    on_series: Callable[[EchoSeries], object],
    rate: float = 1.0,
    start: str | None = None,
    end: str | None = None,
) -> None:
    """``tfx echo TARGET SOURCE -b BAG --play``: the recording replayed in real time from ``start`` to ``end``
    (``echo_times``' grammar) into a buffer as tf_echo's (the stamps' clock, the recording's semantics), and
    ``on_series`` given ``echo_latest`` of it ``rate`` times a second."""
    from tftools.sources.replay import follow_into

    first, last = time_range(streamed.timeline, start, end, default=(None, None))
    replay = streamed.replay(start=first, end=last)
    buffer = Buffer(clock=replay.clock, semantics=streamed.semantics)
    follow_into(replay, buffer, lambda: on_series(echo_latest(buffer, target, source)), period=1.0 / rate)


def echo_times(
    buffer: Buffer,
    timeline: Timeline,
    target: str,
    source: str,
    rate: float = 1.0,
    at: str | None = None,
    every: bool = False,
    start: str | None = None,
    end: str | None = None,
) -> Int64Array:
    """The times ``tfx echo`` looks the transform up at on a recording (its ``buffer`` and ``timeline``):
    the one time ``at`` ("0": the latest), or from ``start`` to ``end`` (``tftools.analysis.times``'s
    grammar; default: where every moving edge between the frames has data, ``chain_span``, else the tf
    data's span) ``every`` stamp of the moving edges between the frames, or ``rate`` times a second (at
    most ``MAX_ECHO_LINES``; more is a ``UsageError``)."""
    frames = list(_moving_edges(buffer, target, source))  # times are on their clock (``Timeline.span_of``)
    if at is not None:
        return np.array([0 if at.strip() == "0" else parse_time(at, timeline, "--at", frames)], np.int64)
    span = chain_span(buffer, target, source) or timeline.span_of(frames)
    first, last = time_range(timeline, start, end, span, frames)
    if every:
        return sample_times(buffer, target, source, first, last)
    echo_line_count(first, last, rate)
    return ticks(first, last, rate)


def echo_line_count(first: int, last: int, rate: float) -> int:
    """How many lines ``tfx echo`` prints from ``first`` to ``last`` at ``rate``; a ``UsageError`` past
    ``MAX_ECHO_LINES``."""
    length = (last - first) / NS_PER_S
    lines = math.floor(length * rate) + 1
    if lines > MAX_ECHO_LINES:
        raise UsageError(
            f"--rate {rate:g} over {length:.3f} s would print {lines:,} lines; tfx echo prints at most "
            f"{MAX_ECHO_LINES:,}",
            "lower --rate, narrow the range with --start/--end, or use --all for one line per sample",
        )
    return lines


def chain_span(buffer: Buffer, target: str, source: str) -> tuple[int, int] | None:
    """The stretch of time over which every moving edge between the frames has data (None: they are not
    connected now, or only by static edges)."""
    edges = list(_moving_edges(buffer, target, source).values())
    if not edges:
        return None
    start = max(hist.oldest_stamp for hist in edges)
    end = min(hist.latest_stamp for hist in edges)
    return (start, end) if start <= end else None


def sample_times(buffer: Buffer, target: str, source: str, start: int, end: int) -> Int64Array:
    """Every stamp of the moving edges between the frames within ``[start, end]``, sorted."""
    edges = list(_moving_edges(buffer, target, source).values())
    if not edges:
        return np.zeros(0, np.int64)
    every = np.unique(np.concatenate([hist.stamps for hist in edges]))
    return every[(every >= start) & (every <= end)]


def _moving_edges(buffer: Buffer, target: str, source: str) -> dict[str, EdgeHistory]:
    """The dynamic edges a lookup between the frames composes now (latest common time), by child frame."""
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
