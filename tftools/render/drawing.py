"""A view-frames graph drawn by Graphviz's ``dot`` into a picture file, written whole or not at all."""

from __future__ import annotations

import os
from pathlib import Path

import graphviz

from tftools.core.errors import TfToolsError
from tftools.render.escape import printable
from tftools.render.files import write_atomically
from tftools.render.graph import SIGNATURE

INSTALL_HINT = (
    "install Graphviz: sudo apt-get install graphviz, brew install graphviz, or https://graphviz.org/download"
)


class GraphvizMissingError(TfToolsError):
    """Graphviz's ``dot`` is not installed: the picture could not be drawn (its source may have been written)."""

    def __init__(self, output: str, source_path: str | None = None) -> None:
        wrote = f"; wrote its source {source_path}" if source_path else ""
        super().__init__(f"Graphviz's `dot` program was not found, so {output} was not drawn{wrote}")
        then = f"; then: dot -T{Path(output).suffix.lstrip('.')} {source_path} -o {output}" if source_path else ""
        self.hint = f"{INSTALL_HINT}{then}"
        self.source_path = source_path


class GraphvizFailedError(TfToolsError):
    """Graphviz's ``dot`` refused the graph (a tfx bug: names are escaped before they reach it)."""

    def __init__(self, output: str, stderr: bytes | str | None) -> None:
        said = stderr.decode(errors="replace") if isinstance(stderr, bytes) else stderr or ""
        first = next((line.strip() for line in said.splitlines() if line.strip()), "no message")
        super().__init__(f"Graphviz's `dot` could not draw {output}: {printable(first)}")
        self.hint = "write the Graphviz source with --format dot, and please report this to tftools"


class OutputExistsError(TfToolsError):
    """A file tfx did not ask for would be overwritten."""

    def __init__(self, path: str) -> None:
        super().__init__(f"{path} exists and was not written by tfx view-frames; not overwriting it")
        self.hint = "move it away, or name the output with -o"


def draw(dot: graphviz.Digraph, fmt: str, output: str = "the graph") -> bytes:
    """``dot`` drawn as ``fmt`` (pdf, svg, png; dot: the source itself) by Graphviz's ``dot`` program."""
    if fmt == "dot":
        return str(dot.source).encode()
    try:
        return bytes(dot.pipe(format=fmt, engine="dot", quiet=True))  # dot's warnings would break tfx's one-line errors
    except graphviz.ExecutableNotFound:
        raise GraphvizMissingError(output) from None
    except graphviz.CalledProcessError as error:
        raise GraphvizFailedError(output, error.stderr) from None


def write_graph(dot: graphviz.Digraph, output: str | os.PathLike[str], fmt: str) -> Path:
    """Write ``dot`` drawn as ``fmt`` to ``output``, whole or not at all (else ``OutputError``). Without
    Graphviz, writes the source beside it (``.gv``, never over a file tfx did not write) and raises
    ``GraphvizMissingError`` naming it."""
    target = Path(output)
    try:
        picture = draw(dot, fmt, str(target))
    except GraphvizMissingError:
        source_path = target.with_suffix(".gv")
        _refuse_foreign(source_path)
        write_atomically(source_path, str(dot.source).encode())
        raise GraphvizMissingError(str(target), str(source_path)) from None
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
