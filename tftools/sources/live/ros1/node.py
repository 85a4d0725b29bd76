"""A ROS1 node in pure Python: registered with the master, serving the slave API, subscribing
and publishing over TCPROS."""

from __future__ import annotations

import contextlib
import os
import threading
import time
from typing import Any, Literal

from tftools.sources.codecs.types import MessageType
from tftools.sources.live.errors import LiveError
from tftools.sources.live.notices import OnNotice, ignore_notice
from tftools.sources.live.ros1 import network
from tftools.sources.live.ros1.publisher import Publication, TcpRosServer
from tftools.sources.live.ros1.subscriber import Admit, OnMessage, Subscription
from tftools.sources.live.ros1.xmlrpc import CALL_TIMEOUT, MasterClient, ReplyError, SlaveServer, uri_list

Reply = list[Any]  # the ROS API's [code, status message, value]


class Node:
    """One node: ``subscribe`` and ``advertise`` topics; ``close`` unregisters everything. Others reach it
    through its slave XML-RPC server; ``shutdown_requested`` is set when one asks it to stop (``rosnode kill``)."""

    def __init__(self, name: str, master_uri: str | None = None, on_notice: OnNotice | None = None) -> None:
        self.name = name
        self.master = MasterClient(network.master_uri(master_uri), name)
        self.host = network.advertised_host()
        self._bind = network.bind_address(self.host)
        self._on_notice = on_notice or ignore_notice
        self.shutdown_requested = threading.Event()
        self._subscriptions: dict[str, Subscription] = {}
        self._publications: dict[str, Publication] = {}
        self._tcpros: TcpRosServer | None = None
        self._lock = threading.Lock()
        try:
            self._slave = SlaveServer(self._bind, self.host, self._handlers())
        except OSError as error:
            raise LiveError(f"cannot open this node's XML-RPC server on {self._bind}: {error.strerror}") from None
        self._slave.start()

    @property
    def uri(self) -> str:
        return self._slave.uri

    def subscribe(
        self, topic: str, msg_type: MessageType, on_message: OnMessage, admit: Admit | None = None
    ) -> Subscription:
        """Listen to ``topic`` from its publishers now and later (raises if the master is not there);
        ``admit`` may decline a publisher from its connection header."""
        subscription = Subscription(
            self.name, topic, msg_type, on_message, self._on_notice, self.master.node_name, admit
        )
        with self._lock:
            self._subscriptions[topic] = subscription
        subscription.update(self.master.register_subscriber(topic, msg_type.name, self.uri))
        return subscription

    def advertise(self, topic: str, msg_type: MessageType, latched: bool = False) -> Publication:
        """Publish ``topic``; the master tells its subscribers, who then connect."""
        with self._lock:
            if self._tcpros is None:
                self._tcpros = TcpRosServer(self._bind, self.host, self._publications.get)
                self._tcpros.start()
            publication = self._publications[topic] = Publication(self.name, topic, msg_type, latched)
        self.master.register_publisher(topic, msg_type.name, self.uri)
        return publication

    def close(self) -> None:
        """Unregister from the master (if it answers within ``CALL_TIMEOUT`` seconds, all calls
        together) and stop every connection."""
        with self._lock:
            subscriptions, self._subscriptions = list(self._subscriptions.values()), {}
            publications, self._publications = list(self._publications.values()), {}
        deadline = time.monotonic() + CALL_TIMEOUT
        for subscription in subscriptions:
            self._unregister("Subscriber", subscription.topic, deadline)
            subscription.close()
        for publication in publications:
            self._unregister("Publisher", publication.topic, deadline)
            publication.close()
        if self._tcpros is not None:
            self._tcpros.close()
        self._slave.close()

    def _unregister(self, role: Literal["Subscriber", "Publisher"], topic: str, deadline: float) -> None:
        left = deadline - time.monotonic()
        if left > 0:
            with contextlib.suppress(LiveError):
                self.master.unregister(role, topic, self.uri, timeout=left)

    # --- the slave API (http://wiki.ros.org/ROS/Slave_API) -----------------------------------

    def _handlers(self) -> dict[str, Any]:
        return {
            "getBusStats": lambda _caller: [1, "", [[], [], []]],
            "getBusInfo": self._bus_info,
            "getMasterUri": lambda _caller: [1, "", self.master.uri],
            "shutdown": self._shutdown,
            "getPid": lambda _caller: [1, "", os.getpid()],
            "getSubscriptions": lambda _caller: [1, "", [[s.topic, s.type.name] for s in self._subs()]],
            "getPublications": lambda _caller: [1, "", [[p.topic, p.type.name] for p in self._pubs()]],
            "paramUpdate": lambda _caller, _key, _value: [1, "", 0],
            "publisherUpdate": self._publisher_update,
            "requestTopic": self._request_topic,
        }

    def _subs(self) -> list[Subscription]:
        with self._lock:
            return list(self._subscriptions.values())

    def _pubs(self) -> list[Publication]:
        with self._lock:
            return list(self._publications.values())

    def _bus_info(self, _caller: str) -> Reply:
        rows: list[list[Any]] = []
        for sub in self._subs():
            rows += [[len(rows), uri, "i", "TCPROS", sub.topic, True] for uri, _callerid in sub.connections]
        for pub in self._pubs():
            rows += [[len(rows), callerid, "o", "TCPROS", pub.topic, True] for callerid in pub.subscribers]
        return [1, "", rows]

    def _shutdown(self, caller: str, message: str = "") -> Reply:
        self._on_notice(f"shut down by {caller}" + (f": {message}" if message else ""))
        self.shutdown_requested.set()
        return [1, "shutdown", 0]

    def _publisher_update(self, _caller: Any, topic: Any, publishers: Any) -> Reply:
        try:
            uris = uri_list(publishers, "its list of publishers")
        except ReplyError as error:
            self._on_notice(f"ignored a publisherUpdate tfx cannot use: {error}")
            return [-1, f"tfx cannot use this publisherUpdate: {error}", 0]
        with self._lock:
            subscription = self._subscriptions.get(topic) if isinstance(topic, str) else None
        if subscription is not None:
            subscription.update(uris)
        return [1, "", 0]

    def _request_topic(self, _caller: Any, topic: Any, protocols: Any) -> Reply:
        with self._lock:
            known = isinstance(topic, str) and topic in self._publications
        if not known or self._tcpros is None:
            return [0, "not a publisher of this topic", []]
        if not isinstance(protocols, list) or not any(isinstance(p, list) and p[:1] == ["TCPROS"] for p in protocols):
            return [0, "no supported protocol: tfx speaks TCPROS only", []]
        return [1, "ready", ["TCPROS", self._tcpros.host, self._tcpros.port]]
