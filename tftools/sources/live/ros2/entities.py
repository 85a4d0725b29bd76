"""``ros_discovery_info`` samples (``rmw_dds_common/msg/ParticipantEntitiesInfo``, CDR): which node
of a participant owns which writers."""

from __future__ import annotations

from dataclasses import dataclass

from tftools.sources.codecs import cdr
from tftools.sources.codecs.decoded import DecodeError
from tftools.sources.codecs.wire import Cursor, wire_of
from tftools.sources.live.ros2.conventions import GID_SIZES, GUID_SIZE


@dataclass(frozen=True)
class NodeEntities:
    """One node of a participant, as ``ros_discovery_info`` lists it: its writers' GUIDs."""

    namespace: str
    name: str
    writers: tuple[bytes, ...]

    @property
    def full_name(self) -> str:
        """``/namespace/name``, as ``ros2 node list`` prints it."""
        return f"{self.namespace.rstrip('/')}/{self.name}"


@dataclass(frozen=True)
class ParticipantEntities:
    """A ``rmw_dds_common/msg/ParticipantEntitiesInfo`` sample: a participant's nodes."""

    participant: bytes  # its DDS GUID (16 bytes)
    nodes: tuple[NodeEntities, ...]
    gid_size: int  # 16 (Iron and later) or 24 (Humble and before)


def decode_participant_entities(data: bytes) -> ParticipantEntities:
    """A ``ros_discovery_info`` sample, in whichever Gid size (16 or 24 bytes) it was written with:
    the one that reads the whole sample; ``ValueError`` if neither does."""
    errors = []
    for gid_size in GID_SIZES:
        try:
            return _participant_entities(data, gid_size)
        except (DecodeError, UnicodeDecodeError) as error:
            errors.append(f"{gid_size}-byte ids: {error}")
    raise ValueError("not a ParticipantEntitiesInfo (" + "; ".join(errors) + ")")


def _participant_entities(data: bytes, gid_size: int) -> ParticipantEntities:
    reader = Cursor(data, wire_of(data, 0, len(data), cdr.WIRES))

    def octets() -> bytes:
        return data[reader.take(gid_size) : reader.pos][:GUID_SIZE]

    def text() -> str:
        start, length = reader.string()
        return data[start : start + length].decode()

    def count(smallest: int) -> int:
        """A sequence's length, refused where its elements cannot fit in what is left."""
        number = reader.uint()
        if number * smallest > reader.rest:
            raise DecodeError(f"a sequence of {number} does not fit")
        return number

    participant = octets()
    nodes = []
    for _ in range(count(8)):
        namespace, name = text(), text()
        for _reader in range(count(gid_size)):
            octets()
        writers = tuple(octets() for _ in range(count(gid_size)))
        nodes.append(NodeEntities(namespace, name, writers))
    if reader.rest >= 4 or any(data[reader.pos :]):  # DDS pads a sample to a multiple of 4 bytes, no more
        raise DecodeError(f"{reader.rest} bytes left over")
    return ParticipantEntities(participant, tuple(nodes), gid_size)
