"""``LiveSource``: what every live system (ROS1 master, ROS2 DDS) offers the commands."""

from __future__ import annotations

from collections.abc import Callable
from types import TracebackType
from typing import Protocol, TypeVar, runtime_checkable

from tftools.core.batch import TransformBatch
from tftools.core.time import Clock

#: Called with each batch of transforms received, from the source's delivery thread (one thread,
#: so calls never overlap); rows are static where they came on ``/tf_static``, with the publisher
#: as authority and the receive time (on the source's clock) as record time.
OnBatch = Callable[[TransformBatch], None]

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


@runtime_checkable
class LiveSource(Protocol):
    """A live system's transforms as they arrive, and the clock they arrive on.

    ``start`` joins the system and returns once listening (raising ``LiveError`` if it cannot,
    e.g. no master), then ``on_batch`` is called with each batch until ``close``.
    """

    #: The transform topics listened to, e.g. ``("/tf", "/tf_static")``.
    topics: tuple[str, ...]

    #: What a capture's ``SourceInfo`` calls this kind of source, e.g. ``"ros1-live"``.
    format: str

    #: Transform messages received so far.
    message_count: int

    @property
    def clock(self) -> Clock:
        """Wall time, or the system's ``/clock`` under ``use_sim_time``."""
        ...

    @property
    def finished(self) -> bool:
        """True once the source stopped on its own (shut down by the system, e.g. ``rosnode kill``)."""
        ...

    def start(self, on_batch: OnBatch) -> None: ...

    def notice(self, message: str) -> None:
        """Say ``message`` (one line) as the source says its own notices, every time it is called."""
        ...

    def describe(self) -> str:
        """What is listened to, for humans and file lists: e.g. ``ROS1 master http://127.0.0.1:11311``."""
        ...

    def close(self) -> None: ...

    def __enter__(self) -> LiveSource: ...

    def __exit__(
        self, kind: type[BaseException] | None, error: BaseException | None, trace: TracebackType | None
    ) -> None: ...


_Self = TypeVar("_Self", bound="ContextManaged")


class ContextManaged:
    """``with source:`` closes it; for LiveSource implementations to inherit."""

    def close(self) -> None:
        raise NotImplementedError

    def __enter__(self: _Self) -> _Self:
        return self

    def __exit__(
        self, kind: type[BaseException] | None, error: BaseException | None, trace: TracebackType | None
    ) -> None:
        self.close()
