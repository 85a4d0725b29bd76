"""Standard output as tfx writes it: whole, whatever ``PYTHONUNBUFFERED`` says, and a failure to write it
(a full disk, a device error) an error of its own, apart from a reader that stopped reading (``| head``).

Python's unbuffered standard output (``-u``, ``PYTHONUNBUFFERED=1``, common in containers) writes straight
to the file and drops what a short write (a disk filling up) left over, without a word; its buffered one
raises a bare ``OSError`` wherever the buffer happened to fill. Here both are one buffered stream (by
lines where the original was a terminal or unbuffered, so that live tables and JSON lines still come as
they are made) whose writes loop until all is written and whose failures are ``OutputError``."""

from __future__ import annotations

import io
import os
import sys
from typing import Any

from tftools.core.errors import TfToolsError


class OutputError(TfToolsError):
    """Standard output could not be written: what the command printed is incomplete."""

    def __init__(self, error: OSError) -> None:
        super().__init__(f"cannot write the output: {error.strerror or error}")
        self.hint = "free some space, or send the output elsewhere"


class ReaderGone(Exception):  # noqa: N818 (not an error: the reader had what it wanted)
    """The reader of standard output stopped reading (``| head``). Not an ``OSError``, which click would
    turn into exit code 1 before tfx sees it."""


class _Descriptor(io.RawIOBase):
    """File descriptor ``fd``, written with ``os.write``: a closed pipe is ``ReaderGone``, any other failure
    ``OutputError``."""

    def __init__(self, fd: int) -> None:
        super().__init__()
        self._fd = fd

    def writable(self) -> bool:
        return True

    def fileno(self) -> int:
        return self._fd

    def isatty(self) -> bool:
        return os.isatty(self._fd)

    def write(self, data: Any) -> int:
        try:
            return os.write(self._fd, data)
        except BrokenPipeError:
            raise ReaderGone from None
        except OSError as error:
            raise OutputError(error) from None


def checked_stdout() -> None:
    """Replace ``sys.stdout``, when it is the process's own standard output, by the checked stream."""
    original = sys.stdout
    if not isinstance(original, io.TextIOWrapper) or original is not sys.__stdout__:  # captured (tests), replaced
        return
    try:
        fd = original.fileno()
    except (OSError, ValueError):
        return
    original.flush()
    line_by_line = original.line_buffering or getattr(original, "write_through", False) or os.isatty(fd)
    sys.stdout = io.TextIOWrapper(
        io.BufferedWriter(_Descriptor(fd)),
        encoding=original.encoding,
        errors=original.errors,
        line_buffering=line_by_line,
    )
