"""``LiveSource``: what every live system (ROS1 master, ROS2 DDS) offers the commands, and the
lifecycle its sources share."""

from __future__ import annotations

import collections
import threading
from collections.abc import Callable, Sequence
from dataclasses import replace
from types import TracebackType
from typing import TYPE_CHECKING, TypeVar

import numpy as np

from tftools.core.batch import TransformBatch, take_rows
from tftools.core.time import Clock, SimClock, WallClock
from tftools.sources.codecs.wire import MAX_FRAME_ID
from tftools.sources.contents import DEFAULT_TOPICS, SentMessages
from tftools.sources.live.notices import NoticeOnce, OnNotice, ignore_notice, printable

if TYPE_CHECKING:
    from tftools.sources.live.header_store import HeaderListener, HeaderStore

#: Called with each batch of transforms received, from the source's delivery thread (one thread,
#: so calls never overlap); rows are static where they came on ``/tf_static``, with the publisher
#: as authority and the receive time (on the source's clock) as record time.
OnBatch = Callable[[TransformBatch], None]

#: Frames a live source passes on, at most: a peer inventing names (200,000 new ones a message) would
#: grow the buffer's tables without bound. Transforms that name more are dropped, and that said once.
MAX_LIVE_FRAMES = 20_000

#: Characters of the frame names a live source passes on, in all, at most (20,000 names of 200 characters; a
#: robot's 500 frames take some 20,000): 20,000 new names of 4,096 characters, each a name, held 1.2 GB in
#: tfx wtf --ros2, whose checks of them took 96 s.
MAX_LIVE_NAME_CHARS = 4 << 20


class FrameLimit:
    """The frames passed on so far, at most ``limit`` and ``chars`` characters of names in all: a batch's rows
    naming a frame past either are dropped."""

    def __init__(self, limit: int, on_notice: OnNotice, chars: int | None = None) -> None:
        self.limit = limit
        self.chars = MAX_LIVE_NAME_CHARS if chars is None else chars
        self.names: set[str] = set()
        self._used_chars = 0
        self._on_notice = on_notice

    def admit(self, batch: TransformBatch) -> TransformBatch:
        """``batch`` less the rows that name a new frame once ``limit`` frames are known, and those that
        name a frame longer than ``MAX_FRAME_ID`` characters (damage, not a name): the frames kept hold
        at most ``limit`` times that."""
        used = np.unique(np.concatenate([batch.parent, batch.child]))
        new = [int(i) for i in used if batch.frame_names[i] not in self.names]
        long = [i for i in new if len(batch.frame_names[i]) > MAX_FRAME_ID]
        if long:
            self._on_notice(
                f"frame names longer than {MAX_FRAME_ID:,} characters heard: transforms naming them are dropped"
            )
            new = [i for i in new if len(batch.frame_names[i]) <= MAX_FRAME_ID]
        room = max(self.limit - len(self.names), 0)
        admitted = self._within_chars([batch.frame_names[i] for i in new[:room]])
        self.names.update(batch.frame_names[i] for i in new[:admitted])
        if len(new) <= admitted and not long:
            return batch
        refused = np.array(new[admitted:] + long, np.int32)
        kept = np.flatnonzero(~(np.isin(batch.parent, refused) | np.isin(batch.child, refused)))
        if len(new) > room:
            self._on_notice(
                f"more than {self.limit:,} frames heard: transforms naming further frames are dropped"
                " (a publisher inventing frame names?)"
            )
        if admitted < min(room, len(new)):
            self._on_notice(
                f"frame names of more than {self.chars:,} characters in all heard: transforms naming further"
                " frames are dropped (a publisher inventing long frame names?)"
            )
        return _names_used(take_rows(batch, kept))

    def _within_chars(self, names: list[str]) -> int:
        """How many of ``names``, in order, fit in what is left of ``chars`` (counted as used)."""
        for count, name in enumerate(names):
            if self._used_chars + len(name) > self.chars:
                return count
            self._used_chars += len(name)
        return len(names)


def _names_used(batch: TransformBatch) -> TransformBatch:
    """``batch`` with a frame name table of the names its rows use: the names of rows dropped are not held
    by the rows kept (a batch of 1,000 dropped names of 4 KiB and one kept transform held them all)."""
    used, index = np.unique(np.concatenate([batch.parent, batch.child]), return_inverse=True)
    names = [batch.frame_names[i] for i in used]
    rows = len(batch)
    return replace(
        batch,
        frame_names=names,
        parent=index[:rows].astype(np.int32),
        child=index[rows:].astype(np.int32),
    )


class TickedClock(SimClock):
    """ROS time under use_sim_time: set by each ``/clock`` message, and how far apart they are."""

    #: The step is the median of this many last steps forward.
    STEPS = 64

    def __init__(self, ros2: bool | None = None) -> None:
        super().__init__()
        self.ros2 = ros2  # the ROS whose /clock it follows (None: not told), for its errors' words
        self._steps: collections.deque[int] = collections.deque(maxlen=self.STEPS)

    @property
    def step(self) -> int:
        """The usual step between ``/clock`` messages (ns; 0 before two of them)."""
        steps = sorted(self._steps)
        return steps[len(steps) // 2] if steps else 0

    def tick(self, now: int) -> None:
        """A ``/clock`` message: ROS time is now ``now`` (back too)."""
        before = self.now()
        self.reset(now)
        if 0 < before < now:
            self._steps.append(now - before)


_Self = TypeVar("_Self", bound="ContextManaged")


class ContextManaged:
    """``with it:`` closes it."""

    def close(self) -> None:
        raise NotImplementedError

    def __enter__(self: _Self) -> _Self:
        return self

    def __exit__(
        self, kind: type[BaseException] | None, error: BaseException | None, trace: TracebackType | None
    ) -> None:
        self.close()


class LiveSource(ContextManaged):
    """A live system's transforms on ``topics`` as they arrive, and the clock they arrive on (wall time,
    or ``/clock`` under ``use_sim_time``). ``start`` joins the system and returns once listening (raising
    ``LiveError`` if it cannot), then ``on_batch`` is called with each batch until ``close``."""

    #: What a capture's ``SourceInfo`` calls this kind of source, e.g. ``"ros1-live"``.
    format: str
    #: The ROS it listens to: ROS 2 (True), ROS 1 (False), or not told (None): its clock's errors say it.
    ros2: bool | None = None

    def __init__(self, topics: Sequence[str] | None, use_sim_time: bool, on_notice: OnNotice | None) -> None:
        self.topics = tuple(topics) if topics else DEFAULT_TOPICS
        self.use_sim_time = use_sim_time
        self.message_count = 0  # transform messages received so far
        self._clock: Clock = TickedClock(self.ros2) if use_sim_time else WallClock()
        self._on_notice = on_notice or ignore_notice
        self._notice_once = NoticeOnce(on_notice)
        self._closed = threading.Event()
        self._lock = threading.Lock()  # the receiving threads' counts and what they told
        self._told_unreadable: set[tuple[str, str]] = set()
        self._frame_limit = FrameLimit(MAX_LIVE_FRAMES, self._notice_once)
        #: Called with the tf messages of each batch (``SentMessages``), before it.
        self.on_sent: Callable[[SentMessages], None] | None = None

    @property
    def clock(self) -> Clock:
        return self._clock

    @property
    def finished(self) -> bool:
        """True once closed, or stopped by the system (e.g. ``rosnode kill``)."""
        return self._closed.is_set()

    def start(self, on_batch: OnBatch) -> None:
        raise NotImplementedError

    def describe(self) -> str:
        """What is listened to, for humans and file lists: e.g. ``ROS1 master http://127.0.0.1:11311``."""
        raise NotImplementedError

    def header_listener(self, store: HeaderStore) -> HeaderListener:
        """A listener of the sensor topics of the system this source listens to."""
        raise TypeError(f"no sensor headers from a {type(self).__name__}")

    def notice(self, message: str) -> None:
        """Say ``message`` (one line) as the source says its own notices, every time it is called."""
        self._on_notice(message)

    @property
    def clock_step(self) -> int:
        """How coarse the source's clock is (ns): the usual step of ``/clock`` under use_sim_time (receive
        times, read off it, lag by up to a step), 0 on the wall clock."""
        return self._clock.step if isinstance(self._clock, TickedClock) else 0

    def _clock_message(self, now: int) -> None:
        """A ``/clock`` message: ROS time is now ``now``, back too (a replay that loops or restarts)."""
        assert isinstance(self._clock, TickedClock)
        self._clock.tick(now)

    def _unreadable(self, sender: str, topic: str, error: Exception) -> None:
        """Say once per publisher and topic that its messages cannot be read (they are dropped): a
        ``ValueError`` is the message's fault, anything else a bug of tfx's decoder."""
        with self._lock:
            if (sender, topic) in self._told_unreadable:
                return
            self._told_unreadable.add((sender, topic))
        reason = str(error) if isinstance(error, ValueError) else f"tfx's {type(error).__name__}: {error}"
        self._notice_once(f"{printable(sender)} sent an unreadable message on {topic} ({reason}); such are dropped")

    def _pass_on(self, on_batch: OnBatch, batch: TransformBatch, sent: SentMessages | None = None) -> None:
        """``batch`` to ``on_batch``, and ``sent``, the messages it came in, to ``on_sent`` first."""
        batch = self._frame_limit.admit(batch)
        if not len(batch):
            return
        try:
            if sent is not None and self.on_sent is not None:
                self.on_sent(sent)
            on_batch(batch)
        except Exception as error:  # the consumer's bug must not stop the listening
            self._notice_once(f"dropped transforms: {type(error).__name__}: {error}")
