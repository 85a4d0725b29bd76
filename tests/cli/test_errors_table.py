"""The library's errors in the command line's words (``tftools.cli.errors.TABLE``): each row words its error
with the option it came from, as tfx said it when the library raised ``UsageError`` itself."""

from __future__ import annotations

from tftools.cli.common import Exit
from tftools.cli.errors import TABLE, UsageError, worded
from tftools.core.errors import InvalidTimeError, TfToolsError, TimeRangeError, TooManyLinesError
from tftools.core.time import NS_PER_S

SPAN = (1_714_741_164_178_000_000, 1_714_741_215_785_000_000)


def test_rows_are_sorted_by_class_name_and_word_library_errors() -> None:
    names = [kind.__name__ for kind in TABLE]
    assert names == sorted(names)
    assert all(issubclass(kind, TfToolsError) and not issubclass(kind, UsageError) for kind in TABLE)


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
