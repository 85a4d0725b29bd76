"""The notices of a live system: one-line messages about what a peer did (a publisher of another type, a
lost connection), each passed on once, peers' text made printable."""

from __future__ import annotations

from collections.abc import Callable

#: Called with a one-line notice: a publisher that speaks another type, a lost connection...
OnNotice = Callable[[str], None]


def printable(text: str, limit: int = 200) -> str:
    """``text`` from a peer (a node name, its error message) fit for one line of a notice: control
    characters (escape codes, newlines) shown escaped, and at most ``limit`` characters of it."""
    shown = "".join(c if c.isprintable() else repr(c)[1:-1] for c in text[:limit])
    return shown + ("..." if len(text) > limit else "")


def ignore_notice(_message: str) -> None:
    """An ``OnNotice`` for no one."""


class NoticeOnce:
    """Passes each distinct notice on once: a publisher failing at every message is told of once."""

    def __init__(self, on_notice: OnNotice | None) -> None:
        self._on_notice = on_notice or ignore_notice
        self._noticed: set[str] = set()

    def __call__(self, message: str) -> None:
        if message not in self._noticed:
            self._noticed.add(message)
            self._on_notice(message)
