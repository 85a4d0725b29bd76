"""Property-based fuzzing of what live peers send: TCPROS frames and connection headers, XML-RPC
replies, and the ROS 1 and ROS 2 (CDR) tf and clock decoders. Each input is either read or refused
with the one error its reader documents, in bounded time and memory.

``TFTOOLS_FUZZ_EXAMPLES`` raises the number of examples (default: a quick run for CI).
"""

from __future__ import annotations

import contextlib
import os
import socket
import struct
import xmlrpc.client

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tftools.sources.codecs import cdr, ros1
from tftools.sources.codecs.decoded import message_clock
from tftools.sources.live.received import Received, decode_received
from tftools.sources.live.ros1 import tcpros
from tftools.sources.live.ros1 import xmlrpc as ros_xmlrpc
from tftools.sources.live.ros2.entities import decode_participant_entities

EXAMPLES = int(os.environ.get("TFTOOLS_FUZZ_EXAMPLES", "60"))
FUZZ = settings(max_examples=EXAMPLES, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def _tf_message(count: int, names: tuple[bytes, bytes] = (b"map", b"odom")) -> bytes:
    body = struct.pack("<I", count)
    for i in range(count):
        body += struct.pack("<III", i, 1, 2)
        body += b"".join(struct.pack("<I", len(n)) + n for n in names)
        body += struct.pack("<7d", 1, 2, 3, 0, 0, 0, 1)
    return body


def _cdr_tf_message(count: int) -> bytes:
    body = b"\x00\x01\x00\x00" + struct.pack("<I", count)
    for _ in range(count):
        body += struct.pack("<iI", 1, 2)
        for name in (b"map\0", b"odom\0"):
            body += struct.pack("<I", len(name)) + name
            body += b"\0" * (-len(body) % 4)
        body += b"\0" * (-(len(body) - 4) % 8)
        body += struct.pack("<7d", 1, 2, 3, 0, 0, 0, 1)
    return body


def mutants(seed: bytes) -> st.SearchStrategy[bytes]:
    """``seed`` with bytes flipped, cut short, or with a huge length written somewhere."""
    size = len(seed)
    flips = st.lists(st.tuples(st.integers(0, max(size - 1, 0)), st.integers(0, 255)), max_size=8).map(
        lambda changes: bytes(_apply(seed, changes))
    )
    cuts = st.integers(0, size).map(lambda n: seed[:n])
    huge = st.tuples(st.integers(0, max(size - 4, 0)), st.sampled_from([0xFFFFFFFF, 0x7FFFFFFF, 1 << 30, 65536])).map(
        lambda at: seed[: at[0]] + struct.pack("<I", at[1]) + seed[at[0] + 4 :]
    )
    return st.one_of(flips, cuts, huge, st.binary(max_size=512))


def _apply(seed: bytes, changes: list[tuple[int, int]]) -> bytearray:
    data = bytearray(seed)
    for at, value in changes:
        if at < len(data):
            data[at] = value
    return data


@FUZZ
@given(mutants(_tf_message(3)))
def test_ros1_tf_decoder(data: bytes) -> None:
    arrivals = decode_received(ros1.decode_tf, [Received("/tf", data, "/x", 0)])
    assert arrivals.readable + len(arrivals.unreadable) == 1
    assert len(arrivals.batch) * 76 <= len(data)  # never more transforms than the bytes can hold


@FUZZ
@given(mutants(b"\x01\x00\x00\x00\x02\x00\x00\x00"))
def test_ros1_clock_decoder(data: bytes) -> None:
    with contextlib.suppress(ValueError):
        message_clock(ros1.decode_clocks, data)


@FUZZ
@given(mutants(_cdr_tf_message(3)))
def test_ros2_tf_decoder(data: bytes) -> None:
    arrivals = decode_received(cdr.decode_tf, [Received("/tf", data, "/x", 0)])
    assert arrivals.readable + len(arrivals.unreadable) == 1
    assert len(arrivals.batch) * 72 <= len(data)


@FUZZ
@given(mutants(b"\x00\x01\x00\x00\x01\x00\x00\x00\x02\x00\x00\x00"))
def test_ros2_clock_decoder(data: bytes) -> None:
    with contextlib.suppress(ValueError):
        message_clock(cdr.decode_clocks, data)


@FUZZ
@given(st.binary(max_size=600))
def test_ros2_discovery_decoder(data: bytes) -> None:
    with contextlib.suppress(ValueError):
        decode_participant_entities(b"\x00\x01\x00\x00" + data)


HEADER = tcpros.encode_header({"callerid": "/talker", "md5sum": "94810edda583a504dfda3829e70d7eec", "type": "x/Y"})


@FUZZ
@given(mutants(HEADER + tcpros.frame(_tf_message(1))))
def test_tcpros_header_and_message_reader(stream: bytes) -> None:
    """Whatever a peer sends then closes: a header and messages, or ``ProtocolError``/``EOFError``."""
    a, b = socket.socketpair()
    with a, b:
        a.sendall(stream[:200_000])
        a.shutdown(socket.SHUT_WR)
        try:
            tcpros.read_header(b, timeout=2)
            while True:
                assert len(tcpros.read_message(b)) <= tcpros.MAX_MESSAGE
        except (tcpros.ProtocolError, EOFError):
            pass


REPLY = xmlrpc.client.dumps(([1, "ok", ["http://127.0.0.1:1/", "http://127.0.0.1:2/"]],), methodresponse=True).encode()


@FUZZ
@given(st.one_of(mutants(REPLY), st.text(max_size=300).map(str.encode)))
def test_xmlrpc_reply_parser(data: bytes) -> None:
    """A reply is parsed or refused with ``ReplyError`` (or a fault), and a URI list validated."""
    try:
        params, _method = ros_xmlrpc.loads(data)
    except (ros_xmlrpc.ReplyError, xmlrpc.client.Fault):
        return
    value = params[0] if params else None
    if isinstance(value, list) and len(value) == 3:
        with contextlib.suppress(ros_xmlrpc.ReplyError):
            ros_xmlrpc.uri_list(value[2], "publishers")
