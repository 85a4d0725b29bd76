"""Where sensor headers heard live go (``HeaderStore``), and what a live system's listener of them offers
(``HeaderListener``); ``sensor_headers.capture_stamped`` listens with both beside tf."""

from __future__ import annotations

import threading
from collections.abc import Sequence
from typing import Protocol

from tftools.core.time import Clock
from tftools.sources.codecs.decoded import Header, Stated
from tftools.sources.codecs.select import placed_nowhere
from tftools.sources.contents import NOT_SENSOR_DATA, StampedRead
from tftools.sources.headers import HeaderCollector
from tftools.sources.live.notices import NoticeOnce, OnNotice

#: Headers kept per topic, at most (a 1 kHz IMU for 200 s): past it, messages are counted, not kept.
MAX_HEADERS_PER_TOPIC = 200_000

#: Sensor topics listened to, at most: each is a subscription (ROS 1: a thread per publisher).
MAX_TOPICS = 256


class HeaderStore:
    """The headers heard per topic, from any listening thread, each with its arrival time on ``clock``.

    ``topics``: those to keep (None: every topic but /tf, /tf_static and /clock)."""

    def __init__(
        self,
        clock: Clock,
        topics: Sequence[str] | None = None,
        on_notice: OnNotice | None = None,
        limit: int = MAX_HEADERS_PER_TOPIC,
    ) -> None:
        self.clock = clock
        self.topics = tuple(topics) if topics is not None else None
        self.notice = NoticeOnce(on_notice)
        self._limit = limit
        self._lock = threading.Lock()
        self._collected: dict[str, HeaderCollector] = {}
        self._without_header: dict[str, str] = {}

    def wants(self, topic: str) -> bool:
        return topic in self.topics if self.topics is not None else topic not in NOT_SENSOR_DATA

    def heard(self, topic: str, msgtype: str, header: Header | None, stated: Stated | None = None) -> None:
        """A message of ``topic`` arrived now; ``header`` None: one whose bytes hold no header; ``stated``: the
        transform it states beside it (an Odometry's). A type whose header places nothing in space
        (``placed_nowhere``: joint states, a gamepad's) is kept only where asked for by topic, as in a recording."""
        if self.topics is None and placed_nowhere(msgtype):
            return
        arrived = self.clock.now()
        with self._lock:
            collector = self._collected.get(topic)
            if collector is None:
                collector = self._collected[topic] = HeaderCollector(msgtype, self._limit)
            collector.add(arrived, header, stated)
            if collector.left_out == 1:
                self.notice(f"{topic}: {self._limit} messages heard, tfx's limit per topic: later ones are not checked")

    def full(self, listened: int) -> bool:
        """Whether ``listened`` topics are already as many as tfx listens to (said once)."""
        if listened < MAX_TOPICS:
            return False
        self.notice(f"more than {MAX_TOPICS} topics are advertised: tfx listens to the first ones")
        return True

    def without_header(self, topic: str, msgtype: str) -> None:
        """``topic`` turned out to be of ``msgtype``, whose messages do not start with a header."""
        with self._lock:
            self._without_header[topic] = msgtype

    def forget(self, _jump: object = None) -> None:
        """Forget what was heard (the clock jumped back: the capture forgets its transforms too)."""
        with self._lock:
            self._collected.clear()

    def read(self) -> StampedRead:
        """Each topic's stamped messages so far, and what could not be kept."""
        with self._lock:
            streams = [c.done(topic) for topic, c in sorted(self._collected.items())]
            problems = [line for topic, c in sorted(self._collected.items()) for line in c.problems(topic)]
            unheard = [t for t in self.topics or () if t not in self._collected]
            problems += [
                f"{t}: {self._without_header[t]} messages have no header"
                if t in self._without_header
                else f"{t}: no message heard (is it published?)"
                for t in unheard
            ]
        return StampedRead(streams, problems)


class HeaderListener(Protocol):
    """Subscribes the sensor topics of one live system into a ``HeaderStore``, until ``close``."""

    def start(self) -> None: ...

    def close(self) -> None: ...
