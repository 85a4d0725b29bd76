"""``/diagnostics`` as diagnostic_updater publishes it: ``Status`` es as a diagnostic_msgs/DiagnosticArray,
encoded for ROS 1 (TCPROS) and ROS 2 (CDR over DDS), and the publishers that send it without a ROS install."""

from __future__ import annotations

import os
import time
from collections.abc import Sequence
from typing import Any

from tftools.analysis.wtf.health import Status
from tftools.sources.codecs.types import ROS2_STORES, ros1_message_type, typestore
from tftools.sources.live.base import ContextManaged
from tftools.sources.live.notices import OnNotice

DIAGNOSTIC_ARRAY = "diagnostic_msgs/msg/DiagnosticArray"
TOPIC = "/diagnostics"


def diagnostic_array(store: str, stamp: int, statuses: Sequence[Status]) -> Any:
    """The DiagnosticArray of ``statuses`` stamped ``stamp`` (ns), as ``store`` (a rosbags type store) types it."""
    types = typestore(store).types
    header_fields: dict[str, Any] = {
        "stamp": types["builtin_interfaces/msg/Time"](sec=stamp // 1_000_000_000, nanosec=stamp % 1_000_000_000),
        "frame_id": "",
    }
    if store.startswith("ros1"):
        header_fields["seq"] = 0
    key_value, status = types["diagnostic_msgs/msg/KeyValue"], types["diagnostic_msgs/msg/DiagnosticStatus"]
    return types[DIAGNOSTIC_ARRAY](
        header=types["std_msgs/msg/Header"](**header_fields),
        status=[
            status(
                level=int(s.level),
                name=s.name,
                message=s.message,
                hardware_id=s.hardware_id,
                values=[key_value(key=k, value=v) for k, v in s.values],
            )
            for s in statuses
        ],
    )


def encode_ros1(stamp: int, statuses: Sequence[Status]) -> bytes:
    """A ROS 1 DiagnosticArray's serialized bytes (what TCPROS frames, and a bag stores)."""
    store = typestore("ros1_noetic")
    return bytes(store.serialize_ros1(diagnostic_array("ros1_noetic", stamp, statuses), DIAGNOSTIC_ARRAY))


def encode_cdr(stamp: int, statuses: Sequence[Status]) -> bytes:
    """A ROS 2 DiagnosticArray as CDR, its encapsulation header first (what DDS carries)."""
    store = typestore(ROS2_STORES[0])
    return bytes(store.serialize_cdr(diagnostic_array(ROS2_STORES[0], stamp, statuses), DIAGNOSTIC_ARRAY))


class DiagnosticsPublisher(ContextManaged):
    """Publishes DiagnosticArrays on ``/diagnostics`` until ``close``."""

    def publish(self, stamp: int, statuses: Sequence[Status]) -> None:
        """Send ``statuses`` stamped ``stamp`` (ns) to every subscriber (raises ``LiveError`` if the system left)."""
        raise NotImplementedError

    def describe(self) -> str:
        raise NotImplementedError


class Ros1DiagnosticsPublisher(DiagnosticsPublisher):
    """A node publishing ``/diagnostics`` as diagnostic_updater's (not latched, queue 1: the latest matters)."""

    def __init__(self, master_uri: str | None = None, on_notice: OnNotice | None = None) -> None:
        from tftools.sources.live.ros1 import network
        from tftools.sources.live.ros1.node import Node

        self._node = Node(network.anonymous_name("tfx_diagnostics"), master_uri, on_notice)
        self._publication = self._node.advertise(TOPIC, ros1_message_type(DIAGNOSTIC_ARRAY))

    @property
    def name(self) -> str:
        return self._node.name

    def publish(self, stamp: int, statuses: Sequence[Status]) -> None:
        self._publication.publish(encode_ros1(stamp, statuses))

    def describe(self) -> str:
        return f"{TOPIC} as node {self._node.name} of ROS1 master {self._node.master.uri}"

    def close(self) -> None:
        self._node.close()


class Ros2DiagnosticsPublisher(DiagnosticsPublisher):
    """A DDS writer on ``rt/diagnostics`` with diagnostic_updater's QoS: rclcpp's ``create_publisher(...,
    "/diagnostics", 1)``, reliable, volatile, keep last 1; announced as node ``/tfx_diagnostics_*``."""

    def __init__(self, on_notice: OnNotice | None = None) -> None:
        from cyclonedds.core import DDSException

        from tftools.sinks.ros2_broadcaster import AnnouncedNode
        from tftools.sources.live.errors import DdsError
        from tftools.sources.live.ros2 import conventions as ros2
        from tftools.sources.live.ros2.dds import Participant
        from tftools.sources.live.ros2.idl import ros2_struct

        self.domain_id = ros2.domain_id()
        self.node_name = f"tfx_diagnostics_{os.getpid()}_{int(time.time() * 1000) % 1_000_000}"
        self._participant = Participant(self.domain_id)
        try:
            self._writer = self._participant.writer(
                ros2.dds_topic(TOPIC), ros2_struct(DIAGNOSTIC_ARRAY), ros2.QosProfile(depth=1)
            )
        except DDSException as error:
            self._participant.close()
            raise DdsError(f"publish on DDS domain {self.domain_id}", error) from None
        self._node = AnnouncedNode(self._participant, self.node_name, [self._writer.guid.bytes], on_notice)

    def publish(self, stamp: int, statuses: Sequence[Status]) -> None:
        from tftools.sources.live.ros2.dds import write_raw

        write_raw(self._writer, encode_cdr(stamp, statuses))

    def describe(self) -> str:
        return f"{TOPIC} as node /{self.node_name} on ROS2 DDS domain {self.domain_id}"

    def close(self) -> None:
        self._node.close()
        self._participant.close()


def open_diagnostics(ros1: bool, on_notice: OnNotice | None = None) -> DiagnosticsPublisher:
    """A publisher of ``/diagnostics`` on the system's ROS 1 master (``ROS_MASTER_URI``) or ROS 2 DDS domain."""
    return Ros1DiagnosticsPublisher(on_notice=on_notice) if ros1 else Ros2DiagnosticsPublisher(on_notice)
