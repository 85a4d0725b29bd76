"""Who publishes what: each DDS writer of a sample, named by its ROS 2 node where announced."""

from __future__ import annotations

import time
from collections import OrderedDict
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from cyclonedds.builtin import BuiltinDataReader, BuiltinTopicDcpsPublication, DcpsEndpoint
from cyclonedds.core import DDSException, Policy
from cyclonedds.sub import DataReader

from tftools.sources.live.notices import OnNotice, ignore_notice
from tftools.sources.live.ros2 import conventions as ros2
from tftools.sources.live.ros2.dds import Participant, take_raw
from tftools.sources.live.ros2.entities import decode_participant_entities
from tftools.sources.live.ros2.idl import participant_entities_info

#: Seconds a new writer's samples wait for its node to be announced before going out unnamed.
NAMING_GRACE = 0.3

#: ``ros_discovery_info`` samples decoded at most per reader and wake-up: one of 1,000 nodes takes 17 ms, and a
#: flood of them kept the DDS thread from /tf (and from stopping) for seconds; the rest wait in the reader.
ANNOUNCEMENTS_A_POLL = 16


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


class Announced:
    """The node of each writer, as each participant's latest ``ros_discovery_info`` says, for at most
    ``MAX_PARTICIPANTS`` participants: beyond, the one announced longest ago is forgotten (its writers go
    unnamed), said once through ``on_notice``."""

    def __init__(self, on_notice: OnNotice = ignore_notice, limit: int | None = None) -> None:
        self._on_notice = on_notice
        self._limit = ros2.MAX_PARTICIPANTS if limit is None else limit
        self._writers: OrderedDict[bytes, dict[bytes, str]] = OrderedDict()  # participant -> writer GUID -> node
        self._node_of_writer: dict[bytes, str] = {}
        self.forgotten = 0

    def __len__(self) -> int:
        return len(self._writers)

    def announce(self, participant: bytes, writers: dict[bytes, str]) -> None:
        """``participant``'s nodes now own ``writers`` (its earlier announcement replaced)."""
        self._forget(participant)
        self._writers[participant] = writers
        self._node_of_writer.update(writers)
        if len(self._writers) > self._limit:
            self._forget(next(iter(self._writers)))
            self.forgotten += 1
            if self.forgotten == 1:
                self._on_notice(
                    f"more than {self._limit:,} participants announced on {ros2.DISCOVERY_TOPIC}: the oldest are"
                    " forgotten, their writers named by participant (a flood of participants?)"
                )

    def node_of(self, writer: bytes) -> str:
        """The node that owns ``writer`` (a GUID), "" where none was announced."""
        return self._node_of_writer.get(writer, "")

    def _forget(self, participant: bytes) -> None:
        for writer in self._writers.pop(participant, {}):
            self._node_of_writer.pop(writer, None)


class Graph:
    """Writers (builtin DCPSPublication topic, by instance handle: the same handle a sample's info
    gives as ``publication_handle``) and the nodes that own them (``ros_discovery_info``, where every
    ROS 2 participant lists its nodes and their writers' GUIDs)."""

    def __init__(
        self, participant: Participant, on_writer: Callable[[Writer, str], None], on_notice: OnNotice = ignore_notice
    ) -> None:
        self._on_writer = on_writer  # told of each writer discovered, with its name
        self.publications = BuiltinDataReader(participant.dds, BuiltinTopicDcpsPublication)
        self.discovery = discovery_readers(participant)
        self._writers: dict[int, Writer] = {}
        self.nodes = Announced(on_notice)
        self._first_asked: dict[int, float] = {}

    @property
    def readers(self) -> tuple[Any, ...]:
        return (self.publications, *self.discovery)

    def poll(self) -> None:
        """Take what the two discovery readers received."""
        for endpoint in self.publications.take(256):
            if isinstance(endpoint, DcpsEndpoint) and endpoint.qos is not None:  # not a writer's disposal
                self._add_writer(endpoint)
        announcements = (sample for reader in self.discovery for sample in take_raw(reader, ANNOUNCEMENTS_A_POLL))
        for data, _info in announcements:
            try:
                entities = decode_participant_entities(data)
            except ValueError:
                continue  # another rmw's idea of the type: its nodes stay unnamed
            self.nodes.announce(entities.participant, {w: n.full_name for n in entities.nodes for w in n.writers})

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
        if writer is not None and self.nodes.node_of(writer.guid):
            return True
        first = self._first_asked.setdefault(handle, time.monotonic())
        return time.monotonic() - first >= NAMING_GRACE

    def authority(self, handle: int, reader: DataReader[Any]) -> str:
        """Who sent a sample: its writer's node (``/namespace/name``), else its DDS participant."""
        writer = self.writer(handle, reader)
        return "unknown publisher" if writer is None else self.name_of(writer)

    def name_of(self, writer: Writer) -> str:
        """``writer``'s node (``/namespace/name``) where announced, else its DDS participant."""
        return self.nodes.node_of(writer.guid) or participant_name(writer.participant)

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
