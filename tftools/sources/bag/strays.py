"""Messages whose record times lie decades from the rest of their file's (a recorder's clock reset, damaged
bytes): left out of a read, and said, so that no span, grid or repeat is sized by them."""

from __future__ import annotations

import dataclasses
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
    """The messages of ``read`` recorded ``APART`` from its most numerous run of record times left out (its
    transforms, clock, headers, messages read whole), and said in one line of its problems; its description's
    start and end brought within the rest where they lie apart too (a stray message of a topic not read)."""
    info = read.info
    tf = [b.record_time for b in read.batches]
    others = [read.clock.record_time, *(s.record_time for s in read.stamped), *(w.record_time for w in read.whole)]
    counted = [t.record_time for t in read.tf_times]  # every tf message, those empty too, where told
    arrays = [*tf, *others, read.sent.record_time, *counted, np.array([info.start, info.end], np.int64)]
    if _spread(arrays) <= APART:  # the usual case, told without a sort
        return
    every = np.concatenate(arrays)
    kept = kept_span(every[every != 0])  # 0: a time not set (an MCAP's robot description logged at 0), kept
    if kept is None:
        return
    first, last = kept

    def inside(record_time: Int64Array) -> BoolArray:
        held: BoolArray = ((record_time >= first) & (record_time <= last)) | (record_time == 0)
        return held

    # a tf message's once, not once a transform
    messages = counted or ([read.sent.record_time] if len(read.sent) else tf)
    left = np.concatenate([np.zeros(0, np.int64), *(t[~inside(t)] for t in [*messages, *others])])
    described = [t for t in (info.start, info.end) if t and not first <= t <= last]
    if not len(left) and not described:  # only transforms without their message's time (none of a bag's)
        return
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
    info.problems.append(_said(left, described, first, last))


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


def _said(left: Int64Array, described: Sequence[int], first: int, last: int) -> str:
    """One line: what was left out, when, and how far from the rest."""
    apart = [int(t) for t in left] or list(described)
    furthest = max(apart, key=lambda t: max(first - t, t - last))
    years = max(first - furthest, furthest - last) / NS_PER_S / (365.25 * 86_400)
    side = "before" if furthest < first else "after"
    what = f"{len(left)} message{'s' if len(left) != 1 else ''}" if len(left) else "its description's start or end"
    past = furthest == TIME_MAX  # a time past what an int64 holds (read from a u64): its true value not held
    when = f"record time {furthest} ns" + (" or later: 2262 on, past what a time holds" if past else "")
    return (
        f"{what} recorded {years:,.1f} years{' or more' if past else ''} {side} the rest ({when}; the rest from "
        f"{first} to {last}): left out as damaged (a recorder's clock reset, or bytes overwritten)"
    )
