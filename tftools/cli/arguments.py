"""Numbers and times given on the command line, checked once, here, against named limits."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, TypeVar

from tftools.cli.common import UsageError
from tftools.core.time import NS_PER_S, from_sec, to_sec

if TYPE_CHECKING:
    from tftools.sources.timeline import Timeline

#: A time more than this many seconds before or after the recording's tf is refused: a typo, not a question.
TIME_SLACK_S = 3600.0
#: ``--rate`` (lines, refreshes or replay speed per second) from one a fortnight to a million a second.
MIN_RATE_HZ = 1e-6
MAX_RATE_HZ = 1e6
#: The longest ``--duration``, ``--window``, ``--cache``, ``--wait`` or threshold: a year.
MAX_SECONDS = 365 * 86400.0
#: ``tfx echo`` prints at most this many lines over a range (``--all`` prints one per sample instead).
MAX_ECHO_LINES = 1_000_000

TIME_FORMS = "absolute seconds (e.g. 1700000012.5), +S after the first tf stamp or -S before the last"


def parse_time(text: str, timeline: Timeline, option: str) -> int:
    """TIME as nanoseconds on the tf stamps' clock: absolute seconds, ``+S`` from the tf data's first
    stamp, ``-S`` from its last (so +1 is a second into the tf, whatever clock the bag was recorded on).

    Not a number, not finite, or more than ``TIME_SLACK_S`` outside the recording's tf: a ``UsageError``
    that says the recording's span."""
    given = text.strip()
    try:
        value = float(given)
    except ValueError:
        raise UsageError(f"{option} {given}: not a time", f"e.g. {option} +3") from None
    if not math.isfinite(value):
        raise UsageError(f"{option} {given}: not a finite number", f"e.g. {option} +3")
    base = timeline.tf_start if given.startswith("+") else timeline.tf_end if given.startswith("-") else 0
    seconds = to_sec(base) + value
    span = f"{to_sec(timeline.tf_start):.3f} to {to_sec(timeline.tf_end):.3f}"
    length = (timeline.tf_end - timeline.tf_start) / NS_PER_S
    spans = ((timeline.tf_start, timeline.tf_end), timeline.stamps_span)  # frames on another clock: theirs too
    if not any(to_sec(first) - TIME_SLACK_S <= seconds <= to_sec(last) + TIME_SLACK_S for first, last in spans):
        where = "before" if seconds < to_sec(timeline.tf_start) else "after"
        raise UsageError(
            f"{option} {given} is more than {TIME_SLACK_S:g} s {where} the recording's tf ({span}, {length:.3f} s)",
            f"give {TIME_FORMS}, e.g. {option} +{length / 2:.1f}",
        )
    return base + from_sec(value)


Default = TypeVar("Default", int, None)


def time_range(
    timeline: Timeline, start: str | None, end: str | None, default: tuple[Default, Default]
) -> tuple[int | Default, int | Default]:
    """``--start`` and ``--end`` as nanoseconds (``default`` where not given); a ``UsageError`` when
    the range is empty."""
    first = parse_time(start, timeline, "--start") if start is not None else default[0]
    last = parse_time(end, timeline, "--end") if end is not None else default[1]
    if first is not None and last is not None and last < first:
        raise UsageError("the time range is empty", "--start must come before --end")
    return first, last


def positive_seconds(value: float, option: str, example: str = "5") -> float:
    """A duration option (``--duration``, ``--window``, ``--cache``, ``--wait``, thresholds): finite,
    above 0 and at most ``MAX_SECONDS``."""
    if not math.isfinite(value) or not 0 < value <= MAX_SECONDS:
        raise UsageError(
            f"{option} {value:g}: must be above 0 and at most a year ({MAX_SECONDS:.0f} s)", f"e.g. {option} {example}"
        )
    return value


def rate_hz(value: float, example: str = "10") -> float:
    """``--rate``: finite, from ``MIN_RATE_HZ`` to ``MAX_RATE_HZ``."""
    if not math.isfinite(value) or not MIN_RATE_HZ <= value <= MAX_RATE_HZ:
        bounds = f"from {MIN_RATE_HZ:g} to {MAX_RATE_HZ:g} a second"
        raise UsageError(f"--rate {value:g}: must be {bounds}", f"e.g. --rate {example}")
    return value


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
