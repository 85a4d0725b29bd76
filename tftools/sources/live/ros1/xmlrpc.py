"""ROS1's XML-RPC: calls to the master and to other nodes, and this node's slave server.

Every exchange is bounded in time and size (the limits below). XML is parsed by Python's expat with
document type declarations refused, as ``defusedxml`` refuses them: XML-RPC has none, and a DTD is
how entity bombs ("billion laughs") come in.
"""

from __future__ import annotations

import http.client
import io
import socket
import socketserver
import threading
import time
import xmlrpc.client
from collections.abc import Callable
from typing import Any, Literal
from urllib.parse import urlsplit
from xml.parsers import expat
from xmlrpc.server import SimpleXMLRPCRequestHandler, SimpleXMLRPCServer

from tftools.sources.live.errors import MasterRefusedError, MasterReplyError, MasterTimeoutError, MasterUnreachableError
from tftools.sources.live.notices import printable

#: Seconds a whole call to the master or another node may take (connect, send, the whole reply).
CALL_TIMEOUT = 3.0

#: The largest reply accepted: a master's getSystemState of a big system is a few hundred KB.
MAX_REPLY = 8 << 20

#: The largest request this node's server accepts: a publisherUpdate of a hundred URIs is a few KB.
MAX_REQUEST = 1 << 20

#: Seconds a peer has to send this node a whole request.
REQUEST_TIMEOUT = 3.0

#: Requests this node serves at once; more are turned away (the caller retries, as the master does).
MAX_CONCURRENT_REQUESTS = 16


class ReplyError(Exception):
    """An answer that is not XML-RPC, too large, or not what the ROS API says it is."""


class _BoundedReader(io.RawIOBase):
    """A socket's bytes until ``deadline`` (``time.monotonic()``), at most ``limit`` of them:
    ``TimeoutError`` or ``ReplyError`` past either, whatever the pace of the peer."""

    def __init__(self, sock: socket.socket, deadline: float, limit: int) -> None:
        super().__init__()
        self._sock = sock
        self._deadline = deadline
        self._left = limit
        self._limit = limit

    def readable(self) -> bool:
        return True

    def readinto(self, buffer: Any) -> int:
        remaining = self._deadline - time.monotonic()
        if remaining <= 0:
            raise TimeoutError("the answer did not come in time")
        if self._left <= 0:
            raise ReplyError(f"larger than {self._limit} bytes")
        self._sock.settimeout(remaining)
        view = memoryview(buffer).cast("B")[: self._left]
        count = self._sock.recv_into(view)
        self._left -= count
        return count


class _ReplySocket:
    """What ``http.client.HTTPResponse`` reads a reply from: a socket, bounded in time and size."""

    def __init__(self, sock: socket.socket, deadline: float) -> None:
        self._reader = io.BufferedReader(_BoundedReader(sock, deadline, MAX_REPLY + (64 << 10)))

    def makefile(self, _mode: str) -> io.BufferedReader[Any]:
        return self._reader


def loads(data: bytes, limit: int = MAX_REPLY) -> tuple[tuple[Any, ...], str | None]:
    """An XML-RPC document's parameters and method name (None in a reply), as
    ``xmlrpc.client.loads`` gives them; ``xmlrpc.client.Fault`` for a fault; ``ReplyError`` for
    anything not XML-RPC, a document type declaration (entities) or more than ``limit`` bytes."""
    if len(data) > limit:
        raise ReplyError(f"{len(data)} bytes, above tfx's limit of {limit}")
    unmarshaller = xmlrpc.client.Unmarshaller()
    parser = expat.ParserCreate(None, None)
    parser.StartElementHandler = unmarshaller.start
    parser.EndElementHandler = unmarshaller.end
    parser.CharacterDataHandler = unmarshaller.data
    parser.StartDoctypeDeclHandler = _refuse_doctype
    parser.EntityDeclHandler = _refuse_doctype
    parser.buffer_text = True
    try:
        unmarshaller.xml(None, None)  # type: ignore[arg-type]  # as ExpatParser: expat gives str
        parser.Parse(data, True)
        return unmarshaller.close(), unmarshaller.getmethodname()
    except (xmlrpc.client.Fault, ReplyError):
        raise
    except Exception as error:  # expat's, the unmarshaller's (ValueError, TypeError, IndexError...)
        raise ReplyError(f"not XML-RPC ({type(error).__name__}: {error})") from None


def _refuse_doctype(*_args: Any) -> None:
    raise ReplyError("a document type declaration, which XML-RPC never has")


def _exchange(uri: str, body: bytes, timeout: float) -> bytes:
    """POST ``body`` to ``uri``; the reply's body. Everything within ``timeout`` seconds."""
    deadline = time.monotonic() + timeout
    parts = urlsplit(uri)
    host, port = parts.hostname or "localhost", parts.port or 80
    request = (
        f"POST {parts.path or '/'} HTTP/1.1\r\nHost: {host}:{port}\r\nUser-Agent: tfx\r\n"
        f"Content-Type: text/xml\r\nContent-Length: {len(body)}\r\nConnection: close\r\n\r\n"
    ).encode("latin-1")
    with socket.create_connection((host, port), timeout=timeout) as sock:
        sock.settimeout(max(deadline - time.monotonic(), 0.001))
        sock.sendall(request + body)
        response = http.client.HTTPResponse(_ReplySocket(sock, deadline))  # type: ignore[arg-type]
        response.begin()
        if response.status != 200:
            raise ReplyError(f"HTTP {response.status} {printable(response.reason)}")
        if response.length is not None and response.length > MAX_REPLY:
            raise ReplyError(f"a reply of {response.length} bytes, above tfx's limit of {MAX_REPLY}")
        data = response.read(MAX_REPLY + 1)
        if len(data) > MAX_REPLY:
            raise ReplyError(f"larger than tfx's limit of {MAX_REPLY} bytes")
        return data


def call(uri: str, method: str, *args: Any, timeout: float = CALL_TIMEOUT) -> tuple[int, str, Any]:
    """One ROS API call: ``(code, status message, value)``, all within ``timeout`` seconds.

    Raises ``TimeoutError`` when it takes longer, ``OSError`` when ``uri`` cannot be reached,
    ``ReplyError`` when the answer is not a ROS API reply (``[int, str, value]``) or too large."""
    body = xmlrpc.client.dumps(args, method).encode()
    try:
        params, _method = loads(_exchange(uri, body, timeout))
    except xmlrpc.client.Fault as fault:
        raise ReplyError(f"an XML-RPC fault: {printable(str(fault.faultString))}") from None
    except (http.client.HTTPException, ValueError) as error:  # ValueError: a bad chunk size
        raise ReplyError(f"not HTTP ({type(error).__name__}: {error})") from None
    reply = params[0] if len(params) == 1 else None
    if not isinstance(reply, list) or len(reply) != 3:
        raise ReplyError("not a ROS API reply [code, status message, value]")
    code, message, value = reply
    if type(code) is not int or not isinstance(message, str):
        raise ReplyError("not a ROS API reply: its code is not an integer or its status not a string")
    return code, message, value


def uri_list(value: Any, what: str) -> list[str]:
    """``value`` checked to be a list of slave API URIs (``http://host:port/``); ``ReplyError`` if not."""
    if not isinstance(value, list):
        raise ReplyError(f"{what} is a {type(value).__name__}, not a list of URIs")
    for item in value:
        if not isinstance(item, str) or not _is_http_uri(item):
            raise ReplyError(f"{what} holds something that is not an http:// URI")
    return value


def _is_http_uri(text: str) -> bool:
    try:
        parts = urlsplit(text)
        return parts.scheme == "http" and bool(parts.hostname) and parts.port is not None and len(text) < 1024
    except ValueError:  # a port out of range, brackets that do not close
        return False


class MasterClient:
    """The master's API (registration and parameters) for one node."""

    def __init__(self, uri: str, caller_id: str) -> None:
        self.uri = uri
        self.caller_id = caller_id

    def _call(self, method: str, *args: Any, timeout: float = CALL_TIMEOUT) -> Any:
        try:
            code, message, value = call(self.uri, method, self.caller_id, *args, timeout=timeout)
        except TimeoutError:
            raise MasterTimeoutError(self.uri, timeout) from None
        except ReplyError as error:
            raise MasterReplyError(self.uri, method, str(error)) from None
        except OSError as error:
            raise MasterUnreachableError(self.uri, _reason(error)) from None
        if code != 1:
            raise MasterRefusedError(self.uri, method, printable(message))
        return value

    def register_subscriber(self, topic: str, topic_type: str, caller_api: str) -> list[str]:
        """Subscribe; the URIs of the topic's current publishers."""
        value = self._call("registerSubscriber", topic, topic_type, caller_api)
        try:
            return uri_list(value, f"the publishers of {topic}")
        except ReplyError as error:
            raise MasterReplyError(self.uri, "registerSubscriber", str(error)) from None

    def register_publisher(self, topic: str, topic_type: str, caller_api: str) -> None:
        """Advertise (the master tells the topic's subscribers, who then connect)."""
        self._call("registerPublisher", topic, topic_type, caller_api)

    def unregister(self, role: Literal["Subscriber", "Publisher"], topic: str, caller_api: str, timeout: float) -> None:
        """Stop subscribing or publishing ``topic`` (``unregisterSubscriber``, ``unregisterPublisher``)."""
        self._call(f"unregister{role}", topic, caller_api, timeout=timeout)

    def node_name(self, uri: str) -> str:
        """The name of the node whose slave API is at ``uri`` (``uri`` itself if the master cannot
        say within ``CALL_TIMEOUT`` seconds, all lookups together)."""
        deadline = time.monotonic() + CALL_TIMEOUT
        try:
            _code, _message, state = call(self.uri, "getSystemState", self.caller_id)
            publishers, subscribers = state[0], state[1]
            names = sorted({node for _topic, nodes in [*publishers, *subscribers] for node in nodes})
            for name in names[:MAX_NAME_LOOKUPS]:
                left = deadline - time.monotonic()
                if left <= 0:
                    break
                code, _message, node_uri = call(self.uri, "lookupNode", self.caller_id, name, timeout=left)
                if code == 1 and node_uri == uri:
                    return str(name)
        except (OSError, ReplyError, ValueError, TypeError, IndexError, KeyError):  # a failed call, an odd reply
            pass
        return uri

    def published_topics(self) -> list[tuple[str, str]]:
        """Each topic some node publishes now, with its type (``getPublishedTopics``); a reply that
        is not a list of (topic, type) pairs is a ``MasterReplyError``."""
        value = self._call("getPublishedTopics", "")
        if not isinstance(value, list) or not all(
            isinstance(pair, list) and len(pair) == 2 and all(isinstance(name, str) for name in pair) for pair in value
        ):
            raise MasterReplyError(self.uri, "getPublishedTopics", "its answer is not a list of topics and types")
        return [(topic, msg_type) for topic, msg_type in value]

    def get_param(self, key: str) -> Any:
        """The parameter's value, or None where it is not set."""
        try:
            return self._call("getParam", key)
        except MasterRefusedError:
            return None


#: Nodes ``node_name`` asks the master about, at most.
MAX_NAME_LOOKUPS = 64


def _reason(error: BaseException) -> str:
    if isinstance(error, ConnectionRefusedError):
        return "connection refused: no master is running there"
    if isinstance(error, socket.gaierror):
        return f"unknown host: {error.strerror}"
    if isinstance(error, OSError) and error.strerror:
        return error.strerror
    return str(error) or type(error).__name__


class _QuietHandler(SimpleXMLRPCRequestHandler):
    """Serves one request: read within ``REQUEST_TIMEOUT`` seconds and ``MAX_REQUEST`` bytes."""

    def setup(self) -> None:
        super().setup()
        self.rfile.close()  # read through a bounded reader instead
        deadline = time.monotonic() + REQUEST_TIMEOUT
        self.rfile = io.BufferedReader(_BoundedReader(self.connection, deadline, MAX_REQUEST + (64 << 10)))

    def do_POST(self) -> None:  # noqa: N802 - http.server calls it so
        try:
            size = int(self.headers.get("content-length", ""))
        except ValueError:
            size = -1
        if not 0 <= size <= MAX_REQUEST:
            self.send_error(413 if size > MAX_REQUEST else 411)
            return
        super().do_POST()

    def log_message(self, format: str, *args: Any) -> None:
        pass


class SlaveServer(socketserver.ThreadingMixIn, SimpleXMLRPCServer):
    """This node's XML-RPC server: the API the master and other nodes call (``publisherUpdate``,
    ``requestTopic``, ``getPid``...). ``handlers`` maps each method name to its function."""

    daemon_threads = True
    allow_reuse_address = True

    def __init__(self, bind: str, advertised_host: str, handlers: dict[str, Callable[..., Any]]) -> None:
        super().__init__((bind, 0), requestHandler=_QuietHandler, logRequests=False, allow_none=False)
        self._slots = threading.BoundedSemaphore(MAX_CONCURRENT_REQUESTS)
        for name, function in handlers.items():
            self.register_function(function, name)
        self.uri = f"http://{advertised_host}:{self.server_address[1]}/"
        self._thread = threading.Thread(
            target=self.serve_forever, kwargs={"poll_interval": 0.1}, name=f"tfx-xmlrpc {self.uri}", daemon=True
        )

    def start(self) -> None:
        self._thread.start()

    def close(self) -> None:
        if self._thread.is_alive():
            self.shutdown()
        self.server_close()

    def process_request(self, request: Any, client_address: Any) -> None:
        if not self._slots.acquire(blocking=False):  # too many at once: turned away, no thread
            self.shutdown_request(request)
            return
        try:
            super().process_request(request, client_address)
        except BaseException:
            self._slots.release()
            raise

    def process_request_thread(self, request: Any, client_address: Any) -> None:
        try:
            super().process_request_thread(request, client_address)
        finally:
            self._slots.release()

    def handle_error(self, request: Any, client_address: Any) -> None:
        """A caller that hangs up, stalls or sends garbage is its own problem: no traceback on stderr."""

    def _marshaled_dispatch(self, data: Any, dispatch_method: Any = None, path: Any = None) -> Any:
        """The reply to one request (bytes, as http.server sends them), the request parsed as ``loads`` does."""
        try:
            params, method = loads(bytes(data), MAX_REQUEST)
            response = xmlrpc.client.dumps((self._dispatch(method or "", params),), methodresponse=True)
        except xmlrpc.client.Fault as fault:
            response = xmlrpc.client.dumps(fault)
        except Exception as error:  # a handler's refusal or a malformed request, as a fault
            response = xmlrpc.client.dumps(xmlrpc.client.Fault(1, f"{type(error).__name__}: {error}"))
        return response.encode("utf-8", "xmlcharrefreplace")
