"""Times asked of a recording, as library values: ``Offset`` (seconds after the first tf stamp, or before
the last, on the clock of the frames asked about) and ``Stamp`` (absolute); ``parse_time_spec`` reads the
one grammar users type (``1700000012.5``, ``+S``, ``-S``), ``resolve_time`` turns a value into nanoseconds
on a recording."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, TypeVar

from tftools.core.errors import InvalidTimeError, TimeRangeError
from tftools.core.time import from_sec, to_sec
from tftools.sources.timeline import Timeline

if TYPE_CHECKING:
    from tftools.sources.stream import StreamedRecording

__all__ = [
    "TIME_SLACK_S",
    "Offset",
    "Stamp",
    "TimeSpec",
    "parse_time_spec",
    "played_range",
    "resolve_range",
    "resolve_time",
    "time_forms",
]

#: A time more than this many seconds before or after the recording's tf is refused: a typo, not a question.
TIME_SLACK_S = 3600.0


def time_forms(example: float) -> str:
    """The forms a time on the command line takes, the absolute one shown by ``example`` (seconds): one on the
    recording's own clock, not the wall clock's 1.7e9 where its tf is stamped from a robot's boot (a Neato's 617 s)."""
    return f"absolute seconds (e.g. {example:.1f}), +S after the first tf stamp or -S before the last"


@dataclass(frozen=True, slots=True)
class Offset:
    """``seconds`` after the first tf stamp, or (``from_end``) added to the last one (so at most 0), on the
    clock of the frames asked about (``Timeline.span_of``): +1 is a second into their tf, whatever clock the
    recording was made on. ``given``: the text it was read from, said back in errors."""

    seconds: float
    from_end: bool = False
    given: str = field(default="", compare=False)

    def __str__(self) -> str:
        return self.given or f"{self.seconds:+g}"


@dataclass(frozen=True, slots=True)
class Stamp:
    """An absolute time on the tf stamps' clock (ns); 0 asks for the latest, as tf2's time 0 does."""

    ns: int
    given: str = field(default="", compare=False)

    def __str__(self) -> str:
        return self.given or f"{to_sec(self.ns):g}"


TimeSpec = Offset | Stamp


def parse_time_spec(text: str, role: str = "time") -> TimeSpec:
    """``text`` as a time: absolute seconds (``Stamp``), ``+S`` or ``-S`` (``Offset``); else an
    ``InvalidTimeError`` (``role``: which time it is, said in it)."""
    given = text.strip()
    try:
        value = float(given)
    except ValueError:
        raise InvalidTimeError(given, None, "not a time", role) from None
    if not math.isfinite(value):
        raise InvalidTimeError(given, None, "not a finite number", role)
    if given.startswith(("+", "-")):
        return Offset(value, from_end=given.startswith("-"), given=given)
    return Stamp(from_sec(value), given=given)


def resolve_time(spec: TimeSpec, timeline: Timeline, frames: Sequence[str] = (), role: str = "time") -> int:
    """``spec`` as nanoseconds on the tf stamps' clock; with ``frames`` (the ones asked about), an
    ``Offset`` counts on the tf data of their clock (``Timeline.span_of``). More than ``TIME_SLACK_S``
    outside the recording's tf: an ``InvalidTimeError`` carrying its span."""
    start, end = timeline.span_of(frames)
    if isinstance(spec, Offset):
        ns = (end if spec.from_end else start) + from_sec(spec.seconds)
        seconds = to_sec(end if spec.from_end else start) + spec.seconds
    else:
        ns, seconds = spec.ns, to_sec(spec.ns)
    spans = ((start, end), timeline.stamps_span)  # frames on another clock: theirs too
    if not any(to_sec(first) - TIME_SLACK_S <= seconds <= to_sec(last) + TIME_SLACK_S for first, last in spans):
        where = "before" if seconds < to_sec(start) else "after"
        raise InvalidTimeError(
            str(spec), (start, end), f"more than {TIME_SLACK_S:g} s {where} the recording's tf", role
        )
    return ns


Default = TypeVar("Default", int, None)


def resolve_range(
    timeline: Timeline,
    start: TimeSpec | None,
    end: TimeSpec | None,
    default: tuple[Default, Default],
    frames: Sequence[str] = (),
) -> tuple[int | Default, int | Default]:
    """``start`` and ``end`` as nanoseconds (``default`` where not given), on the clock of ``frames``
    (``resolve_time``); a ``TimeRangeError`` when the range is empty."""
    first = resolve_time(start, timeline, frames, "start") if start is not None else default[0]
    last = resolve_time(end, timeline, frames, "end") if end is not None else default[1]
    if first is not None and last is not None and last < first:
        lone = (start is None) != (end is None)  # one bound given, past the other end of the default range
        span = default if lone and default[0] is not None and default[1] is not None else None
        raise TimeRangeError(span)
    return first, last


def played_range(
    stream: StreamedRecording,
    start: TimeSpec | None,
    end: TimeSpec | None,
    target: str | None = None,
    source: str | None = None,
) -> tuple[int | None, int | None]:
    """``start`` and ``end`` of a replay of ``stream`` on its clock (None: open), counted as a whole read
    counts them: on the clock of the chain between ``target`` and ``source`` (``resolve_range``), then
    moved to when that chain's first transform stamped from ``start`` and its last stamped up to ``end`` play
    (``StreamedRecording.replay_time``) where its clock is not the replay's. A ``TimeRangeError`` when they
    miss the chain's tf."""
    timeline = stream.timeline
    frames = stream.moving_chain(target, source) if target and source else []
    first, last = resolve_range(timeline, start, end, (None, None), frames)
    reach = timeline.arrival_span(frames)
    if (first is not None and first > reach[1]) or (last is not None and last < reach[0]):
        raise TimeRangeError(reach)
    span = timeline.span_of(frames)
    if span == (timeline.tf_start, timeline.tf_end):
        return first, last
    return (
        None if first is None else stream.replay_time(first, frames),
        None if last is None else stream.replay_time(last, frames, last=True),
    )
