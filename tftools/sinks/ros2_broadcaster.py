"""``Ros2StaticBroadcaster``: static transforms on /tf_static as ROS 2's static_transform_publisher
sends them (one transient local message, keep last 1, holding them all), from a node announced on
``ros_discovery_info`` so that ROS 2 tools (and tftools) name it."""

from __future__ import annotations

import os
import threading
import time
from typing import Any

from cyclonedds.core import DDSException

from tftools.core.transform import Transform
from tftools.sinks.broadcaster import StaticBroadcaster
from tftools.sources.codecs import cdr
from tftools.sources.codecs.types import TF_MESSAGE
from tftools.sources.live.errors import DdsError
from tftools.sources.live.notices import OnNotice, ignore_notice
from tftools.sources.live.ros2 import conventions as ros2
from tftools.sources.live.ros2.dds import Participant, take_raw, write_raw
from tftools.sources.live.ros2.entities import decode_participant_entities
from tftools.sources.live.ros2.graph import discovery_readers
from tftools.sources.live.ros2.idl import announcement, participant_entities_info, ros2_struct

#: Distributions whose rmw_dds_common has 24-byte Gids; later ones have 16.
GID24_DISTROS = frozenset({"ardent", "bouncy", "crystal", "dashing", "eloquent", "foxy", "galactic", "humble"})


class Ros2StaticBroadcaster(StaticBroadcaster):
    """A DDS writer on ``rt/tf_static`` with tf2_ros's StaticBroadcasterQoS, announced as node ``/NAME``
    (``AnnouncedNode``)."""

    def __init__(self, on_notice: OnNotice | None = None) -> None:
        super().__init__()
        self.domain_id = ros2.domain_id()
        self.node_name = f"tfx_static_{os.getpid()}_{int(time.time() * 1000) % 1_000_000}"
        self._on_notice = on_notice or ignore_notice
        self._participant = Participant(self.domain_id)
        self._closed = threading.Event()
        try:
            self._writer = self._participant.writer(
                ros2.dds_topic("/tf_static"), ros2_struct(TF_MESSAGE), ros2.TF_STATIC_BROADCASTER_QOS
            )
        except DDSException as error:
            self._participant.close()
            raise DdsError(f"publish on DDS domain {self.domain_id}", error) from None
        self._node = AnnouncedNode(self._participant, self.node_name, [self._writer.guid.bytes], self._on_notice)

    @property
    def finished(self) -> bool:
        return self._closed.is_set()

    def _publish(self, transforms: list[Transform]) -> None:
        write_raw(self._writer, cdr.encode_tf_message(transforms))

    def describe(self) -> str:
        return f"ROS2 DDS domain {self.domain_id} as node /{self.node_name}"

    @property
    def gid_size(self) -> int:
        return self._node.gid_size

    def close(self) -> None:
        if self._closed.is_set():
            return
        self._closed.set()
        self._node.close()
        self._participant.close()


class AnnouncedNode:
    """Node ``/NAME`` of ``participant`` with ``writers``, announced on ``ros_discovery_info`` as rmw_dds_common's
    GraphCache does, in the system's ``gid_size``: ``ROS_DISTRO``'s where set; else 16 (Iron on) at once,
    switched to 24 for good when another participant's announcement shows Humble's size. A node of the other
    size cannot read the announcement and ignores it, nothing worse. ``close`` before the participant."""

    def __init__(
        self, participant: Participant, name: str, writers: list[bytes], on_notice: OnNotice | None = None
    ) -> None:
        self._participant, self.name, self._writers = participant, name, writers
        self._on_notice = on_notice or ignore_notice
        self._closed = threading.Event()
        self._announcer: Any = None  # kept: deleting it would take the (transient local) announcement back
        distro = os.environ.get("ROS_DISTRO", "").strip().lower()
        self.gid_size = 24 if distro in GID24_DISTROS else 16
        self._announce(self.gid_size)
        self._watcher: threading.Thread | None = None
        if not distro:
            self._watcher = threading.Thread(target=self._watch_gid_size, name="tfx-ros2-announce", daemon=True)
            self._watcher.start()

    def close(self) -> None:
        self._closed.set()
        if self._watcher is not None:
            self._watcher.join(timeout=1.0)

    def _announce(self, gid_size: int) -> None:
        try:
            announcer = self._participant.writer(
                ros2.DISCOVERY_TOPIC, participant_entities_info(gid_size), ros2.DISCOVERY_WRITER_QOS
            )
            announcer.write(announcement(gid_size, self._participant.guid, "/", self.name, self._writers))
        except DDSException as error:
            self._on_notice(f"could not announce node /{self.name} on {ros2.DISCOVERY_TOPIC}: {error}")
            return
        self._announcer, self.gid_size = announcer, gid_size

    def _watch_gid_size(self) -> None:
        readers = discovery_readers(self._participant)
        while not self._closed.wait(0.2):
            for data, _info in (sample for reader in readers for sample in take_raw(reader)):
                try:
                    heard = decode_participant_entities(data)
                except ValueError:
                    continue
                if heard.participant != self._participant.guid and heard.gid_size != self.gid_size:
                    self._announce(heard.gid_size)
                    return
