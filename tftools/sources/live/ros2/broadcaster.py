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
from tftools.sources.live.ros2.cdr import decode_participant_entities
from tftools.sources.live.ros2.dds import Participant, take_raw
from tftools.sources.live.ros2.errors import DdsError
from tftools.sources.live.ros2.graph import discovery_readers
from tftools.sources.live.ros2.idl import TFMessage, announcement, participant_entities_info

#: How long to listen for other nodes' ``ros_discovery_info`` to learn their Gid size.
LEARN_GID_SIZE_FOR = 2.0

#: Distributions whose rmw_dds_common has 24-byte Gids.
_GID24_DISTROS = {"ardent", "bouncy", "crystal", "dashing", "eloquent", "foxy", "galactic", "humble"}


class Ros2StaticBroadcaster(ContextManaged):
    """A DDS writer on ``rt/tf_static`` with tf2_ros's StaticBroadcasterQoS, announced on
    ``ros_discovery_info`` as node ``/NAME`` so that ROS 2 tools (and tftools) name it."""

    def __init__(
        self, on_notice: OnNotice | None = None, domain_id: int | None = None, name: str | None = None
    ) -> None:
        self.domain_id = ros2.domain_id() if domain_id is None else domain_id
        self.node_name = name or f"tfx_static_{os.getpid()}_{int(time.time() * 1000) % 1_000_000}"
        self._on_notice = on_notice or (lambda _message: None)
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
        self._announcer = threading.Thread(target=self._announce, name="tfx-ros2-announce", daemon=True)
        self._announcer.start()

    @property
    def finished(self) -> bool:
        return self._closed.is_set()

    def send(self, transforms: Sequence[Transform]) -> None:
        """Publish ``transforms`` with those sent before, one per child frame (tf2_ros's
        StaticTransformBroadcaster::sendTransform replaces a child's transform), in one message."""
        for t in transforms:
            self._transforms[t.child_frame_id] = t
        self._writer.write(TFMessage.of(list(self._transforms.values())))

    def describe(self) -> str:
        return f"ROS2 DDS domain {self.domain_id} as node /{self.node_name}"

    def close(self) -> None:
        if self._closed.is_set():
            return
        self._closed.set()
        self._announcer.join(timeout=LEARN_GID_SIZE_FOR + 1.0)
        self._participant.close()

    def _announce(self) -> None:
        """Say on ``ros_discovery_info`` that node ``/NAME`` owns the writer, with Gids of the size the
        system uses: ``ROS_DISTRO``'s, else the size other nodes' announcements have, else 16 (Iron on).
        A wrong size would make nodes of the other kind drop the announcement, nothing worse."""
        try:
            gid_size = self._gid_size()
            if gid_size is None or self._closed.is_set():
                return
            self._discovery_writer = self._participant.writer(  # kept: deleting it would retract the sample
                ros2.DISCOVERY_TOPIC, participant_entities_info(gid_size), ros2.DISCOVERY_WRITER_QOS
            )
            owned = [self._writer.guid.bytes]
            self._discovery_writer.write(announcement(gid_size, self._participant.guid, "/", self.node_name, owned))
        except DDSException as error:
            if not self._closed.is_set():
                self._on_notice(f"could not announce node /{self.node_name} on {ros2.DISCOVERY_TOPIC}: {error}")

    def _gid_size(self) -> int | None:
        distro = os.environ.get("ROS_DISTRO", "").strip().lower()
        if distro:
            return 24 if distro in _GID24_DISTROS else 16
        readers = discovery_readers(self._participant)
        deadline = time.monotonic() + LEARN_GID_SIZE_FOR
        while time.monotonic() < deadline:
            for data, _info in (sample for reader in readers for sample in take_raw(reader)):
                try:
                    return decode_participant_entities(data).gid_size
                except ValueError:
                    continue
            if self._closed.wait(0.05):
                return None
        return 16
