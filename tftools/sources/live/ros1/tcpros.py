"""TCPROS on sockets: connection headers and length-prefixed messages."""

from __future__ import annotations

import socket
import struct
from collections.abc import Mapping

_LENGTH = struct.Struct("<I")

#: A header or message larger than this is not TCPROS (a wrong port, garbage): refuse it.
MAX_FRAME = 1 << 30


class ProtocolError(Exception):
    """The other end does not speak TCPROS (or hung up mid-frame)."""


def encode_header(fields: Mapping[str, str]) -> bytes:
    """A connection header: ``key=value`` records, each length-prefixed, the whole length-prefixed."""
    records = b"".join(_LENGTH.pack(len(r)) + r for r in (f"{k}={v}".encode() for k, v in fields.items()))
    return _LENGTH.pack(len(records)) + records


def decode_header(data: bytes) -> dict[str, str]:
    """The fields of a connection header's body (without its total length)."""
    fields: dict[str, str] = {}
    offset = 0
    while offset < len(data):
        if offset + 4 > len(data):
            raise ProtocolError("truncated connection header")
        (size,) = _LENGTH.unpack_from(data, offset)
        record = data[offset + 4 : offset + 4 + size]
        if len(record) != size or b"=" not in record:
            raise ProtocolError("malformed connection header")
        key, _, value = record.decode("utf-8", "replace").partition("=")
        fields[key] = value
        offset += 4 + size
    return fields


def read_exactly(sock: socket.socket, size: int) -> bytes:
    """``size`` bytes, or ``EOFError`` when the peer closes first."""
    chunks = bytearray()
    while len(chunks) < size:
        chunk = sock.recv(min(size - len(chunks), 1 << 20))
        if not chunk:
            raise EOFError("connection closed")
        chunks += chunk
    return bytes(chunks)


def read_frame(sock: socket.socket) -> bytes:
    """One length-prefixed frame (a header or a message)."""
    (size,) = _LENGTH.unpack(read_exactly(sock, 4))
    if size > MAX_FRAME:
        raise ProtocolError(f"a frame of {size} bytes is not TCPROS")
    return read_exactly(sock, size)


def read_header(sock: socket.socket) -> dict[str, str]:
    return decode_header(read_frame(sock))


def frame(message: bytes) -> bytes:
    return _LENGTH.pack(len(message)) + message
