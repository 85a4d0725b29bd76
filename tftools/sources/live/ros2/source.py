"""``Ros2Source``: /tf and /tf_static from a ROS 2 system over DDS, as a ``LiveSource``."""

from __future__ import annotations

import threading
from collections.abc import Sequence
from typing import Any

from cyclonedds.core import DDSException, GuardCondition, InstanceState, ReadCondition, SampleState, ViewState, WaitSet
from cyclonedds.util import duration

from tftools.core.batch import TransformBatch, concat_batches
from tftools.core.time import Clock, SimClock, WallClock
from tftools.sources.bag.contents import DEFAULT_TOPICS, is_static_topic
from tftools.sources.live.base import ContextManaged, OnBatch, OnNotice
from tftools.sources.live.ros2 import conventions as ros2
from tftools.sources.live.ros2.cdr import decode_clock, decode_tf_message
from tftools.sources.live.ros2.dds import Participant, take_raw
from tftools.sources.live.ros2.errors import DdsError
from tftools.sources.live.ros2.graph import Graph, Writer
from tftools.sources.live.ros2.idl import Clock as ClockMsg
from tftools.sources.live.ros2.idl import TFMessage

_ANY_SAMPLE = SampleState.Any | ViewState.Any | InstanceState.Any


class Ros2Source(ContextManaged):
    """Subscribes to ``topics`` (tf2_msgs/msg/TFMessage) on DDS domain ``domain_id`` (``ROS_DOMAIN_ID``)
    with tf2_ros's TransformListener QoS; each sample's authority is its publisher's node.

    ``use_sim_time``: follow ``/clock``; ROS 2 nodes do so only when their parameter says so, so
    ``None`` means wall time.
    """

    format = "ros2-live"

    def __init__(
        self,
        topics: Sequence[str] | None = None,
        use_sim_time: bool | None = None,
        on_notice: OnNotice | None = None,
        domain_id: int | None = None,
    ) -> None:
        self.topics = tuple(topics) if topics else DEFAULT_TOPICS
        self.domain_id = ros2.domain_id() if domain_id is None else domain_id
        self.use_sim_time = bool(use_sim_time)
        self.message_count = 0
        self._clock: Clock = SimClock() if self.use_sim_time else WallClock()
        self._on_notice = on_notice or (lambda _message: None)
        self._noticed: set[str] = set()
        self._participant = Participant(self.domain_id)
        self._closed = threading.Event()
        self._wake: GuardCondition | None = None
        self._thread: threading.Thread | None = None

    @property
    def clock(self) -> Clock:
        return self._clock

    @property
    def finished(self) -> bool:
        return self._closed.is_set()

    def describe(self) -> str:
        return f"ROS2 DDS domain {self.domain_id}"

    def start(self, on_batch: OnBatch) -> None:
        """Create the readers (transient local ones get what was published before) and listen."""
        try:
            listening = self._listen()
        except DDSException as error:
            self.close()
            raise DdsError(f"listen on DDS domain {self.domain_id}", error) from None
        self._thread = threading.Thread(target=self._run, args=(on_batch, *listening), name="tfx-dds", daemon=True)
        self._thread.start()

    def close(self) -> None:
        if self._closed.is_set():
            return
        self._closed.set()
        if self._wake is not None:
            self._wake.set(True)
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join(timeout=2.0)
        self._participant.close()

    # --- receiving ---------------------------------------------------------------------------

    def _listen(self) -> tuple[Graph, list[tuple[str, Any, bool]], Any, WaitSet]:
        participant = self._participant
        graph = Graph(participant, self._check_writer)
        readers = [
            (topic, participant.reader(ros2.dds_topic(topic), TFMessage, ros2.listener_qos(topic)), is_static_topic(topic))
            for topic in self.topics
        ]
        clock = None
        if self.use_sim_time:
            clock = participant.reader(ros2.dds_topic(ros2.CLOCK_TOPIC), ClockMsg, ros2.CLOCK_QOS)
        waitset = WaitSet(participant.dds)
        for reader in [*graph.readers, *(r for _, r, _ in readers), *([clock] if clock else [])]:
            waitset.attach(ReadCondition(reader, _ANY_SAMPLE))
        self._wake = GuardCondition(participant.dds)
        waitset.attach(self._wake)
        return graph, readers, clock, waitset

    def _run(self, on_batch: OnBatch, graph: Graph, readers: list[tuple[str, Any, bool]], clock: Any, waitset: WaitSet) -> None:
        """One thread takes every sample and calls ``on_batch`` with what one wake-up brought."""
        while not self._closed.is_set():
            waitset.wait(duration(seconds=1))
            if self._closed.is_set():
                return
            graph.poll()
            if clock is not None:
                self._tick(clock, graph)
            batches = [b for topic, reader, static in readers for b in self._take(topic, reader, static, graph)]
            if batches:
                try:
                    on_batch(concat_batches(batches))
                except Exception as error:  # the consumer's bug must not stop the listening
                    self._notice_once(f"dropped transforms: {type(error).__name__}: {error}")

    def _take(self, topic: str, reader: Any, static: bool, graph: Graph) -> list[TransformBatch]:
        batches = []
        for data, info in take_raw(reader):
            authority = graph.authority(info.publication_handle, reader)
            try:
                batches.append(decode_tf_message(data, static=static, authority=authority, record_time=self._clock.now()))
            except ValueError as error:
                self._notice_once(f"{authority} sent an unreadable message on {topic} ({error})")
                continue
            self.message_count += 1
        return batches

    def _tick(self, reader: Any, graph: Graph) -> None:
        assert isinstance(self._clock, SimClock)
        for data, info in take_raw(reader):
            try:
                now = decode_clock(data)
            except ValueError as error:
                self._notice_once(f"{graph.authority(info.publication_handle, reader)} sent an unreadable /clock ({error})")
                continue
            if now < self._clock.now():  # a replay that loops or restarts: ROS time jumps back too
                self._clock.reset(now)
            else:
                self._clock.set(now)

    def _check_writer(self, writer: Writer) -> None:
        """Say why a publisher on a listened topic will not be heard (as tf2_ros would not hear it)."""
        topics = {ros2.dds_topic(t): t for t in self.topics}
        expected = ros2.TF_MESSAGE
        if self.use_sim_time:
            topics[ros2.dds_topic(ros2.CLOCK_TOPIC)] = ros2.CLOCK_TOPIC
        topic = topics.get(writer.topic)
        if topic is None:
            return
        if topic == ros2.CLOCK_TOPIC:
            expected = ros2.CLOCK
        who = f"{ros2.participant_label(writer.participant)}"
        if writer.type_name != expected:
            self._notice_once(
                f"{who} publishes {topic} as {ros2.ros_type(writer.type_name)}, not {ros2.ros_type(expected)}: not heard"
            )
        elif topic != ros2.CLOCK_TOPIC:
            wanted = ros2.listener_qos(topic)
            if wanted.transient_local and not writer.transient_local:
                self._notice_once(f"{who} publishes {topic} volatile: tf2 listeners (transient local) do not hear it")
            elif wanted.reliable and not writer.reliable:
                self._notice_once(f"{who} publishes {topic} best effort: tf2 listeners (reliable) do not hear it")

    def _notice_once(self, message: str) -> None:
        if message not in self._noticed:
            self._noticed.add(message)
            self._on_notice(message)
