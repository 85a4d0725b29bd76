"""Replaying a recording on a simulated clock, and the loop that drives any feed of transforms."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Iterable
from typing import Protocol

import numpy as np

from tftools.core.batch import TransformBatch, concat_batches, take_rows
from tftools.core.buffer import Buffer
from tftools.core.time import NS_PER_S, Clock, SimClock
from tftools.sources.ticker import tick_every

OnBatch = Callable[[TransformBatch], None]

#: How often the replay advances its clock when no message is due, like ``rosbag play --hz``.
CLOCK_HZ = 100.0


class Feed(Protocol):
    """Transforms as they arrive and the clock they arrive on: a replay or a live source. ``start``
    returns at once; ``on_batch`` is then called (from any thread) with each batch."""

    @property
    def clock(self) -> Clock: ...

    def start(self, on_batch: OnBatch) -> None: ...

    def close(self) -> None: ...


class Replay:
    """Plays transforms in record order at ``rate`` times real speed while a ``SimClock`` follows bag
    time: ``rosbag play --clock`` seen by a node with ``use_sim_time``. Playing starts at ``start``
    (default: the first row), first delivering the statics recorded before it (a latched
    ``/tf_static`` a late subscriber still gets), and ends at ``end`` (default: the last row).

    ``transforms`` is one batch, or consecutive parts in record order (a stream's windows), taken one
    at a time as the clock reaches them: only the part being played is held.
    """

    def __init__(
        self,
        transforms: TransformBatch | Iterable[TransformBatch],
        *,
        rate: float = 1.0,
        start: int | None = None,
        end: int | None = None,
        sleep: Callable[[float], None] = time.sleep,
        monotonic: Callable[[], float] = time.monotonic,
    ) -> None:
        if not rate > 0:
            raise ValueError(f"the replay rate must be above 0, got {rate}")
        self.rate = rate
        self._parts = iter([transforms] if isinstance(transforms, TransformBatch) else transforms)
        self._part, self._next = TransformBatch.empty(), 0  # the part being played, and its next row
        first = self._pending()
        self.begin = start if start is not None else int(first.record_time[0]) if first is not None else 0
        self.end = end  # where the replay ends: if not given, the last row's record time once it was played
        self._last = self.begin  # the newest row's record time played: the end, unless given
        self._sleep, self._monotonic = sleep, monotonic
        self.clock = SimClock(self.begin)
        self._on_batch: OnBatch | None = None
        self._closed = threading.Event()
        self._finished = threading.Event()
        self._thread: threading.Thread | None = None
        self.error: Exception | None = None

    @property
    def finished(self) -> bool:
        """True once the clock has reached ``end`` (or the replay was closed)."""
        return self._finished.is_set()

    def start(self, on_batch: OnBatch) -> None:
        """Play in a background thread, calling ``on_batch`` from it."""
        self._thread = threading.Thread(target=self.run, args=(on_batch,), name="tfx-replay", daemon=True)
        self._thread.start()

    def run(self, on_batch: OnBatch) -> None:
        """Play in this thread until the end or ``close``; a part that cannot be read (a file changed
        since it was opened) ends the replay, and is kept in ``error``."""
        try:
            self.attach(on_batch)
            started = self._monotonic()
            while not self._closed.is_set() and not self.finished:
                now = self.begin + round((self._monotonic() - started) * self.rate * NS_PER_S)
                self.advance_to(now)
                if not self.finished:
                    self._sleep(self._pause(now))
        except Exception as error:
            self.error = error
        self._finished.set()

    def attach(self, on_batch: OnBatch) -> None:
        """Deliver to ``on_batch`` from now on, starting with the static transforms recorded
        before ``begin``; for driving the replay by hand with ``advance_to``."""
        self._on_batch = on_batch
        earlier_static: list[TransformBatch] = []
        while (part := self._pending()) is not None and int(part.record_time[self._next]) < self.begin:
            skipped = np.arange(self._next, int(np.searchsorted(part.record_time, self.begin, side="left")))
            earlier_static.append(take_rows(part, skipped[part.static[skipped]]))
            self._next += len(skipped)
        if any(len(b) for b in earlier_static):
            on_batch(concat_batches(earlier_static))

    def advance_to(self, bag_time: int) -> None:
        """Deliver every row recorded up to ``bag_time`` (at most ``end``), then set the clock."""
        if self.end is not None:
            bag_time = min(bag_time, self.end)
        while (part := self._pending()) is not None and int(part.record_time[self._next]) <= bag_time:
            upto = int(np.searchsorted(part.record_time, bag_time, side="right"))
            self._last = int(part.record_time[upto - 1])
            if self._on_batch is not None:
                self._on_batch(take_rows(part, np.arange(self._next, upto)))
            self._next = upto
        if self.end is None and self._pending() is None:
            self.end = max(self._last, self.begin)  # every row played: the replay ends at the last
            bag_time = min(bag_time, self.end)
        self.clock.set(bag_time)
        if self.end is not None and bag_time >= self.end:
            self._finished.set()

    def _pending(self) -> TransformBatch | None:
        """The part holding the next row to play, taking the next parts as they are reached; None once
        every row was played."""
        while self._next >= len(self._part):
            part = next(self._parts, None)
            if part is None:
                return None
            self._part, self._next = part, 0
        return self._part

    def _pause(self, now: int) -> float:
        """Wall seconds until the next row is due, at most one clock tick."""
        part = self._pending()
        due = int(part.record_time[self._next]) if part is not None else now
        if self.end is not None:
            due = min(due, self.end)
        return max(0.0, min((due - now) / NS_PER_S / self.rate, 1.0 / CLOCK_HZ))

    def close(self) -> None:
        """Stop playing (the thread ends within one clock tick)."""
        self._closed.set()
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join(timeout=1.0)
        self._finished.set()


def follow(
    feed: Feed,
    on_batch: OnBatch,
    on_tick: Callable[[], object],
    *,
    period: float = 1.0,
    duration: float | None = None,
    sleep: Callable[[float], None] = time.sleep,
    monotonic: Callable[[], float] = time.monotonic,
) -> None:
    """Start ``feed`` into ``on_batch`` and call ``on_tick`` every ``period`` wall seconds until
    ``duration`` seconds have passed or the feed is finished, then once more; the feed is closed, and
    the error that ended it (a replay's ``error``) raised."""
    feed.start(on_batch)
    try:
        finished = lambda: bool(getattr(feed, "finished", False))  # noqa: E731
        tick_every(period, on_tick, stop=finished, duration=duration, first_now=False, sleep=sleep, monotonic=monotonic)
    finally:
        feed.close()
    if (error := getattr(feed, "error", None)) is not None:
        raise error
    on_tick()


def follow_into(
    feed: Feed,
    buffer: Buffer,
    on_tick: Callable[[], object],
    *,
    period: float = 1.0,
    duration: float | None = None,
) -> None:
    """``follow`` with the feed inserted into ``buffer``; ``on_tick`` holds the buffer's lock, so its
    lookups see one state while batches keep arriving."""

    def add(batch: TransformBatch) -> None:
        buffer.insert(batch)

    def tick() -> None:
        with buffer.lock:
            on_tick()

    follow(feed, add, tick, period=period, duration=duration)
