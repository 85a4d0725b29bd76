"""The library's errors in the command line's words (``tftools.cli.errors.table``): each row words its error
with the option it came from, as tfx said it when the library raised ``UsageError`` itself."""

from __future__ import annotations

import re

from tftools.cli.common import Exit
from tftools.cli.errors import UsageError, table, worded
from tftools.core.errors import InvalidTimeError, TfToolsError, TimeRangeError, TooManyLinesError
from tftools.core.time import NS_PER_S

SPAN = (1_714_741_164_178_000_000, 1_714_741_215_785_000_000)


def test_rows_are_sorted_by_class_name_and_word_library_errors() -> None:
    names = [kind.__name__ for kind in table()]
    assert names == sorted(names)
    assert all(issubclass(kind, TfToolsError) and not issubclass(kind, UsageError) for kind in table())


def test_a_time_is_worded_with_its_option() -> None:
    far = _in_cli_words(InvalidTimeError("+99999", SPAN, "more than 3600 s after the recording's tf", "at"))
    assert (
        str(far)
        == "--at +99999 is more than 3600 s after the recording's tf (1714741164.178 to 1714741215.785, 51.607 s)"
    )
    assert far.hint.endswith("e.g. --at +25.8")
    typo = _in_cli_words(InvalidTimeError("soon", None, "not a time", "start"))
    assert (str(typo), typo.hint) == ("--start soon: not a time", "e.g. --start +3")


def test_ranges_and_line_limits_say_what_to_change() -> None:
    empty = _in_cli_words(TimeRangeError())
    assert (str(empty), empty.hint) == ("the time range is empty", "--start must come before --end")
    outside = _in_cli_words(TimeRangeError(SPAN))
    assert outside.hint == "its tf runs from 1714741164.178 to 1714741215.785"
    lines = _in_cli_words(TooManyLinesError(5_160_730, 100000, 51.607, 1_000_000))
    assert str(lines) == "--rate 100000 over 51.607 s would print 5,160,730 lines; tfx echo prints at most 1,000,000"
    assert "--start/--end" in lines.hint


def test_an_error_without_a_row_is_said_as_it_is() -> None:
    error = TfToolsError(f"{NS_PER_S} things")
    assert worded(error) == (error, Exit.UNUSABLE)


def _in_cli_words(error: TfToolsError) -> TfToolsError:
    said, code = worded(error)
    assert code == Exit.UNUSABLE
    return said


#: A tfx option or command in a message: what a Python caller must never be told.
CLI_WORDS = re.compile(r"(?<![\w-])--[a-z]|-[bo] [A-Z]|tfx (?:wtf|echo|static|frames|view-frames|filter|report)\b")
#: A ROS tool's command line, which a message may name as a remedy (``rosbag play --clock BAG``).
ROS_TOOL = re.compile(r"\b(?:rosbag|rosparam|rostopic|ros2 \w+) [^,;()]*")


def _library_errors() -> list[tuple[TfToolsError, str]]:
    """Errors the library raises whose command line words name an option or a command, each with a part of
    those words."""
    from tftools.analysis.tree_file import TreeFileError
    from tftools.render.drawing import GraphTooLargeError, GraphvizFailedError, OutputExistsError
    from tftools.render.plots import PlotUnavailableError
    from tftools.render.wtf_lines import ReportError
    from tftools.sinks.errors import CopyError
    from tftools.sources.errors import NoTransformsError
    from tftools.sources.live.errors import NoClockError, NoRosSelectedError

    bag = "run.bag"
    return [
        (
            NoTransformsError([bag], ["/tf"], ["/scan"]),
            "was /tf recorded? record it with rosbag record /tf /tf_static, or pick other topics with --topic",
        ),
        (  # in the words of the recording's ROS (ros2_mcap_abitobot_no_tf)
            NoTransformsError(["run"], ["/tf"], ["/scan"], ros2=True),
            "was /tf recorded? record it with ros2 bag record /tf /tf_static, or pick other topics with --topic",
        ),
        (NoTransformsError([bag], ["/tf"], ["/tf"]), "`tfx wtf` names their type and encoding"),
        (NoTransformsError([bag], ["/tf"], unread=["/tf: json"]), "or pick other topics with --topic"),
        (NoRosSelectedError(), "give a bag with -b BAG"),
        (NoClockError(5), "tfx ... --wall-time"),
        (
            NoClockError(5, ros2=False),
            "rosbag play --clock BAG), or follow the wall clock (tfx ... --wall-time, or rosparam",
        ),
        (
            NoClockError(5, ros2=True),
            "ros2 bag play --clock BAG), or follow the wall clock (tfx ... --wall-time, the def",
        ),
        (CopyError(bag, "holds no static transforms", "no_statics"), "tfx static X Y Z ... -b IN -o OUT"),
        (CopyError("out.bag", "already exists", "exists"), "or --force to replace it"),
        (CopyError("out", "is a folder", "not_replaceable"), "--force replaces only an earlier output"),
        (CopyError(bag, "cannot be copied whole: cut", "damaged"), "tfx wtf -b BAG says what is damaged"),
        (CopyError(bag, "/x is in json encoding", "encoding"), "tfx static copies ROS 1 bags"),
        (TreeFileError("tree.yaml", "no such file", missing=True, fix="check the path"), "tfx wtf --init BAG >"),
        (TreeFileError("tree.yaml", "has no 'frames:' mapping"), "see tfx wtf --help (--init writes such a file)"),
        (GraphTooLargeError("page.svg", 5000), "tfx view-frames -b BAG -o frames.gv writes its source"),
        (GraphvizFailedError("tree.svg", b"syntax error"), "write the Graphviz source with --format dot"),
        (OutputExistsError("tree.pdf"), "name the output with -o"),
        (PlotUnavailableError("plotting needs matplotlib, which is not installed"), "--plot needs matplotlib"),
        (ReportError("old.jsonl: line 1 is not a line of a tfx wtf report"), "written by tfx wtf --format jsonl"),
    ]


def test_library_errors_name_no_option_and_the_command_line_words_them() -> None:
    for error, cli_words in _library_errors():
        said = f"{error} ({getattr(error, 'hint', '')})"
        assert not CLI_WORDS.search(ROS_TOOL.sub("", said).replace("tfx wtf report", "")), said
        worded_error = _in_cli_words(error)
        assert cli_words in f"{worded_error} ({worded_error.hint})", type(error).__name__


def test_library_errors_cross_a_process_whole() -> None:
    """A fleet's worker hands its reading's error to the command line (``Unreadable.error``), pickled: each
    arrives with its class and attributes, and is worded as the one raised here (Exception's own pickling
    called the class with the message alone, which their constructors do not take)."""
    import pickle

    for error, _ in _library_errors():
        arrived = pickle.loads(pickle.dumps(error))
        assert type(arrived) is type(error) and arrived.args == error.args and vars(arrived) == vars(error)
        here, there = _in_cli_words(error), _in_cli_words(arrived)
        assert (str(there), there.hint) == (str(here), here.hint), type(error).__name__
