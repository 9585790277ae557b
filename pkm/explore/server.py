"""The explorer's local server: the standard library's ThreadingHTTPServer on 127.0.0.1 only, serving the
page, plotly.js from the installed plotly package and the JSON API (:mod:`pkm.explore.api`).

Routes: ``GET /`` the page, ``GET /explore.js``, ``/explore.css`` and ``/plotly.min.js`` its assets,
``GET /api/<endpoint>?field=value&...`` an endpoint's JSON (400 with ``{"error", "field"}`` for a bad
request, 500 with a one-line ``{"error"}`` for anything else), ``POST /api/stop`` (with a JSON content
type, which a page of another origin cannot send without the server's consent) stops the server, and ``POST
/api/cancel`` cancels the computation in flight (answered 409; the server goes on serving). Stopping (the
stop request or :meth:`Server.shutdown`) closes the explorer (:meth:`pkm.explore.api.Explorer.close`): the
computation in flight is cancelled at its next step and answered 503, as is every request after it on a
connection kept open; the server waits up to :data:`CANCEL_WAIT` seconds for the computation to end. A request
whose Host header is not this server's loopback address is refused (403): a page of another site cannot reach
the API through a name that resolves to 127.0.0.1. A POST states its body's length: without a Content-Length
header it is refused with 411, with one that is not a count of bytes with 400, with a body beyond
:data:`MAX_BODY` bytes with 413 (each a JSON ``{"error", "field"}``, the connection then closed, since where the
body ends is unknown). A POST whose body ends before its stated length (the client left) is not acted upon.

A client that leaves before its answer is written is no error of the server's: nothing is printed for it. Any
other failure outside an endpoint is one line on standard error, never a traceback. The listen queue holds
:data:`LISTEN_QUEUE` connections (socketserver's default of 5 left the rest of a burst of connections to the
client's retries or a reset), and a connection that sends nothing for :data:`IDLE_TIMEOUT` seconds is closed, so
that half-sent requests hold no thread for ever.
"""

from __future__ import annotations

import reprlib
import sys
import threading
from functools import cache
from http import HTTPStatus
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from importlib import resources
from typing import Any
from urllib.parse import parse_qsl, urlsplit

from pkm import io
from pkm.errors import PkmError, check_integer
from pkm.explore.api import FIELDS, CancelledError, Explorer, RequestError

HOST = "127.0.0.1"
ASSETS = {"/explore.js": "text/javascript", "/explore.css": "text/css", "/": "text/html"}
MAX_QUERY = 65536
MAX_BODY = 65536  # bytes of a POST's body (the stop request sends "{}")
LISTEN_QUEUE = 128  # connections waiting to be accepted
IDLE_TIMEOUT = 60.0  # seconds a connection may send nothing
CANCEL_WAIT = 10.0  # seconds a stop waits for the computation in flight to reach its next step


def require_plotly() -> None:
    """PkmError with the command that installs plotly, where it is missing."""
    try:
        import plotly  # noqa: F401
    except ImportError:
        raise PkmError("pkm explore needs plotly: pip install 'pkm[explore]'") from None


@cache
def plotly_js() -> bytes:
    """plotly.js as the installed plotly package carries it."""
    require_plotly()
    return (resources.files("plotly") / "package_data" / "plotly.min.js").read_bytes()


def asset(name: str) -> bytes:
    """A file of the page (``index.html``, ``explore.js``, ``explore.css``), package data of pkm.explore."""
    return (resources.files("pkm.explore") / "page" / name).read_bytes()


class _Handler(BaseHTTPRequestHandler):
    server: _HTTPServer
    protocol_version = "HTTP/1.1"
    disable_nagle_algorithm = True  # the body follows the headers at once, not after the client's delayed ACK
    timeout = IDLE_TIMEOUT

    def log_message(self, format: str, *args: Any) -> None:
        if self.server.verbose:
            super().log_message(format, *args)

    def _send(self, status: int, body: bytes, content_type: str) -> None:
        self.send_response(status)
        self.send_header("Content-Type", content_type)
        self.send_header("Content-Length", str(len(body)))
        self.send_header("Cache-Control", "no-store")
        if self.close_connection:
            self.send_header("Connection", "close")
        self.end_headers()
        self.wfile.write(body)

    def _json(self, status: int, data: Any) -> None:
        self._send(status, io.to_json(data).encode(), "application/json")

    def _local(self) -> bool:
        port = self.server.server_address[1]
        if self.headers.get("Host") not in (f"{HOST}:{port}", f"localhost:{port}"):
            self._json(HTTPStatus.FORBIDDEN, {"error": "requests name this server by its loopback address",
                                              "field": "Host"})
            return False
        return True

    def _stopped(self) -> bool:
        """Whether the server has stopped, after answering so (503, the connection then closed)."""
        if not self.server.explorer.closed:
            return False
        self.close_connection = True
        self._json(HTTPStatus.SERVICE_UNAVAILABLE, {"error": "the server has stopped", "field": None})
        return True

    def do_GET(self) -> None:
        if not self._local() or self._stopped():
            return
        parts = urlsplit(self.path)
        if parts.path.startswith("/api/"):
            self._api(parts.path[len("/api/"):], parts.query)
        elif parts.path == "/favicon.ico":
            self._send(HTTPStatus.NO_CONTENT, b"", "image/x-icon")
        elif parts.path == "/plotly.min.js":
            self._send(HTTPStatus.OK, plotly_js(), "text/javascript")
        elif parts.path in ASSETS:
            name = "index.html" if parts.path == "/" else parts.path[1:]
            self._send(HTTPStatus.OK, asset(name), f"{ASSETS[parts.path]}; charset=utf-8")
        else:
            self._json(HTTPStatus.NOT_FOUND, {"error": f"no such path {reprlib.repr(parts.path)}", "field": "path"})

    def _body_length(self) -> int | None:
        """The length of the request's body from its Content-Length header, at most MAX_BODY; None after
        answering a request that states none (411), states it twice differently or not as a count of bytes
        (400), or states more than MAX_BODY (413), the connection then to be closed."""
        given = self.headers.get_all("Content-Length") or []
        text = given[0].strip() if given else ""
        digits = text.lstrip("0") or "0"  # int() refuses more than 4300 digits, leading zeros included
        if not given:
            status, condition = HTTPStatus.LENGTH_REQUIRED, "a Content-Length header (the body's length in bytes)"
        elif len({t.strip() for t in given}) > 1:
            status, condition = HTTPStatus.BAD_REQUEST, "one Content-Length"
        elif not (text.isascii() and text.isdigit()):
            status, condition = HTTPStatus.BAD_REQUEST, "a count of bytes (digits 0-9)"
        elif len(digits) > len(str(MAX_BODY)) or int(digits) > MAX_BODY:
            status, condition = HTTPStatus.REQUEST_ENTITY_TOO_LARGE, f"at most {MAX_BODY} bytes"
        else:
            return int(digits)
        self.close_connection = True
        shown = "none" if not given else reprlib.repr(text if len(given) == 1 else given)
        self._json(status, {"error": f"Content-Length = {shown} violates: {condition}", "field": "Content-Length"})
        return None

    def do_POST(self) -> None:
        length = self._body_length()
        if length is None:
            return
        if len(self.rfile.read(length)) < length:  # the client left before its body: nothing to act on
            self.close_connection = True
            return
        if not self._local() or self._stopped():
            return
        path = urlsplit(self.path).path
        if path not in ("/api/stop", "/api/cancel"):
            self._json(HTTPStatus.NOT_FOUND, {"error": f"no such path {reprlib.repr(self.path)}", "field": "path"})
        elif not (self.headers.get("Content-Type") or "").startswith("application/json"):
            self._json(HTTPStatus.BAD_REQUEST, {"error": f"{path.removeprefix('/api/')} violates: a JSON request "
                                                         "(Content-Type application/json)", "field": "Content-Type"})
        elif path == "/api/cancel":
            self.server.explorer.cancel()
            self._json(HTTPStatus.OK, {"cancelled": True})
        else:
            self._json(HTTPStatus.OK, {"stopped": True})
            threading.Thread(target=self.server.stop, daemon=True).start()

    def _api(self, endpoint: str, query: str) -> None:
        """Answer an endpoint: its answer or the error it raised is computed first and written after, so that a
        client that leaves while it is written is the server's handle_error's (silent), not an endpoint's
        failure."""
        try:
            status, payload = HTTPStatus.OK, self._answer(endpoint, query)
        except RequestError as exc:
            status, payload = HTTPStatus.BAD_REQUEST, exc.to_dict()
        except CancelledError as exc:
            stopped = self.server.explorer.closed
            self.close_connection = stopped
            status = HTTPStatus.SERVICE_UNAVAILABLE if stopped else HTTPStatus.CONFLICT
            payload = {"error": str(exc), "field": None}
        except _UnknownEndpointError:
            status, payload = HTTPStatus.NOT_FOUND, {"error": f"unknown endpoint {reprlib.repr(endpoint)}",
                                                     "field": "endpoint"}
        except PkmError as exc:
            status, payload = HTTPStatus.BAD_REQUEST, {"error": str(exc), "field": None}
        except Exception as exc:
            message = " ".join(f"{type(exc).__name__}: {exc}".split())
            print(f"pkm explore: {endpoint} failed: {message}", file=sys.stderr)
            status, payload = HTTPStatus.INTERNAL_SERVER_ERROR, {"error": message}
        self._json(status, payload)

    def _answer(self, endpoint: str, query: str) -> Any:
        if len(query) > MAX_QUERY:
            raise RequestError("query", f"a query of {len(query)} characters violates: at most {MAX_QUERY}")
        pairs = parse_qsl(query, keep_blank_values=True)
        names = [name for name, _ in pairs]
        repeated = sorted({name for name in names if names.count(name) > 1})
        if repeated:
            raise RequestError(repeated[0], f"field {reprlib.repr(repeated[0])} violates: given once")
        if endpoint not in FIELDS:
            raise _UnknownEndpointError
        return self.server.explorer.handle(endpoint, dict(pairs))


class _UnknownEndpointError(Exception):
    """An endpoint the server does not have."""


class _HTTPServer(ThreadingHTTPServer):
    daemon_threads = True
    request_queue_size = LISTEN_QUEUE

    def __init__(self, explorer: Explorer, port: int, verbose: bool) -> None:
        self.explorer = explorer
        self.verbose = verbose
        super().__init__((HOST, port), _Handler)

    def stop(self) -> None:
        """Close the explorer (the computation in flight cancelled, waited for up to CANCEL_WAIT seconds), then end
        :meth:`serve_forever`."""
        self.explorer.close(timeout=CANCEL_WAIT)
        self.shutdown()

    def handle_error(self, _request: Any, client_address: tuple[str, int]) -> None:
        """A client that left (a reset or closed connection) or fell silent: nothing to report. Anything else
        raised outside an endpoint (which answers its own failures): one line, not socketserver's traceback."""
        exc = sys.exc_info()[1]
        if isinstance(exc, ConnectionError | TimeoutError):
            return
        message = " ".join(f"{type(exc).__name__}: {exc}".split())
        print(f"pkm explore: a request from {client_address[0]} failed: {message}", file=sys.stderr)


class Server:
    """A running explorer: ``url``, :meth:`serve_forever` (in this thread, until :meth:`shutdown` or a stop
    request), :meth:`start` (in a thread of its own) and :meth:`shutdown`, which also closes the socket. Either
    way of stopping closes the explorer: its computation in flight is cancelled."""

    def __init__(self, explorer: Explorer, *, port: int = 0, verbose: bool = False) -> None:
        require_plotly()
        port = check_integer("port", port, 0, 65535)
        try:
            self._httpd = _HTTPServer(explorer, port, verbose)
        except OSError as exc:
            raise PkmError(f"port = {port} violates: a free port of {HOST} ({exc.strerror or exc})") from None
        self.explorer = explorer
        self._thread: threading.Thread | None = None

    @property
    def port(self) -> int:
        return self._httpd.server_address[1]

    @property
    def url(self) -> str:
        return f"http://{HOST}:{self.port}/"

    def serve_forever(self) -> None:
        try:
            self._httpd.serve_forever(poll_interval=0.2)
        finally:
            self._httpd.server_close()

    def start(self) -> Server:
        self._thread = threading.Thread(target=self.serve_forever, name="pkm-explore", daemon=True)
        self._thread.start()
        return self

    def shutdown(self) -> None:
        """Cancel the computation in flight, stop serving and close the socket (waits for the serving thread where
        :meth:`start` began one)."""
        self._httpd.stop()
        if self._thread is not None:
            self._thread.join()
        self._httpd.server_close()
