"""``Ros2StaticBroadcaster``: static transforms on /tf_static as ROS 2's static_transform_publisher
sends them: one transient local message (keep last 1) holding them all."""

from __future__ import annotations

import os
import threading
import time

from cyclonedds.core import DDSException

from tftools.core.transform import Transform
from tftools.sinks import StaticBroadcaster
from tftools.sources.live.base import OnNotice
from tftools.sources.live.errors import DdsError
from tftools.sources.live.ros2 import conventions as ros2
from tftools.sources.live.ros2.announce import NodeAnnouncer
from tftools.sources.live.ros2.dds import Participant
from tftools.sources.live.ros2.idl import TFMessage


class Ros2StaticBroadcaster(StaticBroadcaster):
    """A DDS writer on ``rt/tf_static`` with tf2_ros's StaticBroadcasterQoS, announced on
    ``ros_discovery_info`` as node ``/NAME`` so that ROS 2 tools (and tftools) name it."""

    def __init__(self, on_notice: OnNotice | None = None) -> None:
        super().__init__()
        self.domain_id = ros2.domain_id()
        self.node_name = f"tfx_static_{os.getpid()}_{int(time.time() * 1000) % 1_000_000}"
        self._participant = Participant(self.domain_id)
        self._closed = threading.Event()
        try:
            self._writer = self._participant.writer(
                ros2.dds_topic("/tf_static"), TFMessage, ros2.TF_STATIC_BROADCASTER_QOS
            )
        except DDSException as error:
            self._participant.close()
            raise DdsError(f"publish on DDS domain {self.domain_id}", error) from None
        self._announcer = NodeAnnouncer(self._participant, self.node_name, [self._writer.guid.bytes], on_notice)

    @property
    def finished(self) -> bool:
        return self._closed.is_set()

    def _publish(self, transforms: list[Transform]) -> None:
        self._writer.write(TFMessage.of(transforms))

    @property
    def gid_size(self) -> int:
        """The Gid size its node is announced with (16 or 24), as the system's nodes use."""
        return self._announcer.gid_size

    def describe(self) -> str:
        return f"ROS2 DDS domain {self.domain_id} as node /{self.node_name}"

    def close(self) -> None:
        if self._closed.is_set():
            return
        self._closed.set()
        self._announcer.close()
        self._participant.close()
