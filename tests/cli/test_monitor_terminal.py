"""``tfx monitor``'s tables on a real terminal (a pseudo terminal of 80 and 120 columns): frame and
publisher names are never cut, whatever the width; a narrow terminal folds them onto more lines. Its header
with more than one line (a simulated clock) prints them as lines."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from tests.bags import TfMessage, write_bag
from tests.cli.conftest import SAMPLE_BAGS, tfx
from tests.cli.terminal import REPO, on_terminal, rows, table_cells
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform

__all__ = ["tfx"]  # a fixture, for pytest

BAG = str(SAMPLE_BAGS["ros1"])  # ROS 1 bags name their publishers: the longest names


@pytest.fixture(scope="module")
def truth() -> dict[str, object]:
    done = subprocess.run(
        [sys.executable, "-m", "tftools", "monitor", "-b", BAG, "-f", "json"], cwd=REPO, capture_output=True, text=True
    )
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout)


@pytest.mark.parametrize("columns", [80, 120])
def test_names_are_never_cut(truth: dict[str, object], columns: int) -> None:
    code, screen = on_terminal(["monitor", "-b", BAG], columns)
    assert code == 0, screen
    assert "\u2026" not in screen  # nothing cut short with an ellipsis
    tables = screen[screen.index("Frames:") :].splitlines()
    assert max(len(line) for line in tables) <= columns  # the tables fit: the terminal wraps none of their lines

    frames = rows(table_cells(screen, "Frames:"), header_lines=2, key=3)
    assert all(len(row) == 9 for row in frames)
    shown = {(row[0], row[1], row[2]) for row in frames}
    edges = truth["edges"]
    assert isinstance(edges, list)
    assert shown == {(e["parent"], e["child"], ", ".join(e["authorities"])) for e in edges}

    broadcasters = rows(table_cells(screen, "All Broadcasters:"), header_lines=2, key=1)
    authorities = truth["authorities"]
    assert isinstance(authorities, list)
    assert {row[0] for row in broadcasters} == {a["authority"] for a in authorities}
    for row in broadcasters:
        edges_of = next(a["edges"] for a in authorities if a["authority"] == row[0])
        assert [name.strip() for name in row[-1].split(",")] == [child for _, child in edges_of]


def test_a_wide_terminal_folds_nothing() -> None:
    """At 120 columns every name of the sample robot fits on its line: one line per edge."""
    code, screen = on_terminal(["monitor", "-b", BAG], 120)
    lines = table_cells(screen, "Frames:")
    assert code == 0 and all(line[3] for line in lines[2:])  # every line has its samples: no folded name


def test_a_simulated_clock_header_is_two_lines(tfx, tmp_path: Path) -> None:
    """A bag stamped on simulated time without /clock: the header says delays are unavailable on a line
    of its own (not a literal backslash-n)."""
    start, wall = 1000 * NS_PER_S, 1_700_000_000 * NS_PER_S
    messages = [
        TfMessage("/tf", wall + i * NS_PER_S // 10, [Transform((1.0, 0, 0), (0, 0, 0, 1.0), start + i * NS_PER_S // 10,
                                                               "odom", "base_link")], "/sim")
        for i in range(30)
    ]  # fmt: skip
    result = tfx("monitor", "-b", write_bag(tmp_path / "sim.bag", messages))
    assert result.code == 0, result.stderr
    lines = result.stdout.splitlines()
    assert "\\n" not in result.stdout
    assert lines[0].startswith(str(tmp_path / "sim.bag")) and lines[1].startswith("delays unavailable: ")
