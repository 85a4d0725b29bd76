"""``Ros1Source``: /tf and /tf_static from a ROS1 system, as a ``LiveSource``."""

from __future__ import annotations

import threading
from collections import deque
from collections.abc import Sequence
from typing import TYPE_CHECKING

from tftools.core.batch import TransformBatch, concat_batches
from tftools.sources.codecs import ros1
from tftools.sources.codecs.decoded import message_batch, message_clock
from tftools.sources.codecs.types import CLOCK, TF_MESSAGE, ros1_message_type
from tftools.sources.contents import is_static_topic, sent_of_messages
from tftools.sources.live.base import LiveSource, OnBatch
from tftools.sources.live.notices import NoticeOnce, OnNotice
from tftools.sources.live.ros1 import network
from tftools.sources.live.ros1.node import Node
from tftools.sources.live.ros1.subscriber import OnMessage

if TYPE_CHECKING:
    from tftools.sources.live.header_store import HeaderListener, HeaderStore

#: Transforms received and not yet delivered, at most: past it (the consumer cannot keep up) new
#: messages are dropped, and that is said once. A message alone is always taken.
MAX_QUEUED_TRANSFORMS = 2_000_000


class _DeliveryQueue:
    """Batches from the connections' threads to the one delivery thread, bounded in transforms."""

    def __init__(self, on_notice: OnNotice, limit: int = MAX_QUEUED_TRANSFORMS) -> None:
        self._ready = threading.Condition()
        self._batches: deque[TransformBatch] = deque()
        self._queued = 0
        self._limit = limit
        self._closed = False
        self._on_notice = on_notice
        self.dropped = 0

    def put(self, batch: TransformBatch) -> None:
        with self._ready:
            if self._batches and self._queued + len(batch) > self._limit:
                self.dropped += 1
                if self.dropped == 1:
                    self._on_notice(
                        f"tfx cannot keep up: more than {self._limit} transforms wait to be handled; "
                        "messages are dropped until it catches up"
                    )
                return
            self._batches.append(batch)
            self._queued += len(batch)
            self._ready.notify()

    def take_all(self) -> list[TransformBatch] | None:
        """All batches queued, waiting for one; None once closed."""
        with self._ready:
            while not self._batches and not self._closed:
                self._ready.wait()
            if self._closed:
                return None
            batches, self._batches, self._queued = list(self._batches), deque(), 0
            return batches

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
        static = is_static_topic(topic)

        def receive(data: bytes, callerid: str) -> None:
            try:
                batch = message_batch(
                    ros1.decode_tf, data, static=static, authority=callerid, record_time=self._clock.now()
                )
            except Exception as error:  # ValueError: not a TFMessage; anything else would be a decoder bug
                self._unreadable(callerid, topic, error)
                return
            with self._lock:
                self.message_count += 1
            self._queue.put(batch)

        return receive

    def _on_clock(self, data: bytes, callerid: str) -> None:
        try:
            self._clock_message(message_clock(ros1.decode_clocks, data))
        except ValueError as error:
            self._unreadable(callerid, "/clock", error)

    def _deliver(self, on_batch: OnBatch) -> None:
        """One thread calls ``on_batch``, with whatever arrived while it was busy merged."""
        while (batches := self._queue.take_all()) is not None:
            self._pass_on(on_batch, concat_batches(batches), sent_of_messages(batches))


def param_is_true(value: object) -> bool:
    """A boolean parameter as a user means it: ``true``, or the text ``"true"`` (``rosparam set`` of a
    quoted value); the text ``"false"``, like a missing parameter, is false."""
    if isinstance(value, str):
        return value.strip().lower() in ("true", "1", "yes", "on")
    return isinstance(value, bool | int) and bool(value)
