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
from tests.cli.conftest import SAMPLE_BAGS, Tfx, tfx
from tests.cli.terminal import REPO, lines_rows, on_terminal, table_cells
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
    truth: dict[str, object] = json.loads(done.stdout)
    return truth


@pytest.mark.parametrize("columns", [80, 120])
def test_names_are_never_cut_nor_folded(truth: dict[str, object], columns: int) -> None:
    """Where the table does not fit (its natural width is ~150 columns), one line an edge: the figures,
    then the names whole; a name that does not fit the line goes whole onto the next, under the names."""
    code, screen = on_terminal(["monitor", "-b", BAG], columns)
    assert code == 0, screen
    assert "\u2026" not in screen  # nothing cut short with an ellipsis
    tables = screen[screen.index("Frames:") :].splitlines()
    assert max(len(line) for line in tables) <= columns  # the terminal wraps none of their lines

    edges = truth["edges"]
    assert isinstance(edges, list)
    frames = lines_rows(screen, "Frames:", "Samples")
    assert [names for _, names in frames] == [
        f"{e['parent']} -> {e['child']} by {', '.join(e['authorities'])}" for e in edges
    ]
    for (figures, _), e in zip(frames, edges, strict=True):
        assert figures[:2] == [str(e["count"]), "static" if e["static"] else f"{e['rate_hz']:.2f}"]
        assert len(figures) == (2 if e["static"] else 6)
    first_lines = [line for line in tables if line.lstrip()[:1].isdigit()]
    assert all(f"{e['parent']} -> {e['child']}" in line for e, line in zip(edges, first_lines, strict=False))

    authorities = truth["authorities"]
    assert isinstance(authorities, list)
    broadcasters = lines_rows(screen, "All Broadcasters:", "Messages")
    assert [names for _, names in broadcasters] == [
        f"{a['authority']}: {', '.join(child for _, child in a['edges'])}" for a in authorities
    ]
    assert (
        "Jitter: how irregular an edge's stamps are, the standard deviation of the intervals between them"
        in " ".join(line.strip() for line in tables)
    )


def test_a_wide_terminal_gets_the_table() -> None:
    """At 200 columns the table fits: a row a line, every name in its column, the headers on one line."""
    code, screen = on_terminal(["monitor", "-b", BAG], 200)
    lines = table_cells(screen, "Frames:")
    assert code == 0 and lines[0][:4] == ["Parent", "Frame", "published by", "Samples"]
    assert all(line[3] for line in lines[1:])  # every line has its samples: no folded name
    assert {line[1] for line in lines[1:]} >= {"camera_optical_frame", "left_wheel", "right_wheel"}
    assert (
        "\nJitter: how irregular an edge's stamps are, the standard deviation of the intervals between them\n" in screen
    )


def test_a_simulated_clock_header_is_two_lines(tfx: Tfx, tmp_path: Path) -> None:
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
