"""ROS 2 messages as CDR bytes, the way they travel in DDS samples: decoded with ``struct`` for the
strings and numpy for the numbers, no object per field.

A sample starts with the 4-byte encapsulation header (RTPS 10.5: 0x0000/0x0001 plain CDR big/little
endian, which rmw_cyclonedds writes; 0x0006/0x0007 XCDR2 for final types); alignment counts from
just after it, 8-byte values aligned to 8 in CDR and to 4 in XCDR2.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass

from tftools.core.batch import TransformBatch
from tftools.core.time import NS_PER_S
from tftools.sources.live.ros2.conventions import GID_SIZES, GUID_SIZE
from tftools.sources.live.tf_batch import VALUES_SIZE, tf_batch

_HEADER = 4
_ENCODINGS = {0x00: (">", 8), 0x01: ("<", 8), 0x06: (">", 4), 0x07: ("<", 4)}  # order, largest alignment


class _Reader:
    """A position in a CDR sample, with its byte order and alignment rule."""

    def __init__(self, data: bytes, what: str) -> None:
        if len(data) < _HEADER or data[0] != 0 or data[1] not in _ENCODINGS:
            raise ValueError(f"not a {what}: unknown encapsulation {data[:2].hex() or 'none'}")
        self.data = data
        self.what = what
        self.order, self.max_align = _ENCODINGS[data[1]]
        self.pos = _HEADER
        self._uint = struct.Struct(f"{self.order}I")
        self._time = struct.Struct(f"{self.order}iI")

    def align(self, size: int) -> None:
        size = min(size, self.max_align)
        self.pos += -(self.pos - _HEADER) % size

    def need(self, size: int) -> int:
        start = self.pos
        if start + size > len(self.data):
            raise ValueError(f"not a {self.what}: it ends early")
        self.pos += size
        return start

    def uint(self) -> int:
        self.align(4)
        return int(self._uint.unpack_from(self.data, self.need(4))[0])

    def time(self) -> tuple[int, int]:
        self.align(4)
        sec, nsec = self._time.unpack_from(self.data, self.need(8))
        return sec, nsec

    def string(self) -> bytes:
        size = self.uint()  # with its terminating NUL
        start = self.need(size)
        return self.data[start : start + max(size - 1, 0)]

    def octets(self, size: int) -> bytes:
        start = self.need(size)
        return self.data[start : start + size]

    def at_end(self) -> bool:
        """Nothing left but the padding to a multiple of 4 that DDS may append."""
        rest = self.data[self.pos :]
        return len(rest) < 4 and not any(rest)


def decode_tf_message(data: bytes, *, static: bool, authority: str, record_time: int) -> TransformBatch:
    """One ``tf2_msgs/msg/TFMessage`` sample as a batch; ``ValueError`` if ``data`` is not one."""
    reader = _Reader(data, "TFMessage")
    names: dict[bytes, int] = {}
    ids: list[int] = []
    times: list[int] = []
    value_offsets: list[int] = []
    try:
        count = reader.uint()
        if count * (8 + 4 + 4 + VALUES_SIZE) > len(data):
            raise ValueError("not a TFMessage: it ends early")
        for _ in range(count):
            times += reader.time()  # header.stamp
            for _name in range(2):  # header.frame_id, then child_frame_id
                ids.append(names.setdefault(reader.string(), len(names)))
            reader.align(8)
            value_offsets.append(reader.need(VALUES_SIZE))
    except struct.error as error:
        raise ValueError(f"not a TFMessage: {error}") from None
    return tf_batch(
        data,
        list(names),
        ids,
        times,
        value_offsets,
        reader.order,
        static=static,
        authority=authority,
        record_time=record_time,
    )


def decode_clock(data: bytes) -> int:
    """A ``rosgraph_msgs/msg/Clock`` sample's time in nanoseconds."""
    try:
        sec, nsec = _Reader(data, "Clock").time()
    except struct.error:
        raise ValueError("not a Clock message") from None
    return sec * NS_PER_S + nsec


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
        except (ValueError, struct.error, UnicodeDecodeError) as error:
            errors.append(f"{gid_size}-byte ids: {error}")
    raise ValueError("not a ParticipantEntitiesInfo (" + "; ".join(errors) + ")")


def _participant_entities(data: bytes, gid_size: int) -> ParticipantEntities:
    reader = _Reader(data, "ParticipantEntitiesInfo")
    participant = reader.octets(gid_size)[:GUID_SIZE]
    nodes = []
    for _ in range(_count(reader, 8)):
        namespace = reader.string().decode()
        name = reader.string().decode()
        _readers = [reader.octets(gid_size) for _ in range(_count(reader, gid_size))]
        writers = tuple(reader.octets(gid_size)[:GUID_SIZE] for _ in range(_count(reader, gid_size)))
        nodes.append(NodeEntities(namespace, name, writers))
    if not reader.at_end():
        raise ValueError(f"{len(data) - reader.pos} bytes left over")
    return ParticipantEntities(participant, tuple(nodes), gid_size)


def _count(reader: _Reader, smallest: int) -> int:
    """A sequence's length, refused where its elements cannot fit in what is left."""
    count = reader.uint()
    if count * smallest > len(reader.data) - reader.pos:
        raise ValueError(f"a sequence of {count} does not fit")
    return count
