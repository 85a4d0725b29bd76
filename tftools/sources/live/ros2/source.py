"""``Ros2Source``: /tf and /tf_static from a ROS 2 system over DDS, as a ``LiveSource``."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from cyclonedds.core import DDSException

from tftools.sources.codecs import cdr
from tftools.sources.codecs.decoded import DecodeError, message_clock
from tftools.sources.codecs.types import CLOCK, TF_MESSAGE
from tftools.sources.live.base import LiveSource, OnBatch
from tftools.sources.live.errors import DdsError
from tftools.sources.live.notices import OnNotice, printable
from tftools.sources.live.received import Received, decode_received
from tftools.sources.live.ros2 import conventions as ros2
from tftools.sources.live.ros2.dds import Participant, Waiter, take_raw
from tftools.sources.live.ros2.graph import Graph, Writer
from tftools.sources.live.ros2.idl import ros2_struct

if TYPE_CHECKING:
    from tftools.sources.live.header_store import HeaderListener, HeaderStore


@dataclass(frozen=True)
class _Sample:
    """A transform message received, waiting for its publisher to be named."""

    topic: str  # the ROS name, e.g. "/tf"
    reader: Any
    data: bytes
    handle: int
    record_time: int


@dataclass
class _Listening:
    graph: Graph
    readers: dict[str, Any]  # of each topic
    clock: Any  # the /clock reader under sim time, else None
    pending: list[_Sample] = field(default_factory=list)


class Ros2Source(LiveSource):
    """Subscribes to ``topics`` (tf2_msgs/msg/TFMessage) on DDS domain ``ROS_DOMAIN_ID`` with tf2_ros's
    TransformListener QoS; each sample's authority is its publisher's node. ``use_sim_time`` ``None``
    means wall time, as for a ROS 2 node whose parameter does not say otherwise."""

    format = "ros2-live"
    ros2 = True

    def __init__(
        self,
        topics: Sequence[str] | None = None,
        use_sim_time: bool | None = None,
        on_notice: OnNotice | None = None,
    ) -> None:
        super().__init__(topics, bool(use_sim_time), on_notice)
        self.domain_id = ros2.domain_id()
        self._participant = Participant(self.domain_id)
        self._waiter = Waiter(self._participant)
        self._told_large: set[tuple[str, str]] = set()  # (publisher, topic) told of samples over MAX_TF_SAMPLE

    def describe(self) -> str:
        return f"ROS2 DDS domain {self.domain_id}"

    def header_listener(self, store: HeaderStore) -> HeaderListener:
        from tftools.sources.live.ros2.headers import Ros2HeaderListener

        return Ros2HeaderListener(self.domain_id, store)

    def start(self, on_batch: OnBatch) -> None:
        """Create the readers (transient local ones get what was published before) and listen."""
        try:
            listening = self._listen()
        except DDSException as error:
            self.close()
            raise DdsError(f"listen on DDS domain {self.domain_id}", error) from None
        self._waiter.start(lambda: self._step(on_batch, listening), "tfx-dds", self._notice_once, "DDS samples")

    def close(self) -> None:
        self._closed.set()
        self._waiter.stop()
        self._participant.close()

    def _listen(self) -> _Listening:
        participant = self._participant
        graph = Graph(participant, self._check_writer, self._notice_once)
        tf_type = ros2_struct(TF_MESSAGE)
        readers = {t: participant.reader(ros2.dds_topic(t), tf_type, ros2.listener_qos(t)) for t in self.topics}
        clock = None
        if self.use_sim_time:
            clock = participant.reader(ros2.dds_topic(ros2.CLOCK_TOPIC), ros2_struct(CLOCK), ros2.CLOCK_QOS)
        for reader in [*graph.readers, *readers.values(), *([clock] if clock is not None else [])]:
            self._waiter.watch(reader)
        return _Listening(graph, readers, clock)

    def _step(self, on_batch: OnBatch, listening: _Listening) -> float:
        """Take every sample and call ``on_batch`` with what one wake-up brought; sooner again while
        samples wait for their publisher to be named."""
        listening.graph.poll()
        if listening.clock is not None:
            self._tick(listening.clock, listening.graph)
        arrivals = decode_received(cdr.decode_tf, self._take(listening))
        for message, reason in arrivals.unreadable:
            self._unreadable(message.authority, message.topic, DecodeError(reason))
        self.message_count += arrivals.readable
        if len(arrivals.batch):
            self._pass_on(on_batch, arrivals.batch, arrivals.sent)
        return 0.05 if listening.pending else 1.0

    def _take(self, listening: _Listening) -> list[Received]:
        """New samples, and those held back until their publisher's node is known (a node's
        ``ros_discovery_info`` may come a moment after its first transforms), those whose publisher is known."""
        graph = listening.graph
        samples = listening.pending
        for topic, reader in listening.readers.items():
            for data, info in take_raw(reader):
                if len(data) > ros2.MAX_TF_SAMPLE:
                    self._too_large(topic, len(data), graph.authority(info.publication_handle, reader))
                    continue
                samples.append(_Sample(topic, reader, data, info.publication_handle, self._clock.now()))
        listening.pending = [s for s in samples if not graph.settled(s.handle, s.reader)]
        return [
            Received(s.topic, s.data, graph.authority(s.handle, s.reader), s.record_time)
            for s in samples
            if graph.settled(s.handle, s.reader)
        ]

    def _too_large(self, topic: str, size: int, sender: str) -> None:
        """Say once per publisher and topic that its samples over ``MAX_TF_SAMPLE`` are dropped (the first's size)."""
        if (sender, topic) in self._told_large:  # the DDS thread alone calls this
            return
        self._told_large.add((sender, topic))
        limit = ros2.MAX_TF_SAMPLE >> 20
        self._notice_once(
            f"{printable(sender)} sent a sample of {size / (1 << 20):.1f} MiB on {topic}, larger than {limit} MiB"
            " (100,000 transforms take 8.5 MB): such are dropped unread"
        )

    def _tick(self, reader: Any, graph: Graph) -> None:
        for data, info in take_raw(reader):
            try:
                self._clock_message(message_clock(cdr.decode_clocks, data))
            except ValueError as error:
                self._unreadable(graph.authority(info.publication_handle, reader), ros2.CLOCK_TOPIC, error)

    def _check_writer(self, writer: Writer, who: str) -> None:
        """Say why a publisher on a listened topic will not be heard (as tf2_ros would not hear it)."""
        topics = {ros2.dds_topic(t): (t, ros2.TF_MESSAGE) for t in self.topics}
        if self.use_sim_time:
            topics[ros2.dds_topic(ros2.CLOCK_TOPIC)] = (ros2.CLOCK_TOPIC, ros2.CLOCK)
        topic, expected = topics.get(writer.topic, ("", ""))
        if not topic:
            return
        if writer.type_name != expected:
            sent, wanted = ros2.ros_type(writer.type_name), ros2.ros_type(expected)
            self._notice_once(f"{who} publishes {topic} as {sent}, not {wanted}: not heard")
        elif expected == ros2.TF_MESSAGE:
            qos = ros2.listener_qos(topic)
            if qos.transient_local and not writer.transient_local:
                self._notice_once(f"{who} publishes {topic} volatile: tf2 listeners (transient local) do not hear it")
            elif qos.reliable and not writer.reliable:
                self._notice_once(f"{who} publishes {topic} best effort: tf2 listeners (reliable) do not hear it")
