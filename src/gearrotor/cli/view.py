"""``gearrotor view``: a live view of a model file in the browser.

A small HTTP server on the loopback interface only (127.0.0.1) serves one page: the model in
3-D (:func:`gearrotor.plots.model_view.model_figure_3d`, node and element tooltips) and the
summary of ``gearrotor show``. A watcher thread reads the model file again whenever it changes
(modification time, size or content); the page asks for the state every half second and redraws
on a new version, or shows the validation error in the command line's one-line form
(``error: FILE: FIELD: ...``) until the file is fixed. The first step towards a model editor.

Routes: ``/`` the page, ``/plotly.js`` the plotly bundle (served from the installed package: no
network), ``/state`` ``{"version", "error", "title", "summary"}``, ``/figure.json`` the figure.
"""

from __future__ import annotations

import hashlib
import json
import threading
import time
from http import HTTPStatus
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from typing import Annotated

import typer

from ..errors import ModelError
from .errors import cli_errors, input_error
from .options import count

__all__ = ["view_command", "ModelWatcher", "serve"]

_PAGE = """<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>gearrotor view</title>
<style>
body { font-family: system-ui, sans-serif; margin: 0; color: #222; }
header { background: #24364b; color: white; padding: 10px 20px; }
header h1 { margin: 0; font-size: 1.2em; }
#error { display: none; background: #fde2e2; color: #8b1a1a; padding: 8px 20px;
         font-family: monospace; white-space: pre-wrap; }
#status { font-size: 0.85em; opacity: 0.8; }
pre { margin: 10px 20px; font-size: 0.8em; }
#figure { height: 70vh; }
</style>
<script src="/plotly.js"></script></head>
<body><header><h1 id="title">gearrotor view</h1><div id="status"></div></header>
<div id="error"></div><div id="figure"></div><pre id="summary"></pre>
<script>
let version = -1;
async function poll() {
  try {
    const s = await (await fetch('/state?since=' + version, {cache: 'no-store'})).json();
    if (s.version !== version) {
      version = s.version;
      const err = document.getElementById('error');
      if (s.error) {
        err.textContent = s.error; err.style.display = 'block';
      } else {
        err.textContent = ''; err.style.display = 'none';
        const fig = await (await fetch('/figure.json?v=' + version, {cache: 'no-store'})).json();
        await Plotly.react('figure', fig.data, fig.layout, {responsive: true});
        document.getElementById('summary').textContent = s.summary;
      }
      document.getElementById('title').textContent = s.title;
      document.body.dataset.version = version;
      document.body.dataset.state = s.error ? 'error' : 'ok';
      document.getElementById('status').textContent =
        (s.error ? 'invalid model' : 'model loaded') + ' (version ' + version + ')';
    }
  } catch (e) {
    document.getElementById('status').textContent = 'server stopped';
  }
  setTimeout(poll, 500);
}
poll();
</script></body></html>
"""


class ModelWatcher:
    """The model file's current state: a version number that grows with every change of the
    file, and either the figure and summary of the model or the one-line error."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self.version = 0
        self.error: str | None = None
        self.figure_json = "{}"
        self.summary = ""
        self.title = str(path)
        self._stamp: tuple | None = None
        self._lock = threading.Lock()
        self.refresh()

    def _signature(self) -> tuple:
        try:
            data = self.path.read_bytes()
        except OSError as exc:
            return ("missing", str(exc))
        return ("file", hashlib.sha256(data).hexdigest())

    def refresh(self) -> bool:
        """Reload when the file changed; True when the state changed."""
        stamp = self._signature()
        if stamp == self._stamp:
            return False
        from ..analyses.model_summary import summarize
        from ..io import load_model
        from ..plots.model_view import model_figure_3d

        try:
            train = load_model(self.path)
            fig = model_figure_3d(train)
            fig.update_layout(height=None, autosize=True)
            figure_json = fig.to_json()
            summary = summarize(train).table()
            error, title = None, f"{train.name} — {self.path.name}"
        except Exception as exc:  # noqa: BLE001 - every error is shown in the page
            err = input_error(exc)
            if err is None:
                error = f"internal error: {type(exc).__name__}: {exc}"
            else:
                error = f"error: {err}"
            error = " ".join(error.split())  # one line, as the command line prints it
            figure_json, summary, title = self.figure_json, self.summary, self.title
        with self._lock:
            self._stamp = stamp
            self.version += 1
            self.error, self.figure_json, self.summary, self.title = (
                error,
                figure_json,
                summary,
                title,
            )
        return True

    def state(self) -> dict:
        with self._lock:
            return {
                "version": self.version,
                "error": self.error,
                "title": self.title,
                "summary": self.summary,
            }


def _handler(watcher: ModelWatcher, plotly_js: bytes):
    class Handler(BaseHTTPRequestHandler):
        def log_message(self, *args) -> None:  # quiet: the terminal shows the URL only
            pass

        def _send(self, body: bytes, kind: str, status: int = HTTPStatus.OK) -> None:
            self.send_response(status)
            self.send_header("Content-Type", kind)
            self.send_header("Content-Length", str(len(body)))
            self.send_header("Cache-Control", "no-store")
            self.end_headers()
            self.wfile.write(body)

        def do_GET(self) -> None:  # noqa: N802 - http.server's name
            route = self.path.split("?", 1)[0]
            if route == "/":
                self._send(_PAGE.encode(), "text/html; charset=utf-8")
            elif route == "/plotly.js":
                self._send(plotly_js, "application/javascript")
            elif route == "/state":
                self._send(json.dumps(watcher.state()).encode(), "application/json")
            elif route == "/figure.json":
                with watcher._lock:
                    body = watcher.figure_json.encode()
                self._send(body, "application/json")
            else:
                self._send(b"not found", "text/plain", HTTPStatus.NOT_FOUND)

    return Handler


def serve(path: Path, port: int = 0, *, interval: float = 0.3):
    """Start the server and the watcher (daemon threads); returns ``(server, watcher)``.
    ``server.server_address`` holds the port actually bound (``port=0``: a free one)."""
    from plotly.offline import get_plotlyjs

    watcher = ModelWatcher(path)
    try:
        server = ThreadingHTTPServer(
            ("127.0.0.1", port), _handler(watcher, get_plotlyjs().encode())
        )
    except OSError as exc:
        raise ModelError(
            f"cannot listen on 127.0.0.1:{port}: {exc.strerror or exc}",
            field="--port",
            value=port,
            expected="a free port",
        ) from None
    server.daemon_threads = True

    def watch() -> None:
        while True:
            time.sleep(interval)
            watcher.refresh()

    threading.Thread(target=watch, daemon=True).start()
    threading.Thread(target=server.serve_forever, daemon=True).start()
    return server, watcher


@cli_errors()
def view_command(
    model: Annotated[Path, typer.Argument(help="TOML model file")],
    port: Annotated[
        int,
        typer.Option(parser=count(0, 65535), help="port on 127.0.0.1 (default 0: a free one)"),
    ] = 0,
) -> None:
    """Live view of a model file: serves a page on 127.0.0.1 (loopback only) with the model in
    3-D (node and element tooltips) and its summary, redrawn whenever the file changes; an
    invalid file shows its one-line error in the page until it is fixed. Stop with Ctrl-C
    (exit status 0)."""
    if not model.exists():
        raise ModelError(
            "model file not found",
            field="MODEL",
            value=str(model),
            expected="an existing TOML model file",
        )
    server, watcher = serve(model, port)
    host, bound = server.server_address[:2]
    try:  # from the first line on: a Ctrl-C right after "serving" stops it as cleanly
        typer.echo(f"serving {model} at http://{host}:{bound}/ (Ctrl-C to stop)", err=True)
        if watcher.error:
            typer.echo(watcher.error, err=True)
        while True:  # short sleeps: the kernel may hand a Ctrl-C to any thread of the process
            time.sleep(0.2)  # (the server's, the watcher's); Python then raises it here only
            # when this thread next runs, and a long sleep kept the view up for up to an hour
    except KeyboardInterrupt:
        server.shutdown()
        typer.echo("view stopped", err=True)
