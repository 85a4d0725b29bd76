"""ROS1's XML-RPC: calls to the master and to other nodes, and this node's slave server."""

from __future__ import annotations

import http.client
import socket
import socketserver
import threading
import xmlrpc.client
from collections.abc import Callable
from typing import Any
from xmlrpc.server import SimpleXMLRPCRequestHandler, SimpleXMLRPCServer

from tftools.sources.live.errors import MasterRefusedError, MasterUnreachableError

#: Seconds a call to the master or another node may take before it counts as unreachable.
CALL_TIMEOUT = 3.0


class _TimeoutTransport(xmlrpc.client.Transport):
    def __init__(self, timeout: float) -> None:
        super().__init__()
        self._timeout = timeout

    def make_connection(self, host: Any) -> http.client.HTTPConnection:
        connection = super().make_connection(host)
        connection.timeout = self._timeout
        return connection


def proxy(uri: str, timeout: float = CALL_TIMEOUT) -> xmlrpc.client.ServerProxy:
    """An XML-RPC proxy to ``uri`` whose calls give up after ``timeout`` seconds."""
    return xmlrpc.client.ServerProxy(uri, transport=_TimeoutTransport(timeout))


def call(uri: str, method: str, *args: Any, timeout: float = CALL_TIMEOUT) -> tuple[int, str, Any]:
    """One ROS API call: ``(code, status message, value)``; raises ``OSError`` (and
    ``xmlrpc.client.Error``) when ``uri`` cannot be reached or answers nonsense."""
    code, message, value = getattr(proxy(uri, timeout), method)(*args)
    return int(code), str(message), value


class MasterClient:
    """The master's API (registration and parameters) for one node."""

    def __init__(self, uri: str, caller_id: str) -> None:
        self.uri = uri
        self.caller_id = caller_id

    def _call(self, method: str, *args: Any) -> Any:
        try:
            code, message, value = call(self.uri, method, self.caller_id, *args)
        except (OSError, xmlrpc.client.Error, http.client.HTTPException) as error:
            raise MasterUnreachableError(self.uri, _reason(error)) from None
        if code != 1:
            raise MasterRefusedError(self.uri, method, message)
        return value

    def register_subscriber(self, topic: str, topic_type: str, caller_api: str) -> list[str]:
        """Subscribe; the URIs of the topic's current publishers."""
        return list(self._call("registerSubscriber", topic, topic_type, caller_api))

    def unregister_subscriber(self, topic: str, caller_api: str) -> None:
        self._call("unregisterSubscriber", topic, caller_api)

    def register_publisher(self, topic: str, topic_type: str, caller_api: str) -> list[str]:
        """Advertise; the URIs of the topic's current subscribers."""
        return list(self._call("registerPublisher", topic, topic_type, caller_api))

    def unregister_publisher(self, topic: str, caller_api: str) -> None:
        self._call("unregisterPublisher", topic, caller_api)

    def node_name(self, uri: str) -> str:
        """The name of the node whose slave API is at ``uri`` (``uri`` itself if the master cannot say)."""
        try:
            _code, _message, (publishers, subscribers, _services) = call(self.uri, "getSystemState", self.caller_id)
            for name in sorted({node for _topic, nodes in publishers + subscribers for node in nodes}):
                code, _message, node_uri = call(self.uri, "lookupNode", self.caller_id, name)
                if code == 1 and node_uri == uri:
                    return str(name)
        except (OSError, xmlrpc.client.Error, http.client.HTTPException, ValueError, TypeError):
            pass
        return uri

    def get_param(self, key: str) -> Any:
        """The parameter's value, or None where it is not set."""
        try:
            code, _message, value = call(self.uri, "getParam", self.caller_id, key)
        except (OSError, xmlrpc.client.Error, http.client.HTTPException) as error:
            raise MasterUnreachableError(self.uri, _reason(error)) from None
        return value if code == 1 else None


def _reason(error: BaseException) -> str:
    if isinstance(error, ConnectionRefusedError):
        return "connection refused: no master is running there"
    if isinstance(error, socket.timeout | TimeoutError):
        return f"no answer within {CALL_TIMEOUT:g} s"
    if isinstance(error, socket.gaierror):
        return f"unknown host: {error.strerror}"
    if isinstance(error, OSError) and error.strerror:
        return error.strerror
    return str(error) or type(error).__name__


class _QuietHandler(SimpleXMLRPCRequestHandler):
    def log_message(self, format: str, *args: Any) -> None:
        pass


class _ThreadingServer(socketserver.ThreadingMixIn, SimpleXMLRPCServer):
    daemon_threads = True
    allow_reuse_address = True


class SlaveServer:
    """This node's XML-RPC server: the API the master and other nodes call (``publisherUpdate``,
    ``requestTopic``, ``getPid``...). ``handlers`` maps each method name to its function."""

    def __init__(self, bind: str, advertised_host: str, handlers: dict[str, Callable[..., Any]]) -> None:
        self._server = _ThreadingServer((bind, 0), requestHandler=_QuietHandler, logRequests=False, allow_none=False)
        for name, function in handlers.items():
            self._server.register_function(function, name)
        self.uri = f"http://{advertised_host}:{self._server.server_address[1]}/"
        self._thread = threading.Thread(target=self._server.serve_forever, kwargs={"poll_interval": 0.1}, daemon=True)

    def start(self) -> None:
        self._thread.name = f"tfx-xmlrpc {self.uri}"
        self._thread.start()

    def close(self) -> None:
        if self._thread.is_alive():
            self._server.shutdown()
        self._server.server_close()
