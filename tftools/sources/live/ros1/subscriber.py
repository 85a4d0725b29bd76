"""A subscription: one TCPROS connection per publisher, kept up while the master lists it."""

from __future__ import annotations

import contextlib
import socket
import threading
import time
from collections.abc import Callable, Mapping

from tftools.sources.codecs.types import MessageType
from tftools.sources.live.notices import OnNotice, printable
from tftools.sources.live.ros1 import tcpros
from tftools.sources.live.ros1 import xmlrpc as ros_xmlrpc

#: Called with each message's bytes and its publisher's callerid, from the connection's thread.
OnMessage = Callable[[bytes, str], None]

#: Called with a publisher's connection header (its type, message_definition, callerid...) before
#: its messages: False declines them, quietly (the connection ends, not retried).
Admit = Callable[[Mapping[str, str]], bool]

#: What losing or failing a connection can raise: each means "try again later".
_CONNECTION_ERRORS = (OSError, EOFError, tcpros.ProtocolError)

#: Seconds between attempts to reach a publisher, doubling from the first to the last.
RETRY_FIRST, RETRY_MAX = 0.1, 2.0

#: Publishers listened to per topic, at most: each is one connection and one thread. The master
#: may list more (a system gone wrong, or a hostile one): the first ones listed are heard.
MAX_PUBLISHERS = 64

#: Connection threads per topic at once, those still ending included (a publisher dropped by a
#: ``publisherUpdate`` may take a few seconds to give up): new ones wait for a thread to end.
MAX_THREADS = 2 * MAX_PUBLISHERS

#: Seconds ``Subscription.close`` waits for all its connections' threads together.
CLOSE_TIMEOUT = 1.0


class _RefusedError(Exception):
    """The publisher will not serve us (another message type, not TCPROS): do not retry."""


class _DeclinedError(Exception):
    """Its messages are not wanted (the subscriber's ``admit`` said so): do not retry, say nothing."""


class Subscription:
    """``topic`` from every publisher the master names, each over its own connection."""

    def __init__(
        self,
        caller_id: str,
        topic: str,
        msg_type: MessageType,
        on_message: OnMessage,
        on_notice: OnNotice,
        name_of: Callable[[str], str] = str,
        admit: Admit | None = None,
    ) -> None:
        self.caller_id = caller_id
        self.admit = admit
        self.name_of = name_of  # a publisher's node name from its URI, for messages
        self.topic = topic
        self.type = msg_type
        self.deliver = on_message
        self.notice = on_notice
        self._links: dict[str, _PublisherLink] = {}
        self._lock = threading.Lock()
        self._closed = False
        self._running = 0  # threads of links started and not yet ended, stopped ones included

    def update(self, publishers: list[str]) -> None:
        """The publishers' slave URIs now (from registration or ``publisherUpdate``): connect to the
        new ones (the first ``MAX_PUBLISHERS``), leave those gone."""
        wanted = list(dict.fromkeys(publishers))
        if len(wanted) > MAX_PUBLISHERS:
            self.notice(
                f"the master lists {len(wanted)} publishers of {self.topic}: tfx listens to the first "
                f"{MAX_PUBLISHERS} only"
            )
            wanted = wanted[:MAX_PUBLISHERS]
        with self._lock:
            if self._closed:
                return
            for uri in set(self._links) - set(wanted):
                self._links.pop(uri).stop()
            for uri in wanted:
                if uri not in self._links:
                    self._links[uri] = _PublisherLink(self, uri)
            self._launch()

    def _launch(self) -> None:
        """Start the links not yet started, while fewer than ``MAX_THREADS`` run (under the lock)."""
        for link in self._links.values():
            if self._running >= MAX_THREADS:
                return
            if not link.launched:
                link.launched = True
                self._running += 1
                link.start()

    def ended(self) -> None:
        """A link's thread ends: its place goes to a link waiting for one."""
        with self._lock:
            self._running -= 1
            if not self._closed:
                self._launch()

    @property
    def connections(self) -> list[tuple[str, str]]:
        """(publisher URI, its callerid or "") of each link that is connected."""
        with self._lock:
            return [(uri, link.callerid) for uri, link in self._links.items() if link.connected]

    def close(self) -> None:
        with self._lock:
            self._closed = True
            links, self._links = list(self._links.values()), {}
        for link in links:
            link.stop()
        deadline = time.monotonic() + CLOSE_TIMEOUT
        for link in links:
            if link.launched:
                link.join(timeout=max(deadline - time.monotonic(), 0.0))


class _PublisherLink(threading.Thread):
    """The connection to one publisher: ask it for the topic, read messages, reconnect when lost."""

    def __init__(self, subscription: Subscription, uri: str) -> None:
        super().__init__(name=f"tfx-sub {subscription.topic} {uri}", daemon=True)
        self.sub = subscription
        self.uri = uri
        self.callerid = ""
        self.connected = False
        self.launched = False
        self._stopped = threading.Event()
        self._sock: socket.socket | None = None

    def stop(self) -> None:
        self._stopped.set()
        sock = self._sock
        if sock is not None:
            with contextlib.suppress(OSError):
                sock.shutdown(socket.SHUT_RDWR)  # wakes the blocked recv

    def run(self) -> None:
        try:
            self._run()
        finally:
            self.sub.ended()

    def _run(self) -> None:
        delay = RETRY_FIRST
        complained = False
        while not self._stopped.is_set():
            try:
                self._serve()
                delay = RETRY_FIRST
            except _DeclinedError:
                return
            except _RefusedError as refusal:
                self.sub.notice(f"{printable(self.callerid or self.sub.name_of(self.uri))} {refusal}")
                return
            except ros_xmlrpc.ReplyError as error:
                who = printable(self.sub.name_of(self.uri))
                self.sub.notice(f"{who} answered requestTopic with something not TCPROS ({error}): ignored")
                return
            except _CONNECTION_ERRORS as error:
                if self._stopped.is_set():
                    return
                if self.connected:
                    self.sub.notice(f"lost the connection to {self._who()} ({error}); reconnecting")
                    delay, complained = RETRY_FIRST, False
                elif not complained:  # often a node killed without unregistering: the master still lists it
                    self.sub.notice(f"cannot reach the publisher at {self.uri} ({error}); retrying while listed")
                    complained = True
            except Exception as error:  # a bug of tfx's must not pass for the peer's, nor kill quietly
                self.sub.notice(f"stopped listening to {self._who()}: internal error {type(error).__name__}: {error}")
                return
            finally:
                self.connected = False
                sock, self._sock = self._sock, None
                if sock is not None:
                    sock.close()
            self._stopped.wait(delay)
            delay = min(delay * 2, RETRY_MAX)

    def _who(self) -> str:
        where = printable(self.uri)
        return f"{printable(self.callerid)} ({where})" if self.callerid else f"the publisher at {where}"

    def _serve(self) -> None:
        host, port = self._request_topic()
        if self._stopped.is_set():
            return
        sock = self._sock = socket.create_connection((host, port), timeout=ros_xmlrpc.CALL_TIMEOUT)
        if self._stopped.is_set():
            return
        sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        t = self.sub.type
        sock.settimeout(ros_xmlrpc.CALL_TIMEOUT)
        sock.sendall(
            tcpros.encode_header(
                {
                    "callerid": self.sub.caller_id,
                    "topic": self.sub.topic,
                    "type": t.name,
                    "md5sum": t.md5sum,
                    "message_definition": t.definition,
                    "tcp_nodelay": "1",
                }
            )
        )
        header = tcpros.read_header(sock)
        self.callerid = header.get("callerid", "")[:256]
        if "error" in header:
            raise _RefusedError(f"refused to send {self.sub.topic}: {printable(header['error'], 300)}")
        for field in ("callerid", "md5sum"):
            if not header.get(field):
                raise _RefusedError(f"sent a connection header without {field}, as no ROS publisher does: ignored")
        if "*" not in (header["md5sum"], t.md5sum) and header["md5sum"] != t.md5sum:
            kind, md5sum = printable(header.get("type", "?")), printable(header["md5sum"], 64)
            raise _RefusedError(f"publishes {self.sub.topic} as {kind} (md5sum {md5sum}), not {t.name}: ignored")
        if self.sub.admit is not None and not self.sub.admit(header):
            raise _DeclinedError
        self.connected = True
        while not self._stopped.is_set():
            self.sub.deliver(tcpros.read_message(sock), self.callerid)

    def _request_topic(self) -> tuple[str, int]:
        """Where the publisher serves the topic; ``ReplyError`` when its answer is not TCPROS's."""
        code, message, protocol = ros_xmlrpc.call(
            self.uri, "requestTopic", self.sub.caller_id, self.sub.topic, [["TCPROS"]]
        )
        if code != 1:
            raise OSError(f"it does not offer {self.sub.topic} now: {printable(message)}")
        if (
            not isinstance(protocol, list)
            or len(protocol) < 3
            or protocol[0] != "TCPROS"
            or not isinstance(protocol[1], str)
            or not 0 < len(protocol[1]) < 256
            or type(protocol[2]) is not int
            or not 0 < protocol[2] < 65536
        ):
            raise ros_xmlrpc.ReplyError("its requestTopic answer is not a TCPROS host and port")
        return protocol[1], protocol[2]
