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
    code, output = raw_terminal(args, columns, rows)
    return code, _ESCAPES.sub("", output)


def raw_terminal(
    args: list[str], columns: int, rows: int = 50, cwd: Path = REPO, stderr: bool = True
) -> tuple[int, str]:
    """Exit code and output, colours (escape sequences) and all, of ``tfx args`` run in ``cwd`` on a
    ``columns`` wide terminal; its standard error there too, or (``stderr`` False) nowhere."""
    main, secondary = pty.openpty()
    fcntl.ioctl(secondary, termios.TIOCSWINSZ, struct.pack("HHHH", rows, columns, 0, 0))
    environment = {k: v for k, v in os.environ.items() if k not in ("COLUMNS", "LINES", "NO_COLOR", "TFX_DEBUG")}
    environment["TERM"] = "xterm-256color"
    process = subprocess.Popen(
        [sys.executable, "-m", "tftools", *args], cwd=cwd, stdin=secondary, stdout=secondary,
        stderr=secondary if stderr else subprocess.DEVNULL, env=environment, close_fds=True,
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
    return code, output.decode("utf-8", "replace").replace("\r\n", "\n")


def table_cells(screen: str, title: str) -> list[list[str]]:
    """The cells of the table under ``title``, read from its text: columns are the character ranges that
    are not blank on every line, a row begins on a line whose ``key`` column (the first figure) is filled,
    and a cell folded onto several lines is joined back."""
    lines = screen.splitlines()
    start = lines.index(title) + 1
    # the table ends at a blank line or at its caption (its rows are indented by a column's padding)
    end = next((i for i in range(start, len(lines)) if not lines[i].startswith(" ")), len(lines))
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


def lines_rows(screen: str, title: str, header: str) -> list[tuple[list[str], str]]:
    """The rows of a table written as lines (a terminal too narrow for its columns) under ``title``: each
    row's figures (the words before the names' column, which the ``header`` line's names heading begins)
    and its names, the lines a row went on to joined back."""
    lines = screen.splitlines()
    start = next(i for i in range(lines.index(title) + 1, len(lines)) if lines[i].lstrip().startswith(header))
    names_at = len(lines[start]) - len(lines[start].split("  ")[-1])  # after the last two-space gap
    found: list[tuple[list[str], str]] = []
    for line in lines[start + 1 :]:
        if not line.strip():
            break
        if line[:names_at].strip():
            found.append((line[:names_at].split(), line[names_at:].strip()))
        else:
            figures, names = found[-1]
            found[-1] = (figures, f"{names} {line.strip()}")
    return found
