"""What a person's terminal shows at 80 and 120 columns: ``tfx filter``'s table as paragraphs where it
does not fit, every name whole; each command's help read whole at 80 columns (nothing cut by "…", the
docstrings wrapped once, by the terminal's width); usage lines that name the arguments as they are given."""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

from tests.cli.terminal import REPO, on_terminal
from tests.render.report_scenes import troubled_bags
from tftools.cli.commands import SUBCOMMANDS

ELLIPSIS = "\u2026"


@pytest.fixture(scope="module")
def troubled(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return troubled_bags(tmp_path_factory.mktemp("troubled"))["ros1"]


@pytest.mark.parametrize("columns", [80, 120])
def test_filter_fits_the_terminal(troubled: Path, columns: int) -> None:
    """Its table needs ~190 columns: narrower, a paragraph a topic, its lines after the first indented."""
    done = subprocess.run(
        [sys.executable, "-m", "tftools", "filter", "-b", str(troubled), "-f", "json"], cwd=REPO, capture_output=True,
        text=True,
    )  # fmt: skip
    topics = json.loads(done.stdout)["topics"]
    code, screen = on_terminal(["filter", "-b", str(troubled)], columns)
    assert code == 1, screen  # the camera's frame is not in the tree: its images are lost
    lines = screen.splitlines()[2:]
    assert ELLIPSIS not in screen and max(len(line) for line in lines) <= columns
    paragraphs: list[str] = []
    for line in lines:
        if line.startswith("  "):
            paragraphs[-1] += " " + line.strip()
        elif line.strip() and not line.startswith("exit"):
            paragraphs.append(line)
    assert len(paragraphs) == len(topics)
    for topic, paragraph in zip(topics, paragraphs, strict=True):
        said = f"{topic['topic']} in {', '.join(topic['frame_ids'])}: {topic['messages']} messages; "
        assert paragraph.startswith(said + f"{topic['on_arrival']} on arrival; {topic['later']} later")
        assert f"; {topic['never']} never" in paragraph and "to keep 99.9%: " in paragraph
    assert "waited for odom -> base_link: " in paragraphs[1]  # the scans' edge, its names whole


@pytest.mark.parametrize("name", SUBCOMMANDS)
def test_help_reads_at_80_columns(name: str) -> None:
    code, screen = on_terminal([name, "--help"], 80)
    lines = screen.splitlines()
    assert code == 0 and ELLIPSIS not in screen
    assert max(len(line) for line in lines) <= 80
    usage = screen[: screen.index("\n\n")]
    assert "{" not in usage and "[BAG]" not in usage.replace("[BAG]...", "")  # TARGET SOURCE; many bags: [BAG]...
    assert len(lines) <= 140  # wtf's was 271 lines, its options' help squeezed into 20 columns
    described = screen[
        screen.index("\n\n") : screen.index("\nArguments:" if "\nArguments:" in screen else "\nOptions:")
    ]
    for paragraph in described.split("\n\n"):
        body = paragraph.splitlines()
        if body and body[0].strip() != "Examples:":  # each line of a paragraph filled but its last: wrapped once
            assert all(len(line) > 60 for line in body[:-1]), paragraph


def test_the_commands_are_listed_in_the_order_a_new_user_needs_them() -> None:
    code, screen = on_terminal(["--help"], 80)
    listed = re.findall(r"^\W (" + "|".join(SUBCOMMANDS) + r") ", screen, flags=re.M)  # a row of its panel
    assert code == 0 and listed == list(SUBCOMMANDS) and SUBCOMMANDS[:2] == ("wtf", "report")
