"""Running ``tfx`` in-process as a user would, and the sample bags."""

from __future__ import annotations

import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

from tftools.cli.app import main

SAMPLES = Path(__file__).resolve().parents[2] / "sample_bags"
SAMPLE_BAGS = {"ros1": SAMPLES / "robot.bag", "db3": SAMPLES / "robot_db3", "mcap": SAMPLES / "robot_mcap"}


@dataclass
class Result:
    code: int
    stdout: str
    stderr: str


@pytest.fixture
def tfx(capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch):
    """``tfx(*args) -> Result``: exit code and output of ``tfx args`` through its real entry point."""

    def run(*args: str | Path) -> Result:
        capsys.readouterr()
        monkeypatch.setattr(sys, "argv", ["tfx", *(str(a) for a in args)])
        try:
            main()
            code = 0
        except SystemExit as done:
            code = done.code if isinstance(done.code, int) else (0 if done.code is None else 1)
        out, err = capsys.readouterr()
        return Result(code, out, err)

    return run
