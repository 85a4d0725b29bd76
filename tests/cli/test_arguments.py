"""Times and numbers on the command line: a one-line error with a hint, never a traceback or a huge allocation."""

from __future__ import annotations

import pytest

from tests.cli.conftest import SAMPLE_BAGS, Result, Tfx
from tftools.analysis.echo import MAX_ECHO_LINES

ECHO = ("echo", "map", "base_link", "-b", SAMPLE_BAGS["ros1"])
MONITOR = ("monitor", "-b", SAMPLE_BAGS["mcap"])


def one_line_error(result: Result, *words: str) -> None:
    assert result.code == 2, result.stdout[:300] + result.stderr[:300]
    assert result.stderr.startswith("tfx: error: ") and result.stderr.count("\n") == 1, result.stderr
    assert "Traceback" not in result.stderr and result.stdout == ""
    for word in words:
        assert word in result.stderr


def test_a_recording_given_to_static_is_told_what_reads_its_statics(tfx: Tfx) -> None:
    """`tfx static REC` (two scouts, 2026-12-02, on a Neato and a mapping robot's bags) was told "1 arguments:
    expected 8": it says the argument is a recording, and which commands show, check or repair its statics."""
    said = tfx("static", SAMPLE_BAGS["ros1"])
    assert said.code == 2 and said.stderr.count("\n") == 1, said.stderr
    assert f"{SAMPLE_BAGS['ros1']} is a recording: tfx static publishes the transform its numbers give" in said.stderr
    assert f"tfx frames {SAMPLE_BAGS['ros1']}" in said.stderr and "tfx static --repair -b" in said.stderr
    assert "5 arguments: expected 8" in tfx("static", "1", "2", "3", "a", "b").stderr
    assert "1 argument: expected 8" in tfx("static", "x").stderr


def test_a_format_not_taken_is_not_suggested(tfx: Tfx) -> None:
    said = tfx("view-frames", "--yaml")  # its formats are pdf, svg, png, dot
    assert said.code == 2 and "No such option: --yaml (see tfx view-frames --help)" in said.stderr


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (("--at", "nan"), ("--at nan: not a finite number",)),
        (("--at", "inf"), ("not a finite number",)),
        (("--at", "-inf"), ("not a finite number",)),
        (("--at", "1e10"), ("more than 3600 s after the recording's tf", "1700000000.005 to 1700000014.995")),
        (("--at", "1e300"), ("after the recording's tf",)),
        (("--at", "+1e300"), ("after the recording's tf",)),
        (("--at", "-1e300"), ("before the recording's tf",)),
        (("--at", "soon"), ("--at soon: not a time",)),
        (("--start", "nan"), ("--start nan",)),
        (("--start", "0"), ("before the recording's tf",)),
        (("--end", "1e12"), ("--end 1e12 is more than 3600 s after",)),
        (("--rate", "1e-300"), ("--rate 1e-300: must be from 1e-06 to 1e+06",)),
        (("--rate", "1e12"), ("--rate 1e+12",)),
        (("--rate", "nan"), ("--rate nan",)),
        (("--rate", "inf"), ("--rate inf",)),
        (("--rate", "1e5"), (f"tfx echo prints at most {MAX_ECHO_LINES:,}", "--start/--end")),
        (("--end", "+3000", "--rate", "1000"), ("lines",)),
        (("--play", "--end", "1e12"), ("--end 1e12",)),
        (("--play", "--start", "nan"), ("--start nan",)),
        (("--play", "--start", "+5", "--end", "+1"), ("the time range is empty",)),
        # One bound past the other end of the data: said as outside it, not blamed on an --end never given.
        (("--start", "+100"), ("the time range is outside the recording", "its tf runs from")),
        (("--end", "-100"), ("the time range is outside the recording", "its tf runs from")),
    ],
)
def test_echo_times_and_rates(tfx: Tfx, args: tuple[str, ...], words: tuple[str, ...]) -> None:
    one_line_error(tfx(*ECHO, *args), *words)


@pytest.mark.parametrize(
    "args",
    [
        ("--start", "nan"),
        ("--end", "inf"),
        ("--start", "1e300"),
        ("--window", "nan"),
        ("--window", "1e300", "--play"),
        ("--rate", "inf", "--play"),
        ("--duration", "-inf", "--play"),
    ],
)
def test_monitor_times_and_numbers(tfx: Tfx, args: tuple[str, ...]) -> None:
    one_line_error(tfx(*MONITOR, *args), args[0])


@pytest.mark.parametrize(
    ("option", "value"),
    [("--delay", "nan"), ("--stale-after", "inf"), ("--max-gap", "-1"), ("--future", "1e300"), ("--clock", "nan")],
)
def test_wtf_thresholds(tfx: Tfx, option: str, value: str) -> None:
    one_line_error(tfx("wtf", SAMPLE_BAGS["db3"], option, value), option, "e.g.")


@pytest.mark.parametrize(
    "args",
    [
        ("echo", "map", "odom", "--cache", "nan"),
        ("echo", "map", "odom", "--wait", "inf"),
        ("echo", "map", "odom", "--rate", "nan"),
        ("frames", "--duration", "nan"),
        ("view-frames", "--duration", "inf", "-o", "-"),
        ("wtf", "--duration", "1e300"),
        ("monitor", "--window", "inf"),
        ("static", "0", "0", "0", "0", "0", "0", "a", "b", "--duration", "nan"),
    ],
)
def test_live_numbers_are_checked_before_listening(tfx: Tfx, args: tuple[str, ...]) -> None:
    one_line_error(tfx(*args), "must be")


def test_latest_and_times_within_the_recording_still_work(tfx: Tfx) -> None:
    assert tfx(*ECHO, "--at", "0").code == 0
    assert tfx(*ECHO, "--at", "+3").code == 0
    failed = tfx(*ECHO, "--at", "1699999000")  # before the data, within reach: tf2's answer
    assert failed.code == 1 and "extrapolation" in failed.stdout
    assert tfx(*ECHO, "--rate", "0.5", "--start", "+1", "--end", "-1").stdout.count("At time") == 7


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (("echo", "--rate", "abc", "map", "odom"), ("--rate", "tfx echo --help")),
        (("echo",), ("Missing argument",)),
        (("frames", "--bogus"), ("No such option: --bogus",)),
        (("wtf", "--format", "xml"), ("--format",)),
        (("nope",), ("No such command",)),
        (("echo", "map", "odom", "--time", "5"), ("No such option: --time (did you mean --at? see tfx echo --help)",)),
        (("monitor", "--time", "5"), ("No such option: --time (did you mean --start? see tfx monitor --help)",)),
        (("monitor", "--json"), ("No such option: --json (did you mean --format json? see tfx monitor --help)",)),
        (("frames", "--yaml"), ("did you mean --format yaml?",)),
        (("wtf", "x.bag", "--jsonl"), ("did you mean --format jsonl?",)),
    ],
)
def test_wrong_arguments_are_one_line(tfx: Tfx, args: tuple[str, ...], words: tuple[str, ...]) -> None:
    result = tfx(*args)
    assert result.code == 2 and result.stderr.startswith("tfx: error: ") and result.stderr.count("\n") == 1
    for word in words:
        assert word in result.stderr
