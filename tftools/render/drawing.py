"""A view-frames graph drawn by Graphviz's ``dot`` into a picture file, written whole or not at all."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
from pathlib import Path

import graphviz

from tftools.core.errors import TfToolsError
from tftools.render.escape import printable
from tftools.render.files import write_atomically
from tftools.render.graph import SIGNATURE

INSTALL_HINT = (
    "install Graphviz: sudo apt-get install graphviz, brew install graphviz, or https://graphviz.org/download"
)


#: How long ``dot`` may take to draw one graph: a tree of thousands of frames can take it minutes.
DRAW_SECONDS = 15.0

#: The most frames given to ``dot``: its time grows faster than the square of the frames (a fan of 1,000
#: frames drew in 0.4 s of CPU, 2,000 in 1.8 s, 3,000 in 7.7 s), so a larger graph is not tried: a report of
#: 10,000 frames spent 15 s waiting for it before its page was written.
MAX_DRAWN_FRAMES = 2_000


class GraphNotDrawnError(TfToolsError):
    """The picture could not be drawn by ``dot`` (its Graphviz source may have been written instead)."""

    def __init__(self, message: str, hint: str, source_path: str | None) -> None:
        super().__init__(message)
        self.hint = hint
        self.source_path = source_path

    def with_source(self, output: str, source_path: str) -> GraphNotDrawnError:
        """The same failure, said of ``output`` with its source written at ``source_path`` (each kind
        says it in its own words)."""
        raise NotImplementedError(type(self).__name__)


class GraphvizMissingError(GraphNotDrawnError):
    """Graphviz's ``dot`` is not installed."""

    def __init__(self, output: str, source_path: str | None = None) -> None:
        wrote = f"; wrote its source {source_path}" if source_path else ""
        then = f"; then: dot -T{Path(output).suffix.lstrip('.')} {source_path} -o {output}" if source_path else ""
        super().__init__(
            f"Graphviz's `dot` program was not found, so {output} was not drawn{wrote}",
            f"{INSTALL_HINT}{then}",
            source_path,
        )
        self.output = output

    def with_source(self, output: str, source_path: str) -> GraphNotDrawnError:
        return GraphvizMissingError(output, source_path)


class GraphTooLargeError(GraphNotDrawnError):
    """``dot`` did not finish within ``DRAW_SECONDS`` (a graph of thousands of frames), or was not tried: more
    than ``MAX_DRAWN_FRAMES`` frames (``tried`` False)."""

    def __init__(self, output: str, nodes: int, source_path: str | None = None, *, tried: bool = True) -> None:
        wrote = f"; wrote its source {source_path}" if source_path else ""
        if source_path:
            hint = f"dot -T{Path(output).suffix.lstrip('.')} {source_path} -o {output} draws it without a time limit"
        else:  # drawn for a page: view-frames writes the source
            hint = (
                "write_graph(graph, 'frames.gv', 'dot') writes its source; dot -Tsvg frames.gv -o frames.svg draws it"
            )
        if tried:
            why = f"Graphviz's `dot` did not finish {nodes} frames in {DRAW_SECONDS:.0f} s"
        else:
            why = f"too large to draw, {nodes:,} frames (Graphviz's `dot` is given {MAX_DRAWN_FRAMES:,} at most)"
        super().__init__(f"{output} was not drawn: {why}{wrote}", hint, source_path)
        self.output, self.nodes, self.tried = output, nodes, tried

    def with_source(self, output: str, source_path: str) -> GraphNotDrawnError:
        return GraphTooLargeError(output, self.nodes, source_path, tried=self.tried)


class GraphvizFailedError(TfToolsError):
    """Graphviz's ``dot`` refused the graph (a tfx bug: names are escaped before they reach it)."""

    def __init__(self, output: str, stderr: bytes | str | None) -> None:
        said = stderr.decode(errors="replace") if isinstance(stderr, bytes) else stderr or ""
        first = next((line.strip() for line in said.splitlines() if line.strip()), "no message")
        super().__init__(f"Graphviz's `dot` could not draw {output}: {printable(first)}")
        self.hint = "write the Graphviz source (format dot), and please report this to tftools"


class OutputExistsError(TfToolsError):
    """A file tfx did not ask for would be overwritten."""

    def __init__(self, path: str) -> None:
        super().__init__(f"{path} exists and is not a graph tftools wrote; not overwriting it")
        self.path = path
        self.hint = "move it away, or name another output"


def draw(dot: graphviz.Digraph, fmt: str, output: str = "the graph") -> bytes:
    """``dot`` drawn as ``fmt`` (pdf, svg, png; dot: the source itself) by Graphviz's ``dot`` program."""
    if fmt == "dot":
        return str(dot.source).encode()
    program = shutil.which("dot")
    if program is None:
        raise GraphvizMissingError(output)
    nodes = _nodes(dot)
    if nodes > MAX_DRAWN_FRAMES:
        raise GraphTooLargeError(output, nodes, tried=False)
    try:  # dot's warnings stay in its captured stderr: they would break tfx's one-line errors
        done = subprocess.run(
            [program, f"-T{fmt}"],
            input=str(dot.source).encode(),
            capture_output=True,
            timeout=DRAW_SECONDS,
            check=False,
        )
    except subprocess.TimeoutExpired:
        raise GraphTooLargeError(output, nodes) from None
    except OSError:
        raise GraphvizMissingError(output) from None
    if done.returncode != 0:
        raise GraphvizFailedError(output, done.stderr)
    return done.stdout


def _nodes(dot: graphviz.Digraph) -> int:
    """How many frames the graph draws: its node statements at the top level (the legend's are inside a
    cluster of their own, one tab further in)."""
    return sum(1 for line in dot.body if _NODE.match(line) and " -> " not in line)


#: A top-level node statement of Graphviz's source as the graphviz package writes it: a tab, an id, its
#: attributes if any.
_NODE = re.compile(r'^\t(?!(?:subgraph|graph|node|edge)\b)("(?:[^"\\]|\\.)*"|[\w.]+)(?: \[|\s*$)')


def write_graph(dot: graphviz.Digraph, output: str | os.PathLike[str], fmt: str) -> Path:
    """Write ``dot`` drawn as ``fmt`` to ``output``, whole or not at all (else ``OutputError``). Without
    Graphviz, or when ``dot`` runs out of its time, writes the source beside it (``.gv``, never over a file
    tfx did not write) and raises the ``GraphNotDrawnError`` naming it."""
    target = Path(output)
    try:
        picture = draw(dot, fmt, str(target))
    except GraphNotDrawnError as not_drawn:
        source_path = target.with_suffix(".gv")
        _refuse_foreign(source_path)
        write_atomically(source_path, str(dot.source).encode())
        raise not_drawn.with_source(str(target), str(source_path)) from None
    return write_atomically(target, picture)


def _refuse_foreign(path: Path) -> None:
    if not path.exists():
        return
    try:
        with path.open(encoding="utf-8", errors="replace") as f:
            first = f.readline()
    except OSError:
        first = ""
    if SIGNATURE not in first:
        raise OutputExistsError(str(path))
