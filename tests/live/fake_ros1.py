"""A fake ROS1 master and fake publishers on 127.0.0.1, scripted to misbehave; every one stops with its test."""

from __future__ import annotations

import contextlib
import socket
import struct
import threading
import time
import xmlrpc.client
from collections.abc import Callable, Iterator

from tftools.sources.codecs.types import TF_MESSAGE, ros1_message_type
from tftools.sources.live.ros1 import tcpros

#: An HTTP reply body, or the raw bytes to send (when it starts with b"HTTP/"), or a callable
#: writing whatever it likes on the socket.
Answer = bytes | Callable[[socket.socket], None]


def ros_reply(value: object, code: int = 1, message: str = "") -> bytes:
    return xmlrpc.client.dumps(([code, message, value],), methodresponse=True).encode()


def http(body: bytes) -> bytes:
    return b"HTTP/1.0 200 OK\r\nContent-Type: text/xml\r\nContent-Length: %d\r\n\r\n%s" % (len(body), body)


class _Server:
    """Accepts connections on 127.0.0.1 and serves each on a daemon thread until ``close``."""

    def __init__(self) -> None:
        self.listener = socket.create_server(("127.0.0.1", 0))
        self.listener.settimeout(0.1)
        self.port = self.listener.getsockname()[1]
        self.closed = threading.Event()
        self.clients: list[socket.socket] = []
        threading.Thread(target=self._accept, daemon=True).start()

    def _accept(self) -> None:
        while not self.closed.is_set():
            try:
                sock, _ = self.listener.accept()
            except TimeoutError:
                continue
            except OSError:
                return
            self.clients.append(sock)
            threading.Thread(target=self._serve_quietly, args=(sock,), daemon=True).start()

    def _serve_quietly(self, sock: socket.socket) -> None:
        with contextlib.suppress(OSError, EOFError, ValueError, tcpros.ProtocolError):
            sock.settimeout(10)
            self.serve(sock)
        with contextlib.suppress(OSError):
            sock.close()

    def serve(self, sock: socket.socket) -> None:
        raise NotImplementedError

    def close(self) -> None:
        self.closed.set()
        self.listener.close()
        for sock in self.clients:
            with contextlib.suppress(OSError):
                sock.shutdown(socket.SHUT_RDWR)
                sock.close()


def read_request(sock: socket.socket) -> tuple[str, tuple[object, ...]]:
    """One XML-RPC request: its method and parameters."""
    data = b""
    while b"\r\n\r\n" not in data:
        chunk = sock.recv(4096)
        if not chunk:
            raise EOFError
        data += chunk
    head, _, body = data.partition(b"\r\n\r\n")
    lines = head.lower().split(b"\r\n")
    length = next(int(line.split(b":")[1]) for line in lines if line.startswith(b"content-length"))
    while len(body) < length:
        body += sock.recv(4096)
    params, method = xmlrpc.client.loads(body)
    return str(method), params


class FakeXmlRpc(_Server):
    """Answers each XML-RPC call as ``answers[method]`` says (a missing method: a normal success)."""

    def __init__(self, answers: dict[str, Answer] | None = None) -> None:
        self.answers = dict(answers or {})
        self.calls: list[tuple[str, tuple[object, ...]]] = []
        super().__init__()

    @property
    def uri(self) -> str:
        return f"http://127.0.0.1:{self.port}/"

    def serve(self, sock: socket.socket) -> None:
        method, params = read_request(sock)
        self.calls.append((method, params))
        answer = self.answers.get(method, ros_reply(0))
        if callable(answer):
            answer(sock)
        else:
            sock.sendall(answer if answer.startswith(b"HTTP/") else http(answer))


def trickle(data: bytes, every: float = 0.5) -> Callable[[socket.socket], None]:
    """An answer sent one byte every ``every`` seconds."""

    def send(sock: socket.socket) -> None:
        for byte in data:
            sock.sendall(bytes([byte]))
            time.sleep(every)

    return send


def endless(sock: socket.socket) -> None:
    """An HTTP reply without a length whose body never ends."""
    sock.sendall(b"HTTP/1.0 200 OK\r\nContent-Type: text/xml\r\n\r\n<methodResponse>")
    block = b"<!-- " + b"x" * 65536 + b" -->"
    while True:
        sock.sendall(block)


TF_TYPE = ros1_message_type(TF_MESSAGE)


class FakeTcpRos(_Server):
    """A TCPROS publisher: reads the subscriber's header, then ``behave(sock)`` does the rest."""

    def __init__(self, behave: Callable[[socket.socket], None]) -> None:
        self.behave = behave
        super().__init__()

    def serve(self, sock: socket.socket) -> None:
        tcpros.read_header(sock, timeout=10)  # its own patience: tests shorten tfx's HEADER_TIMEOUT
        self.behave(sock)


def publisher_header(callerid: str = "/fake", md5sum: str = TF_TYPE.md5sum, **more: str) -> bytes:
    """A publisher's connection header; a field given as "" is left out."""
    fields = {"callerid": callerid, "md5sum": md5sum, "type": TF_TYPE.name, **more}
    return tcpros.encode_header({k: v for k, v in fields.items() if v != ""})


def silence(sock: socket.socket) -> None:
    """Never says anything, until the test ends."""
    while sock.recv(4096):
        pass


@contextlib.contextmanager
def fake_publisher(behave: Callable[[socket.socket], None], request_topic: Answer | None = None) -> Iterator[str]:
    """A publisher node: its slave API's URI; ``requestTopic`` answers with its TCPROS port
    unless ``request_topic`` says otherwise."""
    tcp = FakeTcpRos(behave)
    answer = request_topic if request_topic is not None else ros_reply(["TCPROS", "127.0.0.1", tcp.port])
    slave = FakeXmlRpc({"requestTopic": answer})
    try:
        yield slave.uri
    finally:
        slave.close()
        tcp.close()


@contextlib.contextmanager
def fake_master(publishers: list[str] | None = None, **answers: Answer) -> Iterator[FakeXmlRpc]:
    """A master whose ``registerSubscriber`` lists ``publishers`` (unless ``answers`` says otherwise)."""
    replies: dict[str, Answer] = {"registerSubscriber": ros_reply(publishers or []), "getParam": ros_reply(False)}
    replies.update(answers)
    master = FakeXmlRpc(replies)
    try:
        yield master
    finally:
        master.close()


def tf_message(child: str = "b", x: float = 1.0) -> bytes:
    """A serialized TFMessage of one transform a -> ``child``."""
    names = b"".join(struct.pack("<I", len(n)) + n for n in (b"a", child.encode()))
    return struct.pack("<I", 1) + struct.pack("<III", 0, 1, 0) + names + struct.pack("<7d", x, 0, 0, 0, 0, 0, 1)


def steady(callerid: str = "/good", child: str = "b") -> Callable[[socket.socket], None]:
    """A well-behaved publisher: a transform ten times a second."""

    def behave(sock: socket.socket) -> None:
        sock.sendall(publisher_header(callerid))
        while True:
            sock.sendall(tcpros.frame(tf_message(child)))
            time.sleep(0.1)

    return behave
