"""Who publishes what: each DDS writer of a sample, named by its ROS 2 node where announced."""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from cyclonedds.builtin import BuiltinDataReader, BuiltinTopicDcpsPublication, DcpsEndpoint
from cyclonedds.core import DDSException, Policy
from cyclonedds.sub import DataReader

from tftools.sources.live.ros2 import conventions as ros2
from tftools.sources.live.ros2.dds import Participant, take_raw
from tftools.sources.live.ros2.entities import decode_participant_entities
from tftools.sources.live.ros2.idl import participant_entities_info

#: Seconds a new writer's samples wait for its node to be announced before going out unnamed.
NAMING_GRACE = 0.3


@dataclass(frozen=True)
class Writer:
    """A DDS writer as the builtin DCPSPublication topic describes it."""

    guid: bytes
    participant: bytes
    topic: str
    type_name: str
    reliable: bool
    transient_local: bool


def discovery_readers(participant: Participant) -> list[DataReader[Any]]:
    """Readers of ``ros_discovery_info`` in both Gid sizes: ROS 2's rmw_cyclonedds sends no XTypes
    type information, so both match it by type name, but a DDS peer that does (Cyclone DDS's Python
    package) is only matched by the reader of its own size. tftools decodes the bytes either way."""
    return [
        participant.reader(ros2.DISCOVERY_TOPIC, participant_entities_info(size), ros2.DISCOVERY_READER_QOS)
        for size in ros2.GID_SIZES
    ]


def participant_name(guid: bytes) -> str:
    """A participant no node was announced for: its GUID prefix (12 bytes), as Cyclone logs it."""
    prefix = guid[:12].hex()
    return f"dds:{prefix[:8]}:{prefix[8:16]}:{prefix[16:]}"


class Graph:
    """Writers (builtin DCPSPublication topic, by instance handle: the same handle a sample's info
    gives as ``publication_handle``) and the nodes that own them (``ros_discovery_info``, where every
    ROS 2 participant lists its nodes and their writers' GUIDs)."""

    def __init__(self, participant: Participant, on_writer: Callable[[Writer, str], None]) -> None:
        self._on_writer = on_writer  # told of each writer discovered, with its name
        self.publications = BuiltinDataReader(participant.dds, BuiltinTopicDcpsPublication)
        self.discovery = discovery_readers(participant)
        self._writers: dict[int, Writer] = {}
        self._nodes: dict[bytes, dict[bytes, str]] = {}  # participant -> writer GUID -> node name
        self._node_of_writer: dict[bytes, str] = {}
        self._first_asked: dict[int, float] = {}

    @property
    def readers(self) -> tuple[Any, ...]:
        return (self.publications, *self.discovery)

    def poll(self) -> None:
        """Take what the two discovery readers received."""
        for endpoint in self.publications.take(256):
            if isinstance(endpoint, DcpsEndpoint) and endpoint.qos is not None:  # not a writer's disposal
                self._add_writer(endpoint)
        for data, _info in (sample for reader in self.discovery for sample in take_raw(reader)):
            try:
                entities = decode_participant_entities(data)
            except ValueError:
                continue  # another rmw's idea of the type: its nodes stay unnamed
            self._nodes[entities.participant] = {w: n.full_name for n in entities.nodes for w in n.writers}
            self._node_of_writer = {w: n for nodes in self._nodes.values() for w, n in nodes.items()}

    def writer(self, handle: int, reader: DataReader[Any]) -> Writer | None:
        """The writer of a sample (its info's ``publication_handle``) as discovered; ``reader``, the one
        the sample came on, is asked when the builtin topic has not told yet."""
        found = self._writers.get(handle)
        if found is None:
            try:
                endpoint = reader.get_matched_publication_data(handle)
            except DDSException:
                return None
            if isinstance(endpoint, DcpsEndpoint) and endpoint.qos is not None:
                found = self._add_writer(endpoint, handle)
        return found

    def settled(self, handle: int, reader: DataReader[Any]) -> bool:
        """Whether a sample's writer can be named for good: its node is known, or ``NAMING_GRACE``
        seconds passed since tftools first asked (a plain DDS writer has no node)."""
        writer = self.writer(handle, reader)
        if writer is not None and writer.guid in self._node_of_writer:
            return True
        first = self._first_asked.setdefault(handle, time.monotonic())
        return time.monotonic() - first >= NAMING_GRACE

    def authority(self, handle: int, reader: DataReader[Any]) -> str:
        """Who sent a sample: its writer's node (``/namespace/name``), else its DDS participant."""
        writer = self.writer(handle, reader)
        return "unknown publisher" if writer is None else self.name_of(writer)

    def name_of(self, writer: Writer) -> str:
        """``writer``'s node (``/namespace/name``) where announced, else its DDS participant."""
        return self._node_of_writer.get(writer.guid) or participant_name(writer.participant)

    def _add_writer(self, endpoint: DcpsEndpoint, handle: int | None = None) -> Writer:
        qos = endpoint.qos
        writer = Writer(
            guid=endpoint.key.bytes,  # a uuid.UUID's 16 bytes
            participant=endpoint.participant_key.bytes,
            topic=endpoint.topic_name,
            type_name=endpoint.type_name,
            reliable=qos[Policy.Reliability] != Policy.Reliability.BestEffort,  # a writer's default: reliable
            transient_local=qos[Policy.Durability] not in (None, Policy.Durability.Volatile),
        )
        key = endpoint.sample_info.instance_handle if handle is None else handle  # type: ignore[attr-defined]
        if key not in self._writers:
            self._writers[key] = writer
            self._on_writer(writer, self.name_of(writer))
        return writer
