"""Tables that fit the terminal they are printed on: columns where they fit, else one line a row.

A name (a frame, a publisher, a topic) is never cut or folded inside a cell. Where the table's natural
width does not fit, each row is one line, as ``tf_monitor`` prints an edge: its figures first, in
right-aligned columns, then its names whole; names that do not fit the rest of the line go on to
lines of their own, indented under the names, each name whole.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass

from rich.console import Console, ConsoleOptions, RenderableType, RenderResult
from rich.measure import Measurement
from rich.segment import Segment
from rich.style import Style
from rich.table import Table
from rich.text import Text

#: Past this many rows a table is written as lines without measuring it: rich lays a table out at
#: 0.3 ms a row, minutes for the 20,000 frames of a simulated fleet.
MAX_LAID_OUT_ROWS = 2000
#: Between the figures' columns, and between the figures and the names.
_GAP, _BEFORE_NAMES = " ", "  "


@dataclass(frozen=True)
class Row:
    """A row as lines: its figures (one a column) and its names, each a whole word that is never split."""

    figures: Sequence[Text]
    names: Sequence[Text]


class Lines:
    """Rows as lines under a title, a header of the figures' columns and a key line that says their
    units: the figures right-aligned, then the names (``names_header`` says what they are)."""

    def __init__(
        self, title: str, headers: Sequence[str], names_header: str, rows: Sequence[Row], key: str = ""
    ) -> None:
        self.title, self.headers, self.names_header, self.rows, self.key = title, headers, names_header, rows, key

    def __rich_console__(self, console: Console, options: ConsoleOptions) -> RenderResult:
        widths = [len(h) for h in self.headers]
        for row in self.rows:
            widths = [max(w, f.cell_len) for w, f in zip(widths, row.figures, strict=True)]
        indent = sum(widths) + len(_GAP) * (len(widths) - 1) + len(_BEFORE_NAMES)
        room = max(options.max_width - indent, 1)
        bold, dim = Style(bold=True), Style(dim=True)
        yield Segment(self.title + "\n", bold)
        if self.key:
            yield from _wrapped([Text(word) for word in self.key.split(" ")], 0, options.max_width, dim, console)
        header = _GAP.join(h.rjust(w) for h, w in zip(self.headers, widths, strict=True))
        yield Segment(header + _BEFORE_NAMES + self.names_header + "\n", bold)
        for row in self.rows:
            for figure, width in zip(row.figures, widths, strict=True):
                yield Segment(" " * (width - figure.cell_len))
                yield from figure.render(console)
                yield Segment(_GAP)
            yield Segment(_BEFORE_NAMES[len(_GAP) :])
            yield from _wrapped(list(row.names), indent, room, None, console)


def _wrapped(words: list[Text], indent: int, room: int, style: Style | None, console: Console) -> Iterator[Segment]:
    """``words`` one space apart on lines of ``room`` characters, each line after the first ``indent``
    spaces in; a word longer than the room has a line of its own (the terminal wraps it: never cut)."""
    used = 0
    for word in words:
        if used and used + 1 + word.cell_len > room:
            yield Segment("\n" + " " * indent)
            used = 0
        if used:
            yield Segment(" ")
            used += 1
        yield from (Segment(s.text, style or s.style) for s in word.render(console) if s.text != "\n")
        used += word.cell_len
    yield Segment("\n")


class Fitted:
    """A rich ``table`` where its natural width fits the terminal, else ``lines`` (a ``Lines``)."""

    def __init__(self, table: Table, lines: RenderableType) -> None:
        self.table, self.lines = table, lines

    def __rich_console__(self, console: Console, options: ConsoleOptions) -> RenderResult:
        if self.table.row_count > MAX_LAID_OUT_ROWS:
            yield self.lines
            return
        natural = Measurement.get(console, options.update_width(1_000_000), self.table).maximum  # unclamped
        yield self.table if natural <= options.max_width else self.lines


class Paragraphs:
    """Rows as paragraphs: each a list of words (a name is one word, never split) on lines as wide as
    the terminal, the lines after a paragraph's first indented two spaces."""

    def __init__(self, title: Text, paragraphs: Sequence[Sequence[Text]]) -> None:
        self.title, self.paragraphs = title, paragraphs

    def __rich_console__(self, console: Console, options: ConsoleOptions) -> RenderResult:
        yield from _wrapped(list(self.title.split(" ")), 0, options.max_width, None, console)
        for words in self.paragraphs:
            yield from _wrapped(list(words), 2, options.max_width - 2, None, console)
