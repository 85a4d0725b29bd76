"""Replaying a recording on a simulated clock, and the loop that drives any feed of transforms."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager, nullcontext
from typing import Generic, Protocol, TypeVar

import numpy as np

from tftools.core.arrays import Int64Array
from tftools.core.batch import TransformBatch, concat_batches, take_rows
from tftools.core.buffer import Buffer
from tftools.core.time import NS_PER_S, Clock, SimClock, from_sec
from tftools.sources.contents import SentMessages, concat_sent
from tftools.sources.ticker import tick_every

OnBatch = Callable[[TransformBatch], None]
#: Called with the tf messages (``SentMessages``) a feed delivered the transforms of.
OnSent = Callable[[SentMessages], None]

#: How often the replay advances its clock when no message is due, like ``rosbag play --hz``.
CLOCK_HZ = 100.0


class Feed(Protocol):
    """Transforms as they arrive and the clock they arrive on: a replay or a live source. ``start``
    returns at once; ``on_batch`` is then called (from any thread) with each batch."""

    @property
    def clock(self) -> Clock: ...

    def start(self, on_batch: OnBatch) -> None: ...

    def close(self) -> None: ...


class _Timed(Protocol):
    """A part of a replay: rows in record order."""

    @property
    def record_time(self) -> Int64Array: ...

    def __len__(self) -> int: ...


_Part = TypeVar("_Part", bound=_Timed)


class _Parts(Generic[_Part]):
    """Consecutive parts in record order, taken one at a time as a replay reaches them."""

    def __init__(self, parts: Iterator[_Part], empty: _Part) -> None:
        self._parts = parts
        self._part, self._next = empty, 0  # the part being played, and its next row

    def pending(self) -> _Part | None:
        """The part holding the next row to play, taking the next parts as they are reached; None once
        every row was played."""
        while self._next >= len(self._part):
            part = next(self._parts, None)
            if part is None:
                return None
            self._part, self._next = part, 0
        return self._part

    def next_time(self) -> int | None:
        """The record time of the next row to play; None once every row was played."""
        part = self.pending()
        return int(part.record_time[self._next]) if part is not None else None

    def until(self, time: int, *, before: bool = False) -> Iterator[tuple[_Part, Int64Array]]:
        """Each part's rows recorded at or before ``time`` (``before``: before it) not played yet, now played."""
        while (part := self.pending()) is not None and (
            int(part.record_time[self._next]) < time if before else int(part.record_time[self._next]) <= time
        ):
            upto = int(np.searchsorted(part.record_time, time, side="left" if before else "right"))
            rows = np.arange(self._next, upto)
            self._next = upto
            yield part, rows


class Replay:
    """Plays transforms in record order at ``rate`` times real speed while a ``SimClock`` follows bag
    time: ``rosbag play --clock`` seen by a node with ``use_sim_time``. Playing starts at ``start``
    (default: the first row), first delivering the statics recorded before it (a latched
    ``/tf_static`` a late subscriber still gets), and ends at ``end`` (default: the last row).

    ``transforms`` is one batch, or consecutive parts in record order (a stream's windows), taken one
    at a time as the clock reaches them: only the part being played is held. ``sent``: the tf messages
    they came in, alike (``SentMessages``), each delivered to ``on_sent`` (when set) with its transforms.
    """

    def __init__(
        self,
        transforms: TransformBatch | Iterable[TransformBatch],
        *,
        sent: SentMessages | Iterable[SentMessages] = (),
        rate: float = 1.0,
        start: int | None = None,
        end: int | None = None,
        sleep: Callable[[float], None] = time.sleep,
        monotonic: Callable[[], float] = time.monotonic,
        last: Callable[[], int] | None = None,
    ) -> None:
        if not rate > 0:
            raise ValueError(f"the replay rate must be above 0, got {rate}")
        self.rate = rate
        self._rows = _Parts(iter([transforms] if isinstance(transforms, TransformBatch) else transforms), _NO_ROWS)
        self._sent = _Parts(iter([sent] if isinstance(sent, SentMessages) else sent), SentMessages.empty())
        first = self._rows.next_time()
        self.begin = start if start is not None else first if first is not None else 0
        self.end = end  # where the replay ends: if not given, the last row's record time once it was played
        self._recording_end = last  # or later, where the recording went on past its tf: asked once every row played
        self._last = self.begin  # the newest row's record time played: the end, unless given
        self._sleep, self._monotonic = sleep, monotonic
        self.clock = SimClock(self.begin)
        self._on_batch: OnBatch | None = None
        #: Called with the messages of each batch delivered, before it.
        self.on_sent: OnSent | None = None
        self._closed = threading.Event()
        self._finished = threading.Event()
        self._thread: threading.Thread | None = None
        self._turn = threading.Lock()  # held while the replay moves on, or while one instant of it is shown
        self.error: Exception | None = None

    @property
    def finished(self) -> bool:
        """True once the clock has reached ``end`` (or the replay was closed)."""
        return self._finished.is_set()

    @contextmanager
    def held(self) -> Iterator[None]:
        """While held, the replay's clock and what it delivered stay as they are: a table or a line drawn of
        one instant (``follow``), where the replay's thread would otherwise move on between the time a tick
        read and the time its table shows (a monitor at 500x showed one window twice)."""
        with self._turn:
            yield

    def start(self, on_batch: OnBatch) -> None:
        """Play in a background thread, calling ``on_batch`` from it."""
        self._thread = threading.Thread(target=self.run, args=(on_batch,), name="tfx-replay", daemon=True)
        self._thread.start()

    def run(self, on_batch: OnBatch) -> None:
        """Play in this thread until the end or ``close``; a part that cannot be read (a file changed
        since it was opened) ends the replay, and is kept in ``error``."""
        try:
            self.play(on_batch, lambda: False)
        except Exception as error:
            self.error = error
        self._finished.set()

    def play(self, on_batch: OnBatch, between: Callable[[], bool]) -> None:
        """Play in this thread, calling ``between`` after each step (the rows due delivered, the clock set),
        until the end, ``close`` or ``between`` returning True; a part that cannot be read is raised."""
        self.attach(on_batch)
        started = self._monotonic()

        def now() -> int:
            return self.begin + round((self._monotonic() - started) * self.rate * NS_PER_S)

        while not self._closed.is_set() and not self.finished:
            with self._turn:
                self.advance_to(now())
            if between():
                break
            if not self.finished:
                self._sleep(self._pause(now()))  # after ``between``'s ticks: none when they took it past a row due

    def attach(self, on_batch: OnBatch) -> None:
        """Deliver to ``on_batch`` from now on, starting with the static transforms recorded
        before ``begin``; for driving the replay by hand with ``advance_to``."""
        self._on_batch = on_batch
        earlier = [take_rows(part, rows[part.static[rows]]) for part, rows in self._rows.until(self.begin, before=True)]
        sent = [part.taken(rows[part.static[rows]]) for part, rows in self._sent.until(self.begin, before=True)]
        self._deliver(earlier, sent)

    def advance_to(self, bag_time: int) -> None:
        """Deliver every row recorded up to ``bag_time`` (at most ``end``), then set the clock."""
        if self.end is not None:
            bag_time = min(bag_time, self.end)
        for part, rows in self._rows.until(bag_time):
            self._last = int(part.record_time[rows[-1]])
            # the messages of these rows only: taking those up to ``bag_time`` would read every window up to it
            # ahead of its rows (a stream's two iterators share its reads), the whole recording at a fast rate
            sent = [sent.taken(rows) for sent, rows in self._sent.until(self._last)]
            self._deliver([take_rows(part, rows)], sent)
        self._deliver([], [sent.taken(rows) for sent, rows in self._sent.until(bag_time)])
        if self.end is None and self._rows.pending() is None:
            # every row played: the replay ends at the last, or at the recording's end after it
            self.end = max(self._last, self.begin, self._recording_end() if self._recording_end else self._last)
            bag_time = min(bag_time, self.end)
        self.clock.set(bag_time)
        if self.end is not None and bag_time >= self.end:
            self._finished.set()

    def _deliver(self, rows: list[TransformBatch], sent: list[SentMessages]) -> None:
        if any(len(s) for s in sent) and self.on_sent is not None:
            self.on_sent(concat_sent(sent))
        if any(len(b) for b in rows) and self._on_batch is not None:
            self._on_batch(concat_batches(rows))

    def _pause(self, now: int) -> float:
        """Wall seconds until the next row is due, at most one clock tick."""
        due = self._rows.next_time()
        due = due if due is not None else now
        if self.end is not None:
            due = min(due, self.end)
        return max(0.0, min((due - now) / NS_PER_S / self.rate, 1.0 / CLOCK_HZ))

    def close(self) -> None:
        """Stop playing (the thread ends within one clock tick)."""
        self._closed.set()
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join(timeout=1.0)
        self._finished.set()


_NO_ROWS = TransformBatch.empty()


def follow(
    feed: Feed,
    on_batch: OnBatch,
    on_tick: Callable[[], object],
    *,
    period: float = 1.0,
    duration: float | None = None,
    summary: bool = False,
    sleep: Callable[[float], None] = time.sleep,
    monotonic: Callable[[], float] = time.monotonic,
) -> None:
    """Start ``feed`` into ``on_batch`` and call ``on_tick`` every ``period`` seconds until ``duration``
    wall seconds have passed or the feed is finished. A ``Replay`` is played on the calling thread between
    its ticks (``_played_here``), which are seconds of its clock from its beginning, as a node under
    ``use_sim_time`` ticks on ``rosbag play --clock``: each tick its clock reaches is made, none after its end
    (the recording's), and never two at one time of its clock: a replay that ran ahead of its ticks has those
    due made at once, at the time it reached; the first shows it, the others would show it again and are not
    made (monitor's tables, echo's lines). Else wall seconds. A feed that ends before
    its first tick gets one as it ends, so that its state is shown once; with ``summary`` (monitor's last
    table), so does one whose clock moved on since its last tick. The feed is closed, and the error that
    ended it raised."""
    ticks: list[int] = []  # the feed's clock at each tick made

    def tick() -> None:
        with feed.held() if isinstance(feed, Replay) else nullcontext():
            now = feed.clock.now()
            if ticks and now <= ticks[-1] and isinstance(feed, Replay):  # it ran ahead of its ticks: shown already
                return
            ticks.append(now)
            on_tick()

    def finished() -> bool:
        return bool(getattr(feed, "finished", False))

    try:
        if isinstance(feed, Replay):
            _played_here(feed, on_batch, tick, from_sec(period), duration, monotonic)
        else:
            feed.start(on_batch)
            tick_every(
                period, tick, stop=finished, duration=duration, first_now=False, sleep=sleep, monotonic=monotonic
            )
    finally:
        feed.close()
    if (error := getattr(feed, "error", None)) is not None:
        raise error
    if not ticks or (summary and feed.clock.now() > ticks[-1]):
        on_tick()


def _played_here(
    replay: Replay,
    on_batch: OnBatch,
    tick: Callable[[], None],
    period: int,
    duration: float | None,
    monotonic: Callable[[], float],
) -> None:
    """``replay`` played on the calling thread, ``tick`` made after each step that reached a tick due (every
    ``period`` of its clock from its beginning), until it ends or ``duration`` wall seconds pass. Not on a
    thread of its own: glibc served that thread's reads from a second heap (malloc arena), whose peak took one
    of two levels ~22 MB apart at random (a 4 h replay 1.16x the memory of a 1.3 h one, issue 41, perf15)."""
    started = monotonic()
    due = replay.begin + period

    def between() -> bool:
        nonlocal due
        if (now := replay.clock.now()) >= due:  # the ticks it reached at once: one made, at the time it reached
            tick()
            due += period * ((now - due) // period + 1)
        return duration is not None and monotonic() - started >= duration

    replay.play(on_batch, between)


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
