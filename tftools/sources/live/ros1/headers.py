"""Sensor headers from a ROS 1 system: a node of tfx's own subscribes each sensor topic with type
``*`` and md5sum ``*``, as rostopic does, and keeps a publisher's messages when the definition its
connection header carries starts with a ``Header``."""

from __future__ import annotations

import threading
from collections.abc import Mapping

from tftools.sources.codecs.decoded import message_header
from tftools.sources.codecs.select import header_decoder
from tftools.sources.codecs.types import MessageType, definition_starts_with_header, rosidl_name
from tftools.sources.live.errors import LiveError
from tftools.sources.live.header_store import HeaderStore
from tftools.sources.live.ros1 import network
from tftools.sources.live.ros1.node import Node

#: Any message type: a publisher answers with its own type, md5sum and definition.
ANY_TYPE = MessageType("*", "*", "")

#: Seconds between asks to the master for topics advertised since (listening to all of them).
DISCOVER_EVERY = 1.0


class Ros1HeaderListener:
    """The headers of ``store``'s topics from the ROS 1 master at ``master_uri``: those it names, or
    every topic advertised (now and while listening) whose messages start with a header."""

    def __init__(self, master_uri: str, store: HeaderStore) -> None:
        self._store = store
        self._node = Node(network.anonymous_name("tfx_filter"), master_uri, store.notice)
        self._subscribed: set[str] = set()
        self._stopped = threading.Event()
        self._closing = threading.Lock()  # no subscription begins once closing began
        self._discovery: threading.Thread | None = None

    def start(self) -> None:
        """Subscribe the topics named (raises ``LiveError`` if the master is not there), or those
        advertised, then follow new ones in the background."""
        if self._store.topics is not None:
            for topic in self._store.topics:
                self._subscribe(topic)
            return
        self._discover()
        self._discovery = threading.Thread(target=self._keep_discovering, name="tfx-sensor-topics", daemon=True)
        self._discovery.start()

    def close(self) -> None:
        with self._closing:
            self._stopped.set()
        if self._discovery is not None:
            self._discovery.join(timeout=DISCOVER_EVERY)
        self._node.close()

    def _keep_discovering(self) -> None:
        while not self._stopped.wait(DISCOVER_EVERY):
            try:
                self._discover()
            except LiveError as error:
                self._store.notice(f"cannot ask the master for new sensor topics: {error}")

    def _discover(self) -> None:
        for topic, _type in self._node.master.published_topics():
            if topic in self._subscribed or not self._store.wants(topic):
                continue
            if self._store.full(len(self._subscribed)):
                return
            self._subscribe(topic)

    def _subscribe(self, topic: str) -> None:
        self._subscribed.add(topic)
        store = self._store
        msgtype = ""

        def admit(header: Mapping[str, str]) -> bool:
            nonlocal msgtype
            msgtype = rosidl_name(header.get("type", ""))  # as bags name it when read
            if definition_starts_with_header(msgtype, header.get("message_definition", "")):
                return True
            store.without_header(topic, msgtype)
            return False

        def receive(data: bytes, _callerid: str) -> None:
            store.heard(topic, msgtype, *message_header(header_decoder(msgtype, "ros1"), data))

        with self._closing:
            if not self._stopped.is_set():
                self._node.subscribe(topic, ANY_TYPE, receive, admit)
