"""Running ``tfx`` on a pseudo terminal of a given size, as a person's terminal would show it."""

from __future__ import annotations

import fcntl
import os
import pty
import re
import struct
import subprocess
import sys
import termios
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
_ESCAPES = re.compile(r"\x1b\[[0-9;?]*[A-Za-z]")


def on_terminal(args: list[str], columns: int, rows: int = 50) -> tuple[int, str]:
    """Exit code and screen text (escape sequences dropped) of ``tfx args`` on a ``columns`` wide terminal."""
    main, secondary = pty.openpty()
    fcntl.ioctl(secondary, termios.TIOCSWINSZ, struct.pack("HHHH", rows, columns, 0, 0))
    environment = {k: v for k, v in os.environ.items() if k not in ("COLUMNS", "LINES", "NO_COLOR", "TFX_DEBUG")}
    environment["TERM"] = "xterm-256color"
    process = subprocess.Popen(
        [sys.executable, "-m", "tftools", *args], cwd=REPO, stdin=secondary, stdout=secondary, stderr=secondary,
        env=environment, close_fds=True,
    )  # fmt: skip
    os.close(secondary)
    output = b""
    while True:
        try:
            chunk = os.read(main, 65536)
        except OSError:  # the other end closed: the process ended
            break
        if not chunk:
            break
        output += chunk
    os.close(main)
    code = process.wait()
    return code, _ESCAPES.sub("", output.decode("utf-8", "replace")).replace("\r\n", "\n")


def table_cells(screen: str, title: str) -> list[list[str]]:
    """The cells of the table under ``title``, read from its text: columns are the character ranges that
    are not blank on every line, a row begins on a line whose ``key`` column (the first figure) is filled,
    and a cell folded onto several lines is joined back."""
    lines = screen.splitlines()
    start = lines.index(title) + 1
    end = next((i for i in range(start, len(lines)) if not lines[i].strip()), len(lines))
    table = lines[start:end]
    width = max(map(len, table))
    padded = [line.ljust(width) for line in table]
    filled = [any(line[i] != " " for line in padded) for i in range(width)]
    spans: list[tuple[int, int]] = []
    for i, used in enumerate(filled):
        if used and (not spans or spans[-1][1] != i):
            spans.append((i, i + 1))
        elif used:
            spans[-1] = (spans[-1][0], i + 1)
    return [[line[a:b].strip() for a, b in spans] for line in padded]


def rows(cells: list[list[str]], header_lines: int, key: int) -> list[list[str]]:
    """Table lines (``table_cells``) as rows: a row begins where column ``key`` is filled; the cells of
    its following lines are appended (a folded name comes back whole; a wrapped list with its spaces lost)."""
    joined: list[list[str]] = []
    for line in cells[header_lines:]:
        if line[key] or not joined:
            joined.append(list(line))
        else:
            joined[-1] = [a + b for a, b in zip(joined[-1], line, strict=True)]
    return joined
