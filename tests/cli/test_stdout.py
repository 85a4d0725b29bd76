"""Standard output that cannot be written is an error of its own (exit 2, one line), buffered or not
(``PYTHONUNBUFFERED=1``); a reader that stops reading (``| head``) is not an error."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path
from typing import IO

import pytest

from tests.cli.conftest import SAMPLE_BAGS
from tests.cli.test_outputs import tiny_disk

__all__ = ["tiny_disk"]  # a fixture, for pytest

REPO = Path(__file__).resolve().parents[2]
#: ~400 KB of CSV: far more than a pipe's or a buffer's worth.
ECHO_ALL = ["echo", "map", "gripper", "-b", str(SAMPLE_BAGS["ros1"]), "--all", "--format", "csv"]
FULL = Path("/dev/full")


def _environment(unbuffered: bool) -> dict[str, str]:
    environment = {k: v for k, v in os.environ.items() if k not in ("PYTHONUNBUFFERED", "TFX_DEBUG")}
    if unbuffered:
        environment["PYTHONUNBUFFERED"] = "1"
    return environment


def _refused_output(command: list[str], out: IO[str], unbuffered: bool) -> None:
    """``tfx command > out`` fails as a full disk should: exit 2, one line that says so, no "bug", no traceback."""
    done = subprocess.run(
        [sys.executable, "-m", "tftools", *command],
        cwd=REPO,
        stdout=out,
        stderr=subprocess.PIPE,
        text=True,
        env=_environment(unbuffered),
        check=False,
    )
    assert done.returncode == 2, done.stderr
    assert done.stderr.count("\n") == 1, done.stderr
    assert done.stderr.startswith("tfx: error: cannot write the output: No space left on device")
    assert "bug" not in done.stderr


@pytest.mark.skipif(not FULL.exists(), reason="no /dev/full here")
@pytest.mark.parametrize("unbuffered", [False, True], ids=["buffered", "PYTHONUNBUFFERED"])
@pytest.mark.parametrize("command", [ECHO_ALL, ["frames", "-b", str(SAMPLE_BAGS["ros1"])]], ids=["echo", "frames"])
def test_a_full_disk_is_one_line_and_exit_2(command: list[str], unbuffered: bool) -> None:
    with FULL.open("w") as full:
        _refused_output(command, full, unbuffered)


@pytest.mark.parametrize("unbuffered", [False, True], ids=["buffered", "PYTHONUNBUFFERED"])
def test_a_reader_that_stops_is_not_an_error(unbuffered: bool) -> None:
    """As ``tfx echo ... | head -1``: the first line read, the pipe closed, exit 0 and nothing said."""
    process = subprocess.Popen(
        [sys.executable, "-m", "tftools", *ECHO_ALL],
        cwd=REPO,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        env=_environment(unbuffered),
    )
    assert process.stdout is not None and process.stderr is not None
    first = process.stdout.readline()
    process.stdout.close()
    error = process.stderr.read().decode()
    assert process.wait() == 0, error
    assert first.startswith(b"time,stamp_ns,frame_id") and error == ""


def test_everything_is_written_when_unbuffered(tmp_path: Path) -> None:
    """``PYTHONUNBUFFERED=1`` writes the same bytes as buffered output."""
    outputs = []
    for unbuffered in (False, True):
        path = tmp_path / f"pose-{unbuffered}.csv"
        with path.open("w") as out:
            done = subprocess.run(
                [sys.executable, "-m", "tftools", *ECHO_ALL], cwd=REPO, stdout=out, env=_environment(unbuffered)
            )
        assert done.returncode == 0
        outputs.append(path.read_bytes())
    assert outputs[0] == outputs[1] and len(outputs[0]) > 300_000


@pytest.mark.parametrize("unbuffered", [False, True], ids=["buffered", "PYTHONUNBUFFERED"])
def test_a_disk_that_fills_up_midway(tiny_disk: Path, unbuffered: bool) -> None:
    """16 KiB of room for ~400 KB: the first writes succeed, one is cut short, the next fail."""
    with (tiny_disk / "pose.csv").open("w") as out:
        _refused_output(ECHO_ALL, out, unbuffered)
