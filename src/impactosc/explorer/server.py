"""The Bokeh server of the explorer, on a local port, for the holder of its token.

Why Bokeh's server: the page's callbacks run in Python next to the core (no JavaScript to
build, one dependency), and its documents stream new data to the browser as it arrives. The
worker pool is started and warmed before the first page is served, and shared by every page.

Why a token (as Jupyter's): the port is open to every user of the machine, and every page
served starts a diagram on the shared workers and may read records. The address printed carries
``?token=...``; the page, its script (``/autoload.js``) and its websocket are refused (403)
without it, before any document is made. The websocket cannot carry the page's address: it
carries the session token Bokeh signed when it served the page (its payload holds the page's
arguments), which is checked for our signature and our token. A websocket must also come from
a page of this server (its Origin header), and no response allows other origins to read it.
"""

from __future__ import annotations

import hmac
import secrets
import signal
import socket
import sys
import zlib

from impactosc.explorer.scheduler import Scheduler, WorkerPool
from impactosc.explorer.view import RecordAccess, View

__all__ = ["serve", "free_port", "make_server", "new_token", "page_url", "TOKEN_ARGUMENT"]

#: The query argument of the page's address that carries the token
TOKEN_ARGUMENT = "token"
#: Headers Bokeh sets on /autoload.js to let any origin read it
_CROSS_ORIGIN = ("Access-Control-Allow-Origin", "Access-Control-Allow-Headers", "Access-Control-Allow-Credentials")


def free_port() -> int:
    """A port nothing listens on now (the OS picks it)."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def new_token() -> str:
    """A random token for the page's address (as Jupyter's)."""
    return secrets.token_urlsafe(32)


def _same(given, token: str) -> bool:
    if isinstance(given, bytes):
        given = given.decode("utf-8", "replace")
    return isinstance(given, str) and hmac.compare_digest(given.encode(), token.encode())


def _auth(token: str | None):
    """Bokeh's auth hooks, checked in every handler's ``prepare`` (before a session exists): a
    refused request ends there with 403 (Tornado runs no handler after a finished ``prepare``)."""
    from bokeh.server.auth_provider import AuthProvider
    from bokeh.util.token import check_token_signature, get_token_payload
    from tornado.websocket import WebSocketHandler

    def websocket_allowed(handler) -> bool:
        if "Origin" not in handler.request.headers:
            return False  # a browser always sends it; Bokeh's origin check runs only when it is there
        if token is None:
            return True
        protocols = [p.strip() for p in handler.request.headers.get("Sec-WebSocket-Protocol", "").split(",")]
        if len(protocols) != 2 or protocols[0] != "bokeh":
            return False
        app, session_token = handler.application, protocols[1]
        try:
            if not check_token_signature(session_token, secret_key=app.secret_key, signed=app.sign_sessions):
                return False
            arguments = get_token_payload(session_token).get("arguments", {})
        except (ValueError, TypeError, KeyError, zlib.error):  # not a token at all (bad base64, JSON, zlib)
            return False
        return any(_same(v, token) for v in arguments.get(TOKEN_ARGUMENT, []))

    async def check(handler):
        for name in _CROSS_ORIGIN:
            handler.clear_header(name)
        if isinstance(handler, WebSocketHandler):
            allowed = websocket_allowed(handler)
        else:
            allowed = token is None or _same(handler.get_argument(TOKEN_ARGUMENT, ""), token)
        if allowed:
            return "holder of the token"
        # answered here, not by raising: Tornado's error page would set Bokeh's cross-origin headers again
        handler.set_status(403, "missing or wrong token")
        handler.finish("403: missing or wrong token\n")
        return None

    class TokenAuth(AuthProvider):
        get_user_async = staticmethod(check)  # type: ignore[assignment]

        @property
        def get_login_url(self):
            return lambda _handler: "/"  # never used: a refused request is a 403, not a redirect

    return TokenAuth()


def make_server(
    view: View,
    *,
    port: int = 5006,
    workers: int = 2,
    record: dict | None = None,
    snippet_path="explore_view.yaml",
    token: str | None = None,
    access: RecordAccess | None = None,
):
    """(server, pool): a Bokeh server whose page at / is the explorer, bound (port 0: a free one,
    ``server.port`` says which) but not yet started, and its warmed worker pool (shut down by the
    caller). `token` None serves anyone who can reach the port."""
    from bokeh.application import Application
    from bokeh.application.handlers.function import FunctionHandler
    from bokeh.server.server import Server
    from bokeh.util.token import generate_secret_key

    from impactosc.explorer.app import Explorer

    pool = WorkerPool(workers)
    Scheduler(workers, pool=pool).warm()
    access = access or RecordAccess()

    def page(doc):
        Explorer(doc, view, pool, record=record, snippet_path=snippet_path, access=access)

    server = Server(
        {"/": Application(FunctionHandler(page))},
        port=port,
        address="127.0.0.1",
        # port 0: Bokeh's default, localhost:<the port bound> (the address printed)
        allow_websocket_origin=[f"localhost:{port}", f"127.0.0.1:{port}"] if port else None,
        auth_provider=_auth(token),
        secret_key=generate_secret_key(),
        sign_sessions=True,
    )
    return server, pool


def page_url(port: int, token: str | None) -> str:
    """The page's address, with its token."""
    return f"http://localhost:{port}/" + (f"?{TOKEN_ARGUMENT}={token}" if token else "")


def serve(
    view: View,
    *,
    port: int = 5006,
    workers: int = 2,
    record=None,
    browser=True,
    snippet_path="explore_view.yaml",
    token: str | None = None,
    access: RecordAccess | None = None,
) -> None:
    """Serve the explorer until interrupted (Ctrl-C or SIGTERM); prints the address with its
    token (and opens it unless `browser` is false). The worker processes end with the server:
    they are not daemons and would outlive a parent that did not shut the pool down."""
    server, pool = make_server(
        view, port=port, workers=workers, record=record, snippet_path=snippet_path, token=token, access=access
    )
    loop = server.io_loop
    previous = signal.signal(signal.SIGTERM, lambda *_: loop.add_callback_from_signal(loop.stop))
    try:
        server.start()
        url = page_url(server.port, token)
        print(f"impactosc explore: serving {url} (Ctrl-C stops it)", flush=True)
        if browser:
            import webbrowser

            loop.add_callback(webbrowser.open_new_tab, url)
        loop.start()
    finally:
        signal.signal(signal.SIGTERM, previous)
        server.stop()
        pool.shutdown(wait=True, cancel_futures=True)
        sys.stdout.flush()
