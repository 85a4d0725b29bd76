"""TCPROS on sockets: connection headers and length-prefixed messages, read within size and time limits."""

from __future__ import annotations

import socket
import struct
import threading
import time
from collections.abc import Iterator, Mapping
from contextlib import contextmanager

_LENGTH = struct.Struct("<I")

#: The largest message accepted from a peer: a tf message of ~800,000 transforms. A larger length
#: is a wrong port, garbage, or a peer trying to exhaust memory: the connection is dropped.
MAX_MESSAGE = 64 << 20

#: Bytes of messages being received from all peers together: 64 peers each half-way through a 60 MiB
#: message would otherwise hold 3.8 GB. A message that would pass it is refused and its link dropped.
MAX_IN_FLIGHT = 256 << 20

#: The largest connection header accepted. It carries the publisher's full message definition, with
#: comments: 2 KB for tf2_msgs/TFMessage, 8 KB for sensor_msgs/CameraInfo, more for a custom type
#: nesting many; it never carries data.
MAX_HEADER = 1 << 20

#: Seconds a peer has to send a whole connection header, from the first byte asked for.
HEADER_TIMEOUT = 3.0

#: Seconds a message may take to arrive once its first byte has: a peer that stops mid-frame is dropped.
MESSAGE_TIMEOUT = 10.0

#: Bytes asked of the socket at once: a declared length is never allocated before the data comes.
_READ_SIZE = 1 << 20


class ProtocolError(Exception):
    """The other end does not speak TCPROS, hung up mid-frame, or was too slow or too large."""


class _InFlight:
    """The bytes of the messages being received, over every link of the process."""

    def __init__(self, limit: int) -> None:
        self.limit = limit
        self.held = 0
        self._lock = threading.Lock()

    @contextmanager
    def holding(self, size: int) -> Iterator[None]:
        with self._lock:
            if self.held + size > self.limit:
                raise ProtocolError(
                    f"a message of {size} bytes while {self.held} are being received from other peers,"
                    f" above tfx's limit of {self.limit} in all"
                )
            self.held += size
        try:
            yield
        finally:
            with self._lock:
                self.held -= size


IN_FLIGHT = _InFlight(MAX_IN_FLIGHT)


def encode_header(fields: Mapping[str, str]) -> bytes:
    """A connection header: ``key=value`` records, each length-prefixed, the whole length-prefixed."""
    records = b"".join(_LENGTH.pack(len(r)) + r for r in (f"{k}={v}".encode() for k, v in fields.items()))
    return _LENGTH.pack(len(records)) + records


def decode_header(data: bytes) -> dict[str, str]:
    """The fields of a connection header's body (without its total length); ``ProtocolError`` if it is not one."""
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


def read_exactly(sock: socket.socket, size: int, deadline: float | None = None) -> bytes:
    """``size`` bytes, or ``EOFError`` when the peer closes first and ``ProtocolError`` when the
    ``deadline`` (a ``time.monotonic()``; None: wait for ever) passes first. Memory grows with what
    arrives, not with ``size``."""
    chunks = bytearray()
    while len(chunks) < size:
        remaining = None if deadline is None else deadline - time.monotonic()
        if remaining is not None and remaining <= 0:
            raise ProtocolError(f"only {len(chunks)} of {size} bytes came in time")
        sock.settimeout(remaining)
        try:
            chunk = sock.recv(min(size - len(chunks), _READ_SIZE))
        except TimeoutError:
            continue  # the deadline passed: said above
        if not chunk:
            raise EOFError(f"connection closed after {len(chunks)} of {size} bytes")
        chunks += chunk
    return bytes(chunks)


def read_message(sock: socket.socket) -> bytes:
    """One message: waits as long as it takes for one to begin (a latched topic may never send
    another), then at most ``MESSAGE_TIMEOUT`` seconds for the rest; at most ``MAX_MESSAGE`` bytes."""
    (size,) = _LENGTH.unpack(read_exactly(sock, 4))
    if size > MAX_MESSAGE:
        raise ProtocolError(f"a message of {size} bytes, above tfx's limit of {MAX_MESSAGE}: not a tf message")
    with IN_FLIGHT.holding(size):
        return read_exactly(sock, size, time.monotonic() + MESSAGE_TIMEOUT)


def read_header(sock: socket.socket, timeout: float | None = None) -> dict[str, str]:
    """A connection header, whole within ``timeout`` seconds (``HEADER_TIMEOUT``), at most ``MAX_HEADER`` bytes."""
    deadline = time.monotonic() + (HEADER_TIMEOUT if timeout is None else timeout)
    (size,) = _LENGTH.unpack(read_exactly(sock, 4, deadline))
    if size > MAX_HEADER:
        raise ProtocolError(f"a connection header of {size} bytes, above tfx's limit of {MAX_HEADER}: not TCPROS")
    return decode_header(read_exactly(sock, size, deadline))


def frame(message: bytes) -> bytes:
    return _LENGTH.pack(len(message)) + message
