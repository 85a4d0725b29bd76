"""Library noise (issue 32, U3): values near 1e308 and a library's warnings never reach the user as
Python's warning lines; what a warning says is one line of tfx's."""

from __future__ import annotations

import functools
import os
import warnings
from pathlib import Path
from typing import Any

import pytest

from tests.bags import BagFormat, TfMessage, write_bag
from tests.cli.conftest import Tfx
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform


@pytest.fixture(scope="module")
def huge_values(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """map -> odom leaping between -1e308 and 1e308 m at 10 Hz: steps of an infinity of metres."""
    start = 1_700_000_000 * NS_PER_S
    messages = []
    for i in range(50):
        stamp = start + i * NS_PER_S // 10
        leap = 1e308 if i % 2 else -1e308
        transforms = [
            Transform((leap, 1e308, 0.0), (0.0, 0.0, 0.0, 1.0), stamp, "map", "odom"),
            Transform((0.1 * i, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), stamp, "odom", "base_link"),
        ]
        messages.append(TfMessage("/tf", stamp + 1_000_000, transforms, "/node"))
    return write_bag(tmp_path_factory.mktemp("huge") / "huge.bag", messages, BagFormat.ros1)


@pytest.mark.parametrize(
    "command",
    [("wtf", "BAG"), ("view-frames", "-b", "BAG", "-o", "OUT.svg"), ("report", "-b", "BAG", "-o", "OUT.html")],
    ids=["wtf", "view-frames", "report"],
)
def test_values_near_the_largest_float_raise_no_warning(
    tfx: Tfx, huge_values: Path, tmp_path: Path, command: tuple[str, ...]
) -> None:
    args = [str(huge_values) if a == "BAG" else str(tmp_path / a[4:]) if a.startswith("OUT") else a for a in command]
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a warning raised anywhere fails the command
        result = tfx(*args)
    assert result.code in (0, 1), result.stderr
    assert "Warning" not in result.stderr and "internal error" not in result.stderr


def test_a_library_warning_is_one_line_of_tfx(tfx: Tfx, monkeypatch: pytest.MonkeyPatch) -> None:
    from tftools.cli import frames

    real = frames.command

    @functools.wraps(real)
    def warns(*args: Any, **kwargs: Any) -> None:
        warnings.warn("overflow encountered in multiply", RuntimeWarning, stacklevel=1)
        real(*args, **kwargs)

    monkeypatch.setattr(frames, "command", warns)
    result = tfx("frames", "-b", Path(__file__).resolve().parents[2] / "sample_bags" / "robot.bag")
    lines = [line for line in result.stderr.splitlines() if "overflow" in line]
    assert lines == ["tfx: note: overflow encountered in multiply (RuntimeWarning in test_limits_cli)"], result.stderr


def test_a_resumed_report_that_is_a_fifo_is_refused_at_once(tfx: Tfx, tmp_path: Path) -> None:
    """``mkfifo r.jsonl; tfx wtf --resume r.jsonl`` blocked for ever (issue 32, H1)."""
    fifo = tmp_path / "r.jsonl"
    os.mkfifo(fifo)
    bag = Path(__file__).resolve().parents[2] / "sample_bags" / "robot.bag"
    result = tfx("wtf", "--resume", fifo, bag)
    assert result.code == 2 and "a FIFO, not a regular file" in result.stderr, result.stderr
