"""Byte ranges of a file read in few calls: ranges close together share one read, and the system
is asked to fetch them all first, so a file not in the page cache costs one disk wait, not one per range.

A remote file's local copy (``storage.copies``) is filled instead: ``ahead`` and ``need`` are where the
readers say which ranges they are about to read.
"""

from __future__ import annotations

import os
from contextlib import suppress

import numpy as np

from tftools.core.arrays import BoolArray, Int64Array, UInt8Array
from tftools.sources.storage.copies import copy_of

MAX_GAP = 16 << 10  # bytes between two wanted ranges read along with them: cheaper than one more read


def read_ranges(fd: int, starts: Int64Array, ends: Int64Array) -> tuple[UInt8Array, Int64Array, BoolArray]:
    """The file's bytes ``starts[i]:ends[i]``, read in runs (ranges closer than ``MAX_GAP`` share
    one read): the runs' bytes, where each range begins in them, and whether it was read whole."""
    if not len(starts):
        return np.zeros(0, np.uint8), starts, np.zeros(0, bool)
    order = np.argsort(starts, kind="stable")
    low, high = starts[order], ends[order]
    reach = np.maximum.accumulate(high)
    first = np.append(True, low[1:] - reach[:-1] > MAX_GAP)
    firsts = np.flatnonzero(first)
    run = np.cumsum(first) - 1
    run_start, run_end = low[firsts], np.maximum.reduceat(high, firsts)
    placed = np.cumsum(run_end - run_start) - (run_end - run_start)  # where each run goes in the bytes
    ahead(fd, run_start, run_end)
    data = np.empty(int((run_end - run_start).sum()), np.uint8)
    view = data.data  # the array's bytes, read into in place
    complete = np.array(
        [
            read_into(fd, view[at : at + end - start], start)
            for start, end, at in zip(run_start.tolist(), run_end.tolist(), placed.tolist(), strict=True)
        ],
        bool,
    )
    where = np.empty(len(starts), np.int64)
    where[order] = placed[run] + low - run_start[run]
    read = np.empty(len(starts), bool)
    read[order] = complete[run]
    return data, where, read


def ahead(fd: int, starts: Int64Array, ends: Int64Array) -> None:
    """These byte ranges of the file will be read soon: a remote file's copy fetches them now, a
    local file's are read ahead (``prefetch``)."""
    copy = copy_of(fd)
    if copy is None:
        prefetch(fd, starts, ends)
    else:
        copy.fill(starts.tolist(), ends.tolist())


def need(fd: int, start: int, end: int) -> None:
    """``start:end`` of the file is read next: a remote file's copy fetches it (a local file's is there)."""
    copy = copy_of(fd)
    if copy is not None:
        copy.fill([start], [end])


def read_at(fd: int, start: int, end: int) -> bytes:
    """The file's bytes ``start:end`` (fewer where it ends first), a remote file's fetched first. Read
    past any file object's buffer: what it holds of a remote file's copy may predate the fetch."""
    need(fd, start, end)
    return os.pread(fd, max(0, end - start), start)


def prefetch(fd: int, starts: Int64Array, ends: Int64Array) -> None:
    """Have the system start reading these byte ranges of the file, all at once: read one after the
    other, a file not in the page cache would cost a disk's latency per range."""
    if not hasattr(os, "posix_fadvise"):
        return
    for start, end in zip(starts.tolist(), ends.tolist(), strict=True):
        if 0 <= start < end:  # a damaged index may give any range: a hint is only ever skipped
            with suppress(OSError, OverflowError):  # OverflowError: past what an off_t holds
                os.posix_fadvise(fd, start, end - start, os.POSIX_FADV_WILLNEED)


def read_into(fd: int, view: memoryview, offset: int) -> bool:
    """Fill ``view`` from the file at ``offset``; False when the file ends first."""
    while len(view):
        if hasattr(os, "preadv"):
            got = os.preadv(fd, [view], offset)
        else:  # a system without it (e.g. an older macOS): read, then copy
            part = os.pread(fd, len(view), offset)
            view[: len(part)] = part
            got = len(part)
        if not got:
            return False
        view, offset = view[got:], offset + got
    return True
