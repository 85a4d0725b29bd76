"""Record times decades from the rest of their file's (a recorder's clock reset, damaged bytes): how far
apart is too far, and the run of times kept. ``strays`` leaves the others out of a read."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from tftools.core.arrays import BoolArray, Int64Array
from tftools.core.time import NS_PER_S

#: Record times further than this from every other of their file's (ns) are not the recording's: no recorder
#: runs a year without a message, while a clock that jumps decades (a robot booted at 1970, a damaged time) does.
APART = 365 * 86_400 * NS_PER_S


class TfTimes(NamedTuple):
    """One tf channel's messages as read: their topic, publisher (where the file names it, else ""), record
    times and which were empty (held no transform)."""

    topic: str
    publisher: str
    record_time: Int64Array
    empty: BoolArray


def spread_apart(times: Int64Array) -> bool:
    """Whether ``times`` span more than ``APART`` (a cheap first look, before any sort)."""
    return len(times) > 1 and int(times.max()) - int(times.min()) > APART


def kept_span(times: Int64Array) -> tuple[int, int] | None:
    """The first and last of the most numerous run of ``times`` with no step over ``APART`` between
    them, where some lie apart from it; None where none does."""
    if len(times) < 2:
        return None
    ordered = np.sort(times)
    breaks = np.flatnonzero(np.diff(ordered.view(np.uint64)) > APART)  # unsigned: no step of 2**63 or more overflows
    if not len(breaks):
        return None
    bounds = np.concatenate([[0], breaks + 1, [len(ordered)]])
    run = int(np.argmax(np.diff(bounds)))
    return int(ordered[bounds[run]]), int(ordered[bounds[run + 1] - 1])
