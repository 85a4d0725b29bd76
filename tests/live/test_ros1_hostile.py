"""A hostile or broken ROS1 system (fake masters and publishers on 127.0.0.1): every limit holds,
every misbehaving peer is told of once and dropped, and tfx keeps listening to the others."""

from __future__ import annotations

import os
import socket
import struct
import subprocess
import sys
import threading
import time
import xmlrpc.client
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest

from tests.live.fake_ros1 import (
    FakeXmlRpc,
    endless,
    fake_master,
    fake_publisher,
    http,
    publisher_header,
    ros_reply,
    silence,
    steady,
    tf_message,
    trickle,
)
from tftools.core.batch import TransformBatch
from tftools.sources.codecs.types import TF_MESSAGE, ros1_message_type
from tftools.sources.live.errors import LiveError, MasterTimeoutError
from tftools.sources.live.received import Received
from tftools.sources.live.ros1 import node as node_module
from tftools.sources.live.ros1 import publisher, subscriber, tcpros
from tftools.sources.live.ros1 import xmlrpc as ros_xmlrpc
from tftools.sources.live.ros1.source import Ros1Source, _DeliveryQueue

ROOT = Path(__file__).resolve().parents[2]

BOMB = (
    b'<?xml version="1.0"?><!DOCTYPE m [<!ENTITY a "' + b"x" * 1000 + b'">'
    + b"".join(b"<!ENTITY %c \"%s\">" % (98 + i, b"&%c;" % (97 + i) * 10) for i in range(7))
    + b"]><methodResponse><params><param><value><array><data><value><int>1</int></value>"
    b"<value><string></string></value><value><string>&h;</string></value></data></array></value>"
    b"</param></params></methodResponse>"
)  # fmt: skip


@pytest.fixture(autouse=True)
def loopback_only(monkeypatch: pytest.MonkeyPatch) -> None:
    """tfx's nodes listen on 127.0.0.1 only, and no thread may die of an exception."""
    monkeypatch.setenv("ROS_HOSTNAME", "127.0.0.1")
    monkeypatch.delenv("ROS_IP", raising=False)


@pytest.fixture
def thread_deaths(monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """The exceptions that ended a thread during the test (there must be none)."""
    deaths: list[str] = []
    monkeypatch.setattr(threading, "excepthook", lambda a: deaths.append(f"{a.exc_type.__name__}: {a.exc_value}"))
    return deaths


def finishes(function: Callable[[], object], within: float) -> BaseException | object:
    """``function()``'s result or exception; fails the test if it takes longer than ``within`` s."""
    outcome: list[BaseException | object] = []

    def run() -> None:
        try:
            outcome.append(function())
        except BaseException as error:
            outcome.append(error)

    thread = threading.Thread(target=run, daemon=True)
    started = time.monotonic()
    thread.start()
    thread.join(within)
    assert not thread.is_alive(), f"still running after {within} s"
    assert time.monotonic() - started < within
    return outcome[0]


# --- XML-RPC replies ---------------------------------------------------------------------------


def test_a_call_has_a_total_deadline_however_the_bytes_trickle() -> None:
    server = FakeXmlRpc({"getPid": trickle(http(ros_reply(42)), every=0.2)})
    try:
        outcome = finishes(lambda: ros_xmlrpc.call(server.uri, "getPid", "/tfx", timeout=1.0), within=3)
    finally:
        server.close()
    assert isinstance(outcome, TimeoutError)


@pytest.mark.parametrize(
    "answer",
    [endless, b"HTTP/1.0 200 OK\r\nContent-Length: 10000000000\r\n\r\n<methodResponse>"],
    ids=["endless", "declared-10GB"],
)
def test_a_reply_too_large_is_refused_without_reading_it_all(answer: object) -> None:
    server = FakeXmlRpc({"getPid": answer})  # type: ignore[dict-item]  # a hostile answer is the test
    try:
        outcome = finishes(lambda: ros_xmlrpc.call(server.uri, "getPid", "/tfx", timeout=30), within=10)
    finally:
        server.close()
    assert isinstance(outcome, ros_xmlrpc.ReplyError) and "limit" in str(outcome)


def _deep(depth: int) -> bytes:
    nest = b"<value><array><data>" * depth + b"</data></array></value>" * depth
    return b"<methodResponse><params><param>" + nest + b"</param></params></methodResponse>"


JUNK = {
    "not-xml": b"\x00\xffgarbage",
    "entity-bomb": BOMB,
    "external-entity": b'<!DOCTYPE m [<!ENTITY e SYSTEM "file:///etc/passwd">]><methodResponse>&e;</methodResponse>',
    "not-a-triple": xmlrpc.client.dumps(("x",), methodresponse=True).encode(),
    "string-code": ros_reply(False, code="1"),  # type: ignore[arg-type]  # a hostile answer is the test
    "fault": xmlrpc.client.dumps(xmlrpc.client.Fault(1, "no\x1b[31m"), methodresponse=True).encode(),
    "http-500": b"HTTP/1.0 500 Internal Server Error\r\nContent-Length: 0\r\n\r\n",
    "not-http": b"SSH-2.0-OpenSSH_9.2\r\n",
    "huge-int": b"<methodResponse><params><param><value><int>" + b"9" * 100000 + b"</int></value></param></params>"
    b"</methodResponse>",
    "deep-nesting": _deep(100_000),
}


@pytest.mark.parametrize("answer", JUNK.values(), ids=JUNK.keys())
def test_a_master_answering_junk_is_a_one_line_error(answer: bytes) -> None:
    with fake_master(getParam=answer) as master:
        outcome = finishes(lambda: Ros1Source(master.uri, use_sim_time=None), within=5)
    assert isinstance(outcome, LiveError), repr(outcome)
    assert "\n" not in str(outcome) and "\x1b" not in str(outcome) and len(str(outcome)) < 400


URI_JUNK = {
    "a-string": "http://127.0.0.1:1/",
    "numbers": [1, 2],
    "not-http": ["ftp://127.0.0.1:1/"],
    "no-port": ["http://127.0.0.1/"],
    "a-struct": {"a": 1},
}


@pytest.mark.parametrize("publishers", URI_JUNK.values(), ids=URI_JUNK.keys())
def test_a_registration_answered_with_junk_is_a_one_line_error(publishers: object) -> None:
    with fake_master(registerSubscriber=ros_reply(publishers)) as master:
        source = Ros1Source(master.uri, ["/tf"], use_sim_time=False)
        with pytest.raises(LiveError, match="registerSubscriber with something tfx cannot use"):
            source.start(lambda _batch: None)


def test_a_trickling_master_is_a_one_line_error_within_the_deadline() -> None:
    server = FakeXmlRpc({"getParam": trickle(http(ros_reply(False)), every=1.0)})
    env = {**os.environ, "ROS_MASTER_URI": server.uri.rstrip("/"), "ROS_HOSTNAME": "127.0.0.1"}
    try:
        for command in (["frames", "--duration", "3"], ["echo", "a", "b"]):
            started = time.monotonic()
            tfx = [sys.executable, "-m", "tftools", *command]
            result = subprocess.run(tfx, env=env, cwd=ROOT, capture_output=True, text=True, timeout=30)
            assert time.monotonic() - started < 15
            assert result.returncode == 2, result.stderr
            lines = result.stderr.strip().splitlines()
            assert len(lines) == 1 and "Traceback" not in result.stderr
            master = server.uri.rstrip("/")
            assert lines[0].startswith(f"tfx: error: the ROS master at {master} did not answer within 3 s")
    finally:
        server.close()


def test_a_master_that_stalls_at_close_does_not_hold_tfx(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(ros_xmlrpc, "CALL_TIMEOUT", 0.5)
    monkeypatch.setattr(node_module, "CALL_TIMEOUT", 0.5)
    with fake_master(unregisterSubscriber=silence) as master:
        source = Ros1Source(master.uri, ["/tf", "/tf_static", "/a", "/b"], use_sim_time=False)
        source.start(lambda _batch: None)
        started = time.monotonic()
        source.close()
        assert time.monotonic() - started < 1.5  # four unregistrations, one budget


# --- this node's server (the slave API) ----------------------------------------------------------


def _post(uri: str, body: bytes, length: int | None = None) -> bytes:
    host, port = uri.split("//")[1].rstrip("/").split(":")
    with socket.create_connection((host, int(port)), timeout=5) as sock:
        head = f"POST / HTTP/1.0\r\nContent-Type: text/xml\r\nContent-Length: {len(body) if length is None else length}"
        sock.sendall(head.encode() + b"\r\n\r\n" + body)
        reply = b""
        while chunk := sock.recv(65536):
            reply += chunk
    return reply


@pytest.fixture
def listening_node() -> Iterator[tuple[node_module.Node, list[str]]]:
    notices: list[str] = []
    with fake_master() as master:
        node = node_module.Node("/tfx_test", master.uri, notices.append)
        node.subscribe("/tf", ros1_message_type(TF_MESSAGE), lambda _data, _callerid: None)
        try:
            yield node, notices
        finally:
            node.close()


def test_a_junk_publisher_update_is_refused_and_the_node_keeps_serving(
    listening_node: tuple[node_module.Node, list[str]],
) -> None:
    node, notices = listening_node
    slave: Any = xmlrpc.client.ServerProxy(node.uri)  # its answers are untyped lists
    assert slave.publisherUpdate("/master", "/tf", "http://127.0.0.1:1/")[0] == -1  # a string, not a list
    assert slave.publisherUpdate("/master", "/tf", [1, 2])[0] == -1
    assert notices and all("ignored a publisherUpdate" in n for n in notices)
    assert node._subscriptions["/tf"]._links == {}
    assert slave.requestTopic("/x", "/tf", "TCPROS")[0] == 0  # junk protocols: refused, no fault
    assert b"<fault>" in (bombed := _post(node.uri, BOMB)) and b"document type declaration" in bombed
    assert b"413" in _post(node.uri, b"", length=10**9).split(b"\r\n")[0]
    assert slave.getPid("/x")[0] == 1


def test_the_node_serves_a_bounded_number_of_requests_at_once(
    listening_node: tuple[node_module.Node, list[str]], monkeypatch: pytest.MonkeyPatch
) -> None:
    node, _notices = listening_node
    host, port = node.uri.split("//")[1].rstrip("/").split(":")
    before = threading.active_count()
    idle = [socket.create_connection((host, int(port)), timeout=5) for _ in range(60)]  # never send a request
    try:
        time.sleep(0.5)
        assert threading.active_count() - before <= ros_xmlrpc.MAX_CONCURRENT_REQUESTS
    finally:
        for sock in idle:
            sock.close()
    deadline = time.monotonic() + ros_xmlrpc.REQUEST_TIMEOUT + 3
    while True:  # the idle callers' slots come back
        try:
            peer: Any = xmlrpc.client.ServerProxy(node.uri)  # its answers are untyped lists
            assert peer.getPid("/x")[0] == 1
            break
        except (OSError, xmlrpc.client.ProtocolError):
            assert time.monotonic() < deadline
            time.sleep(0.2)


def test_the_tcpros_server_serves_a_bounded_number_of_subscribers(monkeypatch: pytest.MonkeyPatch) -> None:
    server = publisher.TcpRosServer("127.0.0.1", "127.0.0.1", lambda _topic: None)
    server.start()
    before = threading.active_count()
    address = ("127.0.0.1", server.port)
    idle = [socket.create_connection(address, timeout=5) for _ in range(publisher.MAX_SUBSCRIBERS + 40)]
    try:
        time.sleep(0.5)
        assert threading.active_count() - before <= publisher.MAX_SUBSCRIBERS
    finally:
        for sock in idle:
            sock.close()
        server.close()


# --- publishers ----------------------------------------------------------------------------------


def test_3000_publishers_do_not_make_3000_threads(thread_deaths: list[str]) -> None:
    with socket.create_server(("127.0.0.1", 0)) as closed:
        port = closed.getsockname()[1]
    uris = [f"http://127.0.0.1:{port}/{i}" for i in range(3000)]  # nobody there: refused at once
    notices: list[str] = []
    with fake_master(uris) as master:
        before = threading.active_count()
        with Ros1Source(master.uri, ["/tf"], use_sim_time=False, on_notice=notices.append) as source:
            source.start(lambda _batch: None)
            time.sleep(0.5)
            assert threading.active_count() - before <= subscriber.MAX_PUBLISHERS + 5
    assert [n for n in notices if "lists 3000 publishers of /tf" in n] == [
        f"the master lists 3000 publishers of /tf: tfx listens to the first {subscriber.MAX_PUBLISHERS} only"
    ]
    assert not thread_deaths


def test_publisher_updates_in_a_storm_do_not_pile_up_threads(
    listening_node: tuple[node_module.Node, list[str]], thread_deaths: list[str]
) -> None:
    node, _notices = listening_node
    silent = FakeXmlRpc({"requestTopic": silence})  # each link waits out its requestTopic call
    slave: Any = xmlrpc.client.ServerProxy(node.uri)  # its answers are untyped lists
    try:
        for wave in range(20):
            uris = [f"{silent.uri}{wave}/{i}" for i in range(subscriber.MAX_PUBLISHERS)]
            assert slave.publisherUpdate("/master", "/tf", uris)[0] == 1
            links = sum(t.name.startswith("tfx-sub") for t in threading.enumerate())
            assert links <= subscriber.MAX_THREADS
    finally:
        silent.close()
    assert not thread_deaths


def _frames(*messages: bytes, then: Callable[[socket.socket], None] = silence) -> Callable[[socket.socket], None]:
    def behave(sock: socket.socket) -> None:
        sock.sendall(publisher_header("/bad") + b"".join(messages))
        then(sock)

    return behave


def _closes(sock: socket.socket) -> None:
    sock.close()


def _header_only(**fields: str) -> Callable[[socket.socket], None]:
    def behave(sock: socket.socket) -> None:
        sock.sendall(publisher_header(**fields))
        silence(sock)

    return behave


#: A misbehaving publisher (its TCPROS side, and its requestTopic answer) and what tfx says of it.
MALFORMED: dict[str, tuple[Callable[[socket.socket], None], bytes | None, str]] = {
    "huge-frame": (_frames(struct.pack("<I", 100 << 20) + b"\0" * 65536), None, "above tfx's limit"),
    "huge-header": (lambda s: s.sendall(struct.pack("<I", 1 << 30)), None, "connection header of 1073741824 bytes"),
    "no-callerid": (_header_only(callerid=""), None, "without callerid"),
    "no-md5sum": (_header_only(md5sum=""), None, "without md5sum"),
    "wrong-md5sum": (_header_only(callerid="/bad", md5sum="0" * 32), None, "publishes /tf as tf2_msgs/TFMessage"),
    "garbage-messages": (_frames(tcpros.frame(b"\xff" * 300), tcpros.frame(b"")), None, "unreadable message"),
    "closes-mid-frame": (_frames(struct.pack("<I", 1000) + b"\0" * 10, then=_closes), None, "lost the connection"),
    "stalls-mid-frame": (_frames(struct.pack("<I", 1000) + b"\0" * 10), None, "came in time"),
    "never-sends": (silence, None, "came in time"),
    "garbage-header": (lambda s: s.sendall(struct.pack("<I", 8) + b"\xff" * 108), None, "connection header"),
    "request-topic-no-port": (silence, ros_reply(["TCPROS", "127.0.0.1"]), "not TCPROS"),
    "request-topic-string-port": (silence, ros_reply(["TCPROS", "127.0.0.1", "80"]), "not TCPROS"),
    "request-topic-a-number": (silence, ros_reply(7), "not TCPROS"),
    "request-topic-bomb": (silence, BOMB, "document type declaration"),
}


@pytest.mark.parametrize(("behave", "request_topic", "said"), MALFORMED.values(), ids=MALFORMED.keys())
def test_a_malformed_publisher_is_told_of_once_and_the_others_are_heard(
    behave: Callable[[socket.socket], None],
    request_topic: bytes | None,
    said: str,
    thread_deaths: list[str],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(tcpros, "HEADER_TIMEOUT", 0.5)
    monkeypatch.setattr(tcpros, "MESSAGE_TIMEOUT", 0.5)
    monkeypatch.setattr(subscriber, "RETRY_MAX", 0.2)
    notices: list[str] = []
    heard: list[TransformBatch] = []
    with (
        fake_publisher(behave, request_topic) as bad,
        fake_publisher(steady("/good")) as good,
        fake_master([bad, good]) as master,
        Ros1Source(master.uri, ["/tf"], use_sim_time=False, on_notice=notices.append) as source,
    ):
        source.start(heard.append)
        deadline = time.monotonic() + 8
        while not any(said in n for n in notices) and time.monotonic() < deadline:
            time.sleep(0.05)
        assert any(said in n for n in notices), notices
        count = sum(len(b) for b in heard)
        time.sleep(1.5)  # retries of the bad one come and go: told of once, the good one still heard
        assert sum(len(b) for b in heard) > count
    assert len([n for n in notices if said in n]) == 1, notices
    assert all(b.authorities == ["/good"] for b in heard)
    assert all("\n" not in n and "\x1b" not in n for n in notices)
    assert not thread_deaths


def test_a_publisher_of_huge_messages_is_refused_before_it_sends_them() -> None:
    with pytest.raises(tcpros.ProtocolError, match="above tfx's limit"):
        a, b = socket.socketpair()
        with a, b:
            a.sendall(struct.pack("<I", tcpros.MAX_MESSAGE + 1))
            tcpros.read_message(b)


def test_a_header_has_a_total_deadline() -> None:
    a, b = socket.socketpair()
    with a, b:

        def drip() -> None:
            for byte in tcpros.encode_header({"callerid": "/slow" * 10}):
                try:
                    a.send(bytes([byte]))
                except OSError:
                    return
                time.sleep(0.1)

        threading.Thread(target=drip, daemon=True).start()
        outcome = finishes(lambda: tcpros.read_header(b, timeout=0.5), within=2)
    assert isinstance(outcome, tcpros.ProtocolError) and "came in time" in str(outcome)


def test_a_good_message_is_still_read_whole() -> None:
    a, b = socket.socketpair()
    with a, b:
        a.sendall(tcpros.frame(tf_message()))
        assert tcpros.read_message(b) == tf_message()


# --- delivery ------------------------------------------------------------------------------------


def _message(size: int) -> Received:
    return Received("/tf", b"\0" * size, "/x", 0)


def test_the_delivery_queue_is_bounded_and_says_so_once() -> None:
    notices: list[str] = []
    queue = _DeliveryQueue(notices.append, limit=10)
    for _ in range(5):
        queue.put(_message(4))
    assert [len(m.data) for m in queue.take_all() or []] == [4, 4]
    assert queue.dropped == 3 and len(notices) == 1 and "cannot keep up" in notices[0]
    queue.put(_message(50))  # alone: always taken
    assert [len(m.data) for m in queue.take_all() or []] == [50]
    queue.close()
    assert queue.take_all() is None


def test_master_timeout_is_an_unreachable_master() -> None:
    error = MasterTimeoutError("http://127.0.0.1:1", 3.0)
    assert str(error) == "the ROS master at http://127.0.0.1:1 did not answer within 3 s"
    assert isinstance(error, LiveError)
