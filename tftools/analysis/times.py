"""Times a user gives against a recording, in one grammar (``tfx echo --at``, ``--start``, ``--end`` and
``tfx monitor``'s): absolute seconds, ``+S`` after the recording's first tf stamp, ``-S`` before its last."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TypeVar

from tftools.core.errors import UsageError
from tftools.core.time import NS_PER_S, from_sec, to_sec
from tftools.sources.timeline import Timeline

__all__ = ["TIME_FORMS", "TIME_SLACK_S", "parse_time", "time_range"]

#: A time more than this many seconds before or after the recording's tf is refused: a typo, not a question.
TIME_SLACK_S = 3600.0

TIME_FORMS = "absolute seconds (e.g. 1700000012.5), +S after the first tf stamp or -S before the last"


def parse_time(text: str, timeline: Timeline, option: str, frames: Sequence[str] = ()) -> int:
    """TIME as nanoseconds on the tf stamps' clock: absolute seconds, ``+S`` from the tf data's first
    stamp, ``-S`` from its last (so +1 is a second into the tf, whatever clock the bag was recorded on);
    with ``frames`` (the ones asked about), the tf data on their clock (``Timeline.span_of``).

    Not a number, not finite, or more than ``TIME_SLACK_S`` outside the recording's tf: a ``UsageError``
    that says the recording's span."""
    given = text.strip()
    try:
        value = float(given)
    except ValueError:
        raise UsageError(f"{option} {given}: not a time", f"e.g. {option} +3") from None
    if not math.isfinite(value):
        raise UsageError(f"{option} {given}: not a finite number", f"e.g. {option} +3")
    start, end = timeline.span_of(frames)
    base = start if given.startswith("+") else end if given.startswith("-") else 0
    seconds = to_sec(base) + value
    span = f"{to_sec(start):.3f} to {to_sec(end):.3f}"
    length = (end - start) / NS_PER_S
    spans = ((start, end), timeline.stamps_span)  # frames on another clock: theirs too
    if not any(to_sec(first) - TIME_SLACK_S <= seconds <= to_sec(last) + TIME_SLACK_S for first, last in spans):
        where = "before" if seconds < to_sec(start) else "after"
        raise UsageError(
            f"{option} {given} is more than {TIME_SLACK_S:g} s {where} the recording's tf ({span}, {length:.3f} s)",
            f"give {TIME_FORMS}, e.g. {option} +{length / 2:.1f}",
        )
    return base + from_sec(value)


Default = TypeVar("Default", int, None)


def time_range(
    timeline: Timeline,
    start: str | None,
    end: str | None,
    default: tuple[Default, Default],
    frames: Sequence[str] = (),
) -> tuple[int | Default, int | Default]:
    """``--start`` and ``--end`` as nanoseconds (``default`` where not given), on the clock of ``frames``
    (``parse_time``); a ``UsageError`` when the range is empty."""
    first = parse_time(start, timeline, "--start", frames) if start is not None else default[0]
    last = parse_time(end, timeline, "--end", frames) if end is not None else default[1]
    if first is not None and last is not None and last < first:
        raise UsageError("the time range is empty", "--start must come before --end")
    return first, last
