"""Replaying a recording on a simulated clock, and the loop that drives any feed of transforms."""

from __future__ import annotations

import dataclasses
import threading
import time
from collections.abc import Callable
from typing import Protocol

import numpy as np

from tftools.core.batch import TransformBatch, take_rows
from tftools.core.buffer import Buffer
from tftools.core.time import NS_PER_S, Clock, SimClock
from tftools.sources.recording import Recording

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
    """

    def __init__(
        self,
        transforms: TransformBatch,
        *,
        rate: float = 1.0,
        start: int | None = None,
        end: int | None = None,
        sleep: Callable[[float], None] = time.sleep,
        monotonic: Callable[[], float] = time.monotonic,
    ) -> None:
        if not rate > 0:
            raise ValueError(f"the replay rate must be above 0, got {rate}")
        self.transforms = transforms
        self.rate = rate
        records = transforms.record_time
        self.begin = start if start is not None else (int(records[0]) if len(records) else 0)
        self.end = end if end is not None else (int(records[-1]) if len(records) else self.begin)
        self._sleep, self._monotonic = sleep, monotonic
        self._clock = SimClock(self.begin)
        self._next = int(np.searchsorted(records, self.begin, side="left"))
        self._on_batch: OnBatch | None = None
        self._closed = threading.Event()
        self._finished = threading.Event()
        self._thread: threading.Thread | None = None

    @property
    def clock(self) -> SimClock:
        return self._clock

    @property
    def finished(self) -> bool:
        """True once the clock has reached ``end`` (or the replay was closed)."""
        return self._finished.is_set()

    def start(self, on_batch: OnBatch) -> None:
        """Play in a background thread, calling ``on_batch`` from it."""
        self._thread = threading.Thread(target=self.run, args=(on_batch,), name="tfx-replay", daemon=True)
        self._thread.start()

    def run(self, on_batch: OnBatch) -> None:
        """Play in this thread until the end or ``close``."""
        self.attach(on_batch)
        started = self._monotonic()
        while not self._closed.is_set():
            now = self.begin + round((self._monotonic() - started) * self.rate * NS_PER_S)
            self.advance_to(now)
            if self.finished:
                return
            self._sleep(self._pause(now))
        self._finished.set()

    def attach(self, on_batch: OnBatch) -> None:
        """Deliver to ``on_batch`` from now on, starting with the static transforms recorded
        before ``begin``; for driving the replay by hand with ``advance_to``."""
        self._on_batch = on_batch
        records = self.transforms.record_time
        earlier_static = np.flatnonzero(self.transforms.static[: self._next] & (records[: self._next] < self.begin))
        if len(earlier_static):
            on_batch(take_rows(self.transforms, earlier_static))

    def advance_to(self, bag_time: int) -> None:
        """Deliver every row recorded up to ``bag_time`` (at most ``end``), then set the clock."""
        bag_time = min(bag_time, self.end)
        records = self.transforms.record_time
        upto = int(np.searchsorted(records, bag_time, side="right"))
        if upto > self._next and self._on_batch is not None:
            self._on_batch(take_rows(self.transforms, np.arange(self._next, upto)))
        self._next = max(self._next, upto)
        self._clock.set(bag_time)
        if bag_time >= self.end:
            self._finished.set()

    def _pause(self, now: int) -> float:
        """Wall seconds until the next row is due, at most one clock tick."""
        records = self.transforms.record_time
        due = int(records[self._next]) if self._next < len(records) else self.end
        return max(0.0, min((min(due, self.end) - now) / NS_PER_S / self.rate, 1.0 / CLOCK_HZ))

    def close(self) -> None:
        """Stop playing (the thread ends within one clock tick)."""
        self._closed.set()
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join(timeout=1.0)
        self._finished.set()


def replay_of(recording: Recording, *, rate: float = 1.0, start: int | None = None, end: int | None = None) -> Replay:
    """A replay of ``recording`` on the clock its tf is stamped on (``Timeline.playback``): what a node
    with use_sim_time sees while the bag plays with its recorded /clock, or on its record clock."""
    transforms = recording.transforms
    moved = dataclasses.replace(transforms, record_time=recording.timeline.playback(transforms.record_time))
    return Replay(moved, rate=rate, start=start, end=end)


def follow(
    feed: Feed,
    on_batch: OnBatch,
    on_tick: Callable[[], None],
    *,
    period: float = 1.0,
    duration: float | None = None,
    sleep: Callable[[float], None] = time.sleep,
    monotonic: Callable[[], float] = time.monotonic,
) -> None:
    """Start ``feed`` into ``on_batch`` and call ``on_tick`` every ``period`` wall seconds until
    ``duration`` seconds have passed or the feed is finished, then once more; the feed is closed."""
    started = monotonic()
    feed.start(on_batch)
    try:
        next_tick = started + period
        while not getattr(feed, "finished", False):
            now = monotonic()
            if duration is not None and now - started >= duration:
                break
            if now >= next_tick:
                on_tick()
                next_tick += period
                if next_tick <= now:  # fell behind (a slow tick): skip, do not burst
                    next_tick = now + period
                continue
            stop = next_tick if duration is None else min(next_tick, started + duration)
            sleep(max(0.0, min(stop - now, 0.05)))
    finally:
        feed.close()
    on_tick()


def follow_into(
    feed: Feed,
    buffer: Buffer,
    on_tick: Callable[[], None],
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
