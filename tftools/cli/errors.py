"""The library's errors in the command line's words: each class of error the library raises about what was
asked, mapped to the option it came from, a wording and a hint (``WORDING``; exit code 2, as any usage error)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from tftools.core.errors import InvalidTimeError, TfToolsError, TimeRangeError, TooManyLinesError, UsageError
from tftools.core.time import NS_PER_S, to_sec

#: The option a time of a query was given with (``InvalidTimeError.role``).
TIME_OPTIONS = {"at": "--at", "start": "--start", "end": "--end"}


def _invalid_time(error: InvalidTimeError) -> UsageError:
    from tftools.analysis.times import TIME_FORMS

    option = TIME_OPTIONS.get(error.role, error.role)
    if error.span is None:
        return UsageError(f"{option} {error.text}: {error.reason}", f"e.g. {option} +3")
    start, end = error.span
    length = (end - start) / NS_PER_S
    return UsageError(
        f"{option} {error.text} is {error.reason} ({to_sec(start):.3f} to {to_sec(end):.3f}, {length:.3f} s)",
        f"give {TIME_FORMS}, e.g. {option} +{length / 2:.1f}",
    )


def _time_range(error: TimeRangeError) -> UsageError:
    if error.span is None:
        return UsageError("the time range is empty", "--start must come before --end")
    start, end = error.span
    return UsageError(
        "the time range is outside the recording", f"its tf runs from {to_sec(start):.3f} to {to_sec(end):.3f}"
    )


def _too_many_lines(error: TooManyLinesError) -> UsageError:
    return UsageError(
        f"--rate {error.rate:g} over {error.length:.3f} s would print {error.lines:,} lines; tfx echo prints at most "
        f"{error.limit:,}",
        "lower --rate, narrow the range with --start/--end, or use --all for one line per sample",
    )


#: Error class -> its wording for the command line. Rows sorted by class name.
WORDING: dict[type[TfToolsError], Callable[[Any], UsageError]] = {
    InvalidTimeError: _invalid_time,
    TimeRangeError: _time_range,
    TooManyLinesError: _too_many_lines,
}


def in_cli_words(error: TfToolsError) -> TfToolsError:
    """``error`` as the command line says it (``WORDING``), or as it is where it has no row."""
    for kind in type(error).__mro__:
        if kind in WORDING:
            return WORDING[kind](error)
    return error
