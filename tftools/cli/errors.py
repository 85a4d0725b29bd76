"""The command line's errors: ``UsageError``, and the one table that words each library error with the option
it came from and gives its exit code (the library's own messages name no option)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from tftools.cli.common import Exit
from tftools.core.errors import (
    FleetUnavailableError,
    InvalidTimeError,
    InvalidTransformError,
    TfToolsError,
    TimeRangeError,
    TooManyLinesError,
    UnknownFrameError,
)
from tftools.core.time import NS_PER_S, to_sec
from tftools.sinks.errors import FindingsFileError
from tftools.sources.errors import NoStampedDataError, PartOfBagError


class UsageError(TfToolsError):
    """What was asked cannot work: options that do not go together, a value out of range, a name that is not
    there; ``hint`` says what to do instead."""

    def __init__(self, message: str, hint: str = "") -> None:
        super().__init__(message)
        self.hint = hint


@dataclass(frozen=True)
class Row:
    """How the command line says one library error: ``word`` gives its line (message and hint) in the
    options' words; ``code`` is the exit code."""

    word: Callable[[Any], UsageError]
    code: Exit = Exit.UNUSABLE


def _fleet(error: FleetUnavailableError) -> UsageError:
    if error.address is None:  # Dask is not installed
        return UsageError("--dask needs Dask's distributed package, which is not installed", error.hint)
    return UsageError(f"--dask {error}", error.hint.replace("e.g. ", "e.g. --dask "))


def _findings_file(error: FindingsFileError) -> UsageError:
    hint = {"exists": "give another file name, or --force to overwrite it", "folder": "give a file name for --mcap"}
    return UsageError(str(error), hint.get(error.reason, "give another file name for --mcap"))


def _transform(error: InvalidTransformError) -> UsageError:
    if error.recording:
        return UsageError(str(error), f"{error.hint}: tfx frames -b {error.recording} lists its own")
    return UsageError(str(error), error.hint)


def _part_of_bag(error: PartOfBagError) -> UsageError:
    return UsageError(
        f"-b {error.path} is a file of the ROS 2 bag {error.bag}",
        f"give the bag's directory, and a directory for the copy: -b {error.bag} -o OUTPUT",
    )


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


def _said(error: TfToolsError) -> UsageError:
    """An error whose library words are already the command line's."""
    return UsageError(str(error), error.hint)


#: Each library error the command line words its own way (rows sorted by class name).
TABLE: dict[type[TfToolsError], Row] = {
    FindingsFileError: Row(_findings_file),
    FleetUnavailableError: Row(_fleet),
    InvalidTimeError: Row(_invalid_time),
    InvalidTransformError: Row(_transform),
    NoStampedDataError: Row(_said),
    PartOfBagError: Row(_part_of_bag),
    TimeRangeError: Row(_time_range),
    TooManyLinesError: Row(_too_many_lines),
    UnknownFrameError: Row(_said),
}


#: What to do about a recording of a fleet whose task did not finish, by its cause (the values of
#: ``analysis.fleet.UnfinishedCause``), in the options' words; a cause not here keeps the library's hint.
UNFINISHED = {
    "timed_out": "raise --timeout, or check it alone (tfx wtf BAG)",
    "workers_died": "check it alone (tfx wtf BAG): it may crash or exhaust them",
}


def unfinished_hint(cause: float | str, hint: str) -> str:
    """The hint the command line gives for an unfinished task of ``cause`` (the library's ``hint`` else)."""
    return UNFINISHED.get(str(cause), hint)


def worded(error: TfToolsError) -> tuple[TfToolsError, Exit]:
    """``error`` as the command line says it, and the exit code: its class's row (or its nearest base's), else
    as the library said it, with code 2."""
    for kind in type(error).__mro__:
        row = TABLE.get(kind)
        if row is not None:
            return row.word(error), row.code
    return error, Exit.UNUSABLE
