"""``dot`` gets a deadline: a tree it cannot draw in time gives one clear error and its source, not a hang."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import graphviz
import pytest

from tftools.render import drawing

pytestmark = pytest.mark.skipif(shutil.which("dot") is None, reason="Graphviz's dot is not installed")


def big_tree(frames: int) -> graphviz.Digraph:
    dot = graphviz.Digraph()
    for n in range(frames):
        dot.node(f"frame_{n}", label=f"frame {n}")
        if n:
            dot.edge(f"frame_{(n - 1) // 3}", f"frame_{n}")
    return dot


def test_a_graph_dot_cannot_draw_in_time_is_written_as_its_source(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(drawing, "DRAW_SECONDS", 0.001)
    output = tmp_path / "frames.pdf"
    with pytest.raises(drawing.GraphTooLargeError) as raised:
        drawing.write_graph(big_tree(1500), output, "pdf")
    said = str(raised.value)
    assert "did not finish 1500 frames" in said and "frames.gv" in said and "dot -Tpdf" in raised.value.hint
    assert not output.exists() and (tmp_path / "frames.gv").read_text().startswith("digraph")


def test_a_graph_of_more_frames_than_dot_draws_in_seconds_is_not_tried(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Issue 44: a report of 10,000 frames waited DRAW_SECONDS for dot; such a graph is written as its source
    at once, with the count (dot never runs: a deadline of a day would not be reached)."""
    monkeypatch.setattr(drawing, "DRAW_SECONDS", 86_400.0)
    monkeypatch.setattr(subprocess, "run", lambda *_a, **_k: pytest.fail("dot was run"))
    output = tmp_path / "frames.pdf"
    with pytest.raises(drawing.GraphTooLargeError) as raised:
        drawing.write_graph(big_tree(drawing.MAX_DRAWN_FRAMES + 1), output, "pdf")
    said = str(raised.value)
    assert "too large to draw, 2,001 frames (Graphviz's `dot` is given 2,000 at most)" in said
    assert "frames.gv" in said and not output.exists() and (tmp_path / "frames.gv").read_text().startswith("digraph")


def test_a_small_graph_is_drawn(tmp_path: Path) -> None:
    written = drawing.write_graph(big_tree(5), tmp_path / "frames.svg", "svg")
    assert written.read_text().count('<g id="node') == 5
