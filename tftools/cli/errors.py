"""The command line's errors: ``UsageError``, and the one table that words each library error with the option
it came from and gives its exit code (the library's own messages name no option)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from tftools.cli.common import Exit
from tftools.core.errors import FleetUnavailableError, InvalidTransformError, TfToolsError, UnknownFrameError
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


def _said(error: TfToolsError) -> UsageError:
    """An error whose library words are already the command line's."""
    return UsageError(str(error), error.hint)


#: Each library error the command line words its own way (rows sorted by class name).
TABLE: dict[type[TfToolsError], Row] = {
    FindingsFileError: Row(_findings_file),
    FleetUnavailableError: Row(_fleet),
    InvalidTransformError: Row(_transform),
    NoStampedDataError: Row(_said),
    PartOfBagError: Row(_part_of_bag),
    UnknownFrameError: Row(_said),
}


def worded(error: TfToolsError) -> tuple[TfToolsError, Exit]:
    """``error`` as the command line says it, and the exit code: its class's row (or its nearest base's), else
    as the library said it, with code 2."""
    for kind in type(error).__mro__:
        row = TABLE.get(kind)
        if row is not None:
            return row.word(error), row.code
    return error, Exit.UNUSABLE
