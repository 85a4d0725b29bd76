"""Publishing over TCPROS: this node's server for subscribers, and one publication per topic."""

from __future__ import annotations

import contextlib
import socket
import threading
from collections.abc import Callable

from tftools.sources.codecs.types import MessageType
from tftools.sources.live.ros1 import tcpros
from tftools.sources.live.ros1.xmlrpc import CALL_TIMEOUT


class Publication:
    """``topic`` sent to every subscriber connected; latched: the last message goes to newcomers."""

    def __init__(self, caller_id: str, topic: str, msg_type: MessageType, latched: bool) -> None:
        self.caller_id = caller_id
        self.topic = topic
        self.type = msg_type
        self.latched = latched
        self._last: bytes | None = None
        self._subscribers: dict[socket.socket, str] = {}  # connection -> subscriber's callerid
        self._lock = threading.Lock()

    @property
    def subscribers(self) -> list[str]:
        with self._lock:
            return list(self._subscribers.values())

    def publish(self, message: bytes) -> None:
        """Send ``message`` to every subscriber (and keep it for later ones if latched)."""
        data = tcpros.frame(message)
        with self._lock:
            if self.latched:
                self._last = data
            for sock in list(self._subscribers):
                try:
                    sock.sendall(data)
                except OSError:
                    self._drop(sock)

    def accept(self, sock: socket.socket, header: dict[str, str]) -> None:
        """A subscriber's connection whose header asked for this topic: answer and serve it."""
        sock.settimeout(CALL_TIMEOUT)  # for sends: a subscriber that stops reading is dropped
        wanted = header.get("md5sum", "*")
        if wanted not in ("*", self.type.md5sum):
            error = (
                f"Client [{header.get('callerid', '')}] wants topic {self.topic} to have datatype/md5sum "
                f"[{header.get('type', '')}/{wanted}], but our version has [{self.type.name}/{self.type.md5sum}]. "
                "Dropping connection."
            )
            sock.sendall(tcpros.encode_header({"error": error}))
            sock.close()
            return
        reply = {
            "callerid": self.caller_id,
            "latching": "1" if self.latched else "0",
            "md5sum": self.type.md5sum,
            "message_definition": self.type.definition,
            "topic": self.topic,
            "type": self.type.name,
        }
        with self._lock:
            sock.sendall(tcpros.encode_header(reply))
            if self._last is not None:
                sock.sendall(self._last)
            self._subscribers[sock] = header.get("callerid", "")
        # Subscribers send nothing after their header: a read returns only when they leave. Sends
        # keep the timeout: one that stops reading is dropped rather than stalling the others.
        while True:
            try:
                if not sock.recv(4096):
                    break
            except TimeoutError:
                continue
            except OSError:
                break
        with self._lock:
            self._drop(sock)

    def _drop(self, sock: socket.socket) -> None:
        self._subscribers.pop(sock, None)
        with contextlib.suppress(OSError):
            sock.close()

    def close(self) -> None:
        with self._lock:
            for sock in list(self._subscribers):
                with contextlib.suppress(OSError):
                    sock.shutdown(socket.SHUT_RDWR)
                self._drop(sock)


#: Subscribers served at once, all topics together (each is a thread); more are turned away.
MAX_SUBSCRIBERS = 64


class TcpRosServer:
    """Accepts subscribers' connections and hands each to the publication its header names."""

    def __init__(self, bind: str, advertised_host: str, find: Callable[[str], Publication | None]) -> None:
        self._find = find
        self._listener = socket.create_server((bind, 0))
        self.host = advertised_host
        self.port = self._listener.getsockname()[1]
        self._closed = False
        self._slots = threading.BoundedSemaphore(MAX_SUBSCRIBERS)
        self._thread = threading.Thread(target=self._accept, name="tfx-tcpros", daemon=True)

    def start(self) -> None:
        self._thread.start()

    def _accept(self) -> None:
        while not self._closed:
            try:
                sock, _ = self._listener.accept()
            except OSError:
                return
            if not self._slots.acquire(blocking=False):
                sock.close()
                continue
            threading.Thread(target=self._serve, args=(sock,), name="tfx-tcpros-client", daemon=True).start()

    def _serve(self, sock: socket.socket) -> None:
        try:
            sock.settimeout(CALL_TIMEOUT)
            sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            header = tcpros.read_header(sock)
            publication = self._find(header.get("topic", ""))
            if publication is None or "service" in header:
                asked = header.get("topic") or header.get("service", "")
                sock.sendall(tcpros.encode_header({"error": f"no topic {asked} is published by this node"}))
                sock.close()
                return
            publication.accept(sock, header)
        except (OSError, EOFError, tcpros.ProtocolError):
            with contextlib.suppress(OSError):
                sock.close()
        finally:
            self._slots.release()

    def close(self) -> None:
        self._closed = True
        with contextlib.suppress(OSError):
            self._listener.shutdown(socket.SHUT_RDWR)
        self._listener.close()
