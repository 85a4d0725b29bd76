"""Sensor headers from a ROS 2 system over DDS: a participant of tfx's own reads each sensor topic as
its writers advertise it (DDS discovery: topic ``rt/...`` and type name) and decodes each sample's
header from its CDR bytes. rmw_cyclonedds's writers match a reader by type name alone, but a DDS peer
sending XTypes information (Cyclone DDS's Python package) only a reader of the same layout: so a type
ROS 2 defines is read with its whole layout (from rosbags' type stores), another with its name and a
header alone."""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Any

from cyclonedds.builtin import BuiltinDataReader, BuiltinTopicDcpsPublication, DcpsEndpoint
from cyclonedds.core import DDSException
from cyclonedds.idl import IdlStruct, make_idl_struct

from tftools.sources.codecs.decoded import HeaderDecoder, message_header
from tftools.sources.codecs.select import header_decoder
from tftools.sources.codecs.types import starts_with_header
from tftools.sources.live.errors import DdsError
from tftools.sources.live.header_store import HeaderStore
from tftools.sources.live.ros2 import conventions as ros2
from tftools.sources.live.ros2.dds import Participant, Waiter, take_raw
from tftools.sources.live.ros2.idl import ros2_definitions, ros2_struct


def sensor_type(dds_type_name: str, *, unknown_too: bool = False) -> type[IdlStruct] | None:
    """The struct to read a writer of ``dds_type_name`` with, when its messages start with a header:
    the type's whole layout where ROS 2 defines it; for a type no store knows, with ``unknown_too``,
    its name over a header alone (None otherwise, and for types without a header)."""
    rosidl = ros2.ros_type(dds_type_name)
    for store, fielddefs in enumerate(ros2_definitions()):
        if rosidl in fielddefs:
            return ros2_struct(rosidl, store) if starts_with_header(rosidl, fielddefs) else None
    return _header_only(dds_type_name) if unknown_too else None


@functools.cache
def _header_only(dds_type_name: str) -> type[IdlStruct]:
    return make_idl_struct("HeaderOnly", dds_type_name, {"header": ros2_struct("std_msgs/msg/Header")})


@dataclass(frozen=True)
class _SensorReader:
    topic: str  # the ROS name, e.g. "/scan"
    msgtype: str  # rosidl's, e.g. "sensor_msgs/msg/LaserScan"
    reader: Any

    @property
    def decode(self) -> HeaderDecoder:
        return header_decoder(self.msgtype, "cdr")


class Ros2HeaderListener:
    """The headers of ``store``'s topics on DDS domain ``domain_id``: those it names (of any type a
    header can be read from), or every topic whose type ROS 2 defines with a header first."""

    def __init__(self, domain_id: int, store: HeaderStore) -> None:
        self._store = store
        self._participant = Participant(domain_id)
        self._readers: dict[tuple[str, str], _SensorReader | None] = {}  # None: not read (no header)
        self._waiter = Waiter(self._participant)

    def start(self) -> None:
        """Watch for sensor topics' writers and read them, in the background."""
        try:
            publications = BuiltinDataReader(self._participant.dds, BuiltinTopicDcpsPublication)
            self._waiter.watch(publications)
        except DDSException as error:
            raise DdsError(f"listen on DDS domain {self._participant.domain_id}", error) from None
        self._waiter.start(
            lambda: self._step(publications), "tfx-dds-sensors", self._store.notice, "DDS samples of sensor topics"
        )

    def close(self) -> None:
        self._waiter.stop()
        self._participant.close()

    def _step(self, publications: Any) -> float:
        """New writers give new readers (whose data wakes the thread too); each sample taken is one
        message heard, now."""
        for reader in self._discover(publications):
            self._waiter.watch(reader)
        self._take()
        return 1.0

    def _discover(self, publications: Any) -> list[Any]:
        """Readers for the sensor topics' writers discovered since the last call."""
        created = []
        for endpoint in publications.take(256):
            if not isinstance(endpoint, DcpsEndpoint) or not endpoint.topic_name.startswith(f"{ros2.TOPIC_PREFIX}/"):
                continue
            topic = "/" + endpoint.topic_name.removeprefix(f"{ros2.TOPIC_PREFIX}/")
            key = (topic, endpoint.type_name)
            if key in self._readers or not self._store.wants(topic):
                continue
            if self._store.full(len(self._readers)):
                break
            sensor = self._readers[key] = self._sensor_reader(topic, endpoint)
            if sensor is not None:
                created.append(sensor.reader)
        return created

    def _sensor_reader(self, topic: str, endpoint: DcpsEndpoint) -> _SensorReader | None:
        """A reader of ``topic`` matching ``endpoint``'s type, or None (no header, or no reader possible)."""
        msgtype = ros2.ros_type(endpoint.type_name)
        try:
            data_type = sensor_type(endpoint.type_name, unknown_too=self._store.topics is not None)
            if data_type is None:
                self._store.without_header(topic, msgtype)
                return None
            reader = self._participant.reader(endpoint.topic_name, data_type, ros2.SENSOR_QOS)
        except Exception as error:  # DDSException, or a type the IDL cannot express: that topic only
            self._store.notice(f"cannot read {topic} ({msgtype}): {type(error).__name__}: {error}")
            return None
        return _SensorReader(topic, msgtype, reader)

    def _take(self) -> None:
        for sensor in self._readers.values():
            if sensor is None:
                continue
            for data, _info in take_raw(sensor.reader):
                self._store.heard(sensor.topic, sensor.msgtype, *message_header(sensor.decode, data))
