"""The command line's errors: ``UsageError``, and the one table that words each library error with the option
it came from and gives its exit code (the library's own messages name no option)."""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

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

if TYPE_CHECKING:
    from tftools.analysis.tree_file import TreeFileError
    from tftools.render.drawing import GraphTooLargeError, GraphvizFailedError, OutputExistsError
    from tftools.render.plots import PlotUnavailableError
    from tftools.render.wtf_lines import ReportError
    from tftools.sinks.errors import CopyError, FindingsFileError
    from tftools.sources.errors import NoTransformsError, PartOfBagError
    from tftools.sources.live.errors import NoClockError, NoRosSelectedError


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
    if error.recording:  # a frame the recording has: the copy would fail tfx wtf
        return UsageError(
            f"{error}, and tfx wtf would fail the copy", f"{error.hint}: tfx frames -b {error.recording} lists its own"
        )
    return UsageError(str(error), error.hint)


def _part_of_bag(error: PartOfBagError) -> UsageError:
    return UsageError(
        f"-b {error.path} is a file of the ROS 2 bag {error.bag}",
        f"give the bag's directory, and a directory for the copy: -b {error.bag} -o OUTPUT",
    )


#: The option a time of a query was given with (``InvalidTimeError.role``).
TIME_OPTIONS = {"at": "--at", "start": "--start", "end": "--end"}


def _invalid_time(error: InvalidTimeError) -> UsageError:
    from tftools.analysis.times import time_forms

    option = TIME_OPTIONS.get(error.role, error.role)
    if error.span is None:
        return UsageError(f"{option} {error.text}: {error.reason}", f"e.g. {option} +3")
    start, end = error.span
    length = (end - start) / NS_PER_S
    return UsageError(
        f"{option} {error.text} is {error.reason} ({to_sec(start):.3f} to {to_sec(end):.3f}, {length:.3f} s)",
        f"give {time_forms(to_sec((start + end) // 2))}, e.g. {option} +{length / 2:.1f}",
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


def no_transforms(error: NoTransformsError, *, chosen: bool = True) -> UsageError:
    """``error`` in the command line's words, with the one hint of every command for a recording whose
    transforms were not read (``analysis.no_transforms``); ``chosen``: the command's topics can be chosen with
    --topic (not tfx filter's)."""
    from tftools.analysis.no_transforms import no_transforms_data, no_transforms_hint

    data = no_transforms_data(error)
    return UsageError(f"{error}{data.said}", no_transforms_hint(error, chosen=chosen) + data.hint)


def _no_ros(error: NoRosSelectedError) -> UsageError:
    return UsageError(
        str(error),
        "give a bag with -b BAG, or set ROS_MASTER_URI (e.g. http://localhost:11311), or pass --ros1, "
        "or --ros2 for ROS 2 (DDS domain ROS_DOMAIN_ID, default 0)",
    )


def _no_clock(error: NoClockError) -> UsageError:
    from tftools.sources.live.errors import replay_with_clock

    wall = {
        None: "tfx ... --wall-time; ROS 1: rosparam set /use_sim_time false",
        False: "tfx ... --wall-time, or rosparam set /use_sim_time false",
        True: "tfx ... --wall-time, the default on ROS 2",
    }[error.ros2]
    return UsageError(str(error), f"{replay_with_clock(error.ros2)}, or follow the wall clock ({wall})")


def _copy(error: CopyError) -> UsageError:
    hint = {
        "no_statics": "add them with tfx static X Y Z ... -b IN -o OUT",
        "exists": "choose another output path, or --force to replace it",
        "not_replaceable": "--force replaces only an earlier output",
        "damaged": "tfx wtf -b BAG says what is damaged",
        "encoding": "tfx static copies ROS 1 bags, and ROS 2 bags of CDR messages",
    }
    return UsageError(str(error), hint.get(error.reason, error.hint))


def _tree_file(error: TreeFileError) -> UsageError:
    if error.missing:
        return UsageError(str(error), f"{error.fix}; tfx wtf --init BAG > tree.yaml writes one")
    return UsageError(str(error), "see tfx wtf --help (--init writes such a file)")


def _graph_too_large(error: GraphTooLargeError) -> UsageError:
    if error.source_path is None:  # drawn for a page: view-frames writes the source
        hint = "tfx view-frames -b BAG -o frames.gv writes its source; dot -Tsvg frames.gv -o frames.svg draws it"
        return UsageError(str(error), hint)
    return UsageError(str(error), error.hint)


def _graphviz_failed(error: GraphvizFailedError) -> UsageError:
    return UsageError(str(error), "write the Graphviz source with --format dot, and please report this to tftools")


def _output_exists(error: OutputExistsError) -> UsageError:
    return UsageError(
        f"{error.path} exists and was not written by tfx view-frames; not overwriting it",
        "move it away, or name the output with -o",
    )


def _plot_unavailable(error: PlotUnavailableError) -> UsageError:
    return UsageError("--plot needs matplotlib, which is not installed", error.hint)


def _resumed_report(error: ReportError) -> UsageError:
    return UsageError(str(error), "give a report written by tfx wtf --format jsonl")


def _unknown_frame(error: UnknownFrameError) -> UsageError:
    """A frame not there; where tf2 kept no frame at all, what says why (refused transforms, or none read)."""
    if error.frames or not error.frame:
        return _said(error)
    return UsageError(str(error), "tf2 kept no transform: `tfx wtf` says which it refused, and why")


def _said(error: TfToolsError) -> UsageError:
    """An error whose library words are already the command line's."""
    return UsageError(str(error), error.hint)


@functools.cache
def table() -> dict[type[TfToolsError], Row]:
    """Each library error the command line words its own way (rows sorted by class name): the one table,
    built when an error is worded, so that a command loads its errors' modules only then."""
    from tftools.analysis.tree_file import TreeFileError
    from tftools.render.drawing import GraphTooLargeError, GraphvizFailedError, OutputExistsError
    from tftools.render.plots import PlotUnavailableError
    from tftools.render.wtf_lines import ReportError
    from tftools.sinks.errors import CopyError, FindingsFileError
    from tftools.sources.errors import NoStampedDataError, NoTransformsError, PartOfBagError
    from tftools.sources.live.errors import NoClockError, NoRosSelectedError

    return {
        CopyError: Row(_copy),
        FindingsFileError: Row(_findings_file),
        FleetUnavailableError: Row(_fleet),
        GraphTooLargeError: Row(_graph_too_large),
        GraphvizFailedError: Row(_graphviz_failed),
        InvalidTimeError: Row(_invalid_time),
        InvalidTransformError: Row(_transform),
        NoClockError: Row(_no_clock),
        NoRosSelectedError: Row(_no_ros),
        NoStampedDataError: Row(_said),
        NoTransformsError: Row(no_transforms),
        OutputExistsError: Row(_output_exists),
        PartOfBagError: Row(_part_of_bag),
        PlotUnavailableError: Row(_plot_unavailable),
        ReportError: Row(_resumed_report),
        TimeRangeError: Row(_time_range),
        TooManyLinesError: Row(_too_many_lines),
        TreeFileError: Row(_tree_file),
        UnknownFrameError: Row(_unknown_frame),
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
        row = table().get(kind)
        if row is not None:
            return row.word(error), row.code
    return error, Exit.UNUSABLE
