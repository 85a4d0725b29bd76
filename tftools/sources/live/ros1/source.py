"""``Ros1Source``: /tf and /tf_static from a ROS1 system, as a ``LiveSource``."""

from __future__ import annotations

import threading
from collections import deque
from collections.abc import Sequence
from typing import TYPE_CHECKING

from tftools.sources.codecs import ros1
from tftools.sources.codecs.decoded import DecodeError, message_clock
from tftools.sources.codecs.types import CLOCK, TF_MESSAGE, ros1_message_type
from tftools.sources.live.base import LiveSource, OnBatch
from tftools.sources.live.notices import NoticeOnce, OnNotice
from tftools.sources.live.received import Received, decode_received
from tftools.sources.live.ros1 import network
from tftools.sources.live.ros1.node import Node
from tftools.sources.live.ros1.subscriber import OnMessage

if TYPE_CHECKING:
    from tftools.sources.live.header_store import HeaderListener, HeaderStore

#: Bytes of messages received and not yet delivered, at most: past it (the consumer cannot keep up) new
#: messages are dropped, and that is said once. A message alone is always taken.
MAX_QUEUED_BYTES = 128 << 20


class _DeliveryQueue:
    """Messages from the connections' threads to the one delivery thread, bounded in bytes."""

    def __init__(self, on_notice: OnNotice, limit: int = MAX_QUEUED_BYTES) -> None:
        self._ready = threading.Condition()
        self._messages: deque[Received] = deque()
        self._queued = 0
        self._limit = limit
        self._closed = False
        self._on_notice = on_notice
        self.dropped = 0

    def put(self, message: Received) -> None:
        with self._ready:
            if self._messages and self._queued + len(message.data) > self._limit:
                self.dropped += 1
                if self.dropped == 1:
                    self._on_notice(
                        f"tfx cannot keep up: more than {self._limit >> 20} MiB of messages wait to be handled; "
                        "messages are dropped until it catches up"
                    )
                return
            self._messages.append(message)
            self._queued += len(message.data)
            self._ready.notify()

    def take_all(self) -> list[Received] | None:
        """All messages queued, waiting for one; None once closed."""
        with self._ready:
            while not self._messages and not self._closed:
                self._ready.wait()
            if self._closed:
                return None
            messages, self._messages, self._queued = list(self._messages), deque(), 0
            return messages

    def close(self) -> None:
        with self._ready:
            self._closed = True
            self._ready.notify_all()


class Ros1Source(LiveSource):
    """Subscribes to ``topics`` (tf2_msgs/TFMessage) through the master at ``master_uri`` (``ROS_MASTER_URI``),
    following publishers as they come and go. ``use_sim_time`` ``None`` asks the master's ``/use_sim_time``,
    as every ROS node does (which also checks that the master answers)."""

    format = "ros1-live"
    ros2 = False

    def __init__(
        self,
        master_uri: str | None = None,
        topics: Sequence[str] | None = None,
        use_sim_time: bool | None = None,
        on_notice: OnNotice | None = None,
        name: str = "tfx",
    ) -> None:
        notice_once = NoticeOnce(on_notice)
        self._node = Node(network.anonymous_name(name), master_uri, notice_once)
        try:
            if use_sim_time is None:
                use_sim_time = param_is_true(self._node.master.get_param("/use_sim_time"))
        except BaseException:
            self._node.close()
            raise
        super().__init__(topics, use_sim_time, on_notice)
        self._notice_once = notice_once  # the node's: a notice is said once, whoever says it
        self._queue = _DeliveryQueue(self._notice_once)
        self._delivery: threading.Thread | None = None

    @property
    def master_uri(self) -> str:
        return self._node.master.uri

    @property
    def finished(self) -> bool:
        return self._closed.is_set() or self._node.shutdown_requested.is_set()

    def describe(self) -> str:
        return f"ROS1 master {self.master_uri}"

    def header_listener(self, store: HeaderStore) -> HeaderListener:
        from tftools.sources.live.ros1.headers import Ros1HeaderListener

        return Ros1HeaderListener(self.master_uri, store)

    def start(self, on_batch: OnBatch) -> None:
        """Register with the master and listen; raises ``LiveError`` if the master is not there."""
        self._delivery = threading.Thread(target=self._deliver, args=(on_batch,), name="tfx-delivery", daemon=True)
        self._delivery.start()
        try:
            if self.use_sim_time:
                self._node.subscribe("/clock", ros1_message_type(CLOCK), self._on_clock)
            tf_type = ros1_message_type(TF_MESSAGE)
            for topic in self.topics:
                self._node.subscribe(topic, tf_type, self._receiver(topic))
        except BaseException:
            self.close()
            raise

    def close(self) -> None:
        if self._closed.is_set():
            return
        self._closed.set()
        self._node.close()
        self._queue.close()
        if self._delivery is not None and self._delivery is not threading.current_thread():
            self._delivery.join(timeout=1.0)

    def _receiver(self, topic: str) -> OnMessage:
        def receive(data: bytes, callerid: str) -> None:
            self._queue.put(Received(topic, data, callerid, self._clock.now()))

        return receive

    def _on_clock(self, data: bytes, callerid: str) -> None:
        try:
            self._clock_message(message_clock(ros1.decode_clocks, data))
        except ValueError as error:
            self._unreadable(callerid, "/clock", error)

    def _deliver(self, on_batch: OnBatch) -> None:
        """One thread decodes and calls ``on_batch`` with whatever arrived while it was busy, in one batch."""
        while (messages := self._queue.take_all()) is not None:
            arrivals = decode_received(ros1.decode_tf, messages)
            for message, reason in arrivals.unreadable:
                self._unreadable(message.authority, message.topic, DecodeError(reason))
            with self._lock:
                self.message_count += arrivals.readable
            if len(arrivals.batch):
                self._pass_on(on_batch, arrivals.batch, arrivals.sent)


def param_is_true(value: object) -> bool:
    """A boolean parameter as a user means it: ``true``, or the text ``"true"`` (``rosparam set`` of a
    quoted value); the text ``"false"``, like a missing parameter, is false."""
    if isinstance(value, str):
        return value.strip().lower() in ("true", "1", "yes", "on")
    return isinstance(value, bool | int) and bool(value)
