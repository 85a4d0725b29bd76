"""``Ros2StaticBroadcaster``: static transforms on /tf_static as ROS 2's static_transform_publisher
sends them: one transient local message (keep last 1) holding them all."""

from __future__ import annotations

import os
import threading
import time
from collections.abc import Sequence

from cyclonedds.core import DDSException

from tftools.core.transform import Transform
from tftools.sources.live.base import ContextManaged, OnNotice
from tftools.sources.live.ros2 import conventions as ros2
from tftools.sources.live.ros2.announce import NodeAnnouncer
from tftools.sources.live.ros2.dds import Participant
from tftools.sources.live.ros2.errors import DdsError
from tftools.sources.live.ros2.idl import TFMessage


class Ros2StaticBroadcaster(ContextManaged):
    """A DDS writer on ``rt/tf_static`` with tf2_ros's StaticBroadcasterQoS, announced on
    ``ros_discovery_info`` as node ``/NAME`` so that ROS 2 tools (and tftools) name it."""

    def __init__(
        self, on_notice: OnNotice | None = None, domain_id: int | None = None, name: str | None = None
    ) -> None:
        self.domain_id = ros2.domain_id() if domain_id is None else domain_id
        self.node_name = name or f"tfx_static_{os.getpid()}_{int(time.time() * 1000) % 1_000_000}"
        self._participant = Participant(self.domain_id)
        self._closed = threading.Event()
        self._transforms: dict[str, Transform] = {}
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

    def send(self, transforms: Sequence[Transform]) -> None:
        """Publish ``transforms`` with those sent before, one per child frame (tf2_ros's
        StaticTransformBroadcaster::sendTransform replaces a child's transform), in one message."""
        for t in transforms:
            self._transforms[t.child_frame_id] = t
        self._writer.write(TFMessage.of(list(self._transforms.values())))

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
