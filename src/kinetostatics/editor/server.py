"""The editor's HTTP server: 127.0.0.1 only, a random token in every path.

``http://127.0.0.1:PORT/TOKEN/`` serves the page (``page/``) and, below it, the API the
page calls (JSON): ``api/file`` (the text and its mtime), ``api/stat`` (the mtime alone,
polled by the page to notice an edit made in another editor), ``api/schema`` (the JSON
Schema of ``kinetostatics schema``), ``api/texts`` (the page's words in en and zh), POST
``api/analyse`` (``{"text", "generation", "lang"}`` → the problems or the analysis's
document, :mod:`.session`), POST ``api/save`` (``{"text"}``) and
``api/download/NAME`` (results.csv, summary.json, report.pdf).  A request whose path does
not start with the token, or whose ``Host`` is not this address, is refused with 403.
"""

from __future__ import annotations

import hmac
import json
import secrets
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from importlib import resources
from pathlib import Path
from urllib.parse import parse_qs, urlsplit

from ..base.files import json_text
from ..errors import KinetostaticsError
from ..io.schema import schema_text
from .session import DOWNLOADS, Session
from .texts import page_texts

__all__ = ["EditorServer", "make_server", "HOST"]

HOST = "127.0.0.1"
PAGE_FILES = {
    "": "text/html; charset=utf-8",
    "style.css": "text/css; charset=utf-8",
    "text.js": "text/javascript; charset=utf-8",
    "draw.js": "text/javascript; charset=utf-8",
    "curves.js": "text/javascript; charset=utf-8",
    "app.js": "text/javascript; charset=utf-8",
}
MAX_BODY = 16 * 2**20  # a request body larger than this (16 MiB) is refused


def _page(name: str) -> bytes:
    return resources.files(__package__).joinpath("page", name or "index.html").read_bytes()


class EditorServer(ThreadingHTTPServer):
    """A threading server on 127.0.0.1 that holds the session and the token."""

    daemon_threads = True
    allow_reuse_address = False

    def __init__(self, session: Session, port: int = 0, token: str | None = None):
        self.session = session
        self.token = token or secrets.token_urlsafe(24)
        super().__init__((HOST, port), _Handler)

    @property
    def port(self) -> int:
        return int(self.server_address[1])

    @property
    def url(self) -> str:
        return f"http://{HOST}:{self.port}/{self.token}/"


def make_server(path: str | Path, port: int = 0) -> EditorServer:
    """The server of the file ``path`` on 127.0.0.1:``port`` (0: a free port)."""
    return EditorServer(Session(Path(path)), port)


class _Handler(BaseHTTPRequestHandler):
    server: EditorServer
    protocol_version = "HTTP/1.1"

    def log_message(self, format, *args):  # noqa: A002  the base class's name
        pass  # no line per request on the terminal

    # -- replies -------------------------------------------------------------------
    def _send(self, code: int, body: bytes, kind: str, extra: dict | None = None) -> None:
        self.send_response(code)
        self.send_header("Content-Type", kind)
        self.send_header("Content-Length", str(len(body)))
        self.send_header("Cache-Control", "no-store")
        self.send_header("X-Content-Type-Options", "nosniff")
        for k, v in (extra or {}).items():
            self.send_header(k, v)
        self.end_headers()
        if self.command != "HEAD":
            self.wfile.write(body)

    def _json(self, data, code: int = 200) -> None:
        body = data if isinstance(data, str) else json_text(data, indent=None)
        self._send(code, body.encode("utf-8"), "application/json; charset=utf-8")

    def _refuse(self) -> None:
        self._send(403, b"forbidden\n", "text/plain; charset=utf-8")

    # -- routing -------------------------------------------------------------------
    def _route(self) -> tuple[str, dict] | None:
        """The path below the token and the query, or None (refused: wrong token or
        host)."""
        host = (self.headers.get("Host") or "").split(":")[0]
        if host not in (HOST, "localhost"):
            return None
        url = urlsplit(self.path)
        head, _, rest = url.path.lstrip("/").partition("/")
        if not hmac.compare_digest(head.encode(), self.server.token.encode()):
            return None
        return rest, {k: v[-1] for k, v in parse_qs(url.query).items()}

    def do_GET(self) -> None:  # noqa: N802  http.server's name
        route = self._route()
        if route is None:
            return self._refuse()
        rest, query = route
        session = self.server.session
        if rest in PAGE_FILES:
            return self._send(200, _page(rest), PAGE_FILES[rest])
        if rest == "api/file":
            return self._json(session.read())
        if rest == "api/stat":
            return self._json({"mtime": session.mtime()})
        if rest == "api/schema":
            return self._send(200, schema_text().encode(), "application/json; charset=utf-8")
        if rest == "api/texts":
            return self._json(page_texts())
        if rest.startswith("api/download/") and rest.split("/")[-1] in DOWNLOADS:
            return self._download(rest.split("/")[-1], query.get("lang", "en"))
        self._send(404, b"not found\n", "text/plain; charset=utf-8")

    def do_POST(self) -> None:  # noqa: N802  http.server's name
        route = self._route()
        if route is None:
            return self._refuse()
        rest, _ = route
        size = int(self.headers.get("Content-Length") or 0)
        if size > MAX_BODY:
            return self._json({"error": "the text is too large"}, 413)
        try:
            body = json.loads(self.rfile.read(size) or b"{}")
            text = str(body["text"])
        except (ValueError, KeyError, TypeError):
            return self._json({"error": 'the request is not {"text": ...}'}, 400)
        session = self.server.session
        if rest == "api/analyse":
            lang = body.get("lang") if body.get("lang") in ("en", "zh") else "en"
            return self._json(session.answer(text, int(body.get("generation", 0)), lang))
        if rest == "api/save":
            try:
                return self._json(session.save(text))
            except KinetostaticsError as exc:
                return self._json({"error": str(exc)}, 500)
        self._send(404, b"not found\n", "text/plain; charset=utf-8")

    def _download(self, name: str, lang: str) -> None:
        try:
            body = self.server.session.download(name, lang if lang in ("en", "zh") else "en")
        except KinetostaticsError as exc:
            return self._json({"error": str(exc)}, 409)
        self._send(
            200,
            body,
            DOWNLOADS[name],
            {"Content-Disposition": f'attachment; filename="{name}"'},
        )
