"""A recording's check with a time limit (``tfx wtf --timeout``), kept inside the task so that every
executor, local or Dask, applies it the same way; a small module because Dask workers import it."""

from __future__ import annotations

import functools
import threading
from collections.abc import Callable, Sequence
from concurrent import futures
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from tftools.analysis.wtf.fleet import BagReport

CheckGroup = Callable[[Sequence[str]], "BagReport"]


class CheckTimeoutError(Exception):
    """A recording's check ran out of its time."""


def timed(check: CheckGroup, seconds: float | None) -> CheckGroup:
    """``check`` given up after ``seconds`` (none: no limit), raising ``CheckTimeoutError``."""
    return check if seconds is None else functools.partial(_within, check, seconds)


def _within(check: CheckGroup, seconds: float, group: Sequence[str]) -> BagReport:
    outcome: futures.Future[BagReport] = futures.Future()

    def run() -> None:
        try:
            outcome.set_result(check(group))
        except BaseException as error:  # handed to the waiting thread, which raises it
            outcome.set_exception(error)

    threading.Thread(target=run, name="tfx-check", daemon=True).start()
    try:
        return outcome.result(timeout=seconds)
    except futures.TimeoutError:  # the builtin TimeoutError only from Python 3.11
        raise CheckTimeoutError(f"its check took longer than {seconds:g} s") from None
