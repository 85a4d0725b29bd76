"""Announcing a node on ``ros_discovery_info``, so that ROS 2 tools (and tftools) name its writers."""

from __future__ import annotations

import os
import threading
from collections.abc import Sequence
from typing import Any

from cyclonedds.core import DDSException

from tftools.sources.live.base import OnNotice, ignore_notice
from tftools.sources.live.ros2 import conventions as ros2
from tftools.sources.live.ros2.dds import Participant, take_raw
from tftools.sources.live.ros2.entities import decode_participant_entities
from tftools.sources.live.ros2.graph import discovery_readers
from tftools.sources.live.ros2.idl import announcement, participant_entities_info

#: Distributions whose rmw_dds_common has 24-byte Gids; later ones have 16.
GID24_DISTROS = frozenset({"ardent", "bouncy", "crystal", "dashing", "eloquent", "foxy", "galactic", "humble"})


class NodeAnnouncer:
    """Says that node ``/name`` of ``participant`` owns ``writers``, as rmw_dds_common's GraphCache
    does, in the Gid size of the system: ``ROS_DISTRO``'s where set; else 16 (Iron on) at once,
    switched to 24 for good when another participant's announcement shows Humble's size.
    A node of the other size cannot read the announcement and ignores it, nothing worse."""

    def __init__(
        self, participant: Participant, name: str, writers: Sequence[bytes], on_notice: OnNotice | None = None
    ) -> None:
        self._participant = participant
        self._node = (name, list(writers))
        self._on_notice = on_notice or ignore_notice
        self._closed = threading.Event()
        self._writer: Any = None
        distro = os.environ.get("ROS_DISTRO", "").strip().lower()
        self.gid_size = 24 if distro in GID24_DISTROS else 16
        self._publish(self.gid_size)
        self._watcher: threading.Thread | None = None
        if not distro:
            self._watcher = threading.Thread(target=self._watch, name="tfx-ros2-announce", daemon=True)
            self._watcher.start()

    def close(self) -> None:
        self._closed.set()
        if self._watcher is not None:
            self._watcher.join(timeout=1.0)

    def _publish(self, gid_size: int) -> None:
        name, writers = self._node
        try:  # the writer is kept: deleting it would take the (transient local) announcement back
            writer = self._participant.writer(
                ros2.DISCOVERY_TOPIC, participant_entities_info(gid_size), ros2.DISCOVERY_WRITER_QOS
            )
            writer.write(announcement(gid_size, self._participant.guid, "/", name, writers))
        except DDSException as error:
            self._on_notice(f"could not announce node /{name} on {ros2.DISCOVERY_TOPIC}: {error}")
            return
        self._writer, self.gid_size = writer, gid_size

    def _watch(self) -> None:
        readers = discovery_readers(self._participant)
        while not self._closed.wait(0.2):
            for data, _info in (sample for reader in readers for sample in take_raw(reader)):
                try:
                    heard = decode_participant_entities(data)
                except ValueError:
                    continue
                if heard.participant != self._participant.guid and heard.gid_size != self.gid_size:
                    self._publish(heard.gid_size)
                    return
