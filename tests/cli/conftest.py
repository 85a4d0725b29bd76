"""Running ``tfx`` in-process as a user would, and the sample bags."""

from __future__ import annotations

import itertools
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Protocol

import pytest

from tftools.cli.app import main

SAMPLES = Path(__file__).resolve().parents[2] / "sample_bags"
SAMPLE_BAGS = {"ros1": SAMPLES / "robot.bag", "db3": SAMPLES / "robot_db3", "mcap": SAMPLES / "robot_mcap"}


@dataclass
class Result:
    code: int
    stdout: str
    stderr: str


class Tfx(Protocol):
    """The ``tfx`` fixture: ``tfx(*args)`` runs ``tfx args``."""

    def __call__(self, *args: str | Path) -> Result: ...


@pytest.fixture
def tfx(capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch) -> Tfx:
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


#: Frame and publisher names a hostile or careless file can carry: escape sequences, newlines, quotes,
#: backslashes, HTML and Graphviz syntax, rich markup and emoji codes, bidi overrides, 10,000 characters.
HOSTILE_NAMES = (
    "\x1b[31mred\x1b[0m",
    "line\nbreak",
    'quo"te',
    "back\\slash\\",
    "<b>html</b>&{brace}|port:x",
    "[bold]markup[/bold]",
    ":smile:",
    "x" * 4_096,  # the longest a frame name may be (MAX_FRAME_ID): a longer one is damage, left out
    "tab\there\r\x07\u202eevil",
)
HOSTILE_PUBLISHER = "/pub\x1b]0;title\x07[red]x"


@pytest.fixture(scope="session")
def hostile_bags(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """A chain map -> each of ``HOSTILE_NAMES`` in turn, 2 s at 10 Hz, in the three formats."""
    from tests.bags import BagFormat, TfMessage, write_bag
    from tftools.core.time import NS_PER_S
    from tftools.core.transform import Transform

    start = 1_700_000_000 * NS_PER_S
    chain = ["map", *HOSTILE_NAMES]
    messages = []
    for i in range(20):
        stamp = start + i * NS_PER_S // 10
        transforms = [
            Transform((1.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), stamp, parent, child)
            for parent, child in itertools.pairwise(chain)
        ]
        messages.append(TfMessage("/tf", stamp + 1_000_000, transforms, HOSTILE_PUBLISHER))
    folder = tmp_path_factory.mktemp("hostile")
    formats = {"ros1": BagFormat.ros1, "db3": BagFormat.rosbag2_sqlite3, "mcap": BagFormat.rosbag2_mcap}
    names = {"ros1": "hostile.bag", "db3": "hostile_db3", "mcap": "hostile_mcap"}
    return {key: write_bag(folder / names[key], messages, fmt) for key, fmt in formats.items()}
