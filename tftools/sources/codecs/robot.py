"""A robot's own messages read whole, in ROS1 and CDR alike (``wire.Cursor``) and in JSON (``codecs.json``, a
Foxglove MCAP's): ``sensor_msgs/JointState`` (the joints' positions) and ``std_msgs/String``
(``/robot_description``, the URDF)."""

from __future__ import annotations

import struct
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from tftools.core.arrays import Int64Array, UInt8Array
from tftools.sources.codecs import cdr, ros1
from tftools.sources.codecs import json as json_codec
from tftools.sources.codecs.decoded import DecodeError
from tftools.sources.codecs.wire import MAX_FRAME_ID, Cursor, Wire, wire_of

#: A joint name longer than this, or more joints than this in one message, is damage.
MAX_JOINTS = 4096
#: A description longer than this is not read (metadata.yaml's and the URDF file's limit).
MAX_TEXT = 4 << 20

JOINT_STATE = "sensor_msgs/msg/JointState"
STRING = "std_msgs/msg/String"


@dataclass(frozen=True)
class JointState:
    """One message's joints: the stamp of its header (ns), and each named joint's position."""

    stamp: int
    positions: dict[str, float]

    @property
    def key(self) -> tuple[str, ...]:
        """Its kind: the joints it names (a driver may publish several kinds, each at its own rate)."""
        return tuple(self.positions)


#: Decodes many payloads, ``raw[starts[i] : starts[i] + lengths[i]]``: the messages read (indices
#: into the payloads), their values, and the (message, reason) of those that could not be.
WholeDecoder = Callable[[UInt8Array, Int64Array, Int64Array], tuple[list[int], list[Any], list[tuple[int, str]]]]


#: The names already read in a call, by where they start in their message: their bytes and the names.
Seen = dict[int, tuple[bytes, list[str]]]
Reader = Callable[[Cursor, Seen], Any]


def _each(
    raw: UInt8Array, starts: Int64Array, lengths: Int64Array, wires: Sequence[Wire], read: Reader
) -> tuple[list[int], list[Any], list[tuple[int, str]]]:
    read_ok: list[int] = []
    values: list[Any] = []
    failures: list[tuple[int, str]] = []
    seen: Seen = {}
    for message, (start, length) in enumerate(zip(starts.tolist(), lengths.tolist(), strict=True)):
        try:
            values.append(read(Cursor(raw, wire_of(raw, start, length, wires), start, start + length), seen))
        except DecodeError as e:
            failures.append((message, str(e)))
            continue
        read_ok.append(message)
    return read_ok, values, failures


def _text(cursor: Cursor, limit: int) -> str:
    at, size = cursor.string()
    if size > limit:
        raise DecodeError(f"a string of {size} bytes, over the {limit} read")
    return bytes(cursor.raw[at : at + size]).decode("utf-8", "replace")


def _floats(cursor: Cursor) -> tuple[float, ...]:
    count = cursor.uint()
    if count > MAX_JOINTS:
        raise DecodeError(f"{count} values, over the {MAX_JOINTS} read")
    at = cursor.take(8 * count, 8)
    return struct.unpack_from(f"{cursor.wire.order}{count}d", cursor.raw, at)


def _joint_state(cursor: Cursor, seen: Seen) -> JointState:
    stamp, _, _ = cursor.header()
    begin = cursor.pos
    where = begin - cursor.start  # a message's names start where its like's did: its names are the same bytes
    known = seen.get(where)
    if known is not None and cursor.raw[begin : begin + len(known[0])] == known[0]:
        cursor.take(len(known[0]))
        names = known[1]
    else:
        count = cursor.uint()
        if count > MAX_JOINTS or 4 * count > cursor.rest:
            raise DecodeError(f"{count} joint names cannot fit in the message")
        names = [_text(cursor, MAX_FRAME_ID) for _ in range(count)]
        seen[where] = (bytes(cursor.raw[begin : cursor.pos]), names)
    return _joint_state_of(stamp, names, _floats(cursor))


def _joint_state_of(stamp: int, names: Sequence[str], positions: Sequence[float]) -> JointState:
    if len(positions) not in (0, len(names)):
        raise DecodeError(f"{len(names)} names but {len(positions)} positions")
    return JointState(stamp, dict(zip(names, positions, strict=False)))


def _string(cursor: Cursor, _seen: Seen) -> str:
    return _text(cursor, MAX_TEXT)


def _json_joint_state(message: dict[str, Any]) -> JointState:
    stamp, names, positions = json_codec.joint_state_of(message)
    if len(names) > MAX_JOINTS or any(len(name) > MAX_FRAME_ID for name in names):
        raise DecodeError(f"{len(names)} joint names, or one longer than {MAX_FRAME_ID} bytes")
    return _joint_state_of(stamp, names, positions)


def _json_string(message: dict[str, Any]) -> str:
    text = json_codec.string_of(message)
    if len(text) > MAX_TEXT:
        raise DecodeError(f"a string of {len(text)} characters, over the {MAX_TEXT} read")
    return text


def _json_decoder(read: Callable[[dict[str, Any]], Any]) -> WholeDecoder:
    def decode(
        raw: UInt8Array, starts: Int64Array, lengths: Int64Array
    ) -> tuple[list[int], list[Any], list[tuple[int, str]]]:
        return json_codec.decode_whole(raw, starts, lengths, read)

    return decode


def _decoder(wires: Sequence[Wire], read: Reader) -> WholeDecoder:
    def decode(
        raw: UInt8Array, starts: Int64Array, lengths: Int64Array
    ) -> tuple[list[int], list[Any], list[tuple[int, str]]]:
        return _each(raw, starts, lengths, wires, read)

    return decode


#: (rosidl type name, encoding) -> its decoder.
WHOLE_DECODERS: dict[tuple[str, str], WholeDecoder] = {
    (JOINT_STATE, "ros1"): _decoder(ros1.WIRES, _joint_state),
    (JOINT_STATE, "cdr"): _decoder(cdr.WIRES, _joint_state),
    (STRING, "ros1"): _decoder(ros1.WIRES, _string),
    (STRING, "cdr"): _decoder(cdr.WIRES, _string),
    (JOINT_STATE, "json"): _json_decoder(_json_joint_state),
    (STRING, "json"): _json_decoder(_json_string),
}
