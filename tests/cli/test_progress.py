"""The progress bar of a large bag on a terminal: once every byte is read it says so and what runs next
(on a 1-hour bag the checks take seconds: a bar full at "294.3/294.3 MB" looked hung)."""

from __future__ import annotations

import io
import re

import pytest
from rich.console import Console

from tests.cli.conftest import SAMPLE_BAGS
from tftools.cli import common


def test_the_bar_says_what_runs_once_all_is_read(monkeypatch: pytest.MonkeyPatch) -> None:
    screen = io.StringIO()
    monkeypatch.setattr(common, "stderr", Console(file=screen, force_terminal=True, width=100))
    monkeypatch.setattr(common, "LARGE_BYTES", 0)  # the sample bag is a large one
    with common.progress_bar([str(SAMPLE_BAGS["ros1"])], "checking") as progress:
        assert progress is not None
        progress(147_150_000, 294_300_000)
        progress(294_300_000, 294_300_000)
    text = re.sub(r"\x1b\[[0-9;?]*[A-Za-z]", "", screen.getvalue())
    assert "read 294.3 MB, checking" in text
