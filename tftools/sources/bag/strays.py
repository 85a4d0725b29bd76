"""Messages whose record times lie decades from the rest of their file's (a recorder's clock reset, damaged
bytes): left out of a read, and said, so that no span, grid or repeat is sized by them."""

from __future__ import annotations

import dataclasses
import itertools
from collections.abc import Callable, Sequence

import numpy as np

from tftools.core.arrays import BoolArray, Int64Array
from tftools.core.batch import take_rows
from tftools.core.time import NS_PER_S, TIME_MAX
from tftools.sources.bag.apart import APART, TfTimes, kept_span
from tftools.sources.bag.contents import BagFileInfo
from tftools.sources.bag.scan import FileRead
from tftools.sources.contents import StampedMessages


def leave_out_strays(read: FileRead) -> None:
    """The messages of ``read`` (a whole file's) recorded ``APART`` from its most numerous run of record times
    left out (its transforms, clock, headers, messages read whole), and said in one line of its problems; its
    description's start and end brought within the rest where they lie apart too (a stray message of a topic
    not read)."""
    info = read.info
    arrays = [*_message_times(read), *(b.record_time for b in read.batches), np.array([info.start, info.end], np.int64)]
    if _spread(arrays) <= APART:  # the usual case, told without a sort
        return
    every = np.concatenate(arrays)
    kept = kept_span(every[every != 0])  # 0: a time not set (an MCAP's robot description logged at 0), kept
    if kept is None:
        return
    left, described = _left_out(read, *kept)
    if len(left) or described:
        info.problems.append(_said(len(left), _furthest([*left.tolist(), *described], *kept), *kept))


def leave_out_of_window(read: FileRead, kept: tuple[int, int], count: int, said: str, *, described: bool) -> None:
    """A window's ``read``: its messages outside ``kept`` (the span ``TimeRuns`` learnt over every window of its
    file) left out as ``leave_out_strays`` leaves a whole file's, and ``said`` once for the file; a read of the
    descriptions alone (``described``) has the ``count`` messages left out of every window taken off its own."""
    _left_out(read, *kept)
    if described:
        read.info.message_count = max(0, read.info.message_count - count)
    if said not in read.info.problems:
        read.info.problems.append(said)


class TimeRuns:
    """A file's record times gathered window by window as runs with no step over ``APART`` within (first,
    last, how many): a few however long the recording, at most ``MAX_RUNS`` (then the least numerous are
    counted together), so that a windowed read learns the strays a whole read leaves out."""

    MAX_RUNS = 64

    def __init__(self) -> None:
        self.runs: list[tuple[int, int, int]] = []
        self.described: list[int] = []  # the file's description's start and end

    def add(self, read: FileRead) -> None:
        """The message times of one window's ``read``."""
        self.described = [t for t in (read.info.start, read.info.end) if t]
        every = np.concatenate([np.zeros(0, np.int64), *_message_times(read)])
        every = np.sort(every[every != 0])
        if not len(every):
            return
        bounds = [0, *(np.flatnonzero(np.diff(every.view(np.uint64)) > APART) + 1).tolist(), len(every)]
        found = [(int(every[a]), int(every[b - 1]), b - a) for a, b in itertools.pairwise(bounds)]
        self.runs = _merged(self.runs + found)
        if len(self.runs) > self.MAX_RUNS:
            largest = sorted(self.runs, key=lambda r: -r[2])
            rest = largest[self.MAX_RUNS - 1 :]
            joined = (min(r[0] for r in rest), max(r[1] for r in rest), sum(r[2] for r in rest))
            self.runs = sorted([*largest[: self.MAX_RUNS - 1], joined])

    def strays(self) -> tuple[tuple[int, int], int, str] | None:
        """The span kept, how many messages lay apart from it and the line that says so, where some times lie
        apart; else None."""
        if not self.runs:
            return None
        first, last, _ = max(self.runs, key=lambda r: r[2])
        near = [t for t in self.described if first - APART <= t <= last + APART]  # a topic not read's, as whole
        first, last = min([first, *near]), max([last, *near])
        apart = [r for r in self.runs if r[1] < first or r[0] > last]
        described = [t for t in self.described if not first <= t <= last]
        if not apart and not described:
            return None
        ends = [t for r in apart for t in r[:2]] + described
        count = sum(r[2] for r in apart)
        return (first, last), count, _said(count, _furthest(ends, first, last), first, last)


def _merged(runs: list[tuple[int, int, int]]) -> list[tuple[int, int, int]]:
    """``runs`` sorted, those that overlap or lie within ``APART`` of each other joined."""
    joined: list[tuple[int, int, int]] = []
    for first, last, count in sorted(runs):
        if joined and first - joined[-1][1] <= APART:
            was = joined[-1]
            joined[-1] = (was[0], max(was[1], last), was[2] + count)
        else:
            joined.append((first, last, count))
    return joined


def _message_times(read: FileRead) -> list[Int64Array]:
    """The record times of ``read``'s messages, each once: its tf messages (those empty too, where told), its
    clock's, its headers' and those read whole."""
    tf = [t.record_time for t in read.tf_times] or (
        [read.sent.record_time] if len(read.sent) else [b.record_time for b in read.batches]
    )
    return [*tf, read.clock.record_time, *(s.record_time for s in read.stamped), *(w.record_time for w in read.whole)]


def _left_out(read: FileRead, first: int, last: int) -> tuple[Int64Array, list[int]]:
    """``read``'s messages recorded outside ``first`` to ``last`` left out, its counts and description brought
    within; returns their record times and the description's ends that lay outside."""
    info = read.info

    def inside(record_time: Int64Array) -> BoolArray:
        held: BoolArray = ((record_time >= first) & (record_time <= last)) | (record_time == 0)
        return held

    left = np.concatenate([np.zeros(0, np.int64), *(t[~inside(t)] for t in _message_times(read))])
    described = [t for t in (info.start, info.end) if t and not first <= t <= last]
    if not len(left) and not described:  # only transforms without their message's time (none of a bag's)
        return left, described
    transforms = [inside(b.record_time) for b in read.batches]
    dropped_rows = np.flatnonzero(~np.concatenate([np.ones(0, bool), *transforms]))
    read.batches = [take_rows(b, np.flatnonzero(k)) for b, k in zip(read.batches, transforms, strict=True)]
    read.batches = [b for b in read.batches if len(b)]
    clock = inside(read.clock.record_time)
    read.clock = dataclasses.replace(
        read.clock, record_time=read.clock.record_time[clock], clock=read.clock.clock[clock]
    )
    read.sent = read.sent.taken(np.flatnonzero(inside(read.sent.record_time)))
    read.stamped = [_stamped_kept(s, inside(s.record_time), dropped_rows) for s in read.stamped]
    read.whole = [
        dataclasses.replace(w, record_time=w.record_time[k], values=[v for v, h in zip(w.values, k, strict=True) if h])
        for w in read.whole
        for k in [inside(w.record_time)]
    ]
    info.transform_count -= len(dropped_rows)
    info.message_count = max(0, info.message_count - len(left))
    _tf_counts_kept(info, read.tf_times, inside)
    if described:
        info.start, info.end = max(info.start, first) if info.start else 0, min(info.end, last)
    return left, described


def _furthest(times: Sequence[int], first: int, last: int) -> int:
    return max(times, key=lambda t: max(first - t, t - last))


def _tf_counts_kept(info: BagFileInfo, tf_times: Sequence[TfTimes], inside: Callable[[Int64Array], BoolArray]) -> None:
    """``info``'s counts of tf messages per topic (and of empty ones per publisher) without those left out."""
    for channel in tf_times:
        out = ~inside(channel.record_time)
        left, empty = int(out.sum()), int((out & channel.empty).sum())
        count, empties = info.tf_messages.get(channel.topic, (0, 0))
        if left:
            info.tf_messages[channel.topic] = (count - left, empties - empty)
        senders = info.tf_empty_from.get(channel.topic, {})
        if empty and channel.publisher in senders:
            senders[channel.publisher] -= empty
            if not senders[channel.publisher]:
                del senders[channel.publisher]


def _spread(arrays: Sequence[Int64Array]) -> int:
    """From the earliest to the latest time of ``arrays`` but 0 (ns)."""
    lows, highs = [], []
    for times in arrays:
        if len(times) and (int(times.min()) == 0 or int(times.max()) == 0):
            times = times[times != 0]
        if len(times):
            lows.append(int(times.min()))
            highs.append(int(times.max()))
    return max(highs) - min(lows) if lows else 0


def _stamped_kept(stream: StampedMessages, held: BoolArray, dropped_rows: Int64Array) -> StampedMessages:
    """``stream``'s messages ``held``, each still placed among the transforms kept."""
    rows = np.flatnonzero(held)
    columns = {name: getattr(stream, name)[rows] for name in ("record_time", "stamp", "frame")}
    if stream.ordered:
        before = stream.tf_before[rows]
        columns["tf_before"] = before - np.searchsorted(dropped_rows, before, side="left")
    if stream.states_transforms:
        columns["child"], columns["pose"] = stream.child[rows], stream.pose[rows]
    return dataclasses.replace(stream, **columns)


def _said(count: int, furthest: int, first: int, last: int) -> str:
    """One line: how many messages were left out (none: only the description's start or end lay apart), the
    furthest of them, and how far it lies from the rest."""
    years = max(first - furthest, furthest - last) / NS_PER_S / (365.25 * 86_400)
    side = "before" if furthest < first else "after"
    what = f"{count} message{'s' if count != 1 else ''}" if count else "its description's start or end"
    past = furthest == TIME_MAX  # a time past what an int64 holds (read from a u64): its true value not held
    when = f"record time {furthest} ns" + (" or later: 2262 on, past what a time holds" if past else "")
    return (
        f"{what} recorded {years:,.1f} years{' or more' if past else ''} {side} the rest ({when}; the rest from "
        f"{first} to {last}): left out as damaged (a recorder's clock reset, or bytes overwritten)"
    )
