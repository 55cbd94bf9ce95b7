"""The Bokeh server of the explorer, on a local port.

Why Bokeh's server: the page's callbacks run in Python next to the core (no JavaScript to
build, one dependency), and its documents stream new data to the browser as it arrives. The
worker pool is started and warmed before the first page is served, and shared by every page.
"""

from __future__ import annotations

import contextlib
import signal
import socket
import sys

from impactosc.explorer.scheduler import Scheduler, make_pool
from impactosc.explorer.view import View

__all__ = ["serve", "free_port", "make_server"]


def free_port() -> int:
    """A port nothing listens on now (the OS picks it)."""
    with contextlib.closing(socket.socket(socket.AF_INET, socket.SOCK_STREAM)) as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def make_server(
    view: View, *, port: int = 5006, workers: int = 2, record: dict | None = None, snippet_path="explore_view.yaml"
):
    """(server, pool): a Bokeh server whose page at / is the explorer, not yet started, and its
    warmed worker pool (shut down by the caller)."""
    from bokeh.application import Application
    from bokeh.application.handlers.function import FunctionHandler
    from bokeh.server.server import Server

    from impactosc.explorer.app import Explorer

    pool = make_pool(workers)
    Scheduler(workers, pool=pool).warm()

    def page(doc):
        Explorer(doc, view, pool, record=record, snippet_path=snippet_path)

    server = Server(
        {"/": Application(FunctionHandler(page))},
        port=port,
        address="127.0.0.1",
        allow_websocket_origin=[f"localhost:{port}", f"127.0.0.1:{port}"],
    )
    return server, pool


def serve(
    view: View, *, port: int = 5006, workers: int = 2, record=None, browser=True, snippet_path="explore_view.yaml"
) -> None:
    """Serve the explorer until interrupted (Ctrl-C or SIGTERM); prints the address (and opens
    it unless `browser` is false). The worker processes end with the server: they are not
    daemons and would outlive a parent that did not shut the pool down."""
    server, pool = make_server(view, port=port, workers=workers, record=record, snippet_path=snippet_path)
    loop = server.io_loop
    previous = signal.signal(signal.SIGTERM, lambda *_: loop.add_callback_from_signal(loop.stop))
    try:
        server.start()
        url = f"http://localhost:{port}/"
        print(f"impactosc explore: serving {url} (Ctrl-C stops it)", flush=True)
        if browser:
            loop.add_callback(server.show, "/")
        loop.start()
    finally:
        signal.signal(signal.SIGTERM, previous)
        server.stop()
        pool.shutdown(wait=True, cancel_futures=True)
        sys.stdout.flush()
